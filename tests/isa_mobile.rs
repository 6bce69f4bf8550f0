//! `shadelab isa` on the families of `make compilers` (Mesa 25.0.7 built in the user's cache):
//! Qualcomm Adreno through Turnip, Arm Mali through panfrost and lima, Broadcom VideoCore
//! through v3d and vc4 (OpenGL ES), Intel Meteor Lake to Panther Lake through ANV 25.0.7.
//! Every method compiles on every family, in float32 and, where the driver computes float16,
//! in float16; each family ranks gouraud < phong_unnormalized < phong_exact on its own
//! statistic; two runs are identical; a chip the driver does not know is refused. Skipped with
//! a line when the compilers are not built, failing under `SHADELAB_REQUIRE_COMPILERS=1`
//! (which .ci/run sets after `make compilers`).
use std::path::PathBuf;

use shadelab::isa::{self, IsaOptions, IsaReport, Precision};
use shadelab::method;

use crate::isa::{
    assert_identical_runs, assert_references_in_order, families_ready, isa_json_against_its_schema,
};
use crate::support::rerun_test;

/// The families of issue 41.
const FAMILIES: [&str; 18] = [
    "qualcomm:a618",
    "qualcomm:a630",
    "qualcomm:a660",
    "qualcomm:a730",
    "qualcomm:a740",
    "qualcomm:a750",
    "arm:mali450",
    "arm:t860",
    "arm:g72",
    "arm:g52",
    "arm:g57",
    "arm:g610",
    "broadcom:vc4",
    "broadcom:v3d42",
    "intel:mtl",
    "intel:lnl",
    "intel:bmg",
    "intel:ptl",
];

/// The families whose driver computes float16 (the others refuse float16 programs): Midgard
/// (T860) too, whose panfrost back-end has 16-bit ALU operations and says mediump is 10 bits.
const FLOAT16: [&str; 15] = [
    "qualcomm:a618",
    "qualcomm:a630",
    "qualcomm:a660",
    "qualcomm:a730",
    "qualcomm:a740",
    "qualcomm:a750",
    "arm:t860",
    "arm:g72",
    "arm:g52",
    "arm:g57",
    "arm:g610",
    "intel:mtl",
    "intel:lnl",
    "intel:bmg",
    "intel:ptl",
];

/// The OpenGL ES 2.0 families: ESSL 1.00 cannot express every program (no array
/// constructors, gl_VertexID or storage buffers), the methods it cannot are skipped, named in
/// the family's status.
const ES2: [&str; 2] = ["arm:mali450", "broadcom:vc4"];

fn options(methods: &[&str], families: &[&str], precision: Precision) -> IsaOptions {
    IsaOptions {
        methods: methods.iter().map(|m| method::find(m).unwrap()).collect(),
        families: families.iter().map(|f| f.to_string()).collect(),
        driver_files: None,
        scene: None,
        exe: PathBuf::from(env!("CARGO_BIN_EXE_shadelab")),
        precision,
        probes: Vec::new(),
        store: None,
    }
}

fn isa_run(opts: &IsaOptions) -> IsaReport {
    isa::run(opts, &|_| {}).expect("isa run")
}

/// Whether the compilers of `families` are built; when not, the test is skipped with a
/// `SKIPPED: <test>` line written straight to the terminal (`eprintln!` is captured and hidden
/// for a passing test), or fails under `SHADELAB_REQUIRE_COMPILERS=1`.
pub(crate) fn compilers_ready(families: &[&str]) -> bool {
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    families_ready(&test, families, "SHADELAB_REQUIRE_COMPILERS")
}

/// Every method on every family: compiled by Mesa 25.0.7, finite positive figures, the Phong
/// order on the family's ranking statistic, isa.json valid against its schema.
fn every_method_in(precision: Precision, families: &[&str]) -> IsaReport {
    let all: Vec<&str> = method::METHODS.iter().map(|m| m.name).collect();
    assert_eq!(all.len(), 37, "the issue counts 37 methods");
    let r = isa_run(&options(&all, families, precision));
    assert_eq!(r.supported(), families.to_vec(), "{:#?}", r.families);
    for f in &r.families {
        let ranking = f.ranking().expect("a ranking statistic");
        let compiler = f.compiler().expect("a compiler");
        // "Mesa 25.0.7" from our build, "Mesa 25.0.7-2~bpo12+1" from the ANV package.
        let version = compiler.mesa_version.as_deref().unwrap_or_default();
        assert!(
            version == "Mesa 25.0.7" || version.starts_with("Mesa 25.0.7-"),
            "{}: {version}",
            f.id
        );
        assert_eq!(
            f.float16,
            Some(FLOAT16.contains(&f.id.as_str())),
            "{}",
            f.id
        );
        for m in &all {
            let Some(v) = r.ranking_value(&f.family, m) else {
                // Only an OpenGL ES 2.0 family may skip a method, and says which and why.
                assert!(
                    ES2.contains(&f.id.as_str()),
                    "{} {m}: no {}",
                    f.id,
                    ranking.key
                );
                assert!(
                    f.status.contains(&format!("{m}: ")),
                    "{}: {}",
                    f.id,
                    f.status
                );
                continue;
            };
            assert!(v.is_finite() && v > 0.0, "{} {m}: {v}", f.id);
        }
        assert_references_in_order(&r, f, &format!("{} {precision:?}", f.id));
    }
    let dir = tempfile::tempdir().unwrap();
    isa::files::write(dir.path(), &r).unwrap();
    let (json, validator) = isa_json_against_its_schema(dir.path());
    // Teeth: each new vendor's row without its ranking statistic fails the schema.
    for (prefix, key) in [
        ("qualcomm:", "instruction_count"),
        ("arm:", "inst"),
        ("broadcom:", "inst"),
    ] {
        let Some(i) = r
            .results
            .iter()
            .position(|row| row.family.starts_with(prefix))
        else {
            continue;
        };
        let bad = crate::isa::without_statistic(&json, i, key);
        assert!(!validator.is_valid(&bad), "no teeth for {prefix}");
    }
    r
}

#[test]
fn every_method_compiles_on_every_mobile_family() {
    if !compilers_ready(&FAMILIES) {
        return;
    }
    let r = every_method_in(Precision::F32, &FAMILIES);
    // Mali's Bifrost and Valhall name the pipe that bounds their cycle estimate.
    for f in ["arm:g52", "arm:g610"] {
        let row = r
            .row(f, "phong_exact", "fragment", shadelab::isa::RowKind::Draw)
            .unwrap();
        let bound: Vec<&String> = row
            .statistics
            .keys()
            .filter(|k| k.starts_with("bound_"))
            .collect();
        assert_eq!(bound.len(), 1, "{f}: {:?}", row.statistics);
        assert_eq!(row.statistics[bound[0]], row.statistics["cycles"], "{f}");
    }
}

#[test]
fn every_method_compiles_in_float16_where_the_driver_has_it() {
    if !compilers_ready(&FLOAT16) {
        return;
    }
    every_method_in(Precision::F16, &FLOAT16);
    // Teeth: a driver whose mediump is float32 refuses float16 programs.
    let r = isa_run(&options(
        &["phong_exact"],
        &["broadcom:v3d42"],
        Precision::F16,
    ));
    assert!(r.supported().is_empty(), "{:#?}", r.families);
    let status = &r.families[0].status;
    assert!(status.contains("no float16 arithmetic"), "{status}");
}

#[test]
fn mobile_families_compile_identically_twice() {
    if !compilers_ready(&FAMILIES) {
        return;
    }
    let opts = options(
        &[
            "gouraud",
            "phong_unnormalized",
            "phong_exact",
            "newton_raphson",
        ],
        &FAMILIES,
        Precision::F32,
    );
    let (a, b) = (isa_run(&opts), isa_run(&opts));
    assert_eq!(a.supported().len(), FAMILIES.len(), "{:#?}", a.families);
    assert_identical_runs(&a, &b);
}

/// A chip the driver does not know is refused, never measured: Turnip takes no a5xx, panfrost
/// no unknown product id, the v3d shim is a V3D 4.2 only; the real families beside them
/// still compile.
#[test]
fn a_chip_the_driver_does_not_know_is_refused() {
    let fakes = ["qualcomm:a530", "arm:id1234", "broadcom:v3d71"];
    let real = ["qualcomm:a630", "arm:g52", "broadcom:v3d42"];
    if !compilers_ready(&real) {
        return;
    }
    let families: Vec<&str> = fakes.iter().chain(&real).copied().collect();
    let r = isa_run(&options(&["phong_exact"], &families, Precision::F32));
    assert_eq!(r.supported(), real.to_vec(), "{:#?}", r.families);
    for f in r.families.iter().filter(|f| !f.supported) {
        assert!(
            f.status.starts_with("not supported by this driver: "),
            "{}: {}",
            f.id,
            f.status
        );
        assert!(r.results.iter().all(|row| row.family != f.family));
    }
}

/// Without `make compilers` a mobile test is a visible skip (a `SKIPPED: <test>` line on the
/// terminal, never a silent pass), and a failure under `SHADELAB_REQUIRE_COMPILERS=1` (what CI
/// sets): runs this test binary on one mobile test with an empty cache folder.
#[test]
fn missing_compilers_skip_visibly_and_fail_when_required() {
    assert_skips_without_compilers(
        "isa_mobile::a_chip_the_driver_does_not_know_is_refused",
        "qualcomm:a630",
    );
}

/// Runs `test` of this binary with an empty cache folder: without the compilers it passes
/// with a `SKIPPED: <test>: <family> is not set up ... run make compilers` line, and under
/// `SHADELAB_REQUIRE_COMPILERS=1` it fails.
pub(crate) fn assert_skips_without_compilers(test: &str, family: &str) {
    let cache = tempfile::tempdir().unwrap();
    let run = |require: &str| {
        rerun_test(
            test,
            &[
                ("XDG_CACHE_HOME", cache.path().as_os_str()),
                ("SHADELAB_REQUIRE_COMPILERS", require.as_ref()),
            ],
        )
    };
    let skipped = run("0");
    let err = String::from_utf8_lossy(&skipped.stderr);
    assert!(skipped.status.success(), "{err}");
    assert!(
        err.contains(&format!("SKIPPED: {test}: {family} is not set up"))
            && err.contains("run make compilers"),
        "the skip must say SKIPPED, name the test and the command: {err}"
    );
    let required = run("1");
    assert!(
        !required.status.success(),
        "SHADELAB_REQUIRE_COMPILERS=1 must fail {test} without the compilers"
    );
}
