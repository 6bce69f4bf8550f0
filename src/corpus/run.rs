//! One shard of a corpus: each of its meshes compared (as `compare --mesh`: camera fitted to the
//! mesh, default light and material) into DIR/meshes/<id>/result.json (the figures only, no
//! timing and no machine: byte-identical wherever the same build runs on the same driver), its
//! times into timing.json, `--bench`'s replicated timing under bench/; the static GPU cost
//! (`isa`) once, by shard 1; DIR/manifest.json last. A mesh whose result.json matches its
//! content and the configuration is skipped, so a killed shard started again goes on where it
//! stopped; a mesh that fails is recorded with its error and the shard goes on.
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::{content_hash, Config, Mesh, Shard, SCHEMA_VERSION};
use crate::compare::{self, CompareOptions};
use crate::error::{Error, Result};
use crate::gpu::Renderer;
use crate::method::Method;
use crate::output::{self, Provenance};

/// What one shard runs.
pub struct ShardOptions<'a> {
    /// Every mesh of the corpus (the shard takes its own).
    pub meshes: &'a [Mesh],
    /// The corpus as given (folder or list file), recorded in the manifest.
    pub source: String,
    pub out: PathBuf,
    pub shard: Shard,
    pub methods: Vec<&'static Method>,
    pub config: Config,
    /// Run the static GPU cost (shard 1 only), when the RADV ICD is present.
    pub isa: bool,
    /// The shadelab binary that `--bench` and `isa` start (`std::env::current_exe()`).
    pub exe: PathBuf,
}

/// One mesh of the corpus in a manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorpusEntry {
    pub id: String,
    pub path: String,
    pub content_hash: String,
    pub shard: usize,
}

/// One mesh this shard ran.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshStatus {
    pub id: String,
    pub status: String,
    pub error: Option<String>,
    /// Whether a result of an earlier run was kept.
    pub reused: bool,
}

/// The machine a shard ran on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    pub device: String,
    pub driver_info: String,
    pub mesa_version: Option<String>,
    pub llvm_version: Option<String>,
    pub cpu: String,
}

impl Machine {
    /// A short key naming the machine (device, driver and CPU).
    pub fn key(&self) -> String {
        format!("{} | {} | {}", self.device, self.driver_info, self.cpu)
    }
}

/// DIR/manifest.json (docs/corpus-manifest.schema.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub schema_version: u32,
    pub tool: String,
    pub version: String,
    pub git_revision: String,
    pub source: String,
    pub shard: Shard,
    pub config: Config,
    pub config_hash: String,
    pub machine: Machine,
    /// Every mesh of the corpus, with the shard it belongs to.
    pub corpus: Vec<CorpusEntry>,
    /// This shard's meshes, in corpus order.
    pub meshes: Vec<MeshStatus>,
    pub failed: usize,
    /// The static GPU cost: `isa/isa.json` of this folder, or why there is none here.
    pub isa: String,
    pub elapsed_s: f64,
}

/// meshes/<id>/result.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshResult {
    pub schema_version: u32,
    pub id: String,
    pub path: String,
    pub content_hash: String,
    pub config_hash: String,
    /// `ok` or `failed`.
    pub status: String,
    pub error: Option<String>,
    /// compare's summary.json without `timing` and `provenance` (in timing.json and the
    /// manifest), `scene_source` the mesh's relative path; null when the mesh failed.
    pub summary: Option<Value>,
}

/// The figures of one mesh.
fn mesh_summary(r: &Renderer, m: &Mesh, opts: &ShardOptions, dir: &Path) -> Result<(Value, Value)> {
    let mut scene = crate::scene::scene_for_mesh(&m.path)?;
    let c = &opts.config;
    scene.width = c.width;
    scene.height = c.height;
    scene.camera =
        crate::scene::fit_camera(scene.camera.fov_y_deg, c.width as f64 / c.height as f64);
    let copts = CompareOptions {
        threshold: c.threshold,
        images: c.images,
        ..CompareOptions::default()
    };
    let s = compare::compare(r, &scene, &opts.methods, dir, &copts)?;
    let mut v = serde_json::to_value(&s).map_err(|e| Error::output("result.json", e))?;
    let timing = v
        .as_object_mut()
        .and_then(|o| {
            o.remove("provenance");
            o.insert("scene_source".into(), Value::String(m.rel.clone()));
            o.remove("timing")
        })
        .unwrap_or(Value::Null);
    Ok((v, timing))
}

fn write_json<T: Serialize>(path: &Path, v: &T) -> Result<()> {
    let mut bytes =
        serde_json::to_vec_pretty(v).map_err(|e| Error::output(path.display().to_string(), e))?;
    bytes.push(b'\n');
    output::write_bytes_atomic(path, &bytes)
}

/// A finished result of an earlier run for this content and configuration.
fn finished(dir: &Path, hash: &str, config_hash: &str, bench: bool) -> bool {
    let Ok(bytes) = std::fs::read(dir.join("result.json")) else {
        return false;
    };
    let Ok(r) = serde_json::from_slice::<MeshResult>(&bytes) else {
        return false;
    };
    r.status == "ok"
        && r.content_hash == hash
        && r.config_hash == config_hash
        && (!bench || dir.join("bench/bench.json").is_file())
}

/// bench on one mesh (its runs fresh processes of [`ShardOptions::exe`], bench.json in
/// `dir`/bench/), its paired ratio to phong_exact per method.
fn bench_mesh(
    r: &Renderer,
    m: &Mesh,
    opts: &ShardOptions,
    runs: usize,
    dir: &Path,
) -> Result<Value> {
    let c = &opts.config;
    let load = crate::scene::SceneSource {
        mesh: Some(m.path.clone()),
        size: Some((c.width, c.height)),
        ..Default::default()
    };
    let schedule = crate::bench::schedule::Schedule::new(
        crate::bench::schedule::Job::Bench { software: false },
        &crate::bench::schedule::Given {
            runs: Some(runs),
            ..Default::default()
        },
    )?;
    let bopts = crate::bench::BenchOptions {
        runs: if schedule.many() {
            crate::bench::Runs::Many(crate::bench::runs::Launcher {
                exe: opts.exe.clone(),
                scene: load.clone(),
                device: crate::gpu::DeviceSpec {
                    precision: r.precision(),
                    ..Default::default()
                },
                driver_env: Vec::new(),
            })
        } else {
            crate::bench::Runs::One
        },
        schedule,
        command_line: std::env::args().collect(),
        ..crate::bench::BenchOptions::default()
    };
    let out = dir.join("bench");
    std::fs::create_dir_all(&out).map_err(|e| Error::io(&out, e))?;
    let bench = crate::bench::bench(r, &load.load()?, &opts.methods, &out, &bopts)?;
    let ratios = bench
        .methods
        .iter()
        .map(|row| (row.name.clone(), serde_json::json!(row.ratio_median)))
        .collect();
    Ok(Value::Object(ratios))
}

/// Runs one mesh: result.json (written last: its presence means done) and timing.json.
fn run_mesh(r: &Renderer, m: &Mesh, opts: &ShardOptions, hash: &str) -> Result<()> {
    let dir = opts.out.join("meshes").join(&m.id);
    let config_hash = opts.config.hash();
    let t = Instant::now();
    let figures = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        mesh_summary(r, m, opts, &dir)
    }))
    .unwrap_or_else(|_| Err(Error::Internal("compare panicked on this mesh".into())));
    let (summary, error, compare_timing) = match figures {
        Ok((s, t)) => (Some(s), None, t),
        // The mesh's relative path, not where this machine keeps the corpus: the same error
        // text wherever the shard runs.
        Err(e) => {
            let text = e.to_string().replace(&m.path.display().to_string(), &m.rel);
            (None, Some(text), Value::Null)
        }
    };
    let mut error = error;
    let mut bench = Value::Null;
    if let (None, Some(runs)) = (&error, opts.config.bench_runs) {
        match bench_mesh(r, m, opts, runs, &dir) {
            Ok(b) => bench = b,
            Err(e) => error = Some(format!("bench: {e}")),
        }
    }
    let timing = serde_json::json!({
        "id": m.id,
        "elapsed_s": t.elapsed().as_secs_f64(),
        "compare": compare_timing,
        "bench_ratio_median": bench,
    });
    write_json(&dir.join("timing.json"), &timing)?;
    let result = MeshResult {
        schema_version: SCHEMA_VERSION,
        id: m.id.clone(),
        path: m.rel.clone(),
        content_hash: hash.into(),
        config_hash,
        status: if error.is_none() { "ok" } else { "failed" }.into(),
        summary: if error.is_none() { summary } else { None },
        error,
    };
    write_json(&dir.join("result.json"), &result)
}

/// The static GPU cost into DIR/isa (shard 1; skipped when present, or without RADV).
fn static_cost(opts: &ShardOptions) -> String {
    if opts.shard.k != 1 {
        return format!("run by shard 1 of {}", opts.shard.n);
    }
    if !opts.isa {
        return "not run (--no-isa)".into();
    }
    let out = opts.out.join("isa");
    if out.join("isa.json").is_file() {
        return "isa/isa.json".into();
    }
    let iopts = crate::isa::IsaOptions::every_family(
        &opts.methods,
        opts.config.precision,
        opts.exe.clone(),
    );
    log::info!("corpus: static GPU cost (isa) ...");
    match crate::isa::run(&iopts, &|line| log::info!("isa: {line}"))
        .and_then(|rep| crate::isa::files::write(&out, &rep))
    {
        Ok(()) => "isa/isa.json".into(),
        Err(e) => format!("failed: {e}"),
    }
}

/// Runs this shard's meshes and writes its manifest; progress on stderr.
pub fn run_shard(r: &Renderer, opts: &ShardOptions) -> Result<Manifest> {
    let start = Instant::now();
    let mut corpus = Vec::new();
    let mut hashes = Vec::new();
    for m in opts.meshes {
        // An unreadable file is the mesh's failure, not the corpus's.
        let hash = content_hash(&m.path).unwrap_or_else(|e| format!("unreadable: {e}"));
        corpus.push(CorpusEntry {
            id: m.id.clone(),
            path: m.rel.clone(),
            content_hash: hash.clone(),
            shard: super::shard_of(&m.id, opts.shard.n),
        });
        hashes.push(hash);
    }
    let mine: Vec<usize> = (0..opts.meshes.len())
        .filter(|&i| opts.shard.holds(&opts.meshes[i].id))
        .collect();
    let config_hash = opts.config.hash();
    let mut meshes = Vec::new();
    for (n, &i) in mine.iter().enumerate() {
        let m = &opts.meshes[i];
        let dir = opts.out.join("meshes").join(&m.id);
        let reused = finished(
            &dir,
            &hashes[i],
            &config_hash,
            opts.config.bench_runs.is_some(),
        );
        let t = Instant::now();
        if !reused {
            run_mesh(r, m, opts, &hashes[i])?;
        }
        let res: MeshResult = serde_json::from_slice(
            &std::fs::read(dir.join("result.json")).map_err(|e| Error::io(&dir, e))?,
        )
        .map_err(|e| Error::output("result.json", e))?;
        log::info!(
            "corpus: [{}/{}] {} {}{}",
            n + 1,
            mine.len(),
            m.rel,
            if reused {
                "kept (finished earlier)".to_string()
            } else {
                format!("{} in {:.1} s", res.status, t.elapsed().as_secs_f64())
            },
            res.error
                .as_ref()
                .map(|e| format!(": {e}"))
                .unwrap_or_default()
        );
        meshes.push(MeshStatus {
            id: m.id.clone(),
            status: res.status,
            error: res.error,
            reused,
        });
    }
    let isa = static_cost(opts);
    let p: Provenance = r.provenance();
    let manifest = Manifest {
        schema_version: SCHEMA_VERSION,
        tool: p.tool,
        version: p.version,
        git_revision: p.git_revision,
        source: opts.source.clone(),
        shard: opts.shard.clone(),
        config: opts.config.clone(),
        config_hash,
        machine: Machine {
            device: p.device,
            driver_info: p.driver_info,
            mesa_version: p.mesa_version,
            llvm_version: p.llvm_version,
            cpu: crate::output::provenance::cpu_model(),
        },
        corpus,
        failed: meshes.iter().filter(|m| m.status != "ok").count(),
        meshes,
        isa,
        elapsed_s: start.elapsed().as_secs_f64(),
    };
    write_json(&opts.out.join("manifest.json"), &manifest)?;
    Ok(manifest)
}
