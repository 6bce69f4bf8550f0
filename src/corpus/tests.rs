//! Unit tests of the corpus's ids, hash, shards and configuration hash.
use super::*;

#[test]
fn ids_are_relative_paths_sanitised() {
    assert_eq!(mesh_id("a/b c.obj"), "a__b_c.obj");
    assert_eq!(mesh_id("x\\y.obj"), "x__y.obj");
    assert_eq!(mesh_id(".hidden.obj"), "_.hidden.obj");
    assert_eq!(mesh_id("ok-1_2.OBJ"), "ok-1_2.OBJ");
}

#[test]
fn the_hash_is_fnv1a_and_shards_are_one_based() {
    // FNV-1a 64 of "" and "a" (the published test vectors).
    assert_eq!(stable_hash(""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(stable_hash("a"), 0xaf63_dc4c_8601_ec8c);
    let ids: Vec<String> = (0..200).map(|i| format!("m{i}.obj")).collect();
    for n in 1..6 {
        let mut seen = vec![0usize; n];
        for id in &ids {
            let k = shard_of(id, n);
            assert!((1..=n).contains(&k), "{id}: {k} of {n}");
            seen[k - 1] += 1;
        }
        // every shard gets some of 200 ids (a constant hash would put all in one)
        assert!(seen.iter().all(|c| *c > 0), "{n}: {seen:?}");
    }
}

fn env_of(pairs: &'static [(&'static str, &'static str)]) -> impl Fn(&str) -> Option<String> {
    move |k| {
        pairs
            .iter()
            .find(|(n, _)| *n == k)
            .map(|(_, v)| v.to_string())
    }
}

#[test]
fn the_shard_comes_from_the_flag_gitlab_or_slurm() {
    let none = env_of(&[]);
    assert_eq!(Shard::resolve(None, &none).unwrap().source, "none");
    assert_eq!(Shard::resolve(Some("2/3"), &none).unwrap().k, 2);
    for bad in ["0/3", "4/3", "3", "a/b", "1/0"] {
        assert!(Shard::resolve(Some(bad), &none).is_err(), "{bad}");
    }
    let gl = env_of(&[
        ("CI_NODE_INDEX", "3"),
        ("CI_NODE_TOTAL", "4"),
        ("SLURM_ARRAY_TASK_ID", "1"),
    ]);
    let s = Shard::resolve(None, &gl).unwrap();
    assert_eq!(
        (s.k, s.n, s.source.as_str()),
        (3, 4, "CI_NODE_INDEX/CI_NODE_TOTAL")
    );
    // --array=0-2: ids 0..2, min 0 -> shards 1..3
    let sl = env_of(&[
        ("SLURM_ARRAY_TASK_ID", "0"),
        ("SLURM_ARRAY_TASK_MIN", "0"),
        ("SLURM_ARRAY_TASK_COUNT", "3"),
    ]);
    assert_eq!(Shard::resolve(None, &sl).unwrap().k, 1);
    let sl = env_of(&[
        ("SLURM_ARRAY_TASK_ID", "7"),
        ("SLURM_ARRAY_TASK_MIN", "5"),
        ("SLURM_ARRAY_TASK_COUNT", "3"),
    ]);
    assert_eq!(Shard::resolve(None, &sl).unwrap().k, 3);
    let step = env_of(&[
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_STEP", "2"),
        ("SLURM_ARRAY_TASK_COUNT", "2"),
    ]);
    assert!(Shard::resolve(None, &step).is_err());
}

#[test]
fn listing_sorts_refuses_clashing_ids_and_skips_the_output() {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(d.path().join("sub")).unwrap();
    std::fs::create_dir_all(d.path().join("out")).unwrap();
    for f in ["b.obj", "sub/a.obj", "out/x.obj", "note.txt", ".h.obj"] {
        std::fs::write(d.path().join(f), "v 0 0 0\n").unwrap();
    }
    let m = list_dir(d.path(), Some(&d.path().join("out"))).unwrap();
    let ids: Vec<&str> = m.iter().map(|m| m.id.as_str()).collect();
    assert_eq!(ids, ["b.obj", "sub__a.obj"]);
    std::fs::write(d.path().join("sub__a.obj"), "").unwrap();
    let e = list_dir(d.path(), Some(&d.path().join("out"))).unwrap_err();
    assert!(e.to_string().contains("same id"), "{e}");
    let list = d.path().join("list.txt");
    std::fs::write(&list, "# corpus\nb.obj\n\nsub/a.obj\n").unwrap();
    let m = list_file(&list).unwrap();
    assert_eq!(m[1].path, d.path().join("sub/a.obj"));
    std::fs::write(&list, "b.obj\nb.obj\n").unwrap();
    assert!(list_file(&list).is_err());
}

#[test]
fn the_configuration_hash_sees_every_field() {
    let c = Config {
        version: "1".into(),
        compare_schema_version: 2,
        methods: vec!["gouraud".into()],
        width: 64,
        height: 64,
        precision: crate::method::Precision::F32,
        threshold: 1.0 / 255.0,
        bench_runs: None,
        images: false,
    };
    let mut d = c.clone();
    d.width = 65;
    assert_ne!(c.hash(), d.hash());
    let mut d = c.clone();
    d.methods.push("flat".into());
    assert_ne!(c.hash(), d.hash());
    assert_eq!(c.hash(), c.clone().hash());
}
