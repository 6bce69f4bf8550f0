//! `shadelab isa` on RADV's null device (each family in a child process of the built binary):
//! identical statistics across runs, gouraud < phong_unnormalized < phong_exact in inverse
//! throughput on every default family, 16 extra dependent multiplications cost more (teeth),
//! a refused family is reported and not fatal, isa.json against its schema with its failure
//! test. Small method lists keep it to a few seconds.
use std::path::PathBuf;

use shadelab::isa::{self, IsaOptions, IsaReport, Precision, RowKind};
use shadelab::method;

use crate::support::{read_json, run, schema_validator};

fn options(methods: &[&str], families: &[&str]) -> IsaOptions {
    IsaOptions {
        methods: methods.iter().map(|m| method::find(m).unwrap()).collect(),
        families: families.iter().map(|f| f.to_string()).collect(),
        driver_files: None,
        scene: None,
        exe: PathBuf::from(env!("CARGO_BIN_EXE_shadelab")),
        precision: Precision::F32,
        probes: Vec::new(),
        store: None,
    }
}

fn isa_run(opts: &IsaOptions) -> IsaReport {
    isa::run(opts, &|_| {}).expect("isa run")
}

fn inverse_throughput(
    r: &IsaReport,
    family: &str,
    method: &str,
    stage: &str,
    kind: RowKind,
) -> f64 {
    let row = r
        .row(family, method, stage, kind)
        .unwrap_or_else(|| panic!("no {kind} {stage} row of {method} on {family}"));
    let v = row.statistics["inverse_throughput"];
    assert!(v.is_finite() && v > 0.0, "{family} {method}: {v}");
    v
}

#[test]
fn identical_runs_and_the_phong_order_on_every_family() {
    let methods = ["gouraud", "phong_unnormalized", "phong_exact"];
    let opts = options(&methods, &isa::route::amd::DEFAULT_CHIPS);
    let a = isa_run(&opts);
    let b = isa_run(&opts);
    // A bare chip is AMD's; the rows carry the family's one spelling.
    let families: Vec<String> = isa::route::amd::DEFAULT_CHIPS
        .iter()
        .map(|f| format!("amd:{f}"))
        .collect();
    assert_eq!(a.supported(), families, "{:#?}", a.families);
    assert!(!a.results.is_empty());
    for (x, y) in a.results.iter().zip(&b.results) {
        assert_eq!(
            (&x.family, &x.method, &x.stage, &x.kind),
            (&y.family, &y.method, &y.stage, &y.kind)
        );
        assert_eq!(x.statistics, y.statistics, "{} {}", x.family, x.method);
        assert_eq!(x.hash, y.hash, "{} {}", x.family, x.method);
        assert!(x.statistics.values().all(|v| v.is_finite()));
        for k in isa::route::amd::STATISTICS {
            assert!(
                x.statistics.contains_key(k),
                "{} {}: no {k}",
                x.family,
                x.method
            );
        }
    }
    assert_eq!(a.results.len(), b.results.len());
    for f in &families {
        for (stage, kind) in [
            ("fragment", RowKind::Draw),
            ("compute", RowKind::Evaluation),
        ] {
            let it: Vec<f64> = methods
                .iter()
                .map(|m| inverse_throughput(&a, f, m, stage, kind))
                .collect();
            assert!(
                it[0] < it[1] && it[1] < it[2],
                "{f} {stage}: gouraud {} < phong_unnormalized {} < phong_exact {} fails",
                it[0],
                it[1],
                it[2]
            );
        }
        let exact = a.row(f, "phong_exact", "fragment", RowKind::Draw).unwrap();
        assert_eq!(exact.ratio_to_phong_exact["inverse_throughput"], 1.0);
    }
    // The files, and isa.json against its schema.
    let dir = tempfile::tempdir().unwrap();
    isa::files::write(dir.path(), &a).unwrap();
    let (json, validator) = isa_json_against_its_schema(dir.path());
    let asm = dir.path().join("asm/amd_navi21/phong_exact.fragment.s");
    let text = std::fs::read_to_string(&asm).unwrap();
    assert!(
        text.contains("v_"),
        "{} holds no vector instruction",
        asm.display()
    );
    let csv = std::fs::read_to_string(dir.path().join("isa.csv")).unwrap();
    assert_eq!(csv.lines().count(), a.results.len() + 1);
    // Teeth: a row without its inverse throughput, and an unknown stage, are rejected.
    let mut bad = json.clone();
    bad["results"][0]["statistics"]
        .as_object_mut()
        .unwrap()
        .remove("inverse_throughput");
    assert!(!validator.is_valid(&bad), "the schema check has no teeth");
    let mut bad = json.clone();
    bad["results"][0]["stage"] = "geometry".into();
    assert!(!validator.is_valid(&bad), "the schema check has no teeth");
    // Every row names its bound unit, one of the six; the CSV carries it too.
    assert!(a.results.iter().all(|r| r.bound_unit.is_some()));
    assert!(csv.lines().next().unwrap().ends_with(",bound_unit"));
    let mut bad = json.clone();
    bad["results"][0]
        .as_object_mut()
        .unwrap()
        .remove("bound_unit");
    assert!(
        !validator.is_valid(&bad),
        "a row without its bound unit passes"
    );
    let mut bad = json.clone();
    bad["results"][0]["bound_unit"] = "alu".into();
    assert!(!validator.is_valid(&bad), "an unknown bound unit passes");
    // A compiled family says who compiled it and whether now or from the compile store.
    assert_eq!(json["families"][0]["source"], "compiled");
    let mut bad = json.clone();
    bad["families"][0]
        .as_object_mut()
        .unwrap()
        .remove("compiler_id");
    assert!(!validator.is_valid(&bad), "the schema check has no teeth");
    let mut bad = json;
    bad["families"][0]["source"] = "cached".into();
    assert!(!validator.is_valid(&bad), "the schema check has no teeth");
}

/// A compute program loading one value and storing `y`; with `extra`, 16 more dependent
/// multiplications on the way.
fn probe_source(extra: usize) -> String {
    let mut s = String::from(
        "#version 450\nlayout(local_size_x = 64) in;\n\
         layout(set = 0, binding = 0, std430) buffer B { float v[]; };\n\
         void main() {\n  uint i = gl_GlobalInvocationID.x;\n  float x = v[i];\n\
           float y = x * 1.0001 + 0.5;\n",
    );
    for _ in 0..extra {
        s += "  y = y * x;\n";
    }
    s += "  v[i] = y;\n}\n";
    s
}

fn compile_probe(dir: &std::path::Path, name: &str, extra: usize) -> PathBuf {
    let compiler = shaderc::Compiler::new().unwrap();
    let spv = compiler
        .compile_into_spirv(
            &probe_source(extra),
            shaderc::ShaderKind::Compute,
            name,
            "main",
            None,
        )
        .unwrap();
    let path = dir.join(format!("{name}.spv"));
    std::fs::write(&path, spv.as_binary_u8()).unwrap();
    path
}

#[test]
fn sixteen_dependent_multiplications_cost_more() {
    let dir = tempfile::tempdir().unwrap();
    let mut opts = options(&[], &["polaris10", "navi21"]);
    opts.probes = vec![
        compile_probe(dir.path(), "base", 0),
        compile_probe(dir.path(), "base_again", 0),
        compile_probe(dir.path(), "plus16", 16),
    ];
    let r = isa_run(&opts);
    for f in ["amd:polaris10", "amd:navi21"] {
        let stat = |m: &str, k: &str| r.row(f, m, "compute", RowKind::Probe).unwrap().statistics[k];
        for k in ["instructions", "inverse_throughput", "latency"] {
            // The same program compiles to the same cost: the comparison below is not vacuous.
            assert_eq!(stat("base", k), stat("base_again", k), "{f} {k}");
            assert!(
                stat("plus16", k) > stat("base", k),
                "{f} {k}: 16 extra multiplications {} vs {}",
                stat("plus16", k),
                stat("base", k)
            );
        }
        // At least one instruction per multiplication (a dependent chain cannot be folded).
        assert!(stat("plus16", "instructions") >= stat("base", "instructions") + 16.0);
    }
}

#[test]
fn a_refused_family_is_reported_not_fatal() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    // navi24 dies of SIGFPE in Mesa 22.3.6 (TOOLCHAIN.md): a chip RADV knows but cannot do.
    let (code, stdout, stderr) = run(&[
        "isa",
        "--methods",
        "phong_exact",
        "--families",
        "navi24,navi21",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let r: IsaReport =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("isa.json")).unwrap())
            .unwrap();
    // Refused on Mesa 22.3.6, compiled on 25.0.7: either way the run goes on and says which.
    if r.supported() == vec!["amd:navi21"] {
        assert!(
            stdout.contains("navi24: not supported by this driver"),
            "{stdout}"
        );
        assert!(r.results.iter().all(|row| row.family == "amd:navi21"));
    } else {
        assert_eq!(r.supported(), vec!["amd:navi24", "amd:navi21"], "{stdout}");
    }
    // navi24 is refused or not by the driver's version: Mesa 22.3.6 dies of SIGFPE on it
    // (TOOLCHAIN.md), Mesa 25.0.7 compiles it. navi21 beside it says which Mesa this is.
    let opts = options(&["phong_exact"], &["navi24", "navi21"]);
    let r = isa_run(&opts);
    let mesa = (r.families[1].compiler())
        .and_then(|c| c.mesa_version)
        .expect("navi21 compiles and names its Mesa");
    if mesa.starts_with("Mesa 22.") {
        assert!(!r.families[0].supported, "{mesa}: {:?}", r.families[0]);
        assert!(
            r.families[0]
                .status
                .starts_with("not supported by this driver: "),
            "{}",
            r.families[0].status
        );
        assert!(r.results.iter().all(|row| row.family != "amd:navi24"));
    }
    assert!(r.families[1].supported);
}

/// The whole chain on the CLI: compare and bench (without the static cost) feed `isa
/// --compare --bench` (charts, Spearman per family, a refused family reported), whose isa.json
/// feeds `bench --isa` (a cell per family, the refused one `not_supported`, each compiled
/// one judged by its own ratio). Both JSON files against their schemas.
#[test]
fn isa_with_compare_and_bench_then_bench_with_isa() {
    let dir = tempfile::tempdir().unwrap();
    let p = |s: &str| dir.path().join(s).to_str().unwrap().to_string();
    let methods = "gouraud,phong_unnormalized,newton_raphson,phong_exact";
    let scene = ["--scene", "scenes/cube.toml", "--size", "48x48"];
    let ok = |args: &[&str]| {
        let (code, out, err) = run(args);
        assert_eq!(code, 0, "{args:?}\n{out}\n{err}");
        out
    };
    let cmp = p("compare");
    ok(&[
        &["compare"][..],
        &scene[..],
        &["--methods", methods, "--out", cmp.as_str()][..],
    ]
    .concat());
    let bench_args = |out: &str, extra: &[&str]| -> Vec<String> {
        let mut a: Vec<&str> = vec!["bench"];
        a.extend(scene);
        a.extend([
            "--methods",
            methods,
            "--runs",
            "1",
            "--repeat",
            "3",
            "--warmup",
            "1",
            "--isolated-rounds",
            "3",
            "--out",
            out,
        ]);
        a.extend(extra);
        a.into_iter().map(String::from).collect()
    };
    let b1 = p("b1");
    let args = bench_args(&b1, &["--no-isa"]);
    ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let bench1 = read_json(dir.path().join("b1/bench.json"));
    assert_eq!(bench1["static_cost"]["source"], "skipped (--no-isa)");
    let cells = bench1["speed_claims"][0]["cells"].as_array().unwrap();
    assert!(cells
        .iter()
        .all(|c| !c["cost_model"].as_str().unwrap().starts_with("isa:")));
    let isa_dir = p("isa");
    let bench1_json = dir.path().join("b1/bench.json");
    ok(&[
        "isa",
        "--methods",
        methods,
        "--families",
        "navi24,navi21",
        "--compare",
        cmp.as_str(),
        "--bench",
        bench1_json.to_str().unwrap(),
        "--out",
        isa_dir.as_str(),
    ]);
    let isa_json = read_json(dir.path().join("isa/isa.json"));
    let schema = schema_validator("docs/isa.schema.json");
    assert!(schema.is_valid(&isa_json), "isa.json vs its schema");
    let charts: Vec<&str> = isa_json["charts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    // navi24 is refused by Mesa 22.3.6's RADV and compiled by 25.0.7's: a chart and a rank
    // correlation for each family compiled, none for a refused one.
    let navi24 = isa_json["families"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["family"] == "amd:navi24")
        .map(|f| f["supported"] == true)
        .expect("navi24 is reported");
    let compiled: Vec<&str> = if navi24 {
        vec!["navi24", "navi21"]
    } else {
        vec!["navi21"]
    };
    let want: Vec<String> = compiled
        .iter()
        .flat_map(|c| [format!("charts/amd_{c}.svg"), format!("charts/amd_{c}.png")])
        .collect();
    assert_eq!(charts, want);
    for c in &charts {
        assert!(dir.path().join("isa").join(c).is_file(), "{c}");
    }
    let rho = &isa_json["spearman"];
    assert_eq!(rho.as_array().unwrap().len(), compiled.len(), "{rho}");
    let rho = rho
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["family"] == "amd:navi21")
        .expect("navi21's rank correlation");
    assert_eq!(rho["methods"], 4);
    let r = rho["spearman"]
        .as_f64()
        .expect("a rank correlation over 4 methods");
    assert!((-1.0..=1.0).contains(&r), "{r}");
    // bench reads the isa.json: a cell per family, named.
    let b2 = p("b2");
    let isa_file = dir.path().join("isa/isa.json");
    let args = bench_args(&b2, &["--isa", isa_file.to_str().unwrap()]);
    ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let bench2 = read_json(dir.path().join("b2/bench.json"));
    assert!(schema_validator("docs/bench.schema.json").is_valid(&bench2));
    assert!(bench2["static_cost"]["source"]
        .as_str()
        .unwrap()
        .starts_with("read from"));
    let report: IsaReport = serde_json::from_value(isa_json).unwrap();
    let claims = bench2["speed_claims"].as_array().unwrap();
    assert!(!claims.is_empty());
    for c in claims {
        let cells = c["cells"].as_array().unwrap();
        let cell = |m: &str| {
            cells
                .iter()
                .find(|x| x["cost_model"] == m)
                .unwrap_or_else(|| panic!("no {m} cell"))
        };
        for m in ["lavapipe_frame", "lavapipe_isolated", "software"] {
            cell(m);
        }
        // The software engine's column is timed by this bench (its programs paired per round).
        let sw = cell("software");
        assert!(
            ["agrees", "disagrees", "inconclusive"].contains(&sw["verdict"].as_str().unwrap()),
            "{sw}"
        );
        assert!(
            sw["note"].as_str().unwrap().contains("paired per round"),
            "{sw}"
        );
        // A family the driver refused is no column; bench.json's static_cost names it.
        assert_eq!(
            cells.iter().any(|x| x["cost_model"] == "isa:amd:navi24"),
            navi24,
            "{c}"
        );
        let navi = cell("isa:amd:navi21");
        let it = |m: &serde_json::Value| {
            inverse_throughput(
                &report,
                "amd:navi21",
                m.as_str().unwrap(),
                "fragment",
                RowKind::Draw,
            )
        };
        let ratio = it(&c["num"]) / it(&c["den"]);
        assert_eq!(navi["ratio"].as_f64().unwrap(), ratio);
        let below = c["claimed_below"].as_f64().unwrap();
        let agrees = if below == 1.0 {
            ratio < 1.0
        } else {
            ratio <= below
        };
        assert_eq!(
            navi["verdict"],
            if agrees { "agrees" } else { "disagrees" },
            "{c}"
        );
    }
    // bench.json's static_cost names each family with its status: navi24 refused or compiled
    // as its Mesa does (above).
    let families = bench2["static_cost"]["families"].as_array().unwrap();
    let navi24_status = families
        .iter()
        .find(|f| f[0] == "amd:navi24")
        .and_then(|f| f[1].as_str())
        .unwrap_or_else(|| panic!("navi24 not named: {families:?}"));
    assert_eq!(
        navi24_status.starts_with("not supported"),
        !navi24,
        "{families:?}"
    );
    // The op-count claim per compiled family, in the claims list.
    let claims_list = bench2["claims"].as_array().unwrap();
    assert!(claims_list.iter().any(|c| c["measured"]
        .as_str()
        .unwrap()
        .starts_with("isa:amd:navi21: phong_exact")));
    // Teeth: a missing --isa file is a usage error.
    let args = bench_args(&p("b3"), &["--isa", "/nonexistent/isa.json"]);
    let (code, _, err) = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 2, "{err}");
}

/// `--cost-model isa:FAMILY` ranks auto's candidates by that family's static cost; a family
/// the driver refuses is a clear error (exit 2), not a silent fallback.
#[test]
fn auto_ranks_by_a_gpu_family_and_refuses_an_unknown_one() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("a.png");
    let base = [
        "render",
        "--scene",
        "scenes/torus.toml",
        "--size",
        "64x64",
        "--method",
        "auto",
        "--out",
        png.to_str().unwrap(),
        "--cost-model",
    ];
    let (code, _, err) = run(&[&base[..], &["isa:polaris10"]].concat());
    assert_eq!(code, 0, "{err}");
    // A bare chip is AMD's; the model is named by its one spelling.
    assert!(
        err.contains("auto: candidates by isa:amd:polaris10"),
        "{err}"
    );
    // gouraud is the cheapest on every family, phong_exact last (the fallback).
    let line = err
        .lines()
        .find(|l| l.starts_with("auto: candidates"))
        .unwrap();
    let order = line.split("): ").nth(1).unwrap();
    assert!(order.starts_with("gouraud "), "{line}");
    assert!(
        err.contains(" by isa:amd:polaris10: "),
        "the grouping line: {err}"
    );
    let (code, _, err) = run(&[&base[..], &["isa:bogus"]].concat());
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("isa:bogus"), "{err}");
    let (code, _, err) = run(&[&base[..], &["gpu"]].concat());
    assert_eq!(code, 2, "{err}");
}

/// The families of issue 40's vendors, beside AMD's.
const VENDOR_FAMILIES: [&str; 12] = [
    "intel:skl",
    "intel:icl",
    "intel:tgl",
    "intel:adl",
    "intel:dg2",
    "nvidia:nvc0",
    "nvidia:nve4",
    "nvidia:nv117",
    "nvidia:nv134",
    "nvidia:nv162",
    "terascale:cypress",
    "terascale:cayman",
];

/// Family `f` of `r` ranks gouraud < phong_unnormalized < phong_exact on its own statistic
/// (`what` names the family, and the precision where it matters, in the message).
pub(crate) fn assert_references_in_order(r: &IsaReport, f: &isa::FamilyStatus, what: &str) {
    let names = ["gouraud", "phong_unnormalized", "phong_exact"];
    let order: Vec<f64> = names
        .iter()
        .map(|m| r.ranking_value(&f.family, m).unwrap())
        .collect();
    // In a per-pipe model, two programs bound by the same memory or varying pipe at the same
    // figure are equal: the part they share bounds both (Mali's load/store).
    let shared_bound = |a: usize, b: usize| {
        let unit = |m: &str| {
            r.row(&f.family, m, "fragment", RowKind::Draw)
                .and_then(|row| row.bound_unit)
        };
        use isa::throughput::Unit;
        order[a] == order[b]
            && unit(names[a]) == unit(names[b])
            && matches!(
                unit(names[a]),
                Some(Unit::LoadStore | Unit::Varying | Unit::Texture)
            )
    };
    let below = |a: usize, b: usize| order[a] < order[b] || shared_bound(a, b);
    assert!(
        order[0] < order[2] && below(0, 1) && below(1, 2),
        "{what}: {} gouraud {} < phong_unnormalized {} < phong_exact {} fails",
        f.ranking().expect("a ranking statistic").key,
        order[0],
        order[1],
        order[2]
    );
}

/// Whether every vendor of `families` is set up (scripts/setup-vendors.sh); when one is not,
/// the test is skipped with a visible `SKIPPED` line, or fails under
/// `SHADELAB_REQUIRE_VENDORS=1` (which .ci/run sets, after `make test` set the routes up).
fn vendors_ready(test: &str, families: &[&str]) -> bool {
    families_ready(test, families, "SHADELAB_REQUIRE_VENDORS")
}

/// Whether every family of `families` is set up; when one is not, the test `test` is skipped
/// with a visible `SKIPPED` line naming the command that sets it up, or fails when the
/// environment variable `require` is 1 (CI sets it).
pub(crate) fn families_ready(test: &str, families: &[&str], require: &str) -> bool {
    for f in families {
        let (vendor, chip) = isa::route::resolve(f).unwrap();
        if let Err(why) = vendor.setup_for(&chip, None) {
            let msg = format!(
                "{test}: {f} is not set up ({why}); run {}",
                vendor.setup_command_for(&chip)
            );
            if std::env::var(require).as_deref() == Ok("1") {
                panic!("{require}=1 but {msg}");
            }
            // Straight to the terminal: `eprintln!` is captured and hidden for a passing test.
            use std::io::Write as _;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {msg}");
            return false;
        }
    }
    true
}

/// Every method compiles on every family of Intel, NVIDIA and TeraScale; each family says who
/// compiled it and ranks gouraud < phong_unnormalized < phong_exact on its own statistic;
/// isa.json passes its schema (with teeth on a vendor's required statistic).
#[test]
fn every_method_compiles_on_every_vendor_family() {
    if !vendors_ready(
        "every_method_compiles_on_every_vendor_family",
        &VENDOR_FAMILIES,
    ) {
        return;
    }
    let all: Vec<&str> = method::METHODS.iter().map(|m| m.name).collect();
    assert_eq!(all.len(), 37, "the issue counts 37 methods");
    let r = isa_run(&options(&all, &VENDOR_FAMILIES));
    assert_eq!(r.supported(), VENDOR_FAMILIES.to_vec(), "{:#?}", r.families);
    for f in &r.families {
        let ranking = f.ranking().expect("a ranking statistic");
        let compiler = f.compiler().expect("a compiler");
        // The system's Mesa (22.3.6 on Debian 12, 25.0.7 on 13), the same for every family
        // of these routes: they all use the installed drivers.
        let mesa = compiler.mesa_version.clone().unwrap_or_default();
        assert!(mesa.starts_with("Mesa "), "{}: {mesa:?}", f.id);
        assert_eq!(
            Some(mesa),
            r.families[0].compiler().and_then(|c| c.mesa_version),
            "{}",
            f.id
        );
        assert_eq!(compiler.production, f.vendor == "intel", "{}", f.id);
        assert_eq!(f.float16, Some(f.vendor == "intel"), "{}", f.id);
        for m in &all {
            let v = r
                .ranking_value(&f.family, m)
                .unwrap_or_else(|| panic!("{} {m}: no {}", f.id, ranking.key));
            assert!(v.is_finite() && v > 0.0, "{} {m}: {v}", f.id);
        }
        assert_references_in_order(&r, f, &f.id);
        assert_eq!(r.ranking_ratio(&f.family, "phong_exact"), Some(1.0));
    }
    // Intel: every width's figures, the dispatched one's unprefixed, and the assembly.
    let tgl = r
        .row("intel:tgl", "phong_exact", "fragment", RowKind::Draw)
        .unwrap();
    let w = tgl.statistics["dispatch_width"];
    assert!(w == 8.0 || w == 16.0 || w == 32.0, "{w}");
    assert_eq!(
        tgl.statistics["cycle_count"],
        tgl.statistics[&format!("simd{w}_cycle_count")]
    );
    // The ranking is the busier unit's FMAs per pixel at that width, not brw's latency.
    let (fpu, em) = (tgl.statistics["fpu_fmas"], tgl.statistics["em_fmas"]);
    assert_eq!(fpu, tgl.statistics[&format!("simd{w}_fpu_fmas")]);
    assert_eq!(tgl.statistics["model_cycles"], fpu.max(em));
    assert!(fpu > 0.0 && em > 0.0, "{fpu} {em}");
    assert_ne!(
        tgl.statistics["model_cycles"],
        tgl.statistics["cycle_count"]
    );
    assert!(tgl.statistics.contains_key("simd8_instruction_count"));
    let dir = tempfile::tempdir().unwrap();
    isa::files::write(dir.path(), &r).unwrap();
    let asm = std::fs::read_to_string(dir.path().join("asm/intel_tgl/phong_exact.fragment.s"));
    assert!(asm.unwrap().contains("// SIMD8"));
    let (json, validator) = isa_json_against_its_schema(dir.path());
    // Teeth: a nouveau row without its instruction count fails the schema.
    let mut bad = json;
    let i = r
        .results
        .iter()
        .position(|row| row.family.starts_with("nvidia:"))
        .unwrap();
    bad["results"][i]["statistics"]
        .as_object_mut()
        .unwrap()
        .remove("inst");
    assert!(!validator.is_valid(&bad), "the schema check has no teeth");
}

/// Two runs give identical statistics on every vendor family.
#[test]
fn vendor_families_compile_identically_twice() {
    if !vendors_ready(
        "vendor_families_compile_identically_twice",
        &VENDOR_FAMILIES,
    ) {
        return;
    }
    let opts = options(
        &[
            "gouraud",
            "phong_unnormalized",
            "phong_exact",
            "newton_raphson",
        ],
        &VENDOR_FAMILIES,
    );
    let (a, b) = (isa_run(&opts), isa_run(&opts));
    assert_eq!(
        a.supported().len(),
        VENDOR_FAMILIES.len(),
        "{:#?}",
        a.families
    );
    assert_identical_runs(&a, &b);
}

/// A chipset the driver cannot do is refused, never measured: nouveau gives Tesla (nv50) no
/// OpenGL 4.3 context (its GL is 3.3, Mesa 22.3.6 and 25.0.7), r600 has no OpenGL 4.3 on R600
/// itself; the families beside them still compile. A name no route knows never reaches
/// a driver (it aborted the radeon shim's child, found no ANV device): it is refused before
/// any child starts, with the vendor's known chips.
#[test]
fn a_fake_chipset_is_refused_on_every_vendor() {
    for fake in ["nvidia:nvzz", "terascale:bogus", "intel:bogus", "amd:bogus"] {
        let e = isa::run(&options(&["phong_exact"], &[fake, "amd:navi21"]), &|_| {})
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        let (vendor, chip) = fake.split_once(':').unwrap();
        assert!(
            e.starts_with(&format!("unknown chip '{chip}' for {vendor}; known: ")),
            "{fake}: {e}"
        );
    }
    let fakes = ["nvidia:nv50", "terascale:r600"];
    let real = ["nvidia:nv162", "terascale:cayman", "intel:tgl"];
    if !vendors_ready("a_fake_chipset_is_refused_on_every_vendor", &real) {
        return;
    }
    let families: Vec<&str> = fakes.iter().chain(&real).copied().collect();
    let r = isa_run(&options(&["phong_exact"], &families));
    assert_eq!(r.supported(), real.to_vec(), "{:#?}", r.families);
    for f in r.families.iter().filter(|f| !f.supported) {
        assert!(
            f.status.starts_with("not supported by this driver: "),
            "{}",
            f.status
        );
        assert!(r.results.iter().all(|row| row.family != f.family));
    }
    let nv50 = r.family("nvidia:nv50").unwrap();
    assert!(nv50.status.contains("OpenGL 4.3"), "{}", nv50.status);
}

/// The per-vendor rules of docs/isa.schema.json are generated from the routes (each vendor's
/// `required_statistics`, src/isa/schema.rs): the file must hold exactly that text.
/// `SHADELAB_BLESS=1` writes it (after adding a route).
#[test]
fn the_schema_requires_each_vendors_statistics() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/isa.schema.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let want = isa::schema::vendor_rules();
    if std::env::var("SHADELAB_BLESS").as_deref() == Ok("1") {
        let new = isa::schema::with_rules(&text, &want).expect("the schema's allOf block");
        std::fs::write(&path, new).unwrap();
        return;
    }
    let have = isa::schema::rules_in(&text).expect("the schema's allOf block");
    assert!(
        have == want,
        "docs/isa.schema.json's per-vendor rules are not the routes' (a route added or its \
         statistics changed): run SHADELAB_BLESS=1 cargo test --release --locked --test \
         integration -- isa::the_schema_requires\nhave:\n{have}\nwant:\n{want}"
    );
    // The block is the schema's own allOf (parsed), one rule per route.
    let schema: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rules = schema["properties"]["results"]["items"]["allOf"]
        .as_array()
        .unwrap();
    let with_draw_rules = isa::route::VENDORS
        .iter()
        .filter(|v| !v.required_draw_statistics().is_empty())
        .count();
    assert_eq!(rules.len(), isa::route::VENDORS.len() + with_draw_rules);
}

/// `json` (an isa.json) with the statistic `key` of its row `i` removed: a schema's teeth.
pub(crate) fn without_statistic(
    json: &serde_json::Value,
    i: usize,
    key: &str,
) -> serde_json::Value {
    let mut bad = json.clone();
    bad["results"][i]["statistics"]
        .as_object_mut()
        .unwrap()
        .remove(key);
    bad
}

/// DIR/isa.json checked against docs/isa.schema.json (every error named), and the validator for
/// a test's teeth.
pub(crate) fn isa_json_against_its_schema(
    dir: &std::path::Path,
) -> (serde_json::Value, jsonschema::Validator) {
    let json = read_json(dir.join("isa.json"));
    let validator = schema_validator("docs/isa.schema.json");
    let errors: Vec<String> = validator
        .iter_errors(&json)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "isa.json vs its schema:\n{}",
        errors.join("\n")
    );
    (json, validator)
}

/// Two runs gave the same rows with the same statistics, every one finite.
pub(crate) fn assert_identical_runs(a: &IsaReport, b: &IsaReport) {
    assert_eq!(a.results.len(), b.results.len());
    for (x, y) in a.results.iter().zip(&b.results) {
        assert_eq!(
            (&x.family, &x.method, &x.stage),
            (&y.family, &y.method, &y.stage)
        );
        assert_eq!(x.statistics, y.statistics, "{} {}", x.family, x.method);
        assert!(x.statistics.values().all(|v| v.is_finite()));
    }
}

/// Every draw row of every family set up whose compiler reports registers carries them and
/// the waves they allow (Mali's carry none: its shader-db lines have no register count), each
/// finite and above zero; isa.json's schema requires them per vendor. Teeth: a Qualcomm or AMD
/// draw row without its waves fails the schema.
#[test]
fn every_family_reports_registers_and_the_waves_they_allow() {
    let families = crate::store::set_up_families(
        "isa::every_family_reports_registers_and_the_waves_they_allow",
    );
    if families.is_empty() {
        return;
    }
    let fams: Vec<&str> = families.iter().map(String::as_str).collect();
    let opts = IsaOptions {
        store: isa::store::default_store(),
        ..options(&["gouraud", "phong_exact"], &fams)
    };
    let r = isa_run(&opts);
    assert_eq!(r.supported(), fams, "{:#?}", r.families);
    use isa::occupancy::{REGISTERS_KEY, WAVES_KEY};
    for row in r.results.iter().filter(|x| x.kind == RowKind::Draw) {
        let mali = row.family.starts_with("arm:");
        let waves_stated =
            !mali && !row.family.starts_with("terascale:") && row.family != "intel:ptl";
        for (key, want) in [(REGISTERS_KEY, !mali), (WAVES_KEY, waves_stated)] {
            let v = row.statistics.get(key);
            assert_eq!(
                v.is_some(),
                want,
                "{} {} {}: {key}",
                row.family,
                row.method,
                row.stage
            );
            if let Some(v) = v {
                assert!(
                    v.is_finite() && *v > 0.0,
                    "{} {}: {key} {v}",
                    row.family,
                    row.method
                );
            }
        }
    }
    let dir = tempfile::tempdir().unwrap();
    isa::files::write(dir.path(), &r).unwrap();
    let (json, validator) = isa_json_against_its_schema(dir.path());
    for vendor in ["qualcomm:", "amd:"] {
        let Some(i) = r
            .results
            .iter()
            .position(|x| x.family.starts_with(vendor) && x.kind == RowKind::Draw)
        else {
            continue;
        };
        let bad = without_statistic(&json, i, WAVES_KEY);
        assert!(
            !validator.is_valid(&bad),
            "{vendor} row without its waves passes"
        );
    }
}
