//! The triangle domain against random triangles: three unit normals pairwise at most theta
//! apart (equilateral ones among them, the worst), random weights, every input rounded to
//! float32 as the device receives it. No sample leaves the proven range of N.N or exceeds a
//! proven bound of the triangle domain; the edge domain's range and bounds are exceeded (the
//! teeth: the old single domain, stress's edge, did not hold for triangles).
use glam::{DVec2, DVec3};

use super::covered;
use super::*;
use crate::method::formulas::{normalize_exact, Lighting};
use crate::method::{self, Fragment};

fn f32r(v: DVec3) -> DVec3 {
    DVec3::new(
        f64::from(v.x as f32),
        f64::from(v.y as f32),
        f64::from(v.z as f32),
    )
}

fn unit(rng: &mut fastrand::Rng) -> DVec3 {
    loop {
        let v = DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 2.0 - DVec3::ONE;
        let l = v.length();
        if l > 1e-3 && l <= 1.0 {
            return v / l;
        }
    }
}

/// An orthonormal pair across `a`.
fn across(a: DVec3) -> (DVec3, DVec3) {
    let u = a.any_orthonormal_vector();
    (u, a.cross(u))
}

/// Three unit normals pairwise at most `theta_deg` apart: half the time pairwise exactly
/// min(theta, 120) apart (the equilateral configuration, whose centroid is the domain's
/// smallest |N|), else three within a cap of radius theta about a random axis, redrawn until
/// every pair is within theta.
fn normals(theta_deg: f64, rng: &mut fastrand::Rng) -> [DVec3; 3] {
    let axis = unit(rng);
    let (u, v) = across(axis);
    if rng.bool() {
        let c = theta_deg.min(120.0).to_radians().cos();
        let tilt = ((2.0 / 3.0) * (1.0 - c)).sqrt().min(1.0).asin();
        let phase = rng.f64() * std::f64::consts::TAU;
        return [0.0, 1.0, 2.0].map(|i: f64| {
            let phi = phase + i * std::f64::consts::TAU / 3.0;
            axis * tilt.cos() + (u * phi.cos() + v * phi.sin()) * tilt.sin()
        });
    }
    let r = theta_deg.to_radians();
    loop {
        let n = [0; 3].map(|_| {
            let cos_g = 1.0 - rng.f64() * (1.0 - r.cos());
            let sin_g = (1.0 - cos_g * cos_g).max(0.0).sqrt();
            let phi = rng.f64() * std::f64::consts::TAU;
            axis * cos_g + (u * phi.cos() + v * phi.sin()) * sin_g
        });
        let ok = (0..3).all(|i| n[i].angle_between(n[(i + 1) % 3]) <= r);
        if ok {
            return n;
        }
    }
}

/// Barycentric weights: uniform on the triangle, near the centroid, or on an edge.
fn weights(rng: &mut fastrand::Rng) -> DVec3 {
    let w = match rng.u32(0..4) {
        0 => DVec3::splat(1.0) + (DVec3::new(rng.f64(), rng.f64(), rng.f64()) - 0.5) * 0.02,
        1 => DVec3::new(rng.f64(), 1.0 - rng.f64(), 0.0).abs(),
        _ => DVec3::new(rng.f64(), rng.f64(), rng.f64()).map(|x| -(x.max(1e-300)).ln()),
    };
    w / (w.x + w.y + w.z)
}

/// A random triangle of the domain up to `theta_deg` as the method receives it (normals and
/// weights rounded to float32).
fn triangle(theta_deg: f64, rng: &mut fastrand::Rng) -> Fragment {
    let n = normals(theta_deg, rng).map(f32r);
    Fragment {
        weights: f32r(weights(rng)),
        pixel: DVec2::ZERO,
        window: [DVec2::ZERO; 3],
        corner_normals: n,
        flat_normal: normalize_exact(n[0] + n[1] + n[2]),
        pn_mids: n,
    }
}

/// One white light along `l`, viewed from `v`, the cases' material at `shininess`.
fn lighting(l: DVec3, v: DVec3, shininess: f64) -> Lighting {
    let f = |x: f64| f64::from(x as f32);
    Lighting::new(
        DVec3::splat(f(crate::cases::AMBIENT)),
        DVec3::splat(f(crate::cases::DIFFUSE)),
        DVec3::splat(f(crate::cases::SPECULAR)),
        shininess,
        &[(l, DVec3::ONE, (l + v).try_normalize().unwrap_or(l))],
    )
}

/// (length error, largest colour error over a random light and view and over the light and
/// view along the exact normal) of `m` on `fr`.
fn errors_at(m: &Method, fr: &Fragment, shininess: f64, rng: &mut fastrand::Rng) -> (f64, f64) {
    let exact = normalize_exact(fr.interpolated_normal());
    let mut colour = 0.0f64;
    let mut length = 0.0;
    for (l, v) in [(exact, exact), (unit(rng), unit(rng))] {
        let lit = lighting(l, v, shininess);
        let s = m.eval_f64(fr, &lit);
        length = (s.normal.expect("a covered method has a normal").length() - 1.0).abs();
        let e = (s.color - lit.shade(exact)).abs().max_element();
        assert!(e.is_finite(), "{}: {e} on {fr:?}", m.name);
        colour = colour.max(e);
    }
    (length, colour)
}

#[test]
fn no_random_triangle_has_its_squared_length_below_the_proven_range_and_edges_do_not_reach_it() {
    let mut rng = fastrand::Rng::with_seed(39);
    for theta in [5.0, 17.82, 40.0, 90.0, 119.0, 120.0, 150.0, 180.0] {
        let range = covered::triangle_z_range(theta);
        let edge = covered::z_range(theta);
        let (mut lowest, mut below_edge) = (f64::INFINITY, 0);
        for _ in 0..20_000 {
            let z = triangle(theta, &mut rng)
                .interpolated_normal()
                .length_squared();
            assert!(range.contains(z), "{theta} deg: z = {z} outside {range:?}");
            lowest = lowest.min(z);
            below_edge += usize::from(z < edge.lo);
        }
        // tight: the equilateral centroids come within 1e-3 of the proven lower end
        let exact_lo = ((1.0 + 2.0 * theta.to_radians().cos()) / 3.0).max(0.0);
        assert!(lowest - exact_lo < 1e-3, "{theta} deg: lowest {lowest}");
        assert!(range.lo <= exact_lo && exact_lo - range.lo < 1e-6);
        // the teeth: the edge domain's range misses triangles (it reaches 0 itself at 180)
        if theta < 180.0 {
            assert!(below_edge > 100, "{theta} deg: {below_edge}");
        }
    }
}

#[test]
fn random_triangles_stay_within_the_triangle_bounds_and_exceed_the_edge_bounds() {
    let mut rng = fastrand::Rng::with_seed(27);
    for theta in [17.82, 40.0, 90.0, 150.0] {
        let opts = ProveOptions {
            max_angle_deg: theta,
            ..ProveOptions::default()
        };
        for m in method::METHODS.iter() {
            let Some(k) = covered::factor_of(m) else {
                continue;
            };
            let tri = prove_domain(m, k, Domain::Triangle, &opts);
            let edge = prove_domain(m, k, Domain::Edge, &opts);
            let bound = |p: &DomainProof| {
                let length = p.metrics[0].proven_upper.unwrap();
                (length, p.colour.proven_upper.unwrap_or(f64::INFINITY))
            };
            let ((length, colour), (edge_length, edge_colour)) = (bound(&tri), bound(&edge));
            let (mut worst_length, mut worst_colour) = (0.0f64, 0.0f64);
            for _ in 0..4000 {
                let fr = triangle(theta, &mut rng);
                let (l, c) = errors_at(m, &fr, opts.shininess, &mut rng);
                // + 1e-12: the f64 twin's own rounding (the proof bounds real values)
                assert!(l <= length + 1e-12, "{} {theta}: {l} > {length}", m.name);
                assert!(
                    c <= colour * (1.0 + 1e-9) + 1e-12,
                    "{} {theta}: {c} > {colour}",
                    m.name
                );
                worst_length = worst_length.max(l);
                worst_colour = worst_colour.max(c);
            }
            // the teeth: methods whose error grows as |N| falls break the edge's bounds
            if [
                "newton_raphson",
                method::phong_unnormalized().name,
                "lyon_taylor",
            ]
            .contains(&m.name)
            {
                assert!(
                    worst_length > edge_length * 1.2 && worst_colour > edge_colour,
                    "{} {theta}: {worst_length} vs edge {edge_length}, {worst_colour} vs \
                     {edge_colour}",
                    m.name
                );
            }
        }
    }
}

/// Three unit normals pairwise `theta_deg` apart, at their centroid (weights 1/3, rounded).
fn centroid(theta_deg: f64) -> Fragment {
    let mut rng = fastrand::Rng::with_seed(1);
    loop {
        let fr = triangle(theta_deg, &mut rng);
        let n = fr.corner_normals;
        let pairwise = (0..3).map(|i| n[i].angle_between(n[(i + 1) % 3]).to_degrees());
        if pairwise.clone().all(|a| (a - theta_deg).abs() < 1e-5) {
            return Fragment {
                weights: f32r(DVec3::splat(1.0 / 3.0)),
                ..fr
            };
        }
    }
}

/// The figures: pairwise 90 deg, Newton-Raphson 0.230 and Romanyuk 5.53e-2 at the
/// centroid, against the edge's 0.116 and 3.53e-3; Newton-Raphson's edge valid angle 17.82 deg
/// gives 6.95e-3 (> 1/255) at the centroid of three normals that far apart.
#[test]
fn proof_json_covers_the_centroid_of_three_normals_pairwise_90_deg_apart() {
    let methods: Vec<&'static Method> = ["newton_raphson", "romanyuk_poly"]
        .iter()
        .map(|n| method::find(n).unwrap())
        .collect();
    let r = run(&methods, &ProveOptions::default()).unwrap();
    let json = serde_json::to_value(&r).unwrap();
    let mut rng = fastrand::Rng::with_seed(2);
    let fr = centroid(90.0);
    for (i, m) in methods.iter().enumerate() {
        let (at_centroid, _) = errors_at(m, &fr, 50.0, &mut rng);
        let tri = &json["methods"][i]["domains"][0];
        assert_eq!(tri["domain"], "triangle");
        let proven = tri["metrics"][0]["proven_upper"].as_f64().unwrap();
        assert!(
            at_centroid <= proven,
            "{}: {at_centroid} > {proven}",
            m.name
        );
        // within the tolerance: the centroid is the worst point of these two
        assert!(proven <= at_centroid * 1.011, "{}: {proven}", m.name);
        let edge = r.methods[i].over(Domain::Edge).unwrap();
        assert!(at_centroid > 1.5 * edge.metrics[0].proven_upper.unwrap());
    }
    // Newton-Raphson's valid angle: proven over triangles, below the edge's
    let nr = &r.methods[0];
    let tri_deg = nr
        .over(Domain::Triangle)
        .unwrap()
        .max_valid_angle
        .proven_deg;
    let edge_deg = nr.over(Domain::Edge).unwrap().max_valid_angle.proven_deg;
    let (tri_deg, edge_deg) = (tri_deg.unwrap(), edge_deg.unwrap());
    let mut colour_at = |theta: f64| errors_at(methods[0], &centroid(theta), 50.0, &mut rng).1;
    assert!(colour_at(edge_deg) > 1.0 / 255.0, "{edge_deg}");
    assert!(colour_at(tri_deg) <= 1.0 / 255.0, "{tri_deg}");
    assert!(
        tri_deg > 15.0 && tri_deg < edge_deg,
        "{tri_deg} vs {edge_deg}"
    );
}

/// The triangle's real points: for every z of the domain's range, a stress case of three
/// normals pairwise at most theta apart with that z, seen and lit along its exact normal, that
/// `stress --replay` accepts (and a row it could not draw is refused).
#[test]
fn the_triangle_points_are_replayable_triangles_of_the_domain_with_the_z_asked_for() {
    let nr = method::find("newton_raphson").unwrap();
    for theta in [17.82, 40.0, 90.0, 120.0, 150.0] {
        let range = Domain::Triangle.z_range(theta);
        for i in 0..=20 {
            let z = range.lo.max(0.02) + (1.0 - range.lo.max(0.02)) * f64::from(i) / 20.0;
            let p = Domain::Triangle.point_for_z(z, theta);
            let spec = Domain::Triangle.spec_at(&p, 50.0);
            let case = crate::cases::Case::new(spec);
            let n = case.fragment.corner_normals;
            for j in 0..3 {
                let a = n[j].angle_between(n[(j + 1) % 3]).to_degrees();
                assert!(a <= theta + 1e-4, "{theta} deg, z {z}: pair {j} at {a} deg");
            }
            let got = case.fragment.interpolated_normal().length_squared();
            // the strip's rows put w2 on a grid of 1e-5
            assert!(
                (got - z).abs() < 1e-4,
                "{theta} deg: z {got} for {z} ({spec:?})"
            );
            let (view, light) = (case.phong_normal.z, case.lighting.lights()[0].0);
            assert!(view > 1.0 - 1e-9, "{theta} deg, z {z}: {spec:?}");
            assert!(light.dot(case.phong_normal) > 1.0 - 1e-9, "{spec:?}");
            let file = crate::stress::case_report(nr, &case, None, method::Precision::F32).unwrap();
            let json = serde_json::to_string(&file).unwrap();
            let back =
                crate::stress::replay::parse(std::path::Path::new("c.json"), json.as_bytes())
                    .unwrap();
            assert_eq!(back.spec, spec);
        }
    }
    let p = std::path::Path::new("c.json");
    let case = crate::cases::Case::new(Domain::Triangle.spec_at(&[90.0, 0.5, 0.3], 50.0));
    let ok = serde_json::to_value(
        crate::stress::case_report(nr, &case, None, method::Precision::F32).unwrap(),
    )
    .unwrap();
    assert!(ok["spec"]["row"].as_u64().unwrap() > 0, "{ok}");
    let refused = |path: &str, v: serde_json::Value| {
        let mut j = ok.clone();
        *j.pointer_mut(path).unwrap() = v;
        crate::stress::replay::parse(p, j.to_string().as_bytes())
            .unwrap_err()
            .to_string()
    };
    assert!(refused("/spec/row", 100_000.into()).contains("spec.row = 100000"));
    assert!(refused("/spec/shape", "sliver_row".into()).contains("spec.row"));
    assert!(refused("/spec/apex_deg", 1e9.into()).contains("apex_deg"));
}
