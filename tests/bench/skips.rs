//! `shadelab skips`: the work changes, the pixels do not.
use crate::support::*;

/// `shadelab skips` on a closed mesh: every row draws the same pixels, culling halves the
/// fragment invocations, the rows are paired over the same rounds, and skips.json matches its
/// schema. With `--cull none` no culled row appears.
#[test]
fn skips_change_the_work_but_not_the_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let study = |extra: &[&str]| {
        let out = dir.path().join(extra.join("_"));
        let mut args = vec![
            "skips",
            "--scene",
            "scenes/torus.toml",
            "--size",
            "96x96",
            "--validate",
            "--repeat",
            "6",
            "--warmup",
            "1",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = run(&args);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains(" (default) |"), "{stdout}");

        read_json(out.join("skips.json"))
    };
    let v = study(&[]);
    assert!(std::fs::read_to_string(dir.path().join("skips.md"))
        .unwrap()
        .contains("| cull+no_normal (default) |"));
    let validator = schema_validator("docs/skips.schema.json");
    assert!(
        validator.is_valid(&v),
        "skips.json does not match its schema"
    );
    let mut broken = v.clone();
    broken["rows"][0]["variant"]
        .as_object_mut()
        .unwrap()
        .remove("prepass");
    assert!(
        !validator.is_valid(&broken),
        "the schema check has no teeth"
    );

    assert_eq!(
        v["culls"], true,
        "the torus is closed and consistently oriented"
    );
    let rows = v["rows"].as_array().unwrap();
    let row = |name: &str| {
        rows.iter()
            .find(|r| r["name"] == name)
            .unwrap_or_else(|| panic!("no row {name}"))
    };
    let names: Vec<&str> = rows.iter().map(|r| r["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "none",
            "cull",
            "cull+no_normal",
            "cull+no_normal+prepass",
            "cull+no_normal+front_to_back",
            "auto+cull+no_normal"
        ]
    );
    let covered = row("none")["covered_pixels"].as_u64().unwrap();
    assert!(covered > 1000, "{covered}");
    for r in rows {
        assert_eq!(
            r["covered_pixels"], covered,
            "{}: skips change no pixel",
            r["name"]
        );
        for k in ["ratio_to_none", "ratio_to_default"] {
            assert_eq!(
                r[k]["rounds"], 6,
                "{} {k}: paired over every round",
                r["name"]
            );
            let (lo, m, hi) = (
                r[k]["ci95_low"].as_f64().unwrap(),
                r[k]["median"].as_f64().unwrap(),
                r[k]["ci95_high"].as_f64().unwrap(),
            );
            assert!(
                lo > 0.0 && lo <= m && m <= hi,
                "{} {k}: {lo} {m} {hi}",
                r["name"]
            );
        }
    }
    assert_eq!(rows.iter().filter(|r| r["is_default"] == true).count(), 1);
    assert_eq!(v["default"], "cull+no_normal");
    let inv = |name: &str| row(name)["fragment_invocations"].as_u64().unwrap();
    // Culling leaves out the back faces: fewer fragments, by how much depends on the driver's
    // count (lavapipe 22.3.6 counts whole pixel blocks: under 0.6 of the unculled; 25.0.7 the
    // fragments left after early depth: 4340 of 6426, 0.675): at most 0.8 of them.
    assert!(
        inv("cull") * 10 < inv("none") * 8,
        "cull {} none {}",
        inv("cull"),
        inv("none")
    );
    assert_eq!(
        inv("cull"),
        inv("cull+no_normal"),
        "the normal target changes no fragment"
    );
    // The pre-pass's own fragments are counted too.
    assert!(inv("cull+no_normal+prepass") > inv("cull+no_normal"));

    // Teeth of the culling rows: with culling off there is none.
    let v = study(&["--cull", "none"]);
    assert_eq!(v["culls"], false);
    let rows = v["rows"].as_array().unwrap();
    assert!(rows.iter().all(|r| r["variant"]["cull"] == false));
    assert_eq!(v["default"], "no_normal");
}
