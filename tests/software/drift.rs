//! The recurrences' float32 drift along long spans (one triangle 1024 pixels wide), each method
//! against a bound derived from its recurrence, and the product's `drift_allowance` against it.
use glam::{DVec2, DVec3};
use shadelab::method::{find, Geometry};
use shadelab::scene::{Interpolation, Params, SceneInputs, MAX_LIGHTS};
use shadelab::software::{drift_allowance, render};
use shadelab::truth::evaluate;

/// One triangle across a `w`-pixel-wide image whose rows are spans of up to ~w pixels, with
/// vertex normals `deg` degrees apart; identity MVP (positions are NDC).
fn long_spans(w: u32, deg: f64) -> SceneInputs {
    let h = 8u32;
    let ndc = |x: f64, y: f64| {
        [
            (2.0 * x / w as f64 - 1.0) as f32,
            (2.0 * y / h as f64 - 1.0) as f32,
            0.5,
        ]
    };
    let positions = vec![
        ndc(0.2, 0.1),
        ndc(w as f64 - 0.3, 0.2),
        ndc(0.4, h as f64 - 0.1),
    ];
    let r = deg.to_radians() / 2.0;
    let n = |a: f64, b: f64| {
        let v = DVec3::new(a.sin(), b.sin(), a.cos() * b.cos()).normalize();
        [v.x as f32, v.y as f32, v.z as f32]
    };
    let mut identity = [[0.0f32; 4]; 4];
    (0..4).for_each(|i| identity[i][i] = 1.0);
    let l = DVec3::new(0.3, 0.2, 1.0).normalize();
    let hv = (l + DVec3::Z).normalize();
    let f4 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let mut params = Params {
        mvp: identity,
        ambient: [0.05, 0.05, 0.05, 0.0],
        diffuse: [0.7, 0.7, 0.7, 0.0],
        specular: [0.3, 0.3, 0.3, 20.0],
        light_dir: [[0.0; 4]; MAX_LIGHTS],
        light_color: [[0.0; 4]; MAX_LIGHTS],
        half_vec: [[0.0; 4]; MAX_LIGHTS],
        const_color: [0.8, 0.8, 0.8, 1.0],
    };
    params.light_dir[0] = f4(l);
    params.half_vec[0] = f4(hv);
    params.light_color[0] = [1.0, 1.0, 1.0, 0.0];
    let mut inputs = SceneInputs {
        width: w,
        height: h,
        interpolation: Interpolation::ScreenLinear,
        geometry: Geometry::Mesh,
        positions,
        view_normals: vec![n(-r, 0.0), n(r, 0.0), n(-r, 0.3)],
        flat_normals: vec![[0.0, 0.0, 1.0]],
        pn_mids: vec![[[0.0, 0.0, 1.0]; 3]],
        window: Vec::new(),
        params,
        light_count: 1,
        cull_front: None,
    };
    inputs.window = inputs
        .clip_corners()
        .map(|c| {
            let p: DVec2 = inputs.to_window(c);
            [p.x as f32, p.y as f32]
        })
        .collect();
    inputs
}

/// Largest |software - f64 twin| (normal components, or colour channels for methods without a
/// normal) per bucket of the step index n along the span.
fn drift(method: &str, w: u32, deg: f64) -> Vec<(u32, f64)> {
    let inputs = long_spans(w, deg);
    let m = find(method).unwrap();
    let (frame, ids) = render(&inputs, m, 2, true).unwrap();
    let ids = ids.unwrap();
    let truth = evaluate(&inputs, &ids, m);
    let edges = [16u32, 64, 256, 1024, 4096];
    let mut worst = vec![0.0f64; edges.len()];
    for (i, t) in truth.pixels.iter().enumerate() {
        let Some(t) = t else { continue };
        let x = i as u32 % w;
        let y = i as u32 / w;
        // the row's first covered pixel
        let row = &ids.prim[(y * w) as usize..((y + 1) * w) as usize];
        let first = row.iter().position(|&p| p > 0).unwrap() as u32;
        let n = x - first;
        let b = edges.iter().position(|&e| n < e).unwrap();
        let (sw, tw) = match t.normal {
            Some(v) => (frame.normal[i], v),
            None => (frame.color[i], t.color),
        };
        let e = (0..3)
            .map(|c| (sw[c] as f64 - tw[c]).abs())
            .fold(0.0, f64::max);
        assert!(e.is_finite(), "{method}: non-finite at {x},{y}");
        worst[b] = worst[b].max(e);
    }
    edges
        .iter()
        .copied()
        .zip(worst)
        .filter(|&(e, _)| e <= w.next_power_of_two().max(16))
        .collect()
}

/// The bound on |software - f64 twin| `n` steps into a span, derived from each method's
/// recurrence (u = 2^-24, K = 32 roundings for a formula evaluated in full, as the truth's
/// K_FORMULA), in the units the drift test compares: normal components for methods with a
/// normal, colour channels for the two that shade cosines.
fn derived_bound(method: &str, n: f64) -> f64 {
    let (u, k) = (1.0 / 16_777_216.0, 32.0);
    // colour per cosine of the drift scene's lighting: diffuse 0.7 + 20 x specular 0.3
    let slope = 6.7;
    match method {
        // Chebyshev N(k+1) = 2 cos(phi) N(k) - N(k-1): an error made j steps back is amplified
        // by at most j + 1 (|U_j| <= j + 1); 3 roundings a step sum to 1.5 u n^2; the two
        // closed-form seeds (K u each) carried n steps add 2 K u n.
        "spherical_angular" => 1.5 * u * n * n + 2.0 * k * u * n,
        // Second-order forward differences on unit-size values whose first difference is at most
        // 2/W a step (the span's whole change over W >= n pixels): the value's rounding each
        // step (n u), the first difference's roundings summed twice (n^2/2 u 2/W <= n u), the
        // seeds (K u each; the first difference's carried n steps, n K u 2/W <= 2 K u): at
        // most u (3 K + 2 n).
        "quadratic_scanline" => u * (3.0 * k + 2.0 * n),
        // The same on the cosines, times the lighting's slope, plus 1e-5 for the shading's own
        // float32 rounding (pow of a cosine near 1).
        "hast_euler" | "bishop_weimer" => slope * u * (3.0 * k + 2.0 * n) + 1e-5,
        // Per-pixel methods: a first-order difference (n roundings of a unit vector, 2 per
        // step) and the formula once (K u).
        "phong_exact" => u * (4.0 * n + k),
        other => panic!("no derived bound for {other}"),
    }
}

#[test]
fn recurrence_drift_against_span_length_stays_within_its_derived_bound() {
    // A measurement: printed with --nocapture, and in README "Software engine".
    for method in [
        "spherical_angular",
        "quadratic_scanline",
        "hast_euler",
        "bishop_weimer",
        "phong_exact",
    ] {
        for deg in [30.0, 90.0] {
            let d = drift(method, 1024, deg);
            let line: Vec<String> = d.iter().map(|(e, v)| format!("n<{e}: {v:.1e}")).collect();
            println!(
                "{method:<20} {deg:>3} deg, 1024 px spans: {}",
                line.join("  ")
            );
            for (e, v) in d {
                let bound = derived_bound(method, e as f64);
                // not vacuous: a tenth of the range of a normal component or a colour
                assert!(bound < 0.1, "{method} n<{e}: bound {bound}");
                assert!(v <= bound, "{method} {deg} deg n<{e}: {v:e} > {bound:e}");
            }
        }
    }
}

#[test]
fn the_products_drift_allowance_covers_the_derived_bounds() {
    // verify widens each pixel's bound by software::drift_allowance (normal units, times the
    // lighting's slope for colours): it must hold every derived bound, or verify could fail a
    // correct recurrence.
    for e in [16.0, 64.0, 256.0, 1024.0, 4096.0] {
        for (m, slope) in [
            ("spherical_angular", 1.0),
            ("quadratic_scanline", 1.0),
            ("hast_euler", 6.7),
            ("phong_exact", 1.0),
        ] {
            let derived = derived_bound(m, e) - if slope > 1.0 { 1e-5 } else { 0.0 };
            assert!(
                drift_allowance(e) * slope >= derived,
                "{m} n<{e}: allowance {} < derived {derived}",
                drift_allowance(e) * slope
            );
        }
    }
}

#[test]
fn drift_allowance_is_not_vacuous() {
    // Teeth: a drift as large as the 4096-step one docs/formulas.md#spherical-angular-interpolation
    // reports for the float32 recurrence (-30 %) exceeds the allowance at 256 steps; the
    // first-order stepping of the per-pixel methods drifts linearly (n steps of a few roundings),
    // far below it.
    assert!(0.3 > drift_allowance(256.0));
    let d = drift("phong_exact", 1024, 90.0);
    let u = 1.0 / 16_777_216.0;
    assert!(d.iter().all(|&(e, v)| v < 4.0 * u * e as f64), "{d:?}");
    // and the derived bound of a forward-difference recurrence fails a drift that grows with
    // n^2 at one rounding a step (what a first difference rounded against the value, not
    // carried, would give)
    assert!(u * 1024.0 * 1024.0 > derived_bound("quadratic_scanline", 1024.0));
}
