//! `shadelab isa` on Apple's G13 (M1) through Mesa 25.0.7's Honeykrisp (asahi's Vulkan driver)
//! on its noop drm-shim (`make compilers`): every method compiles in float32 and float16; the
//! ranking statistic is the compiler's cycle model (`alu`, the bound unit named); gouraud <
//! phong_unnormalized < phong_exact on it; two runs are identical; a chip the shim is not is
//! refused. Skipped with a line when the compilers are not built, failing under
//! `SHADELAB_REQUIRE_COMPILERS=1`.
use std::path::PathBuf;

use shadelab::isa::{self, IsaOptions, IsaReport, Precision};
use shadelab::method;

use crate::isa::{assert_identical_runs, assert_references_in_order, isa_json_against_its_schema};
use crate::isa_mobile::compilers_ready;

/// Every AGX family the shim and the compiler can be.
const FAMILIES: [&str; 1] = ["apple:g13"];

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

/// Every method in `precision`: compiled by Mesa 25.0.7's Honeykrisp on the G13G, each draw's
/// fragment program with a finite positive cycle figure, its bound unit named with that
/// figure, the Phong order, isa.json valid against its schema (with teeth).
fn every_method_in(precision: Precision) -> IsaReport {
    let all: Vec<&str> = method::METHODS.iter().map(|m| m.name).collect();
    assert_eq!(all.len(), 37, "the issue counts 37 methods");
    let r = isa_run(&options(&all, &FAMILIES, precision));
    assert_eq!(r.supported(), FAMILIES.to_vec(), "{:#?}", r.families);
    for f in &r.families {
        let ranking = f.ranking().expect("a ranking statistic");
        assert_eq!(ranking.key, "alu");
        let compiler = f.compiler().expect("a compiler");
        assert_eq!(compiler.mesa_version.as_deref(), Some("Mesa 25.0.7"));
        assert_eq!(compiler.api, "Vulkan");
        assert_eq!(f.float16, Some(true), "{}", f.id);
        assert!(f
            .device_name
            .as_deref()
            .is_some_and(|d| d.contains("(G13G ")));
        for m in &all {
            let row = r
                .row(&f.family, m, "fragment", shadelab::isa::RowKind::Draw)
                .unwrap_or_else(|| panic!("{} {m}: no fragment row", f.id));
            let s = &row.statistics;
            // gouraud's and trueform's fragment programs only pass the interpolated colour on:
            // no ALU cycle at all (0); every other figure is positive.
            let alu = s["alu"];
            let passes_colour_on = ["gouraud", "trueform"].contains(m);
            assert!(
                alu.is_finite() && (alu > 0.0 || (alu == 0.0 && passes_colour_on)),
                "{} {m}: {alu}",
                f.id
            );
            // alu is the larger unit's estimate, and that unit is the one named bound.
            assert_eq!(alu, s["fscib"].max(s["ic"]), "{} {m}: {s:?}", f.id);
            let bound: Vec<&String> = s.keys().filter(|k| k.starts_with("bound_")).collect();
            assert!(!bound.is_empty(), "{} {m}: no bound unit in {s:?}", f.id);
            for b in bound {
                assert_eq!(s[b], alu, "{} {m}: {b}", f.id);
                assert_eq!(s[&b["bound_".len()..]], alu, "{} {m}: {b}", f.id);
            }
            assert!(s["inst"] > 0.0 && s["spills"] == 0.0, "{} {m}: {s:?}", f.id);
        }
        assert_references_in_order(&r, f, &format!("{} {precision:?}", f.id));
    }
    let dir = tempfile::tempdir().unwrap();
    isa::files::write(dir.path(), &r).unwrap();
    let (json, validator) = isa_json_against_its_schema(dir.path());
    // Teeth: a row without the cycle model fails the schema.
    let mut bad = json.clone();
    bad["results"][0]["statistics"]
        .as_object_mut()
        .unwrap()
        .remove("alu");
    assert!(!validator.is_valid(&bad), "no teeth for apple's alu");
    r
}

#[test]
fn every_method_compiles_on_g13_in_float32_and_float16() {
    if !compilers_ready(&FAMILIES) {
        return;
    }
    let f32 = every_method_in(Precision::F32);
    let f16 = every_method_in(Precision::F16);
    // The float16 programs are other programs: 16-bit arithmetic (hfma, hmul) changes the
    // cycle figures of at least phong_exact's fragment program.
    let stat = |r: &IsaReport| {
        r.row(
            "apple:g13",
            "phong_exact",
            "fragment",
            shadelab::isa::RowKind::Draw,
        )
        .unwrap()
        .statistics
        .clone()
    };
    assert_ne!(
        stat(&f32),
        stat(&f16),
        "float16 compiled the float32 program"
    );
}

#[test]
fn g13_compiles_identically_twice() {
    if !compilers_ready(&FAMILIES) {
        return;
    }
    let methods = [
        "gouraud",
        "phong_unnormalized",
        "phong_exact",
        "newton_raphson",
    ];
    for precision in [Precision::F32, Precision::F16] {
        let opts = options(&methods, &FAMILIES, precision);
        let (a, b) = (isa_run(&opts), isa_run(&opts));
        assert_eq!(a.supported(), FAMILIES.to_vec(), "{:#?}", a.families);
        assert_identical_runs(&a, &b);
    }
}

/// The shim is a G13G: a G14 (M2), a G13X and an unknown chip are refused by name before any
/// child starts (the route knows only the G13), never measured.
#[test]
fn a_chip_the_asahi_shim_is_not_is_refused() {
    if !compilers_ready(&FAMILIES) {
        return;
    }
    for chip in ["g14", "g13x", "g99"] {
        let family = format!("apple:{chip}");
        let e = isa::run(
            &options(&["phong_exact"], &[&family, "apple:g13"], Precision::F32),
            &|_| {},
        )
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
        assert!(
            e.starts_with(&format!("unknown chip '{chip}' for apple; known: g13")),
            "{family}: {e}"
        );
    }
    // Teeth: the G13 alone compiles.
    let r = isa_run(&options(&["phong_exact"], &FAMILIES, Precision::F32));
    assert_eq!(r.supported(), FAMILIES.to_vec(), "{:#?}", r.families);
}

/// Without `make compilers` the Apple tests are a visible skip naming the command, and a
/// failure under `SHADELAB_REQUIRE_COMPILERS=1`.
#[test]
fn missing_asahi_skips_visibly_and_fails_when_required() {
    crate::isa_mobile::assert_skips_without_compilers(
        "isa_apple::a_chip_the_asahi_shim_is_not_is_refused",
        "apple:g13",
    );
}
