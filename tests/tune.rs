//! `shadelab tune`: tune.json against its schema (with teeth), the table's answer per cost
//! model, the candidates' method files through `compare` within their proven colour bounds, the
//! same form with other coefficients compiling to the same statistics (what the classes
//! assume), `--max-angle`'s domain, and the refusals.
use std::path::Path;

use crate::support::*;

fn tune_ok(args: &[&str], out: &Path) -> (serde_json::Value, String) {
    let mut a = vec!["tune"];
    a.extend(args);
    let o = out.display().to_string();
    a.extend(["--out", &o]);
    let (code, stdout, stderr) = run(&a);
    assert_eq!(code, 0, "{args:?}\n{stdout}\n{stderr}");
    (read_json(out.join("tune.json")), stdout)
}

fn candidates(r: &serde_json::Value) -> &Vec<serde_json::Value> {
    r["candidates"].as_array().unwrap()
}

/// The float32 bound of a candidate.
fn f32_bound(c: &serde_json::Value) -> &serde_json::Value {
    c["bounds"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["precision"] == "f32")
        .unwrap()
}

/// A scene through tune with one cost model: the report is valid, the table answers the model,
/// every tuned candidate has its method file, and every candidate's compare error on the scene
/// (its file through `--method-file`, the papers' by name) stays within its proven float32
/// colour bound, up to the lighting's own float32 rounding (phong_exact's compare error). At
/// the scene's own size: at other sizes lavapipe draws a few sliver pixels whose weights are
/// off by far more than their rounding (the truth's ill-conditioned pixels), where a
/// polynomial, the papers' too, leaves the domain (docs/tune.md, limits).
#[test]
fn tune_on_a_scene_writes_files_whose_compare_error_is_within_their_proof() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t");
    let scene = "scenes/sphere_coarse.toml";
    let (r, stdout) = tune_ok(
        &[
            "--scene",
            scene,
            "--error-budget",
            "1/255",
            "--cost-model",
            "isa:amd:navi21",
        ],
        &out,
    );
    assert_schema(
        &r,
        "docs/tune.schema.json",
        "/candidates/0/bounds/0",
        "colour",
    );
    assert!(out.join("tune.txt").is_file());
    let answer = &r["cost_models"][0];
    assert_eq!(answer["model"], "isa:amd:navi21");
    let statement = answer["statement"].as_str().unwrap();
    assert!(
        stdout.contains(&format!("isa:amd:navi21: {statement}")),
        "{stdout}"
    );
    assert!(
        statement.starts_with("none is cheaper than phong_exact")
            || answer["cheapest"]["within_budget"] == true,
        "{answer}"
    );
    // the domain holds every covered pixel's z; the minimax fits are certified optima
    let (lo, hi) = (
        r["domain"]["z_range"][0].as_f64().unwrap(),
        r["domain"]["z_range"][1].as_f64().unwrap(),
    );
    let px = &r["domain"]["mesh"]["pixels_z"];
    assert!(
        px["min"].as_f64().unwrap() >= lo && px["max"].as_f64().unwrap() <= hi,
        "{px}"
    );
    let mut files = Vec::new();
    let mut names = Vec::new();
    for c in candidates(&r) {
        let id = c["id"].as_str().unwrap().to_string();
        if c["family"] == "paper" || c["family"] == "reference" {
            assert!(c["file"].is_null());
        } else {
            let f = out.join(c["file"].as_str().unwrap());
            assert!(f.is_file(), "{f:?}");
            files.extend(["--method-file".to_string(), f.display().to_string()]);
            assert_eq!(c["remez"]["equioscillates"], true, "{c}");
        }
        names.push(id);
    }
    let cmp = dir.path().join("c");
    let list = names.join(",");
    let mut a: Vec<&str> = files.iter().map(String::as_str).collect();
    let o = cmp.display().to_string();
    a.extend(["compare", "--scene", scene, "--methods", &list, "--out", &o]);
    let (code, so, se) = run(&a);
    assert_eq!(code, 0, "{so}{se}");
    let s = read_json(cmp.join("summary.json"));
    let max = |n: &str| {
        s["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()["max_abs_error"]
            .as_f64()
            .unwrap()
    };
    let lighting = max("phong_exact");
    let mut checked = 0;
    for c in candidates(&r) {
        let id = c["id"].as_str().unwrap();
        if let Some(bound) = f32_bound(c)["colour"].as_f64() {
            let got = max(id);
            assert!(
                got <= bound + lighting + 1e-6,
                "{id}: compare {got:e} > proven {bound:e}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked}");
}

/// What the classes assume: a form's compiled code does not depend on its coefficients. Two
/// quartics fitted on different ranges compile to the same statistics on two families; a cubic
/// does not (the teeth).
#[test]
fn the_same_form_with_other_coefficients_compiles_alike() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    tune_ok(&["--max-angle", "40", "--cost-model", "isa:amd:tahiti"], &a);
    tune_ok(&["--max-angle", "90", "--cost-model", "isa:amd:tahiti"], &b);
    let file = |d: &Path, id: &str| d.join(format!("methods/{id}.glsl")).display().to_string();
    let (q40, q90, c90) = (
        file(&a, "angle40_triangle_minimax4"),
        file(&b, "angle90_triangle_minimax4"),
        file(&b, "angle90_triangle_minimax3"),
    );
    assert_ne!(std::fs::read(&q40).unwrap(), std::fs::read(&q90).unwrap());
    let isa = dir.path().join("isa");
    let o = isa.display().to_string();
    let (code, so, se) = run(&[
        "--method-file",
        &q40,
        "--method-file",
        &q90,
        "--method-file",
        &c90,
        "isa",
        "--families",
        "amd:tahiti,amd:navi21",
        "--methods",
        "angle40_triangle_minimax4,angle90_triangle_minimax4,angle90_triangle_minimax3",
        "--out",
        &o,
    ]);
    assert_eq!(code, 0, "{so}{se}");
    let rows = read_json(isa.join("isa.json"))["results"]
        .as_array()
        .unwrap()
        .clone();
    let stats = |fam: &str, m: &str| {
        rows.iter()
            .find(|x| {
                x["family"] == fam
                    && x["method"] == m
                    && x["kind"] == "draw"
                    && x["stage"] == "fragment"
            })
            .unwrap()["statistics"]
            .clone()
    };
    for fam in ["amd:tahiti", "amd:navi21"] {
        let (x, y) = (
            stats(fam, "angle40_triangle_minimax4"),
            stats(fam, "angle90_triangle_minimax4"),
        );
        assert_eq!(x["inverse_throughput"], y["inverse_throughput"], "{fam}");
        assert_eq!(x["instructions"], y["instructions"], "{fam}: {x} vs {y}");
        assert_ne!(
            x["instructions"],
            stats(fam, "angle90_triangle_minimax3")["instructions"]
        );
    }
}

/// `--max-angle`: prove's triangle domain ((1 + 2 cos theta)/3 up), the default material, no
/// mesh; the papers re-fitted; the refusals.
#[test]
fn tune_over_an_angle_and_its_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a");
    let (r, stdout) = tune_ok(
        &["--max-angle", "40", "--cost-model", "isa:amd:tahiti"],
        &out,
    );
    assert_schema(&r, "docs/tune.schema.json", "/papers/0", "best_rel");
    assert_eq!(r["source"]["kind"], "max_angle");
    assert_eq!(r["source"]["domain"], "triangle");
    let lo = r["domain"]["z_range"][0].as_f64().unwrap();
    let exact = (1.0 + 2.0 * 40f64.to_radians().cos()) / 3.0;
    assert!(lo <= exact && exact - lo < 1e-6, "{lo} vs {exact}");
    assert!(r["domain"]["mesh"].is_null() && r["classes"].as_array().unwrap().is_empty());
    assert!(stdout.contains("the papers re-fitted"), "{stdout}");
    let (e, _) = tune_ok(
        &[
            "--max-angle",
            "40",
            "--domain",
            "edge",
            "--cost-model",
            "isa:amd:tahiti",
        ],
        &dir.path().join("e"),
    );
    let edge_lo = e["domain"]["z_range"][0].as_f64().unwrap();
    assert!(
        (edge_lo - 20f64.to_radians().cos().powi(2)).abs() < 1e-6,
        "{edge_lo}"
    );
    let o = dir.path().join("x").display().to_string();
    let (code, _, err) = run(&["tune", "--max-angle", "0", "--out", &o]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--max-angle 0: expected degrees in (0, 180]"),
        "{err}"
    );
    let (code, _, err) = run(&["tune", "--out", &o]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = run(&[
        "tune",
        "--max-angle",
        "40",
        "--cost-model",
        "gpu:x",
        "--out",
        &o,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("isa:FAMILY"), "{err}");
}

/// The f32 length bound of candidate `id` in tune.json: (proven, found at a real z).
fn tuned_length(r: &serde_json::Value, id: &str) -> (f64, f64) {
    let c = candidates(r).iter().find(|c| c["id"] == id).unwrap();
    let b = f32_bound(c);
    (
        b["length_error"].as_f64().unwrap(),
        b["found_length_error"].as_f64().unwrap(),
    )
}

/// Whether prove's length bound (`upper`, `found`) over the triangle domain and tune's over
/// the same domain's z enclose the same maximum consistently: tune's bound is prove's (the
/// real formula, its found value within 1 %) plus the rounding of float32 arithmetic.
fn consistent(upper: f64, found: f64, tune: (f64, f64)) -> bool {
    let (bound, tune_found) = tune;
    tune_found <= upper && upper <= bound && (found - tune_found).abs() <= 0.01 * tune_found
}

/// A tuned file is a row with its f64 formula: `verify` accepts it (its twin agrees with the
/// device, Vulkan and the software engine; judged against another formula it fails), `prove`
/// bounds it, consistently with tune.json's proof of that candidate (and not with another
/// candidate's), `stress` runs it.
#[test]
fn a_tuned_file_is_accepted_by_verify_and_prove() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t");
    let (r, _) = tune_ok(
        &["--max-angle", "40", "--cost-model", "isa:amd:tahiti"],
        &out,
    );
    let id = "angle40_triangle_newton1_seed1";
    let file = out.join(format!("methods/{id}.glsl")).display().to_string();
    let scene = "scenes/sphere_coarse.toml";
    for engine in ["vulkan", "software"] {
        let (code, so, se) = run(&[
            "--method-file",
            &file,
            "verify",
            "--scene",
            scene,
            "--methods",
            id,
            "--engine",
            engine,
        ]);
        assert_eq!(code, 0, "{engine}: {so}{se}");
    }
    let (code, so, _) = run(&[
        "--method-file",
        &file,
        "verify",
        "--scene",
        scene,
        "--methods",
        id,
        "--against",
        "phong_unnormalized",
    ]);
    assert_ne!(code, 0, "the teeth: another formula is not its twin\n{so}");
    let (code, so, se) = run(&["--method-file", &file, "list", "--json"]);
    assert_eq!(code, 0, "{se}");
    let list: serde_json::Value = serde_json::from_str(&so).unwrap();
    let row = list["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == id)
        .unwrap()
        .clone();
    assert_eq!(row["family"], "tuned", "{row}");
    assert!(list["software_forms"][id].is_object(), "a software form");
    let p = dir.path().join("p");
    let (code, so, se) = run(&[
        "--method-file",
        &file,
        "prove",
        "--methods",
        id,
        "--max-angle",
        "40",
        "--out",
        p.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{so}{se}");
    let proof = read_json(p.join("proof.json"));
    let tri = proof["methods"][0]["domains"]
        .as_array()
        .unwrap()
        .iter()
        .find(|d| d["domain"] == "triangle")
        .unwrap()["metrics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["metric"] == "length_error")
        .unwrap()
        .clone();
    let (upper, found) = (
        tri["proven_upper"].as_f64().unwrap(),
        tri["found"].as_f64().unwrap(),
    );
    let mine = tuned_length(&r, id);
    assert!(
        consistent(upper, found, mine),
        "prove {upper:e} {found:e}, tune {mine:?}"
    );
    let other = tuned_length(&r, "angle40_triangle_minimax2");
    assert!(!consistent(upper, found, other), "the teeth: {other:?}");
    let s = dir.path().join("s");
    let (code, so, se) = run(&[
        "--method-file",
        &file,
        "stress",
        "--methods",
        id,
        "--out",
        s.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{so}{se}");
}

/// A tuned file whose code is not what its line says is refused (exit 2, naming the way out);
/// without its line it is the user's own method again, which `verify` refuses for want of a
/// twin.
#[test]
fn an_edited_tuned_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t");
    tune_ok(
        &["--max-angle", "40", "--cost-model", "isa:amd:tahiti"],
        &out,
    );
    let id = "angle40_triangle_minimax2";
    let text = std::fs::read_to_string(out.join(format!("methods/{id}.glsl"))).unwrap();
    let scene = "scenes/sphere_coarse.toml";
    let verify = |text: &str| {
        let d = dir.path().join("e");
        std::fs::create_dir_all(&d).unwrap();
        let f = d.join(format!("{id}.glsl"));
        std::fs::write(&f, text).unwrap();
        let f = f.display().to_string();
        run(&[
            "--method-file",
            &f,
            "verify",
            "--scene",
            scene,
            "--methods",
            id,
        ])
    };
    let (code, so, se) = verify(&text);
    assert_eq!(code, 0, "as written: {so}{se}");
    let line = text
        .lines()
        .find(|l| l.contains("shadelab-tuned:"))
        .unwrap();
    let edited = text.replacen("k = k * z + R(", "k = k * z + R(0.5) + R(", 1);
    assert_ne!(edited, text);
    let (code, _, se) = verify(&edited);
    assert_eq!(code, 2, "{se}");
    assert!(
        se.contains("its code differs from its // shadelab-tuned: line")
            && se.contains("delete that line to use it as your own method"),
        "{se}"
    );
    let mine = edited.replace(&format!("{line}\n"), "");
    let (code, _, se) = verify(&mine);
    assert_eq!(code, 2, "{se}");
    assert!(se.contains("needs the method's f64 twin"), "{se}");
}

/// The classes' answers for auto: each answer that is a fitted form names its file under
/// methods/classes/, a tuned file proven on the class's domain with the class's coefficients
/// (one per class and form); the folder given to `--method-file` makes them auto candidates,
/// and `auto` ranked by a model under which a class form is cheaper draws one.
#[test]
fn the_classes_files_are_auto_candidates_that_auto_draws() {
    // VideoCore IV is the family under which a class form is cheaper: `make compilers` builds it.
    if !crate::isa_mobile::compilers_ready(&["broadcom:vc4"]) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t");
    let (r, _) = tune_ok(
        &[
            "--scene",
            "scenes/torus.toml",
            "--cost-model",
            "isa:amd:tahiti",
            "--cost-model",
            "isa:broadcom:vc4",
        ],
        &out,
    );
    let mut files = std::collections::BTreeSet::new();
    for c in r["classes"].as_array().unwrap() {
        for a in c["answers"].as_array().unwrap() {
            let fitted = a["form"]
                .as_str()
                .is_some_and(|f| f.starts_with("minimax d") || f.starts_with("newton k"));
            assert_eq!(a["file"].is_string(), fitted, "{a}");
            let Some(f) = a["file"].as_str() else {
                continue;
            };
            let text = std::fs::read_to_string(out.join(f)).unwrap();
            let t = shadelab::method::tuned::Tuned::of_text(&text)
                .unwrap()
                .unwrap();
            assert_eq!(serde_json::json!(t.domain), c["domain"], "{f}");
            assert_eq!(serde_json::json!(t.coeffs), a["coeffs"], "{f}");
            assert!(t.matches(&text));
            files.insert(f.to_string());
        }
    }
    assert!(
        !files.is_empty(),
        "the torus has classes with a fitted form"
    );
    let classes = out.join("methods/classes");
    let on_disk = std::fs::read_dir(&classes).unwrap().count();
    assert_eq!(on_disk, files.len(), "one file per class and form");
    let cmp = dir.path().join("c");
    let (code, so, se) = run(&[
        "--method-file",
        classes.to_str().unwrap(),
        "compare",
        "--scene",
        "scenes/torus.toml",
        "--methods",
        "auto",
        "--cost-model",
        "isa:broadcom:vc4",
        "--out",
        cmp.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{so}{se}");
    let s = read_json(cmp.join("summary.json"));
    let drawn: usize = s["auto"]["triangles"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| {
            files
                .iter()
                .any(|f| f.contains(&format!("/{}.glsl", p[0].as_str().unwrap())))
        })
        .map(|p| p[1].as_u64().unwrap() as usize)
        .sum();
    assert!(drawn > 0, "{}", s["auto"]);
}

/// One name per concept: tune's error budget is `--error-budget`, as every command's; the
/// former `--budget` is still read, with a deprecation warning, and both at once are refused.
/// (An angle out of range stops each run before any work, after the budget was read.)
#[test]
fn tune_reads_the_former_budget_flag_with_a_deprecation_warning() {
    let tune = |budget_flag: &[&str]| {
        let mut a = vec!["tune", "--max-angle", "400", "--out", "/nonexistent/tune"];
        a.extend(budget_flag);
        run(&a)
    };
    let (code, _, err) = tune(&["--budget", "1/255"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--budget is deprecated: use --error-budget"),
        "{err}"
    );
    assert!(err.contains("--max-angle 400"), "{err}");
    // Teeth: the current name warns of nothing; both names at once are a usage error.
    let (code, _, err) = tune(&["--error-budget", "1/255"]);
    assert_eq!(code, 2, "{err}");
    assert!(!err.contains("deprecated"), "{err}");
    let (code, _, err) = tune(&["--error-budget", "1/255", "--budget", "1/255"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot be used with"), "{err}");
}

/// A planar mesh (every vertex at z = 0, normals computed: every vertex normal equal) lost every
/// GPU cost model: its degree-3 and -4 fits on the zero-width domain were handed over unproven,
/// every family's child refused them, and each model read "not supported by this driver".
/// Now the domain gets the fits it supports, every model is measured, and the answer says in
/// words that no normalisation is needed.
#[test]
fn tune_on_a_planar_mesh_measures_every_model_and_says_no_normalisation_is_needed() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("planar.obj");
    let n = 6;
    let mut text = String::new();
    for j in 0..=n {
        for i in 0..=n {
            text += &format!(
                "v {} {} 0\n",
                i as f64 / n as f64 - 0.5,
                j as f64 / n as f64 - 0.5
            );
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c) = (a + 1, a + n + 1);
            text += &format!("f {a} {b} {}\nf {a} {} {c}\n", c + 1, c + 1);
        }
    }
    std::fs::write(&obj, text).unwrap();
    let out = dir.path().join("t");
    let (r, stdout) = tune_ok(
        &[
            "--mesh",
            obj.to_str().unwrap(),
            "--cost-model",
            "isa:amd:navi21",
        ],
        &out,
    );
    assert_schema(&r, "docs/tune.schema.json", "", "note");
    let note = r["note"]
        .as_str()
        .unwrap_or_else(|| panic!("no note: {stdout}"));
    assert!(note.contains("no normalisation is needed"), "{note}");
    assert!(
        stdout.contains("answer: no normalisation is needed"),
        "{stdout}"
    );
    for a in r["cost_models"].as_array().unwrap() {
        assert!(a["error"].is_null(), "a model lost: {a}");
    }
    let skipped: Vec<&str> = r["skipped"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert!(
        skipped.iter().any(|s| s.starts_with("planar_minimax3")),
        "{skipped:?}"
    );
    // every candidate with a file is proven (a bound below 1), and is costed
    for c in candidates(&r) {
        if c["file"].is_string() {
            let b = f32_bound(c)["length_error"].as_f64().unwrap();
            assert!(b < 1.0, "{c}");
            assert!(!c["costs"].as_array().unwrap().is_empty(), "{c}");
        }
    }
}
