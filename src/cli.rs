//! The command line: argument parsing (clap) and one function per command. `main.rs` only calls
//! [`run`] and maps its result to an exit code.
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::error::{Error, Result};
use crate::methods::{self, Method, METHODS};
use crate::render::{Renderer, Shading};
use crate::scene::{self, Interpolation, Scene};
use crate::vk::{Context, ContextDesc};
use crate::{mesh, output, shaders, truth};

/// Exit code: a threshold was exceeded (results were still written).
pub const EXIT_THRESHOLD: u8 = 1;
/// Exit code: usage, input or runtime error.
pub const EXIT_ERROR: u8 = 2;

#[derive(Parser, Debug)]
#[command(
    name = "shadelab",
    version,
    about = "Fast Phong-shading methods against exact Phong, on software Vulkan"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Args, Debug, Clone)]
struct SceneArgs {
    /// Scene file (TOML; see README "Scene format").
    #[arg(
        long,
        value_name = "FILE",
        required_unless_present = "mesh",
        conflicts_with = "mesh"
    )]
    scene: Option<PathBuf>,
    /// OBJ mesh instead of a scene: camera fitted to its bounds, default light and material.
    #[arg(long, value_name = "FILE.obj")]
    mesh: Option<PathBuf>,
    /// Image size, overriding the scene's.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Interpolation of the varyings, overriding the scene's.
    #[arg(long, value_enum)]
    interpolation: Option<InterpArg>,
}

#[derive(Args, Debug, Clone)]
struct DeviceArgs {
    /// Case-insensitive substring of the Vulkan device name (default: lavapipe / llvmpipe).
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
    /// Run under the Khronos validation layer; any message makes the command fail (exit 2).
    #[arg(long)]
    validate: bool,
}

#[derive(ValueEnum, Debug, Clone, Copy)]
enum InterpArg {
    ScreenLinear,
    Perspective,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render one method to an 8-bit PNG (and optionally the float images as .npy).
    Render {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Method identifier (see `shadelab list`).
        #[arg(long, default_value = "phong_exact")]
        method: String,
        /// Output PNG (sRGB, alpha 0 on the background).
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        /// Also write the linear float colour as .npy, shape (H, W, 4), float32.
        #[arg(long, value_name = "FILE.npy")]
        float: Option<PathBuf>,
        /// Also write the shading normal as .npy, shape (H, W, 4), float32 (w 1 where defined).
        #[arg(long, value_name = "FILE.npy")]
        normals: Option<PathBuf>,
    },
    /// Check GPU methods against their own formula evaluated in f64 at the rasterizer's weights.
    Verify {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Comma-separated method identifiers, or `all`.
        #[arg(long, default_value = "all")]
        methods: String,
        /// Judge every method against this method's f64 formula instead of its own (teeth checks).
        #[arg(long, value_name = "METHOD")]
        against: Option<String>,
    },
    /// Compare methods against the f64 exact-Phong truth: statistics, heatmaps, JSON/CSV.
    Compare {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Comma-separated method identifiers, or `all`.
        #[arg(long, default_value = "all")]
        methods: String,
        /// Output directory (summary.json, summary.csv, reference.png, <method>/*.png).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Exit 1 when any method's METRIC (a summary.json name) is above VALUE; repeatable.
        #[arg(long = "fail-above", value_name = "METRIC=VALUE")]
        fail_above: Vec<String>,
        /// Heatmap scales: `fixed` (shared by all methods) or `auto` (per image).
        #[arg(long, value_enum, default_value = "fixed")]
        scale: crate::compare::ScaleMode,
        /// Luminance error above which a pixel counts in pixels_above_threshold.
        #[arg(long, default_value_t = 1.0 / 255.0)]
        threshold: f64,
    },
    /// Run time against error: validated timing, Pareto chart, the papers' claims, sweeps.
    Bench {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Comma-separated method identifiers, or `all`.
        #[arg(long, default_value = "all")]
        methods: String,
        /// Output directory (bench.json, bench.csv, pareto.svg/png, claims.json/md).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Timed submissions per program (interleaved rounds).
        #[arg(long, default_value_t = 40)]
        repeat: usize,
        /// Discarded submissions per program (the first includes lavapipe's shader JIT).
        #[arg(long, default_value_t = 3)]
        warmup: usize,
        /// The compare metric on the Pareto chart's y axis.
        #[arg(long, default_value = "p99_abs_error")]
        error_metric: String,
        /// Also time phong_exact's program under a second name (a precision control).
        #[arg(long)]
        control: bool,
        /// Also sweep image size (128..2048) or triangle count (~100..~1,000,000); repeatable.
        #[arg(long, value_enum)]
        sweep: Vec<crate::bench::Sweep>,
    },
    /// List the methods (`--json` for machines).
    List {
        #[arg(long)]
        json: bool,
    },
    /// Generate a procedural mesh as OBJ, or regenerate the shipped meshes of scenes/.
    Mesh {
        /// Generator: uv_sphere, icosphere, torus or cube.
        #[arg(required_unless_present = "shipped")]
        generator: Option<String>,
        /// Generator parameters as key=value.
        params: Vec<String>,
        /// Output OBJ file.
        #[arg(long, value_name = "FILE.obj", required_unless_present = "shipped")]
        out: Option<PathBuf>,
        /// Write every shipped mesh into DIR instead.
        #[arg(long, value_name = "DIR", conflicts_with_all = ["generator", "out"])]
        shipped: Option<PathBuf>,
    },
    /// Compile glsl/ into spirv/ with shaderc (`--check`: only verify spirv/ is fresh).
    Shaders {
        #[arg(long)]
        check: bool,
        #[arg(long, default_value = "glsl")]
        glsl: PathBuf,
        #[arg(long, default_value = "spirv")]
        spirv: PathBuf,
    },
    /// The main job on the shipped scenes: render every scene of DIR with exact Phong into OUT.
    Demo {
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// List the Vulkan devices the loader reports.
    Devices,
}

fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT such as 512x512, got {s:?}"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("expected WIDTHxHEIGHT such as 512x512, got {s:?}"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// Parses the command line and runs it. Errors are printed once by the caller.
pub fn run() -> Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Compare {
            scene,
            device,
            methods,
            out,
            fail_above,
            scale,
            threshold,
        } => cmd_compare(
            &scene,
            &device,
            &methods,
            &out,
            &fail_above,
            scale,
            threshold,
        ),
        Command::Render {
            scene,
            device,
            method,
            out,
            float,
            normals,
        } => cmd_render(
            &scene,
            &device,
            &method,
            &out,
            float.as_deref(),
            normals.as_deref(),
        ),
        Command::Verify {
            scene,
            device,
            methods,
            against,
        } => cmd_verify(&scene, &device, &methods, against.as_deref()),
        Command::Bench {
            scene,
            device,
            methods,
            out,
            repeat,
            warmup,
            error_metric,
            control,
            sweep,
        } => {
            let opts = crate::bench::BenchOptions {
                repeat,
                warmup,
                error_metric,
                control,
                sweeps: sweep,
            };
            cmd_bench(&scene, &device, &methods, &out, &opts)
        }
        Command::List { json } => cmd_list(json),
        Command::Mesh {
            generator,
            params,
            out,
            shipped,
        } => cmd_mesh(generator, &params, out, shipped),
        Command::Shaders { check, glsl, spirv } => cmd_shaders(check, &glsl, &spirv),
        Command::Demo {
            scenes,
            out,
            device,
        } => cmd_demo(&scenes, &out, &device),
        Command::Devices => {
            for d in Context::list_devices()? {
                println!("{d}");
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn load_scene(args: &SceneArgs) -> Result<Scene> {
    let mut scene = match (&args.scene, &args.mesh) {
        (Some(s), _) => scene::load_scene(s)?,
        (None, Some(m)) => scene::scene_for_mesh(m)?,
        (None, None) => return Err(Error::Usage("give --scene FILE or --mesh FILE".into())),
    };
    if let Some((w, h)) = args.size {
        scene.width = w;
        scene.height = h;
        if args.scene.is_none() && h > 0 {
            // --mesh: the camera was fitted for the default aspect; refit it for this one.
            scene.camera = scene::fit_camera(scene.camera.fov_y_deg, w as f64 / h as f64);
        }
    }
    if let Some(i) = args.interpolation {
        scene.interpolation = match i {
            InterpArg::ScreenLinear => Interpolation::ScreenLinear,
            InterpArg::Perspective => Interpolation::Perspective,
        };
    }
    if let Some(report) = &scene.mesh_report {
        for w in &report.warnings {
            eprintln!("shadelab: warning: {}: {w}", scene.mesh.source);
        }
    }
    Ok(scene)
}

fn renderer(args: &DeviceArgs) -> Result<Renderer> {
    let ctx = Context::new(&ContextDesc {
        device: args.device.clone(),
        validate: args.validate,
    })?;
    Ok(Renderer::new(ctx))
}

/// With `--validate`, any collected message is an error (exit 2), printed in full.
fn check_validation(ctx: &Arc<Context>) -> Result<()> {
    let msgs = ctx.validation_messages();
    if msgs.is_empty() {
        return Ok(());
    }
    for m in &msgs {
        eprintln!("validation: {m}");
    }
    Err(Error::Device(format!(
        "the validation layer reported {} message(s) (printed above)",
        msgs.len()
    )))
}

fn select_methods(list: &str) -> Result<Vec<&'static Method>> {
    if list == "all" {
        return Ok(METHODS.iter().collect());
    }
    list.split(',')
        .filter(|s| !s.is_empty())
        .map(|s| methods::find(s.trim()))
        .collect()
}

fn cmd_render(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    method: &str,
    out: &Path,
    float: Option<&Path>,
    normals: Option<&Path>,
) -> Result<ExitCode> {
    let method = methods::find(method)?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let prepared = r.prepare(&scene, &[method])?;
    let (frame, _) = r.render(prepared.for_method(method), Shading::Method(method), false)?;
    output::write_png_srgb(out, frame.width, frame.height, &frame.color)?;
    if let Some(f) = float {
        output::write_npy_rgba(f, frame.width, frame.height, &frame.color)?;
    }
    if let Some(n) = normals {
        output::write_npy_rgba(n, frame.width, frame.height, &frame.normal)?;
    }
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}

fn cmd_verify(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    against: Option<&str>,
) -> Result<ExitCode> {
    let methods = select_methods(list)?;
    let against = against.map(methods::find).transpose()?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let exact = methods::find("phong_exact")?;
    let mut all = methods.clone();
    all.push(exact);
    let prepared = r.prepare(&scene, &all)?;
    // The reference: f64 exact Phong at the rasterizer's weights on the scene's own triangles.
    let (_, base_ids) = r.render(prepared.base(), Shading::Method(exact), true)?;
    let base_ids = base_ids.ok_or_else(|| Error::Device("the id pass returned nothing".into()))?;
    let reference = truth::evaluate(&prepared.base().inputs, &base_ids, exact);
    println!(
        "scene {} at {}x{}: each method against its own f64 formula (error/bound <= 1 passes), and against f64 exact \
         Phong (ill-conditioned sliver pixels left out; NaN/ill = non-finite pixels, well-/ill-conditioned)",
        scene.name, scene.width, scene.height
    );
    println!(
        "{:<32} {:>7} {:>9} {:>9} {:>6} | {:>9} {:>9} {:>8} {:>8} {:>10} {:>8}",
        "method",
        "pixels",
        "dI/bound",
        "dN/bound",
        "ill",
        "max|dI|",
        "mean|dI|",
        "max deg",
        "mean deg",
        "max|len-1|",
        "NaN/ill"
    );
    let opt = |v: Option<f64>, prec: usize| {
        v.map(|x| format!("{x:.prec$}"))
            .unwrap_or_else(|| "-".into())
    };
    let mut failed = Vec::new();
    for m in methods {
        let gpu = prepared.for_method(m);
        let (frame, ids) = r.render(gpu, Shading::Method(m), true)?;
        let ids = ids.ok_or_else(|| Error::Device("the id pass returned nothing".into()))?;
        let a = truth::agreement(
            &frame,
            &truth::evaluate(&gpu.inputs, &ids, against.unwrap_or(m)),
        );
        let e = truth::error_stats(&frame, m.has_normal, &reference);
        if !a.within_bound() {
            failed.push(format!(
                "{} (ratio {:.3}, worst pixel {:?}, coverage mismatches {}, non-finite {})",
                m.name,
                a.max_color_ratio.max(a.max_normal_ratio),
                a.worst_pixel,
                a.coverage_mismatch,
                a.non_finite
            ));
        }
        println!(
            "{:<32} {:>7} {:>9.3} {:>9.3} {:>6} | {:>9.2e} {:>9.2e} {:>8} {:>8} {:>10} {:>8}",
            m.name,
            a.covered,
            a.max_color_ratio,
            a.max_normal_ratio,
            a.ill_conditioned,
            e.max_abs_error,
            e.mean_abs_error,
            opt(e.max_normal_angle_deg, 3),
            opt(e.mean_normal_angle_deg, 3),
            opt(e.max_normal_length_error, 5),
            format!("{}/{}", e.non_finite, e.non_finite_ill_conditioned),
        );
    }
    check_validation(r.context())?;
    if failed.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        let whose = against
            .map(|a| format!("{}'s", a.name))
            .unwrap_or_else(|| "their own".into());
        eprintln!(
            "outside the float32 bound of {whose} formula: {}",
            failed.join("; ")
        );
        Ok(ExitCode::from(EXIT_THRESHOLD))
    }
}

fn cmd_compare(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    out: &Path,
    fail_above: &[String],
    scale: crate::compare::ScaleMode,
    threshold: f64,
) -> Result<ExitCode> {
    use crate::compare;
    let limits = fail_above
        .iter()
        .map(|s| compare::parse_limit(s))
        .collect::<Result<Vec<_>>>()?;
    if !(threshold.is_finite() && threshold >= 0.0) {
        return Err(Error::Usage(format!(
            "--threshold must be a finite number >= 0, got {threshold}"
        )));
    }
    let methods = select_methods(list)?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let opts = compare::CompareOptions {
        scale,
        threshold,
        progress: true,
        images: true,
    };
    let summary = compare::compare(&r, &scene, &methods, out, &opts)?;
    print!("{}", compare::table(&summary));
    eprintln!(
        "wrote {} ({} methods, {:.1} s; metrics {:.0} Mpixel/s, FLIP {:.1} Mpixel/s)",
        out.join("summary.json").display(),
        summary.methods.len(),
        summary.timing.total_ms / 1e3,
        summary.timing.metric_pixels_per_second / 1e6,
        summary.timing.flip_pixels_per_second / 1e6
    );
    check_validation(r.context())?;
    let over = compare::exceeded(&summary, &limits);
    if over.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    for (m, k, v, limit) in &over {
        eprintln!("threshold exceeded: {m} {k} = {v:.6e} > {limit:e}");
    }
    Ok(ExitCode::from(EXIT_THRESHOLD))
}

fn cmd_bench(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    out: &Path,
    opts: &crate::bench::BenchOptions,
) -> Result<ExitCode> {
    let methods = select_methods(list)?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let report = crate::bench::bench(&r, &scene, &methods, out, opts)?;
    println!(
        "scene {} at {}x{}, {} triangles; clock: {}; LP_NUM_THREADS={}; {} repetitions",
        report.scene,
        report.width,
        report.height,
        report.triangles,
        report.clock.clock,
        report.lp_num_threads.as_deref().unwrap_or("unset"),
        report.repeat
    );
    println!(
        "{:<32} {:>9} {:>19} {:>8} {:>9} {:>8} {:>12}",
        "program", "median ms", "95% CI ms", "ns/px", "x phong", "floor+ms", report.error_metric
    );
    let mut rows: Vec<&crate::bench::MethodTiming> = std::iter::once(&report.floor)
        .chain(&report.methods)
        .collect();
    rows[1..].sort_by(|a, b| a.median_ms.total_cmp(&b.median_ms));
    for m in rows {
        let err = m
            .error
            .as_ref()
            .and_then(|e| e.metric(&report.error_metric));
        println!(
            "{:<32} {:>9.3} {:>19} {:>8.2} {:>9.3} {:>8.3} {:>12}{}",
            m.name,
            m.median_ms,
            format!("[{:.3}, {:.3}]", m.ci95_low_ms, m.ci95_high_ms),
            m.ns_per_pixel,
            m.ratio_to_phong_exact,
            m.above_floor_ms,
            err.map(|e| format!("{e:.3e}"))
                .unwrap_or_else(|| "-".into()),
            if report.pareto_front.contains(&m.name) {
                "  pareto"
            } else {
                ""
            }
        );
    }
    for s in &report.sweeps {
        for (name, per_m, loglog) in &s.slopes {
            println!(
                "sweep {:?}: {name}: {per_m:.4} ms per million {}, log-log slope {loglog:.3}",
                s.sweep, s.work
            );
        }
    }
    eprintln!(
        "wrote {} ({:.1} s)",
        out.join("bench.json").display(),
        report.total_s
    );
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}

fn cmd_list(json: bool) -> Result<ExitCode> {
    if json {
        let text =
            serde_json::to_string_pretty(&serde_json::json!({ "version": 1, "methods": METHODS }))
                .map_err(|e| Error::Usage(e.to_string()))?;
        println!("{text}");
    } else {
        for m in METHODS {
            println!("{:<22} {}", m.name, m.description);
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn cmd_mesh(
    generator: Option<String>,
    params: &[String],
    out: Option<PathBuf>,
    shipped: Option<PathBuf>,
) -> Result<ExitCode> {
    if let Some(dir) = shipped {
        for p in mesh::write_shipped(&dir)? {
            eprintln!("wrote {}", p.display());
        }
        return Ok(ExitCode::SUCCESS);
    }
    let (Some(name), Some(out)) = (generator, out) else {
        return Err(Error::Usage(
            "give a generator and --out FILE.obj, or --shipped DIR".into(),
        ));
    };
    let g = mesh::parse_generator_args(&name, params)?;
    let m = g.build()?;
    mesh::write_obj(&m, &out)?;
    eprintln!("wrote {} ({} triangles)", out.display(), m.triangle_count());
    Ok(ExitCode::SUCCESS)
}

fn cmd_shaders(check: bool, glsl: &Path, spirv: &Path) -> Result<ExitCode> {
    if check {
        shaders::check_fresh(glsl, spirv)?;
        println!("{} is fresh", spirv.display());
    } else {
        let n = shaders::write_spirv(glsl, spirv)?;
        println!("wrote {n} SPIR-V modules to {}", spirv.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn cmd_demo(scenes_dir: &Path, out: &Path, dev: &DeviceArgs) -> Result<ExitCode> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenes_dir)
        .map_err(|e| Error::io(scenes_dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(Error::Usage(format!(
            "no scene files (*.toml) in {}",
            scenes_dir.display()
        )));
    }
    let r = renderer(dev)?;
    let method = methods::find("phong_exact")?;
    for (i, f) in files.iter().enumerate() {
        let start = Instant::now();
        let scene = scene::load_scene(f)?;
        let prepared = r.prepare(&scene, &[method])?;
        let gpu = prepared.base();
        let (frame, _) = r.render(gpu, Shading::Method(method), false)?;
        let stem = f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let png = out.join(format!("{stem}.png"));
        output::write_png_srgb(&png, frame.width, frame.height, &frame.color)?;
        eprintln!(
            "[{}/{}] {} -> {} ({}x{}, {} triangles, {:.0} ms)",
            i + 1,
            files.len(),
            f.display(),
            png.display(),
            frame.width,
            frame.height,
            gpu.inputs.triangle_count(),
            start.elapsed().as_secs_f64() * 1e3
        );
    }
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}
