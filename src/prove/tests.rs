//! The interval type against exact arithmetic (with a deliberately un-widened product as
//! teeth), the generic formulas in both instantiations, the branch-and-bound on the covered
//! methods, and the planted spike the grid misses and the proof catches.
use super::bnb::ATOL;
use super::covered::{self, Metric};
use super::interval::Interval;
use super::*;
use crate::method::formulas as f;
use crate::method::kernel::formula;
use crate::method::real::Real;
use crate::method::{self, Geometry, Kernel, Reference, Scale};

/// Whether the exact product x*y lies in `i` (x*y = p + e exactly, e from an FMA).
fn holds_product(i: Interval, x: f64, y: f64) -> bool {
    let p = x * y;
    let e = x.mul_add(y, -p);
    let above_lo = p > i.lo || (p == i.lo && e >= 0.0);
    let below_hi = p < i.hi || (p == i.hi && e <= 0.0);
    above_lo && below_hi
}

/// Whether the exact sum x+y lies in `i` (TwoSum).
fn holds_sum(i: Interval, x: f64, y: f64) -> bool {
    let s = x + y;
    let bb = s - x;
    let e = (x - (s - bb)) + (y - bb);
    (s > i.lo || (s == i.lo && e >= 0.0)) && (s < i.hi || (s == i.hi && e <= 0.0))
}

fn random_interval(rng: &mut fastrand::Rng) -> Interval {
    let a = (rng.f64() - 0.5) * 10f64.powi(rng.i32(-3..4));
    let b = (rng.f64() - 0.5) * 10f64.powi(rng.i32(-3..4));
    Interval::new(a.min(b), a.max(b))
}

/// A point of `i`: its ends often (where rounding bites), else inside.
fn point_in(i: Interval, rng: &mut fastrand::Rng) -> f64 {
    match rng.u32(0..4) {
        0 => i.lo,
        1 => i.hi,
        _ => i.lo + rng.f64() * (i.hi - i.lo),
    }
    .clamp(i.lo, i.hi)
}

/// The product with its ends rounded to nearest, not outward (the teeth).
fn mul_nearest(a: Interval, b: Interval) -> Interval {
    let p = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi];
    Interval::new(
        p.iter().copied().fold(f64::INFINITY, f64::min),
        p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// How many of `n` random (interval, point) pairs have the exact product outside `op`'s.
fn product_misses(op: fn(Interval, Interval) -> Interval, n: usize) -> usize {
    let mut rng = fastrand::Rng::with_seed(27);
    (0..n)
        .filter(|_| {
            let (a, b) = (random_interval(&mut rng), random_interval(&mut rng));
            let (x, y) = (point_in(a, &mut rng), point_in(b, &mut rng));
            !holds_product(op(a, b), x, y)
        })
        .count()
}

#[test]
fn every_operation_holds_the_exact_result_of_its_points() {
    assert_eq!(product_misses(|a, b| a * b, 20_000), 0);
    let mut rng = fastrand::Rng::with_seed(5);
    for _ in 0..20_000 {
        let (a, b) = (random_interval(&mut rng), random_interval(&mut rng));
        let (x, y) = (point_in(a, &mut rng), point_in(b, &mut rng));
        assert!(holds_sum(a + b, x, y), "{a:?} + {b:?} at {x}, {y}");
        assert!(holds_sum(a - b, x, -y), "{a:?} - {b:?} at {x}, {y}");
        assert!(holds_product(a.sqr(), x, x), "{a:?}^2 at {x}");
        if !b.contains(0.0) {
            // x / y = q exactly iff q y = x: the true quotient lies in [lo, hi] iff
            // lo y <= x <= hi y (y > 0; reversed for y < 0), checked with exact products.
            let q = a / b;
            let (lo_e, hi_e) = (q.lo.mul_add(y, -x), q.hi.mul_add(y, -x));
            if y > 0.0 {
                assert!(lo_e <= 0.0 && hi_e >= 0.0, "{a:?} / {b:?} at {x}, {y}");
            } else {
                assert!(lo_e >= 0.0 && hi_e <= 0.0, "{a:?} / {b:?} at {x}, {y}");
            }
        }
        let pos = Interval::new(a.lo.abs().min(a.hi.abs()), a.mag());
        let z = point_in(pos, &mut rng);
        let r = pos.sqrt();
        // sqrt(z) in [lo, hi] iff lo^2 <= z <= hi^2, exactly by FMA.
        assert!(r.lo.mul_add(r.lo, -z) <= 0.0 && r.hi.mul_add(r.hi, -z) >= 0.0);
        let ang = Interval::new(-0.5 * rng.f64(), 1.5);
        let t = point_in(ang, &mut rng);
        assert!(ang.sin().contains(t.sin()) && ang.cos().contains(t.cos()));
    }
}

#[test]
fn a_product_rounded_to_nearest_is_caught_leaving_points_out() {
    assert!(product_misses(mul_nearest, 20_000) > 100);
}

#[test]
fn the_generic_formulas_give_the_f64_value_inside_the_interval_one() {
    type Both = (fn(f64) -> f64, fn(Interval) -> Interval);
    let ks: [Both; 4] = [
        (f::k_newton, f::k_newton),
        (f::k_lyon2, f::k_lyon2),
        (f::k_lyon_shift, f::k_lyon_shift),
        (f::k_romanyuk, f::k_romanyuk),
    ];
    let mut rng = fastrand::Rng::with_seed(1);
    for _ in 0..2000 {
        let z = rng.f64() * 1.5;
        for (k64, ki) in ks {
            assert!(ki(Interval::point(z)).contains(k64(z)));
        }
        let s = f::mikami_sqrt(z, f::beta_quadratic(z));
        let si = f::mikami_sqrt(Interval::point(z), f::beta_quadratic(Interval::point(z)));
        assert!(si.contains(s));
    }
    // f64 instantiation: the same operations as the literal formula.
    let z = 0.7f64;
    assert_eq!(f::k_newton(z).to_bits(), (0.5 * (3.0 - z)).to_bits());
}

fn quick() -> ProveOptions {
    ProveOptions {
        max_boxes: 50_000,
        max_seconds: 30.0,
        ..ProveOptions::default()
    }
}

#[test]
fn newton_is_proven_within_one_percent_of_its_midpoint_error() {
    let m = method::find("newton_raphson").unwrap();
    let k = covered::factor_of(m).unwrap();
    let o = prove_metric(m, k, Metric::Length, Domain::Edge, 90.0, &quick());
    // The worst is the edge's midpoint at 90 degrees: z = cos^2(45 deg).
    let z = 45f64.to_radians().cos().powi(2);
    let exact = (1.0 - f::k_newton(z) * z.sqrt()).abs();
    assert!(o.converged, "{o:?}");
    assert!(o.found <= o.proven_upper + ATOL, "{o:?}");
    assert!(o.proven_upper >= exact * (1.0 - 1e-6), "{o:?} vs {exact}");
    assert!(o.proven_upper <= exact * 1.011, "{o:?} vs {exact}");
    let angle = prove_metric(m, k, Metric::Angle, Domain::Edge, 90.0, &quick());
    assert_eq!(angle.proven_upper, 0.0);
}

#[test]
fn every_covered_method_converges_and_its_colour_bound_holds_the_found_colour() {
    let opts = ProveOptions {
        max_angle_deg: 40.0,
        ..quick()
    };
    let grid = stress_grid(40.0, opts.shininess);
    for m in method::METHODS.iter() {
        let Some(k) = covered::factor_of(m) else {
            continue;
        };
        let p = prove_method(m, k, &grid, &opts);
        let mut bounds = Vec::new();
        for domain in Domain::ALL {
            let outcomes = [Metric::Length, Metric::LengthSigned, Metric::Angle]
                .map(|x| prove_metric(m, k, x, domain, 40.0, &opts));
            for (i, o) in outcomes.iter().enumerate() {
                // [1], the signed length error, is auxiliary (to 1e-6, not within the tolerance)
                assert!(o.converged || i == 1, "{} {domain:?}: {o:?}", m.name);
                assert!(
                    o.found <= o.proven_upper + ATOL,
                    "{} {domain:?}: {o:?}",
                    m.name
                );
            }
            let bound = colour_bound(&outcomes, opts.shininess).unwrap();
            let found = p.over(domain).unwrap().colour.found.unwrap();
            // + 1e-12: the f64 twin's own rounding (a method exact on the domain is proven 0)
            assert!(
                found <= bound * (1.0 + 1e-9) + 1e-12,
                "{} {domain:?}: {found} > {bound}",
                m.name
            );
            bounds.push(bound);
        }
        // stress's cases are edges, inside both domains
        let grid_found = p.stress_grid.colour_found.unwrap();
        for bound in bounds {
            assert!(
                grid_found <= bound * (1.0 + 1e-9) + 1e-12,
                "{}: {grid_found} > {bound}",
                m.name
            );
        }
    }
}

#[test]
fn methods_out_of_reach_say_why() {
    for m in method::METHODS.iter() {
        if covered::factor_of(m).is_none() {
            assert!(covered::out_of_reach(m).len() > 20, "{}", m.name);
        }
    }
    assert!(covered::factor_of(method::find("slerp").unwrap()).is_none());
}

// ---- the planted spike ----------------------------------------------------------------------

const SPIKE: f64 = 0.05;
const SPIKE_WIDTH: f64 = 1e-6;

/// The squared length of the edge's normal at (theta degrees, t).
fn z_at(theta: f64, t: f64) -> f64 {
    let h = (0.5 * theta).to_radians();
    h.cos().powi(2) + (1.0 - 2.0 * t).powi(2) * h.sin().powi(2)
}

/// Exact normalisation plus a narrow spike (a Lorentzian of height [`SPIKE`]) at z = z(37
/// deg, 0.3): between the grid's angles and pixels.
fn k_spike<T: Real>(z: T) -> T {
    let u = (z - T::c(z_at(37.0, 0.3))) / T::c(SPIKE_WIDTH);
    T::c(1.0) / z.sqrt() + T::c(SPIKE) / (T::c(1.0) + u * u)
}

static SPIKED: Method = Method {
    name: "test_spike",
    description: "exact normalisation with a planted spike (test only)",
    citation: "",
    inputs: &[method::Input::InterpolatedNormal],
    family: method::Family::PerPixelNormalisation,
    properties: &[],
    geometry: Geometry::Mesh,
    has_normal: true,
    reference: Reference::Phong,
    validity: "",
    claims: &[],
    glsl: "",
    kernel: Kernel::Scaled(Scale::times(&formula!(k_spike))),
};

#[test]
fn a_spike_the_grid_misses_is_caught_by_the_proof() {
    let grid = stress_grid(90.0, 50.0);
    let worst = grid
        .cases
        .iter()
        .filter(|c| !c.ill_conditioned)
        .map(|c| {
            let s = SPIKED.eval_f64(&c.fragment, &c.lighting);
            (s.normal.unwrap().length() - 1.0).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < SPIKE / 100.0, "the grid hit the spike: {worst}");
    let opts = ProveOptions {
        max_boxes: 20_000,
        ..quick()
    };
    let k = covered::factor_of(&SPIKED).unwrap();
    let o = prove_metric(&SPIKED, k, Metric::Length, Domain::Edge, 90.0, &opts);
    let peak = SPIKE * z_at(37.0, 0.3).sqrt();
    assert!(o.proven_upper >= peak * 0.999, "{o:?}");
    assert!(!o.converged || o.found >= peak * 0.99, "{o:?}");
}

// ---- the engines' guarded normalisations, the triangle's z range -----------------------------

#[test]
fn the_guarded_normalisations_hold_their_f64_values_and_are_proven_exact_only_above_the_guard() {
    let (safe, clamp) = (
        covered::factor_of(method::find("safe_normalize").unwrap()).unwrap(),
        covered::factor_of(method::find("filament_clamp").unwrap()).unwrap(),
    );
    let mut rng = fastrand::Rng::with_seed(3);
    for _ in 0..2000 {
        // below HALF_MIN, around 1, above 65504
        let z = 10f64.powf(rng.f64() * 12.0 - 7.0);
        assert!(safe.k(Interval::point(z)).contains(f::k_safe(z)), "{z}");
        assert!(clamp.k(Interval::point(z)).contains(f::k_clamp(z)), "{z}");
    }
    // exact on the domain: proven 0; a box reaching below the guard is not exact (teeth)
    let unit = Interval::new(0.25, 1.0);
    assert_eq!(covered::upper(safe, Metric::Length, unit), 0.0);
    assert_eq!(covered::upper(clamp, Metric::Length, unit), 0.0);
    let tiny = Interval::new(1e-6, 1e-5);
    assert!(covered::upper(safe, Metric::Length, tiny) > 0.5);
    let huge = Interval::new(7e4, 1e5);
    assert!(covered::upper(clamp, Metric::Length, huge) > 0.01);
}

#[test]
fn the_triangle_range_holds_the_centroid_of_three_normals_that_the_edge_range_misses() {
    for theta in [40.0, 60.0, 90.0, 120.0] {
        // three unit normals pairwise theta apart, equal weights
        let c = (1.0 + 2.0 * f64::cos(f64::to_radians(theta))) / 3.0;
        let tilt = (1.0 - c).sqrt().asin();
        let n = [0.0, 120.0, 240.0].map(|a: f64| {
            let a = a.to_radians();
            glam::DVec3::new(tilt.sin() * a.cos(), tilt.sin() * a.sin(), tilt.cos())
        });
        let ang = n[0].angle_between(n[1]).to_degrees();
        assert!((ang - theta).abs() < 1e-9, "{ang} vs {theta}");
        let z = ((n[0] + n[1] + n[2]) / 3.0).length_squared();
        assert!(covered::triangle_z_range(theta).contains(z), "{theta}: {z}");
        assert!(
            !covered::z_range(theta).contains(z),
            "{theta}: the edge reaches {z}"
        );
        assert!(covered::triangle_z_range(theta).lo <= covered::z_range(theta).lo);
    }
}
