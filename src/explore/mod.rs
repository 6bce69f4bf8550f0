//! `shadelab explore`: a page on this machine where a method is picked or edited and its error
//! map and its cost on every GPU family appear while one types (docs/explore.md). The server
//! ([`api`], axum on tokio) answers JSON; the page ([`api::PAGE`], plain HTML/CSS/JS embedded
//! in the binary) uses nothing else. Its figures are the commands': a render is
//! [`crate::compare::compare`] of the one method in a worker process ([`render`]), a cost is
//! [`crate::isa::run_with`] of the method and phong_exact on one family ([`cost`]) through the
//! compile store and the compiler workers. An edited method is registered as a method file
//! ([`edits`]). Only the user gets answers ([`guard`]): the token, the Host and the Origin.
//!
//! The server runs until SIGINT or SIGTERM; [`crate::cleanup`]'s handler then kills the
//! workers and removes the temporary folder (its edits), as for any run.
pub mod api;
pub mod cost;
pub mod edits;
pub mod guard;
pub mod render;

use std::collections::{HashMap, VecDeque};
use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use crate::error::{Error, Result};
use crate::isa::IsaReport;
use crate::method::Precision;

/// An uploaded mesh's largest size, bytes.
pub const UPLOAD_BYTES: usize = 32 << 20;
/// Uploaded meshes kept; the least recently used goes first.
pub const MAX_UPLOADS: usize = 8;
/// Image sizes accepted (pixels a side).
pub const SIZES: std::ops::RangeInclusive<u32> = 64..=1024;
/// isa reports kept for the disassembly of a family the page asks for.
const MAX_REPORTS: usize = 512;

/// What `shadelab explore` serves.
#[derive(Debug, Clone)]
pub struct ExploreOptions {
    pub scenes: PathBuf,
    pub models: Option<PathBuf>,
    pub bind: IpAddr,
    /// 0: a free port.
    pub port: u16,
    /// The longest a render or one family's compile may take (its worker is stopped past it).
    pub deadline: Duration,
    /// The shadelab binary its workers run.
    pub exe: PathBuf,
    /// A folder the page's files are read from instead of the binary's copies.
    pub assets: Option<PathBuf>,
    /// A report's folder, whose stress/stress.json gives each method's valid angle.
    pub report: Option<PathBuf>,
}

/// A scene the page offers.
#[derive(Debug, Clone)]
pub struct SceneEntry {
    /// `torus` (a scene file's stem) or `teapot.obj` (a model's file name).
    pub id: String,
    pub model: bool,
    pub path: PathBuf,
}

/// A mesh sent to the server, kept in memory.
#[derive(Debug, Clone)]
pub struct Upload {
    pub id: String,
    pub name: String,
    pub bytes: Arc<crate::child::Bytes>,
}

/// The (family, method, precision) of a kept isa report.
pub type ReportKey = (String, String, Precision);

/// A running server's state.
pub struct Server {
    pub guard: guard::Guard,
    pub addr: SocketAddr,
    pub exe: PathBuf,
    pub assets: Option<PathBuf>,
    /// stress's largest valid angle per method, from `--report`'s stress.json.
    pub stress_angles: HashMap<String, f64>,
    pub scenes: Vec<SceneEntry>,
    /// Every default family id, and whether its route is set up (why not).
    pub families: Vec<(String, std::result::Result<(), String>)>,
    pub edits: edits::Edits,
    /// The render workers (their own pool: a render never waits behind compiles).
    pub renders: crate::workers::Pool,
    uploads: Mutex<(u64, VecDeque<Upload>)>,
    /// The newest `seq` seen per (tab, endpoint).
    seqs: Mutex<HashMap<(String, &'static str), u64>>,
    /// isa's reports of (family, method, precision), the newest last.
    reports: Mutex<VecDeque<(ReportKey, Arc<IsaReport>)>>,
    /// Request and reply files of the workers, and the edits.
    pub temp: crate::cleanup::TempDir,
}

impl Server {
    /// The state of a server listening on `addr`.
    pub fn new(opts: &ExploreOptions, addr: SocketAddr) -> Result<Server> {
        let temp = crate::cleanup::TempDir::new("explore")
            .map_err(|e| Error::io(std::env::temp_dir(), e))?;
        let edits = edits::Edits::new(&temp.path().join("edits"))?;
        let families = crate::isa::families(&crate::isa::route::default_family_ids())?
            .into_iter()
            .map(|f| (f.id(), f.vendor.setup_for(f.chip, None).map(|_| ())))
            .collect();
        Ok(Server {
            guard: guard::Guard::new(addr).map_err(|e| Error::io("/dev/urandom", e))?,
            addr,
            exe: opts.exe.clone(),
            assets: opts.assets.clone(),
            stress_angles: match &opts.report {
                Some(r) => stress_angles(&r.join("stress").join("stress.json"))?,
                None => HashMap::new(),
            },
            scenes: scenes(&opts.scenes, opts.models.as_deref())?,
            families,
            edits,
            renders: crate::workers::Pool::new(crate::workers::Limits {
                deadline: opts.deadline,
                parallel: 1,
                ..crate::workers::Limits::default()
            }),
            uploads: Mutex::new((0, VecDeque::new())),
            seqs: Mutex::new(HashMap::new()),
            reports: Mutex::new(VecDeque::new()),
            temp,
        })
    }

    /// Whether a request of `tab` numbered `seq` to `endpoint` is the newest: it records the
    /// number, and a later call with an older one is answered false (superseded).
    pub fn newest(&self, tab: &str, endpoint: &'static str, seq: u64) -> bool {
        let Ok(mut seqs) = self.seqs.lock() else {
            return true;
        };
        let newest = seqs.entry((tab.to_string(), endpoint)).or_insert(seq);
        if seq > *newest {
            *newest = seq;
        }
        seq >= *newest
    }

    /// Keeps `upload`, the oldest going beyond [`MAX_UPLOADS`]; its id.
    pub fn keep_upload(&self, name: String, bytes: Vec<u8>) -> String {
        let mut u = self.uploads.lock().unwrap_or_else(|p| p.into_inner());
        u.0 += 1;
        let id = format!("u{}", u.0);
        u.1.push_back(Upload {
            id: id.clone(),
            name,
            bytes: Arc::new(crate::child::Bytes(bytes)),
        });
        while u.1.len() > MAX_UPLOADS {
            u.1.pop_front();
        }
        id
    }

    /// The upload `id`, now the most recently used.
    pub fn upload(&self, id: &str) -> Option<Upload> {
        let mut u = self.uploads.lock().unwrap_or_else(|p| p.into_inner());
        let at = u.1.iter().position(|x| x.id == id)?;
        let found = u.1.remove(at)?;
        u.1.push_back(found.clone());
        Some(found)
    }

    /// The report kept for (family, method, precision).
    pub fn report(&self, key: &ReportKey) -> Option<Arc<IsaReport>> {
        let r = self.reports.lock().ok()?;
        r.iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
    }

    /// Keeps a report, the oldest going beyond [`MAX_REPORTS`].
    pub fn keep_report(&self, key: ReportKey, report: IsaReport) {
        if let Ok(mut r) = self.reports.lock() {
            r.retain(|(k, _)| *k != key);
            r.push_back((key, Arc::new(report)));
            while r.len() > MAX_REPORTS {
                r.pop_front();
            }
        }
    }
}

/// Each method's `max_valid_angle_deg` of a stress.json (docs/stress.schema.json).
fn stress_angles(path: &Path) -> Result<HashMap<String, f64>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Error::Usage(format!("{}: not a stress.json ({e})", path.display())))?;
    Ok(v["methods"]
        .as_array()
        .map(|ms| {
            ms.iter()
                .filter_map(|m| {
                    Some((
                        m["name"].as_str()?.to_string(),
                        m["max_valid_angle_deg"].as_f64()?,
                    ))
                })
                .collect()
        })
        .unwrap_or_default())
}

/// The scenes of `dir` (`*.toml`) and the meshes of `models`, sorted.
fn scenes(dir: &Path, models: Option<&Path>) -> Result<Vec<SceneEntry>> {
    let mut out = Vec::new();
    let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut files: Vec<PathBuf> = rd
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("toml"))
        .collect();
    files.sort();
    for p in files {
        let id = p
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        out.push(SceneEntry {
            id,
            model: false,
            path: p,
        });
    }
    if out.is_empty() {
        return Err(Error::Usage(format!(
            "--scenes {}: no scene file (*.toml) in it",
            dir.display()
        )));
    }
    if let Some(m) = models {
        for p in crate::geometry::mesh_files(m, crate::geometry::Depth::Flat, None)? {
            let id = p
                .file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            out.push(SceneEntry {
                id,
                model: true,
                path: p,
            });
        }
    }
    Ok(out)
}

/// Serves until the process is stopped (SIGINT/SIGTERM: [`crate::cleanup`]); `ready` gets
/// the URL to open once the server listens.
pub fn serve(opts: &ExploreOptions, ready: &dyn Fn(&str)) -> Result<()> {
    let listener = std::net::TcpListener::bind((opts.bind, opts.port))
        .map_err(|e| Error::Usage(format!("--bind {} --port {}: {e}", opts.bind, opts.port)))?;
    listener
        .set_nonblocking(true)
        .map_err(|e| Error::Internal(format!("explore: {e}")))?;
    let addr = listener
        .local_addr()
        .map_err(|e| Error::Internal(format!("explore: {e}")))?;
    let server = Arc::new(Server::new(opts, addr)?);
    ready(&server.guard.url(addr));
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| Error::Internal(format!("explore: no runtime: {e}")))?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::from_std(listener)
            .map_err(|e| Error::Internal(format!("explore: {e}")))?;
        axum::serve(listener, api::router(server))
            .await
            .map_err(|e| Error::Internal(format!("explore: the server stopped: {e}")))
    })
}
