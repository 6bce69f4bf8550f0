//! Unit tests of the corpus's ids, hash, shards, configuration hash and answer (the report's rule).
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

/// One answer-table implementation: the corpus's answer is the report's rule on the same
/// errors and cost models, cell for cell, and the isa figures become the same static rows.
#[test]
fn the_corpus_answer_is_the_reports_on_the_same_inputs() {
    use crate::compare::Metric;
    use crate::cost::CostModelId;
    use crate::method::Precision;
    use crate::report::answer::{answer, Budget, SceneError};
    use std::collections::BTreeMap;
    // Three meshes (one failed), three methods: (max, p99) per mesh.
    let figures = [
        (
            "a",
            [
                ("phong_exact", 1e-6, 1e-7),
                ("fast", 2e-3, 1e-4),
                ("rough", 0.1, 0.01),
            ],
        ),
        (
            "b",
            [
                ("phong_exact", 1e-6, 1e-7),
                ("fast", 3e-3, 2e-4),
                ("rough", 3e-3, 1e-3),
            ],
        ),
    ];
    let mut meshes = Vec::new();
    let mut errors = Vec::new();
    for (id, rows) in figures {
        let methods: Vec<serde_json::Value> = rows
            .iter()
            .map(|(n, max, p99)| {
                serde_json::json!({"name": n, "covered_pixels": 50, "non_finite_pixels": 0,
                                   "max_abs_error": max, "p99_abs_error": p99})
            })
            .collect();
        for (n, max, p99) in rows {
            errors.push(SceneError {
                scene: id.into(),
                method: n.into(),
                precision: Precision::F32,
                covered_pixels: 50,
                non_finite_pixels: 0,
                metrics: BTreeMap::from([
                    (Metric::MaxAbsError, Some(max)),
                    (Metric::P99AbsError, Some(p99)),
                ]),
                evidence: format!("meshes/{id}/result.json"),
            });
        }
        meshes.push(merged(
            id,
            "ok",
            Some(serde_json::json!({ "methods": methods })),
        ));
    }
    meshes.push(merged("broken", "failed", None));
    let isa = crate::isa::cost::Compiled {
        report: serde_json::from_value(serde_json::json!({"version": 1, "precision": "f32",
            "scene": "s", "kernel_counts": [2, 3], "model": "m", "elapsed_s": 0.0,
            "families": [{"family": "gfx1100", "supported": true, "status": "compiled",
                "device_name": null, "driver_name": null, "driver_info": null,
                "elapsed_ms": null, "statistics": []}],
            "results": [isa_row("phong_exact", 1.0), isa_row("fast", 0.8),
                        isa_row("rough", 0.5)]}))
        .unwrap(),
        evidence: "isa/isa.json".into(),
    };
    let models = crate::costs::builtin().models(&super::tables::evidence(&meshes, Some(&isa)));
    assert_eq!(models.len(), 1, "{models:?}");
    assert_eq!(models[0].id, *"isa:gfx1100");
    let corpus = super::tables::answer_of(&meshes, Precision::F32, models.clone());
    let names: Vec<String> = ["phong_exact", "fast", "rough"].map(String::from).to_vec();
    let report = answer(&["a".into(), "b".into()], &names, &errors, models);
    assert_eq!(corpus.cells, report.cells);
    assert_eq!(corpus.checks, report.checks);
    // max 1/255: fast (0.8) and rough (0.5) both within on a and b? rough is not (0.1 on a).
    let c = corpus
        .cell(
            &Budget::parse_id("max_1_255").unwrap(),
            &CostModelId::parse("isa:gfx1100").unwrap(),
        )
        .unwrap();
    assert_eq!(c.answer.method, "fast");
    assert_eq!(c.binding.as_ref().unwrap().scene, "a");
    // Teeth: a mesh's different figure changes the corpus's cells, not the report's.
    if let Some(s) = &mut meshes[1].result.summary {
        s["methods"][1]["max_abs_error"] = serde_json::json!(0.5);
    }
    let changed = super::tables::answer_of(&meshes, Precision::F32, report.cost_models.clone());
    assert_ne!(changed.cells, report.cells);
}

fn merged(id: &str, status: &str, summary: Option<serde_json::Value>) -> super::merge::Merged {
    super::merge::Merged {
        result: super::run::MeshResult {
            schema_version: 1,
            id: id.into(),
            path: format!("{id}.obj"),
            content_hash: String::new(),
            config_hash: String::new(),
            status: status.into(),
            error: (status != "ok").then(|| "broken".into()),
            summary,
        },
        bytes: Vec::new(),
        machine: "m".into(),
        timing: serde_json::Value::Null,
    }
}

fn isa_row(method: &str, ratio: f64) -> serde_json::Value {
    serde_json::json!({"family": "gfx1100", "method": method, "stage": "fragment", "kind": "draw",
                       "program": method, "statistics": {"inverse_throughput": 70.0 * ratio},
                       "ratio_to_phong_exact": {"inverse_throughput": ratio}, "hash": []})
}
