//! `shadelab isa`: what each method costs on real GPU generations of several vendors, without
//! the GPUs. Each vendor is a compiler route of [`vendor`] (one file each): AMD through RADV's
//! null device and the production ACO compiler, Intel through ANV on Mesa's noop drm-shim,
//! NVIDIA and AMD TeraScale through nouveau's and r600's OpenGL compilers on drm-shims
//! ([`gl_child`]); Vulkan routes read VK_KHR_pipeline_executable_properties' statistics and
//! disassembly, OpenGL routes the compiler's shader-db line (../shared/TOOLCHAIN.md "RADV null
//! device", "Other vendors' production-path compilers").
//!
//! Each family is compiled by a compiler worker of its own ([`child`], a long-lived child of
//! [`crate::workers`] speaking [`crate::child`]'s jobs), one per core at a time, with the vendor's
//! environment (driver selection, preloaded shim, chip variable) set before the driver loads:
//! a family the driver refuses or crashes on (Mesa 22.3.6 dies of SIGFPE on navi24; nouveau
//! falls back to llvmpipe on Ampere) is reported as not supported, a vendor that is not set up
//! as such with the command that sets it up, never fatal. [`request`] is what a child is asked
//! and prints; [`table`] turns the children's reports into rows and ratios to phong_exact,
//! [`report`] into isa.json's report with each family's status; [`files`] writes isa.json,
//! isa.csv, the disassembly; [`rank`] holds the Spearman correlation with lavapipe's isolated
//! cost and [`op_count`] the op-count judgement on AMD's compiled instructions. The figures are each
//! compiler's static model or counts (`FamilyStatus::ranking` says which), not timings: they
//! rank programs, they do not time them.
pub mod calibrate;
pub mod chart;
pub mod child;
pub mod cost;
pub mod files;
pub mod gl_child;
pub mod identity;
pub mod kernel;
pub mod occupancy;
pub mod op_count;
pub mod per_method;
pub mod rank;
pub mod report;
pub mod request;
pub mod route;
pub mod schema;
pub mod stderr;
pub mod store;
pub mod table;
pub mod throughput;

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::method::Method;
pub use report::{FamilyStatus, IsaReport};
pub use request::{ChildReport, ChildRequest, Compiled, CompiledKind, RowKind};
pub use route::{Family, Vendor};
pub use table::Row;

/// The isolated kernel's two evaluation counts: the cost of one evaluation is the difference.
/// Both >= 2 so that both programs sum their results the same way (`REPEAT == 1` stores the
/// colour alone), and small enough that NIR unrolls both loops fully (a loop left rolled would
/// count once, weighted x8, whatever its trip count).
pub const KERNEL_COUNTS: [u32; 2] = [2, 3];

pub use crate::method::Precision;

/// What `shadelab isa` runs.
#[derive(Debug, Clone)]
pub struct IsaOptions {
    pub methods: Vec<&'static Method>,
    pub families: Vec<String>,
    /// The Vulkan ICD manifest of the RADV build to use (VK_DRIVER_FILES); `None`: the
    /// system's RADV, found by the loader's rules ([`crate::gpu::icd`]).
    pub driver_files: Option<PathBuf>,
    /// Scene whose timed draw is compiled; `None`: [`request::DEFAULT_SCENE`].
    pub scene: Option<PathBuf>,
    /// The shadelab binary the children run (`std::env::current_exe()` from the CLI; tests
    /// pass Cargo's `CARGO_BIN_EXE_shadelab`).
    pub exe: PathBuf,
    pub precision: Precision,
    /// Extra compute programs compiled as they are ([`ChildRequest::probes`]).
    pub probes: Vec<PathBuf>,
    /// The compile store the children's replies are read from and written to; `None`:
    /// every family compiled now, nothing stored (`--no-cache`).
    pub store: Option<store::Store>,
}

impl IsaOptions {
    /// `methods` (phong_exact added when missing) on every family of every vendor (a route
    /// that is not set up is reported as such), with the system's RADV, isa's default scene and
    /// `exe`'s children: what the report, bench's speed claims and a corpus compile.
    pub fn every_family(
        methods: &[&'static Method],
        precision: Precision,
        exe: PathBuf,
    ) -> IsaOptions {
        let mut ms = methods.to_vec();
        if !ms.iter().any(|m| m.name == crate::method::PHONG_EXACT) {
            ms.insert(0, crate::method::phong_exact());
        }
        IsaOptions {
            methods: ms,
            families: route::default_family_ids(),
            driver_files: None,
            scene: None,
            exe,
            precision,
            probes: Vec::new(),
            store: store::default_store(),
        }
    }
}

/// Who compiled a family's figures and whether now or earlier (read from the store).
#[derive(Debug, Clone)]
pub struct Provenance {
    /// SHA-256 of the route's [`identity::CompilerIdentity`].
    pub compiler_id: String,
    pub source: store::Source,
}

/// How one child ended.
#[derive(Debug)]
pub enum ChildOutcome {
    Compiled(ChildReport, Provenance),
    /// Not supported by this driver: what happened (signal, exit code, stderr tail).
    Failed(String),
    /// The child refused the request's inputs before compiling (a method file that does not
    /// load): nothing was asked of the driver.
    Refused(String),
    /// The family's compiler worker was stopped while it compiled (past its deadline or
    /// memory cap, or killed from outside: [`crate::workers`]); not the driver's answer.
    Stopped(String),
    /// The vendor's route is not set up (why); no child was started.
    NotSetUp(String),
}

/// Runs one child for `family` (the protocol of [`crate::child`], its request and reply under
/// `dir`) and reads its report, or reads the reply stored for the same request and compiler
/// ([`store`]); a route that is not set up starts none. A driver that does not know the chip
/// under one name gets the next of [`Vendor::driver_chips`].
pub fn run_child(opts: &IsaOptions, family: &Family, dir: &std::path::Path) -> ChildOutcome {
    run_child_with(opts, family, dir, false)
}

/// [`run_child`], with the timed draws alone when `draws_only` (no isolated kernel).
fn run_child_with(
    opts: &IsaOptions,
    family: &Family,
    dir: &std::path::Path,
    draws_only: bool,
) -> ChildOutcome {
    let driver_files = opts.driver_files.as_deref();
    let setup = match family.vendor.setup_for(family.chip, driver_files) {
        Ok(s) => s,
        Err(why) => return ChildOutcome::NotSetUp(why),
    };
    let names = family.vendor.driver_chips(family.chip, &setup);
    let req = ChildRequest {
        family: family.id(),
        methods: opts.methods.iter().map(|m| m.name.to_string()).collect(),
        scene: opts.scene.clone(),
        kernel_counts: KERNEL_COUNTS,
        probes: opts.probes.clone(),
        precision: opts.precision,
        draws_only,
    };
    let method_files = files_of(opts, &req.methods);
    // Per method entries as well as the whole request's (requests with probes: the whole's
    // only): the methods already stored are read, a child compiles the others.
    let per_method = req.probes.is_empty() && req.methods.len() > 1;
    let mut attempts = Vec::new();
    for name in &names {
        let env = match family.vendor.child_env(name, &setup, driver_files) {
            Ok(env) => env,
            Err(why) => return ChildOutcome::NotSetUp(why),
        };
        let compiler = family.vendor.compiler();
        let identity = identity::CompilerIdentity::new(
            &compiler.driver,
            &compiler.api,
            &env,
            family.vendor.compiler_files(&env),
        );
        let provenance = |source| Provenance {
            compiler_id: identity.digest(),
            source,
        };
        let key_of = |r: &ChildRequest| {
            let files = files_of(opts, &r.methods);
            store::KeyMaterial::new(&opts.exe, r, &files, name, identity.clone()).ok()
        };
        let material = opts.store.as_ref().and_then(|_| key_of(&req));
        // Any of the driver's names stored: no child (a first name the driver refuses would
        // cost a child before the second one's hit).
        if let (Some(s), Some(m)) = (&opts.store, &material) {
            match s.get(m) {
                Some(store::Stored::Compiled(r)) => {
                    return ChildOutcome::Compiled(r, provenance(store::Source::FromStore));
                }
                Some(store::Stored::Refused(why)) => return ChildOutcome::Failed(why),
                None => {}
            }
        }
        let parts = match (&opts.store, per_method) {
            (Some(s), true) => match stored_parts(s, &req, &key_of) {
                Ok(whole) => {
                    return ChildOutcome::Compiled(whole, provenance(store::Source::FromStore))
                }
                Err(parts) => parts,
            },
            _ => Vec::new(),
        };
        attempts.push((
            name,
            env,
            material,
            parts,
            provenance(store::Source::Compiled),
        ));
    }
    compile(opts, family, dir, &req, &method_files, attempts)
}

/// One try of a family under one of the driver's names: its environment, the whole request's
/// key, the methods' [`Part`]s (none: the whole request) and the provenance of a compile now.
type Attempt<'a> = (
    &'a String,
    Vec<(String, String)>,
    Option<store::KeyMaterial>,
    Vec<Part>,
    Provenance,
);

/// Starts a child for each of `attempts` in turn until one replies (or refuses for good): the
/// whole request, or the methods no entry holds; what it replies is stored.
fn compile(
    opts: &IsaOptions,
    family: &Family,
    dir: &std::path::Path,
    req: &ChildRequest,
    method_files: &[PathBuf],
    attempts: Vec<Attempt>,
) -> ChildOutcome {
    let mut refused = Vec::new();
    let n = attempts.len();
    for (i, (name, env, material, parts, provenance)) in attempts.into_iter().enumerate() {
        // The methods no entry holds: the child compiles those alone.
        let missing: Vec<String> = parts
            .iter()
            .filter(|p| p.2.is_none())
            .map(|p| p.0.clone())
            .collect();
        let asked = if parts.is_empty() {
            req.clone()
        } else {
            per_method::sub_request(req, &missing)
        };
        let spawn = crate::child::Spawn {
            exe: opts.exe.clone(),
            driver_env: env,
            method_files: if parts.is_empty() {
                method_files.to_vec()
            } else {
                files_of(opts, &missing)
            },
            show_stderr: log::log_enabled!(log::Level::Debug),
        };
        // A reply, or the child's own refusal under this name (the final answer: not a name
        // the driver does not know with another to try), is stored under this name's key.
        let keep = |m: &Option<store::KeyMaterial>, stored: store::Stored| {
            if let (Some(s), Some(m)) = (&opts.store, m) {
                if let Err(e) = s.put(m, stored) {
                    log::warn!("compile store: {}: not stored ({e})", family.id());
                }
            }
        };
        match crate::workers::call(&spawn, &asked, dir, &table::asm_dir(&family.id())) {
            Ok(r) => {
                let r = if parts.is_empty() {
                    r
                } else {
                    match complete(r, &missing, parts, &keep) {
                        Some(whole) => whole,
                        None => {
                            return ChildOutcome::Failed(format!(
                                "{}: the child's reply does not hold the methods asked",
                                family.id()
                            ))
                        }
                    }
                };
                keep(&material, store::Stored::Compiled(r.clone()));
                return ChildOutcome::Compiled(r, provenance);
            }
            Err(f) if f.refused_input => return ChildOutcome::Refused(f.why),
            Err(f) if f.stopped => return ChildOutcome::Stopped(f.why),
            Err(f) if i + 1 < n && family.vendor.unknown_chip(&f.why) => {
                refused.push(format!("`{name}`: {}", f.why));
            }
            Err(f) => {
                let why = if refused.is_empty() {
                    f.why
                } else {
                    refused.push(format!("`{name}`: {}", f.why));
                    refused.join("; ")
                };
                if f.replied {
                    keep(&material, store::Stored::Refused(why.clone()));
                }
                return ChildOutcome::Failed(why);
            }
        }
    }
    ChildOutcome::Failed(refused.join("; "))
}

/// A method's own entry: the method, its key, its stored reply if any.
type Part = (String, Option<store::KeyMaterial>, Option<ChildReport>);

/// The user's method files among `names`.
fn files_of(opts: &IsaOptions, names: &[String]) -> Vec<PathBuf> {
    crate::method::user::paths_of(
        &opts
            .methods
            .iter()
            .copied()
            .filter(|m| names.iter().any(|n| n == m.name))
            .collect::<Vec<_>>(),
    )
}

/// The whole reply of `req` from its methods' entries in `s` when every method has one; else
/// each method's [`Part`] (key and entry, if any).
fn stored_parts(
    s: &store::Store,
    req: &ChildRequest,
    key_of: &dyn Fn(&ChildRequest) -> Option<store::KeyMaterial>,
) -> std::result::Result<ChildReport, Vec<Part>> {
    let mut parts: Vec<Part> = Vec::new();
    for m in &req.methods {
        let key = key_of(&per_method::sub_request(req, std::slice::from_ref(m)));
        let hit = key.as_ref().and_then(|k| match s.get(k) {
            Some(store::Stored::Compiled(r)) => Some(r),
            _ => None,
        });
        parts.push((m.clone(), key, hit));
    }
    if parts.iter().all(|p| p.2.is_some()) {
        let whole = per_method::merge(parts.iter().filter_map(|p| p.2.clone()).collect());
        if let Some(r) = whole {
            return Ok(r);
        }
    }
    Err(parts)
}

/// The whole reply from the child's reply `r` for the `missing` methods and the stored
/// `parts` (method, key, stored reply) in the request's order; each newly compiled method is
/// stored under its own key. `None` when `r` cannot be cut per method.
fn complete(
    r: ChildReport,
    missing: &[String],
    parts: Vec<Part>,
    keep: &dyn Fn(&Option<store::KeyMaterial>, store::Stored),
) -> Option<ChildReport> {
    let mut fresh = per_method::split(&r, missing)?.into_iter();
    let mut whole = Vec::new();
    for (_, key, stored) in parts {
        let part = match stored {
            Some(p) => p,
            None => {
                let p = fresh.next()?;
                keep(&key, store::Stored::Compiled(p.clone()));
                p
            }
        };
        whole.push(part);
    }
    per_method::merge(whole)
}

/// The families of `ids` (family ids, or bare AMD chip names), in order; an unknown vendor
/// or a chip its route does not know is a usage error, before any child starts.
pub fn families(ids: &[String]) -> Result<Vec<Family>> {
    ids.iter()
        .map(|id| {
            let (vendor, chip) = route::resolve(id).map_err(Error::Usage)?;
            route::check_chip(vendor, &chip).map_err(Error::Usage)?;
            // Chips live as long as the run: a family is a small, fixed set of names, leaked
            // once per process (the CLI and tests make a handful).
            let chip: &'static str = Box::leak(chip.into_boxed_str());
            Ok(Family { vendor, chip })
        })
        .collect()
}

/// Compiles every family (as many at a time as [`crate::workers::parallel`]) and builds the
/// report.
pub fn run(opts: &IsaOptions, progress: &(dyn Fn(&str) + Sync)) -> Result<IsaReport> {
    run_with(opts, false, progress)
}

/// [`run`], with the timed draws alone when `draws_only` (no isolated kernel: what
/// [`calibrate`] compiles).
pub fn run_with(
    opts: &IsaOptions,
    draws_only: bool,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<IsaReport> {
    if opts.families.is_empty() {
        return Err(Error::Usage("--families: no family given".into()));
    }
    let families = families(&opts.families)?;
    let start = Instant::now();
    let dir =
        crate::cleanup::TempDir::new("isa").map_err(|e| Error::io(std::env::temp_dir(), e))?;
    let queue: Mutex<Vec<(usize, Family)>> =
        Mutex::new(families.iter().copied().enumerate().rev().collect());
    let done: Mutex<Vec<(usize, ChildOutcome)>> = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..crate::workers::parallel().min(families.len()) {
            s.spawn(|| loop {
                let next = queue.lock().ok().and_then(|mut q| q.pop());
                let Some((i, family)) = next else { break };
                let outcome = run_child_with(opts, &family, dir.path(), draws_only);
                let id = family.id();
                progress(&match &outcome {
                    ChildOutcome::Compiled(r, p) if p.source == store::Source::FromStore => {
                        format!("{id}: {} from the compile store", r.device_name)
                    }
                    ChildOutcome::Compiled(r, _) => {
                        format!("{id}: {} in {:.0} ms", r.device_name, r.elapsed_ms)
                    }
                    ChildOutcome::Failed(why) => format!("{id}: not supported ({why})"),
                    ChildOutcome::Refused(why) => format!("{id}: input refused ({why})"),
                    ChildOutcome::Stopped(why) => format!("{id}: compiler worker stopped ({why})"),
                    ChildOutcome::NotSetUp(why) => format!(
                        "{id}: not set up ({why}); run {}",
                        family.vendor.setup_command_for(family.chip)
                    ),
                });
                if let Ok(mut d) = done.lock() {
                    d.push((i, outcome));
                }
            });
        }
    });
    let mut outcomes = done
        .into_inner()
        .map_err(|_| Error::Internal("isa: a child thread panicked".into()))?;
    if outcomes.len() != families.len() {
        return Err(Error::Internal(format!(
            "isa: {} of {} families came back",
            outcomes.len(),
            families.len()
        )));
    }
    outcomes.sort_by_key(|(i, _)| *i);
    let outcomes: Vec<(Family, ChildOutcome)> = outcomes
        .into_iter()
        .map(|(i, o)| (families[i], o))
        .collect();
    report::report(opts, outcomes, start.elapsed().as_secs_f64())
}
