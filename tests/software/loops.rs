//! The span and pixel loops of the software engine allocate nothing (a counting allocator).
use shadelab::method::Geometry;
use shadelab::scene::SceneInputs;
use shadelab::software;

use crate::support::*;

/// The allocation counter of the test crate's global allocator (tests/fuzz/engine.rs): per
/// thread, so other tests running at the same time do not enter the count (the software engine
/// on 1 thread draws on the calling thread).
mod allocations {
    pub fn count() -> u64 {
        crate::fuzz::engine::allocations_on_this_thread()
    }
}

/// A shader that counts the allocations made inside the wrapped shader's rows.
struct CountRows<S> {
    inner: S,
    allocs: std::sync::atomic::AtomicU64,
    rows: std::sync::atomic::AtomicU64,
    /// Teeth: allocate in every row.
    leak: bool,
}

impl<S: software::raster::Shader> software::raster::Shader for CountRows<S> {
    type Setup = S::Setup;
    fn setup(&self, tri: &software::raster::Tri) -> S::Setup {
        self.inner.setup(tri)
    }
    fn row(
        &self,
        tri: &software::raster::Tri,
        setup: &S::Setup,
        span: software::raster::RowSpan,
        out: &mut software::raster::RowOut,
        scratch: &mut Vec<glam::Vec3>,
    ) {
        use std::sync::atomic::Ordering::Relaxed;
        let before = allocations::count();
        if self.leak {
            std::hint::black_box(vec![0u8; 16]);
        }
        self.inner.row(tri, setup, span, out, scratch);
        self.allocs
            .fetch_add(allocations::count() - before, Relaxed);
        self.rows.fetch_add(1, Relaxed);
    }
}

#[test]
fn the_span_and_pixel_loops_allocate_nothing() {
    use shadelab::method::formulas as f;
    use shadelab::method::real::V3;
    use software::spans::{n4, stepped, Along, SpanShader};
    let scene = shipped_scene("sphere_fine", 256);
    let inputs = SceneInputs::new(&scene, Geometry::Mesh);
    let tris = software::raster::setup(&inputs).unwrap();
    let lit = software::lighting::<f32>(&inputs.params, inputs.light_count);
    fn counted<S: software::raster::Shader>(
        tris: &[software::raster::Tri],
        s: S,
        leak: bool,
    ) -> (u64, u64) {
        let c = CountRows {
            inner: s,
            allocs: 0.into(),
            rows: 0.into(),
            leak,
        };
        // 1 thread: the rows run on this thread, where the counter counts
        software::raster::draw(256, 256, tris, &c, 1, true);
        (c.allocs.into_inner(), c.rows.into_inner())
    }
    let alongs = [
        Along::Slerp,
        Along::Chebyshev,
        Along::Quadratic { approx_mid: false },
        Along::Dichotomy(shadelab::method::scanline::inv_root_exact),
        Along::Segments(3, None),
        Along::Segments(3, Some(shadelab::method::scanline::inv_root_poly1)),
        Along::BishopWeimer,
        Along::HastEuler,
    ];
    for along in alongs {
        let (allocs, rows) = counted(&tris, SpanShader { along, lit }, false);
        assert!(rows > 1000, "{along:?}: {rows} rows");
        assert_eq!(allocs, 0, "{along:?}: {allocs} allocations in {rows} rows");
    }
    let per_pixel = stepped(
        |t: &software::raster::Tri| (t.n, ()),
        move |v: glam::Vec3, _: &()| {
            let m = f::normalize_exact(V3::<f32>::of(v));
            (lit.shade(m).f32(), n4(m))
        },
    );
    let (allocs, rows) = counted(&tris, per_pixel, false);
    assert_eq!(
        allocs, 0,
        "per-pixel form: {allocs} allocations in {rows} rows"
    );
    // teeth: a row that allocates is counted, once per row
    let (allocs, rows) = counted(
        &tris,
        SpanShader {
            along: Along::Chebyshev,
            lit,
        },
        true,
    );
    assert_eq!(allocs, rows);
}
