//! `shadelab isa` on RADV's null device (each family in a child process of the built binary):
//! identical statistics across runs, gouraud < phong_unnormalized < phong_exact in inverse
//! throughput on every default family, 16 extra dependent multiplications cost more (teeth),
//! a refused family is reported and not fatal, isa.json against its schema with its failure
//! test. Small method lists keep it to a few seconds.
use std::path::PathBuf;

use shadelab::isa::{self, IsaOptions, IsaReport, Precision};
use shadelab::method;

use crate::support::{read_json, run, schema_validator};

fn options(methods: &[&str], families: &[&str]) -> IsaOptions {
    IsaOptions {
        methods: methods.iter().map(|m| method::find(m).unwrap()).collect(),
        families: families.iter().map(|f| f.to_string()).collect(),
        driver_files: PathBuf::from(isa::DEFAULT_DRIVER_FILES),
        scene: None,
        exe: PathBuf::from(env!("CARGO_BIN_EXE_shadelab")),
        precision: Precision::F32,
        probes: Vec::new(),
    }
}

fn isa_run(opts: &IsaOptions) -> IsaReport {
    isa::run(opts, &|_| {}).expect("isa run")
}

fn inverse_throughput(r: &IsaReport, family: &str, method: &str, stage: &str, kind: &str) -> f64 {
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
    let opts = options(&methods, &isa::DEFAULT_FAMILIES);
    let a = isa_run(&opts);
    let b = isa_run(&opts);
    assert_eq!(
        a.supported(),
        isa::DEFAULT_FAMILIES.to_vec(),
        "{:#?}",
        a.families
    );
    assert!(!a.results.is_empty());
    for (x, y) in a.results.iter().zip(&b.results) {
        assert_eq!(
            (&x.family, &x.method, &x.stage, &x.kind),
            (&y.family, &y.method, &y.stage, &y.kind)
        );
        assert_eq!(x.statistics, y.statistics, "{} {}", x.family, x.method);
        assert_eq!(x.hash, y.hash, "{} {}", x.family, x.method);
        assert!(x.statistics.values().all(|v| v.is_finite()));
        for k in isa::table::REQUIRED {
            assert!(
                x.statistics.contains_key(k),
                "{} {}: no {k}",
                x.family,
                x.method
            );
        }
    }
    assert_eq!(a.results.len(), b.results.len());
    for f in isa::DEFAULT_FAMILIES {
        for (stage, kind) in [("fragment", "draw"), ("compute", "evaluation")] {
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
        let exact = a.row(f, "phong_exact", "fragment", "draw").unwrap();
        assert_eq!(exact.ratio_to_phong_exact["inverse_throughput"], 1.0);
    }
    // The files, and isa.json against its schema.
    let dir = tempfile::tempdir().unwrap();
    isa::files::write(dir.path(), &a).unwrap();
    let json = read_json(dir.path().join("isa.json"));
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
    let asm = dir.path().join("asm/navi21/phong_exact.fragment.s");
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
    let mut bad = json;
    bad["results"][0]["stage"] = "geometry".into();
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
    for f in ["polaris10", "navi21"] {
        let stat = |m: &str, k: &str| r.row(f, m, "compute", "probe").unwrap().statistics[k];
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
    // navi24 dies of SIGFPE in Mesa 22.3.6 (TOOLCHAIN.md), "bogus" is no chip at all.
    let (code, stdout, stderr) = run(&[
        "isa",
        "--methods",
        "phong_exact",
        "--families",
        "bogus,navi21",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(
        stdout.contains("bogus: not supported by this driver"),
        "{stdout}"
    );
    let r: IsaReport =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("isa.json")).unwrap())
            .unwrap();
    assert_eq!(r.supported(), vec!["navi21"]);
    assert!(r.results.iter().all(|row| row.family == "navi21"));
    let opts = options(&["phong_exact"], &["navi24"]);
    let r = isa_run(&opts);
    assert!(!r.families[0].supported);
    assert!(
        r.families[0]
            .status
            .starts_with("not supported by this driver: "),
        "{}",
        r.families[0].status
    );
    assert!(r.results.is_empty());
}
