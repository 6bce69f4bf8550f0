//! Frame times of the software engine against lavapipe for the same draw, in the same run
//! (run by scripts/software_bench.sh; a benchmark, never a test). Usage:
//! `software_bench SCENE.toml SIZE REPEAT [METHOD,...|all]`.
//!
//! Clocks: the Vulkan figure is submit-to-fence wall time of one recorded draw (timed_draws);
//! the software figure is the wall time of `software::render` (set-up, binning, rasterization
//! and shading; the images allocated and cleared inside it). Draws alternate (Vulkan, software)
//! so that a busy machine slows both alike; medians and quartiles are printed.
use std::time::Instant;

use shadelab::gpu::vk::{Context, ContextDesc};
use shadelab::gpu::{Renderer, Shading};
use shadelab::method::{self, METHODS};
use shadelab::scene::{self, SceneInputs};
use shadelab::software;

fn quartiles(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
    (q(0.25), q(0.5), q(0.75))
}

fn main() -> shadelab::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .map_or("scenes/sphere_fine.toml", String::as_str);
    let size: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1024);
    let repeat: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(15);
    let list = args.get(4).map_or("all", String::as_str);
    let mut scene = scene::load_scene(std::path::Path::new(path))?;
    scene.width = size;
    scene.height = size;
    let threads = software::default_threads();
    let exact = method::find("phong_exact")?;

    let r = Renderer::new(Context::new(&ContextDesc {
        device: None,
        validate: false,
    })?);
    let prepared = r.prepare(&scene, &[exact])?;
    let draws = r.timed_draws(&[(prepared.base(), Shading::Method(exact))])?;
    let inputs = &prepared.base().inputs;
    // Warm-up: lavapipe JIT-compiles at the first draw.
    draws.run(0)?;
    software::render(inputs, exact, threads, false)?;
    let (mut vk, mut sw) = (Vec::new(), Vec::new());
    for _ in 0..repeat {
        vk.push(draws.run(0)?.wall_ms);
        let t = Instant::now();
        software::render(inputs, exact, threads, false)?;
        sw.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let (v, s) = (quartiles(vk), quartiles(sw));
    println!(
        "{} at {size}x{size}, {} triangles, {repeat} alternating draws, software on {threads} threads",
        scene.name,
        inputs.triangle_count()
    );
    println!(
        "phong_exact lavapipe  median {:7.2} ms (IQR {:.2}-{:.2})",
        v.1, v.0, v.2
    );
    println!(
        "phong_exact software  median {:7.2} ms (IQR {:.2}-{:.2})",
        s.1, s.0, s.2
    );
    println!(
        "software / lavapipe frame-time ratio: {:.2} (target <= 2)",
        s.1 / v.1
    );

    println!("\nsoftware frame time per method (median of {repeat}, ms; ratio to phong_exact):");
    let methods: Vec<_> = if list == "all" {
        METHODS.iter().collect()
    } else {
        list.split(',')
            .map(method::find)
            .collect::<shadelab::Result<_>>()?
    };
    for m in methods {
        let inputs = SceneInputs::new(&scene, m.geometry);
        software::render(&inputs, m, threads, false)?;
        let mut t = Vec::new();
        for _ in 0..repeat {
            let t0 = Instant::now();
            software::render(&inputs, m, threads, false)?;
            t.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        let q = quartiles(t);
        let form = software::form(m.name);
        println!(
            "{:<32} {:8.2} (IQR {:.2}-{:.2})  x{:.2}  {}",
            m.name,
            q.1,
            q.0,
            q.2,
            q.1 / s.1,
            if form.scanline {
                "scanline form"
            } else {
                "per-pixel form"
            }
        );
    }
    Ok(())
}
