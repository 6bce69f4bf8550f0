//! The real-world meshes of ../shared/models (quads, missing normals, creases, slivers, 70k
//! triangles): every method loads, renders without NaN/Inf under validation, and agrees with its
//! own f64 formula within the float32 bound (the README's claim, checked here for every method).
use shadelab::method::METHODS;
use shadelab::{scene, truth};

use crate::support::*;

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
