//! A new per-pixel method is its GLSL file and one row, claims included (issue 38; docs/methods.md
//! "How to add a method"): a test-only method, whose GLSL this test writes and whose row (kernel
//! and claims) it builds here, registered with nothing else added anywhere, goes through
//! `verify` on both engines, `stress` (its validity claim judged from the row), `prove` (its
//! kernel bounded, its bound claim proven), `list --json` and the report's answer.
use std::collections::BTreeMap;

use shadelab::compare::Metric;
use shadelab::compare::{compare, CompareOptions};
use shadelab::cost::{CostFigure, CostKind, CostModel, CostModelId, Measure};
use shadelab::engine::Engine;
use shadelab::method::kernel::{formula, Generic};
use shadelab::method::real::Real;
use shadelab::method::{
    self, Basis, Bound, Check, Claim, Criteria, Family, Geometry, Input, Kernel, Kind, Method,
    Precision, Property, Reference, Scale, Verdict,
};
use shadelab::prove::{self, ProveOptions};
use shadelab::report::answer::{answer, SceneError};
use shadelab::report::budget::METRICS;
use shadelab::stress::{self, StressOptions};
use shadelab::verify::{verify, verify_software};

use crate::support::*;

/// Two Newton-Raphson steps for 1/sqrt(z) from 1: y = (3 - z)/2, then y (3 - z y^2)/2; the
/// same operations in the same order as [`GLSL`].
fn k_two_steps<T: Real>(z: T) -> T {
    let y = T::c(0.5) * (T::c(3.0) - z);
    y * (T::c(0.5) * (T::c(3.0) - z * y * y))
}

/// The method's one formula, in every number type.
static K: Generic = formula!(k_two_steps);

const NAME: &str = "two_newton_steps";

/// The method's GLSL file, written by the test.
const GLSL: &str =
    "// two_newton_steps: a test-only method (tests/one_row.rs), two Newton steps for
// 1/sqrt(z) from 1.
// shadelab-inputs: interpolated_normal
real3 methodNormal() {
    real z = dot(R3(vNormal), R3(vNormal));
    real y = R(0.5) * (R(3.0) - z);
    return R3(vNormal) * (y * (R(0.5) * (R(3.0) - z * y * y)));
}
";

/// Its claims: a length bound where two steps leave 0.098 % (z = 0.75 is 60 degrees between
/// the vertex normals), and the validity up to 60 degrees by both criteria.
static CLAIMS: [Claim; 2] = [
    Claim {
        claim: "test: the length error is at most 0.1 % for z in [0.75, 1]",
        kind: Kind::ErrorBound(Bound::Length {
            at_most: 0.001,
            z: (0.75, 1.0),
        }),
        basis: Basis::Proven,
        check: Check::Proof,
    },
    Claim {
        claim: "test: usable for angles between vertex normals up to 60 degrees",
        kind: Kind::Validity {
            up_to_deg: 60.0,
            criteria: Criteria::LengthAndColour,
        },
        basis: Basis::Proven,
        check: Check::Proof,
    },
];

/// Writes the GLSL file and registers the row (once per test process).
fn the_method() -> &'static Method {
    static ONCE: std::sync::OnceLock<&'static Method> = std::sync::OnceLock::new();
    ONCE.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("shadelab-one-row-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("{NAME}.glsl"));
        std::fs::write(&path, GLSL).unwrap();
        let glsl: &'static str = Box::leak(path.display().to_string().into_boxed_str());
        let row: &'static Method = Box::leak(Box::new(Method {
            name: NAME,
            description: "two Newton-Raphson steps for 1/sqrt(z) from 1 (test only)",
            citation: "tests/one_row.rs",
            inputs: &[Input::InterpolatedNormal],
            family: Family::PerPixelNormalisation,
            properties: &[Property::SqrtFree],
            kernel: Kernel::Scaled(Scale::times(&K)),
            geometry: Geometry::Mesh,
            has_normal: true,
            reference: Reference::Phong,
            validity: "angle between vertex normals <= 60 degrees",
            claims: &CLAIMS,
            glsl,
        }));
        shadelab::gpu::shaders::register_row(&path, row).unwrap();
        method::find(NAME).unwrap()
    })
}

#[test]
fn a_method_of_one_row_passes_verify_on_both_engines() {
    let m = the_method();
    assert!(m.twin().is_some(), "its twin comes from its kernel");
    let r = validated_renderer();
    for name in ["sphere_coarse", "torus"] {
        let scene = shipped_scene(name, 64);
        let gpu = verify(Engine::Vulkan(&r), &scene, &[m], None).unwrap();
        assert!(gpu.passed(), "{name}: {}", gpu.failures().join("; "));
        let sw = verify_software(&scene, &[m], None, 2).unwrap();
        assert!(sw.passed(), "{name}: {}", sw.failures().join("; "));
        // teeth: judged against another method's formula, the same image fails
        let newton = method::find("newton_raphson").unwrap();
        let wrong = verify(Engine::Vulkan(&r), &scene, &[m], Some(newton)).unwrap();
        assert!(!wrong.passed(), "{name}: passed against Newton's formula");
    }
    // teeth: a row whose GLSL computes one step while its kernel says two fails on both
    let one_step = mismatched_row();
    let scene = shipped_scene("sphere_coarse", 64);
    let gpu = verify(Engine::Vulkan(&r), &scene, &[one_step], None).unwrap();
    assert!(
        !gpu.passed(),
        "the GLSL and the row disagree, yet verify passed"
    );
    let sw = verify_software(&scene, &[one_step], None, 2).unwrap();
    assert!(
        sw.passed(),
        "the software engine runs the row's kernel, its twin the same"
    );
    assert_validation_clean(r.context());
}

/// A row whose GLSL file (one Newton step) is not its kernel (two steps).
fn mismatched_row() -> &'static Method {
    let name = "two_newton_steps_one_in_glsl";
    let dir = std::env::temp_dir().join(format!("shadelab-one-row-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.glsl"));
    let glsl = GLSL.replace("(y * (R(0.5) * (R(3.0) - z * y * y)))", "y");
    assert_ne!(glsl, GLSL);
    std::fs::write(&path, glsl).unwrap();
    let row: &'static Method = Box::leak(Box::new(Method {
        name,
        claims: &[],
        glsl: Box::leak(path.display().to_string().into_boxed_str()),
        ..*the_method()
    }));
    shadelab::gpu::shaders::register_row(&path, row).unwrap();
    method::find(name).unwrap()
}

#[test]
fn a_method_of_one_row_is_stressed_proven_and_its_claims_judged() {
    let m = the_method();
    // stress: the sweeps, and its validity claim read from its row
    let r = validated_renderer();
    let s = stress::run(r.context(), &[m], &StressOptions::default()).unwrap();
    assert_eq!(s.methods.len(), 1);
    assert!(s.methods[0].device_evaluated, "{:?}", s.methods[0]);
    let c = s
        .claims
        .iter()
        .find(|c| c.method == NAME)
        .expect("stress judges the row's validity claim");
    assert_eq!(c.claim, CLAIMS[1].claim);
    assert_ne!(c.verdict, Verdict::NotChecked, "{c:?}");
    // prove: its kernel is covered, its length error bounded at the claimed range's end
    let p = prove::run(
        &[m],
        &ProveOptions {
            max_angle_deg: 60.0,
            ..ProveOptions::default()
        },
    )
    .unwrap();
    assert_eq!(p.methods.len(), 1, "{:?}", p.out_of_reach);
    let bound = p
        .claims
        .iter()
        .find(|c| c.claim == CLAIMS[0].claim)
        .unwrap();
    assert_eq!(
        (bound.basis, bound.verdict),
        (Basis::Proven, Verdict::Agrees)
    );
    // two steps at z = 0.75: k = 1.1535644..., k sqrt(z) - 1 = -9.84e-4
    let e = (k_two_steps(0.75f64) * 0.75f64.sqrt() - 1.0).abs();
    let upper = bound.proven_upper.unwrap();
    assert!(e <= upper && upper <= e * 1.01, "{e} vs proven {upper}");
    // list --json: both claims judged now, the validity by proof too
    let json = prove::bounds::json(m);
    let claims = json["claims"].as_array().unwrap();
    assert_eq!(claims.len(), 2);
    assert!(claims.iter().all(|c| c["basis"] == "proven"), "{json}");
    assert_eq!(claims[1]["verdict"], "agrees", "{}", claims[1]);
    // teeth: the same row with a tighter figure disagrees (a real point exceeds it)
    let tight = Claim {
        kind: Kind::ErrorBound(Bound::Length {
            at_most: 0.0005,
            z: (0.75, 1.0),
        }),
        ..CLAIMS[0]
    };
    assert_eq!(prove::bounds::judge(m, &tight).verdict, Verdict::Disagrees);
    assert_validation_clean(r.context());
}

#[test]
fn a_method_of_one_row_takes_part_in_the_reports_answer() {
    let m = the_method();
    let r = validated_renderer();
    let methods = [
        m,
        method::phong_exact(),
        method::find("newton_raphson").unwrap(),
    ];
    let out = std::env::temp_dir().join(format!("shadelab-one-row-answer-{}", std::process::id()));
    let scenes = ["sphere_coarse", "torus"];
    let mut errors = Vec::new();
    for name in scenes {
        let sum = compare(
            &r,
            &shipped_scene(name, 64),
            &methods,
            &out.join(name),
            &CompareOptions::default(),
        )
        .unwrap();
        for s in &sum.methods {
            let metrics: BTreeMap<Metric, Option<f64>> =
                METRICS.iter().map(|k| (*k, k.of(s))).collect();
            errors.push(SceneError {
                scene: name.into(),
                method: s.name.clone(),
                precision: Precision::F32,
                covered_pixels: s.covered_pixels,
                non_finite_pixels: s.non_finite_pixels,
                metrics,
                evidence: format!("{name}/summary.json"),
            });
        }
    }
    // a static cost model of the compiled programs: each method's counted arithmetic (SPIR-V,
    // weighted by components) over phong_exact's, measured now
    let ops = |n: &str| {
        let program =
            shadelab::gpu::shaders::program_name(n, shadelab::scene::Interpolation::Perspective);
        let bytes = shadelab::gpu::shaders::embedded(&program, "frag").unwrap();
        let c = shadelab::gpu::spirv::count_ops(bytes).unwrap();
        f64::from(c.div + c.sqrt + c.inverse_sqrt + c.mul + c.add + c.pow + c.other_transcendental)
    };
    let reference = ops(method::PHONG_EXACT);
    let figures = methods
        .iter()
        .map(|x| {
            let ratio = ops(x.name) / reference;
            CostFigure {
                method: x.name.into(),
                value: Some(ops(x.name)),
                ratio: Some(ratio),
                ci95_low: None,
                ci95_high: None,
                verdict: shadelab::cost::rule::static_cheaper(Some(ratio)),
                evidence: String::new(),
                note: "SPIR-V arithmetic".into(),
            }
        })
        .collect();
    let model = CostModel {
        id: CostModelId::of("spirv_ops"),
        title: "SPIR-V arithmetic".into(),
        kind: CostKind::Static,
        measure: Measure {
            statistic: "arithmetic instructions of the fragment shader".into(),
            unit: "instructions".into(),
        },
        description: "test".into(),
        precision: Precision::F32,
        figures,
        pairs: Vec::new(),
    };
    let names: Vec<String> = methods.iter().map(|x| x.name.to_string()).collect();
    let scenes: Vec<String> = scenes.iter().map(|s| s.to_string()).collect();
    let a = answer(&scenes, &names, &errors, vec![model]);
    // it is checked against every budget like any row, and its figures are its own
    let mine: Vec<_> = a.checks.iter().filter(|c| c.method == NAME).collect();
    assert_eq!(mine.len(), a.budgets.len());
    let loose = mine.iter().find(|c| c.budget.id() == "max_4_255").unwrap();
    assert!(loose.worst.is_some_and(|w| w > 0.0), "{loose:?}");
    // its figures are its own: the worst of its scenes' errors under each budget's metric
    for c in &mine {
        let b = a.budgets.iter().find(|b| **b == c.budget).unwrap();
        let worst = errors
            .iter()
            .filter(|e| e.method == NAME)
            .map(|e| e.metrics[&b.metric].unwrap())
            .fold(0.0, f64::max);
        assert_eq!(c.worst, Some(worst), "{c:?}");
    }
    // two steps are more accurate than one: under every budget its worst error is below
    // Newton's, and wherever Newton meets a budget, so does it
    for c in &mine {
        let newton = a
            .checks
            .iter()
            .find(|n| n.method == "newton_raphson" && n.budget == c.budget)
            .unwrap();
        assert!(c.worst.unwrap() < newton.worst.unwrap(), "{c:?} {newton:?}");
        assert!(c.meets || !newton.meets, "{c:?} {newton:?}");
    }
    assert!(!a.cells.is_empty());
    let _ = std::fs::remove_dir_all(&out);
}

/// A row that says it is a baseline of tune is one, with nothing added to tune: the
/// same formula registered as a row with `Property::TuneBaseline` is among tune's papers, its
/// factor the row's in every number type tune proves in (a float32 program's rounding
/// enclosed, not unknown). Teeth: the row without the property is no baseline.
#[test]
fn a_method_of_one_row_is_a_tune_baseline_when_its_row_says_so() {
    use shadelab::method::interval::Interval;
    use shadelab::method::rounded::{Rounded, F32};
    use shadelab::tune::candidate::{self, Family as TuneFamily};
    let plain = the_method();
    assert!(
        !candidate::papers().iter().any(|c| c.id == NAME),
        "a row without TuneBaseline became a baseline"
    );
    let name = "two_newton_steps_baseline";
    let dir = std::env::temp_dir().join(format!("shadelab-one-row-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.glsl"));
    std::fs::write(&path, GLSL.replace("two_newton_steps", name)).unwrap();
    let row: &'static Method = Box::leak(Box::new(Method {
        name,
        properties: &[Property::SqrtFree, Property::TuneBaseline],
        claims: &[],
        glsl: Box::leak(path.display().to_string().into_boxed_str()),
        ..*plain
    }));
    shadelab::gpu::shaders::register_row(&path, row).unwrap();
    let papers = candidate::papers();
    let c = papers
        .iter()
        .find(|c| c.id == name)
        .expect("the registered row is a tune baseline");
    assert_eq!(c.family, TuneFamily::Paper);
    for z in [0.5f64, 0.75, 0.9, 1.0] {
        assert_eq!(c.k(z), k_two_steps(z), "z = {z}");
    }
    let r = c.k(Rounded::<F32>::input(
        Interval::point(0.75),
        Interval::point(0.0),
    ));
    let exact = k_two_steps(0.75f64);
    assert!(
        r.computed().lo <= exact && exact <= r.computed().hi,
        "{r:?}"
    );
    assert!(
        r.e.hi - r.e.lo < 1e-5,
        "its float32 rounding is bounded: {r:?}"
    );
    // the table's own baselines are still there, and still first
    assert_eq!(papers[0].id, "phong_unnormalized");
}
