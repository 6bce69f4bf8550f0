//! The real-world meshes of ../shared/models (quads, missing normals, creases, slivers, 70k
//! triangles) all load, render without NaN/Inf under validation, and agree with the f64 truth.
use shadelab::gpu::Shading;
use shadelab::method::METHODS;
use shadelab::{method, scene, truth};

use crate::support::*;

#[test]
fn every_shared_model_renders_and_matches_f64() {
    let Some(files) = model_files() else { return };
    assert!(
        files.len() >= 5,
        "expected the 5 models of the README, found {files:?}"
    );
    let r = validated_renderer();
    let m = method::find("phong_exact").unwrap();
    for f in files {
        let mut s = scene::scene_for_mesh(&f).unwrap_or_else(|e| panic!("{e}"));
        s.width = 96;
        s.height = 96;
        let prepared = r.prepare(&s, &METHODS.iter().collect::<Vec<_>>()).unwrap();
        let gpu = prepared.base();
        let (frame, ids) = r.render(gpu, Shading::Method(m), true).unwrap();
        let a = truth::agreement(&frame, &truth::evaluate(&gpu.inputs, &ids.unwrap(), m));
        eprintln!(
            "{}: {} triangles, {a:?}",
            f.display(),
            gpu.inputs.triangle_count()
        );
        assert!(
            a.covered > 500,
            "{}: only {} pixels covered",
            f.display(),
            a.covered
        );
        assert_eq!(a.non_finite, 0, "{}: NaN/Inf in the output", f.display());
        assert!(a.within_bound(), "{}: {a:?}", f.display());
    }
    assert_validation_clean(r.context());
}
