//! The real-world meshes of ../shared/models (quads, missing normals, creases, slivers, 70k
//! triangles): every method loads, renders without NaN/Inf under validation, and agrees with its
//! own f64 formula within the float32 bound (the README's claim, checked here for every method).
use shadelab::method::METHODS;
use shadelab::{scene, truth};

use shadelab::geometry::load_mesh;

use crate::support::*;

/// Every model loads with the triangle count, normals and triangulation its README states,
/// unit normals and a fitted radius of 1 (moved here from the unit tests, so the models
/// folder has one rule: tests/support.rs `models_dir`).
#[test]
fn shared_models_load() {
    let Some(dir) = models_dir() else { return };
    // (file, triangles from the README, normals computed?, needed triangulation?)
    let models = [
        ("spot.obj", 5856, true, false),
        ("teapot.obj", 6320, true, false),
        ("fandisk.obj", 12946, true, false),
        ("stanford-bunny.obj", 69451, true, false),
        // 500 faces of which 468 quads: 32 + 2 * 468 triangles.
        ("suzanne.obj", 968, false, true),
    ];
    for (name, triangles, computed, polygons) in models {
        let path = dir.join(name);
        let (mesh, report) = load_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            report.triangles + report.dropped_zero_area,
            triangles,
            "{name}: {report:?}"
        );
        // A real model loses at most a few degenerate triangles, never a visible part.
        assert!(
            report.dropped_zero_area * 100 <= triangles,
            "{name}: dropped {} of {triangles}",
            report.dropped_zero_area
        );
        assert_eq!(mesh.triangle_count(), report.triangles, "{name}");
        assert_eq!(
            report.computed_normals, computed,
            "{name}: computed normals"
        );
        assert_eq!(
            report.had_quads_or_polygons, polygons,
            "{name}: triangulated"
        );
        for (i, n) in mesh.normals.iter().enumerate() {
            assert!(
                n.iter().all(|c| c.is_finite()),
                "{name}: normal {i} = {n:?}"
            );
            let len = glam::Vec3::from(*n).as_dvec3().length();
            assert!((len - 1.0).abs() <= 1e-6, "{name}: |normal {i}| = {len}");
        }
        let r = mesh
            .positions
            .iter()
            .map(|&p| glam::Vec3::from(p).as_dvec3().length())
            .fold(0.0, f64::max);
        assert!((r - 1.0).abs() <= 1e-6, "{name}: fitted radius {r}");
        eprintln!(
            "{name}: {} triangles, {} dropped, warnings {:?}",
            report.triangles, report.dropped_zero_area, report.warnings
        );
    }
}

/// A missing models folder is a visible skip, and a failure under SHADELAB_REQUIRE_MODELS=1
/// (what CI sets): runs this test binary on `shared_models_load` with a folder that is not there.
#[test]
fn missing_models_skip_visibly_and_fail_when_required() {
    let run = |require: &str| {
        rerun_test(
            "models::shared_models_load",
            &[
                ("SHADELAB_MODELS", "/nonexistent/shadelab-models".as_ref()),
                ("SHADELAB_REQUIRE_MODELS", require.as_ref()),
            ],
        )
    };
    let skipped = run("0");
    let err = String::from_utf8_lossy(&skipped.stderr);
    assert!(skipped.status.success(), "{err}");
    assert!(
        err.contains("SKIPPED: models::shared_models_load: no models folder"),
        "the skip must say SKIPPED and name the test: {err}"
    );
    let required = run("1");
    assert!(
        !required.status.success(),
        "SHADELAB_REQUIRE_MODELS=1 must fail a test without models"
    );
}

#[test]
fn every_method_on_every_shared_model_is_within_its_bound() {
    let Some(files) = model_files() else { return };
    assert!(
        files.len() >= 5,
        "expected the 5 models of the README, found {files:?}"
    );
    let r = validated_renderer();
    let mut outside = Vec::new();
    let mut worst = (0.0f64, String::new());
    for f in &files {
        let mut s = scene::scene_for_mesh(f).unwrap_or_else(|e| panic!("{e}"));
        // small: 19 methods x 5 meshes; 64 px still covers > 200 pixels of each
        s.width = 64;
        s.height = 64;
        let prepared = r.prepare(&s, &METHODS.iter().collect::<Vec<_>>()).unwrap();
        for m in METHODS {
            let gpu = prepared.for_method(m);
            let (frame, ids) = r
                .render(gpu, shadelab::gpu::Shading::Method(m), true)
                .unwrap();
            let a = truth::agreement(&frame, &truth::evaluate(&gpu.inputs, &ids.unwrap(), m));
            let ratio = a.max_color_ratio.max(a.max_normal_ratio);
            eprintln!(
                "{} {}: ratio {ratio:.3}; non-finite {} well-, {} ill-conditioned, {} overflow",
                f.display(),
                m.name,
                a.non_finite,
                a.non_finite_ill_conditioned,
                a.overflow
            );
            assert!(a.covered > 200, "{} {}: {a:?}", f.display(), m.name);
            if ratio > worst.0 {
                worst = (ratio, format!("{} {}", f.display(), m.name));
            }
            if !a.within_bound() {
                outside.push(format!("{} {}: {a:?}", f.display(), m.name));
            }
        }
    }
    eprintln!("largest error/bound ratio: {:.3} ({})", worst.0, worst.1);
    assert!(outside.is_empty(), "{}", outside.join("\n"));
    assert_validation_clean(r.context());
}

/// `shadelab plan` on every model and shipped scene, text and JSON: the counts add up, the
/// topology decides culling, and the JSON carries every method's validity range.
#[test]
fn plan_reads_every_scene_and_model() {
    let Some(models) = model_files() else { return };
    let inputs = scenes_and_models(&models);
    assert!(inputs.len() >= 6, "{inputs:?}");
    for (path, flag) in &inputs {
        let (code, text, err) = run(&["plan", flag, path]);
        assert_eq!(code, 0, "{path}: {err}");
        assert!(
            text.contains("closed and consistently oriented") && text.contains("skip back faces"),
            "{text}"
        );
        let (code, json, err) = run(&["plan", flag, path, "--json"]);
        assert_eq!(code, 0, "{path}: {err}");
        let p: serde_json::Value = serde_json::from_str(&json).unwrap();
        let n = p["triangles"].as_u64().unwrap();
        assert_eq!(
            p["front_facing"].as_u64().unwrap() + p["back_facing"].as_u64().unwrap(),
            n
        );
        let binned: u64 = p["normal_angle_deg"]["histogram"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| b[2].as_u64().unwrap())
            .sum();
        assert_eq!(binned, n, "{path}");
        assert_eq!(p["methods"].as_array().unwrap().len(), METHODS.len());
        let culled = p["skips"][0]["applies"].as_bool().unwrap();
        assert_eq!(
            culled,
            p["closed_and_oriented"].as_bool().unwrap(),
            "{path}"
        );
    }
}

/// `auto` meets its budget on every covered pixel of every shipped scene and shared model (the
/// benchmark script checks 512x512 and 1024x1024): max abs error, luminance and each channel.
/// Teeth: the same choice at a budget 16x larger breaks the smaller budget somewhere.
#[test]
fn auto_meets_its_budget_on_every_scene_and_model() {
    let Some(models) = model_files() else { return };
    let inputs = scenes_and_models(&models);
    let dir = tempfile::tempdir().unwrap();
    let budget = 1.0 / 255.0;
    let worst = |path: &str, flag: &str, e: f64, out: &str| -> f64 {
        let out = dir.path().join(out);
        let (code, _, err) = run(&[
            "compare",
            flag,
            path,
            "--size",
            "128x128",
            "--methods",
            "auto",
            "--error-budget",
            &format!("{e}"),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{path}: {err}");
        let s = read_json(out.join("summary.json"));
        let a = s["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == "auto")
            .unwrap()
            .clone();
        assert_eq!(a["non_finite_pixels"], 0, "{path}");
        let mut w = a["max_abs_error"].as_f64().unwrap();
        for c in a["channels"].as_array().unwrap() {
            w = w.max(c["max_abs_error"].as_f64().unwrap());
        }
        let chosen: u64 = s["auto"]["triangles"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t[1].as_u64().unwrap())
            .sum();
        assert_eq!(
            chosen,
            s["triangles"].as_u64().unwrap(),
            "{path}: every triangle chosen once"
        );
        w
    };
    let mut broken = 0;
    for (i, (path, flag)) in inputs.iter().enumerate() {
        let w = worst(path, flag, budget, &format!("a{i}"));
        assert!(
            w <= budget,
            "{path}: auto's worst error {w} over its budget {budget}"
        );
        if worst(path, flag, 16.0 * budget, &format!("b{i}")) > budget {
            broken += 1;
        }
    }
    assert!(
        broken > 0,
        "a 16x budget never broke 1/255: the check has no teeth"
    );
}

/// The shared models (`--mesh`) and every shipped scene (`--scene`), as command-line pairs.
fn scenes_and_models(models: &[std::path::PathBuf]) -> Vec<(String, &'static str)> {
    let mut inputs: Vec<(String, &str)> = models
        .iter()
        .map(|m| (m.to_str().unwrap().to_string(), "--mesh"))
        .collect();
    let mut scenes: Vec<_> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    scenes.sort();
    inputs.extend(
        scenes
            .iter()
            .map(|p| (p.to_str().unwrap().to_string(), "--scene")),
    );
    inputs
}
