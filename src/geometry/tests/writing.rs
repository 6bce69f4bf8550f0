//! OBJ writing: round trips through the loader, deduplication, the header.
use super::*;

#[test]
fn obj_text_round_trips_through_the_loader() {
    for g in all_generators() {
        let built = g.build().unwrap();
        let text = obj_text(&built, "round trip\n\nsecond line");
        assert_eq!(
            text,
            obj_text(&built, "round trip\n\nsecond line"),
            "deterministic"
        );
        assert!(
            text.starts_with("# round trip\n#\n# second line\n"),
            "header: {}",
            &text[..60.min(text.len())]
        );
        let (loaded, report) = load_text(&text).unwrap();
        assert!(
            !report.computed_normals && report.dropped_zero_area == 0,
            "{}: {report:?}",
            g.describe()
        );
        let mut fitted = built.clone();
        fit_unit(&mut fitted);
        assert_eq!(loaded.triangle_count(), fitted.triangle_count());
        for (i, ((pa, pb), (na, nb))) in loaded
            .positions
            .iter()
            .zip(&fitted.positions)
            .zip(loaded.normals.iter().zip(&fitted.normals))
            .enumerate()
        {
            assert_close(
                &format!("{}: position {i}", g.describe()),
                (dvec(*pa) - dvec(*pb)).length(),
                0.0,
                1e-6,
            );
            assert_close(
                &format!("{}: normal {i}", g.describe()),
                (dvec(*na) - dvec(*nb)).length(),
                0.0,
                1e-6,
            );
        }
    }
}

#[test]
fn obj_text_deduplicates_vertices() {
    let cube = Generator::Cube {}.build().unwrap();
    let text = obj_text(&cube, "");
    let count = |kw: &str| {
        text.lines()
            .filter(|l| l.split_whitespace().next() == Some(kw))
            .count()
    };
    assert_eq!(
        (count("v"), count("vn"), count("f")),
        (8, 8, 12),
        "cube text:\n{text}"
    );
}

#[test]
fn write_obj_writes_a_loadable_file_with_a_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sub/ico.obj");
    let mesh = Generator::Icosphere { subdivisions: 1 }.build().unwrap();
    write_obj(&mesh, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.starts_with("# written by shadelab from: generator icosphere subdivisions=1\n"),
        "{}",
        &text[..80]
    );
    let (loaded, _) = load_obj(&path).unwrap();
    assert_eq!(loaded.triangle_count(), 80);
}
