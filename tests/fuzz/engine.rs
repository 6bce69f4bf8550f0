//! The fuzz engine: feeds one target the inputs of a [`Mutator`], one at a time on the calling
//! thread, and reports what went wrong. Per input it
//! - catches a panic (`catch_unwind`; a panic hook records the message and location without
//!   printing, on fuzzing threads only, so the other tests of this binary keep their output);
//! - times the parse, and counts every input over [`Limits::time`] as a failure;
//! - records the largest single allocation (the global allocator below, active on fuzzing
//!   threads only), and counts every input over [`Limits::alloc_bytes`] as a failure: a reader
//!   must never size a buffer from a number in the file;
//! - a watchdog thread saves the input and ends the process with exit code 1 when one input
//!   runs past [`Limits::hang`] (a loop that never ends cannot be caught from inside), and the
//!   allocator does the same before a request over [`ABORT_BYTES`] (it would abort the process
//!   unrecorded).
//!
//! Every failing input (up to [`SAVED_FAILURES`] per run) and the slowest one are written to the
//! output folder, so they can be replayed and kept as regression files.
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::{Cell, RefCell};
use std::collections::HashSet;
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

use super::mutate::Mutator;
use super::Target;

/// What counts as a failure besides a panic.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Longest a single input may take (issue 10: "no input taking > 1 s").
    pub time: Duration,
    /// After this long on one input the watchdog saves it and ends the process.
    pub hang: Duration,
    /// Largest single allocation one input may cause. 256 MiB: the largest legitimate one
    /// from a seed file is 13 MiB (the bunny), and a generated mesh at
    /// MAX_GENERATED_TRIANGLES (1M) is 36 MB per array (48 MiB with Vec's doubling).
    pub alloc_bytes: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            time: Duration::from_secs(1),
            hang: Duration::from_secs(10),
            alloc_bytes: 256 << 20,
        }
    }
}

/// A request this large would abort the process (or swap the machine) before the harness
/// could record it: the allocator saves the input and exits instead.
pub const ABORT_BYTES: usize = 4 << 30;
/// Failing inputs written to disk per run (all are counted).
pub const SAVED_FAILURES: usize = 20;

/// One run's settings.
#[derive(Debug, Clone)]
pub struct Config {
    /// Inputs to try, the seeds' whole files first.
    pub inputs: u64,
    /// Random seed: the same seed gives the same inputs.
    pub seed: u64,
    pub limits: Limits,
    /// Where failing and slowest inputs are written.
    pub out_dir: PathBuf,
}

#[derive(Debug, Clone, PartialEq)]
pub enum FailureKind {
    Panic(String),
    Slow(Duration),
    Alloc(usize),
}

#[derive(Debug, Clone)]
pub struct Failure {
    pub kind: FailureKind,
    /// Where the input was written (`None` past [`SAVED_FAILURES`]).
    pub saved: Option<PathBuf>,
    pub origin: String,
}

/// What one run of one target found.
#[derive(Debug, Clone)]
pub struct Report {
    pub target: &'static str,
    pub inputs: u64,
    /// Inputs the reader accepted (the rest it rejected with an error).
    pub accepted: u64,
    /// Distinct error messages with numbers and quoted text blanked: a rough measure of how
    /// many of the reader's checks the inputs reached.
    pub distinct_errors: usize,
    pub elapsed: Duration,
    pub slowest: Duration,
    pub slowest_origin: String,
    pub slowest_len: usize,
    pub slowest_saved: Option<PathBuf>,
    pub largest_alloc: usize,
    pub failures: Vec<Failure>,
}

impl Report {
    pub fn panics(&self) -> usize {
        self.count(|k| matches!(k, FailureKind::Panic(_)))
    }
    pub fn slow(&self) -> usize {
        self.count(|k| matches!(k, FailureKind::Slow(_)))
    }
    pub fn greedy(&self) -> usize {
        self.count(|k| matches!(k, FailureKind::Alloc(_)))
    }
    fn count(&self, f: impl Fn(&FailureKind) -> bool) -> usize {
        self.failures.iter().filter(|x| f(&x.kind)).count()
    }

    /// One line per target, the lines scripts/fuzz.sh prints.
    pub fn summary(&self) -> String {
        format!(
            "{}: {} inputs ({} accepted, {} distinct errors) in {:.1} s, {} panics, {} over {} s, {} over the allocation limit; slowest {:.3} s ({}, {} bytes{}), largest allocation {:.1} MiB",
            self.target,
            self.inputs,
            self.accepted,
            self.distinct_errors,
            self.elapsed.as_secs_f64(),
            self.panics(),
            self.slow(),
            Limits::default().time.as_secs_f64(),
            self.greedy(),
            self.slowest.as_secs_f64(),
            self.slowest_origin,
            self.slowest_len,
            self.slowest_saved
                .as_ref()
                .map_or(String::new(), |p| format!(", saved as {}", p.display())),
            self.largest_alloc as f64 / (1 << 20) as f64,
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Per-thread state read by the panic hook and the allocator.
// ---------------------------------------------------------------------------------------------
/// What the watchdog and the allocator need to save the input in flight.
struct Shared {
    target: &'static str,
    ext: &'static str,
    out_dir: PathBuf,
    input: Mutex<Vec<u8>>,
    /// Nanoseconds since `epoch` at which the input in flight started; `u64::MAX` when idle.
    started: AtomicU64,
    epoch: Instant,
}

thread_local! {
    /// True while this thread runs a target on an input.
    static FUZZING: Cell<bool> = const { Cell::new(false) };
    static LARGEST: Cell<usize> = const { Cell::new(0) };
    /// The run in progress on this thread (its `Arc` outlives the pointer's use).
    static RUN: Cell<*const Shared> = const { Cell::new(std::ptr::null()) };
    static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
    /// Allocations (and reallocations) made by this thread so far, for
    /// [`allocations_on_this_thread`].
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

/// How many allocations and reallocations this thread has made so far (tests/software.rs
/// checks with it that the software engine's span loops allocate nothing).
pub fn allocations_on_this_thread() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

/// The system allocator, noting the largest request made on a fuzzing thread.
pub struct Tracking;

#[global_allocator]
static ALLOCATOR: Tracking = Tracking;

fn note(size: usize) {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
    let _ = FUZZING.try_with(|f| {
        if !f.get() {
            return;
        }
        LARGEST.with(|m| m.set(m.get().max(size)));
        if size > ABORT_BYTES {
            f.set(false);
            let run = RUN.with(Cell::get);
            // SAFETY: `run` is set only inside `run_target`, which keeps its `Arc<Shared>`
            // alive until after it resets the pointer.
            if let Some(shared) = unsafe { run.as_ref() } {
                save_and_exit(shared, &format!("asked for one allocation of {size} bytes"));
            }
        }
    });
}

// SAFETY: every call is forwarded unchanged to `System`; `note` only reads and writes
// const-initialised thread-locals without destructors (so it never allocates itself, except
// on the way to exiting the process).
unsafe impl GlobalAlloc for Tracking {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Installs (once per process) a panic hook that records panics of fuzzing threads instead
/// of printing them, and hands every other panic to the previous hook.
fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if FUZZING.with(Cell::get) {
                let at = info
                    .location()
                    .map_or(String::new(), |l| format!(" at {}:{}", l.file(), l.line()));
                let msg = info
                    .payload()
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| info.payload().downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "(non-string payload)".into());
                LAST_PANIC.with(|p| *p.borrow_mut() = Some(format!("{msg}{at}")));
            } else {
                previous(info);
            }
        }));
    });
}

fn save(out_dir: &Path, name: &str, input: &[u8]) -> Option<PathBuf> {
    std::fs::create_dir_all(out_dir).ok()?;
    let path = out_dir.join(name);
    std::fs::write(&path, input).ok()?;
    Some(path)
}

fn save_and_exit(shared: &Shared, why: &str) -> ! {
    let input = shared.input.lock().map(|i| i.clone()).unwrap_or_default();
    let name = format!("fatal-{}.{}", shared.target, shared.ext);
    let saved = save(&shared.out_dir, &name, &input);
    eprintln!(
        "fuzz: FATAL: target {} {why}; input ({} bytes) saved as {}",
        shared.target,
        input.len(),
        saved.map_or("(could not save)".into(), |p| p.display().to_string())
    );
    std::process::exit(1)
}

/// Blanks digits and backquoted text, so "index 7 is past the 3 vertices" and "index 9 is
/// past the 5 vertices" count as one error.
fn error_shape(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len());
    let mut quoted = false;
    for c in msg.chars() {
        match c {
            '`' => {
                quoted = !quoted;
                out.push('`');
            }
            _ if quoted => {}
            '0'..='9' => {
                if !out.ends_with('#') {
                    out.push('#');
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// Runs `target` on `cfg.inputs` inputs from a [`Mutator`] over its seeds.
pub fn run_target(target: &Target, cfg: &Config) -> Report {
    install_panic_hook();
    let mut mutator = Mutator::new(target, cfg.seed);
    let shared = Arc::new(Shared {
        target: target.name,
        ext: target.syntax.extension(),
        out_dir: cfg.out_dir.clone(),
        input: Mutex::new(Vec::new()),
        started: AtomicU64::new(u64::MAX),
        epoch: Instant::now(),
    });
    let stop = Arc::new(AtomicBool::new(false));
    let watchdog = {
        let (shared, stop, hang) = (shared.clone(), stop.clone(), cfg.limits.hang);
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(50));
                let started = shared.started.load(Ordering::Relaxed);
                let now = shared.epoch.elapsed().as_nanos() as u64;
                if started != u64::MAX && now.saturating_sub(started) > hang.as_nanos() as u64 {
                    save_and_exit(&shared, &format!("still runs one input after {hang:?}"));
                }
            }
        })
    };

    let mut report = Report {
        target: target.name,
        inputs: 0,
        accepted: 0,
        distinct_errors: 0,
        elapsed: Duration::ZERO,
        slowest: Duration::ZERO,
        slowest_origin: String::new(),
        slowest_len: 0,
        slowest_saved: None,
        largest_alloc: 0,
        failures: Vec::new(),
    };
    let mut slowest_input = Vec::new();
    let mut errors = HashSet::new();
    let mut input = Vec::new();
    let t_run = Instant::now();
    RUN.with(|r| r.set(Arc::as_ptr(&shared)));
    for _ in 0..cfg.inputs {
        let origin = mutator.next(&mut input);
        if let Ok(mut current) = shared.input.lock() {
            current.clear();
            current.extend_from_slice(&input);
        }
        shared
            .started
            .store(shared.epoch.elapsed().as_nanos() as u64, Ordering::Relaxed);
        LARGEST.with(|m| m.set(0));
        FUZZING.with(|f| f.set(true));
        let t0 = Instant::now();
        let result = panic::catch_unwind(AssertUnwindSafe(|| (target.parse)(&input)));
        let dt = t0.elapsed();
        FUZZING.with(|f| f.set(false));
        shared.started.store(u64::MAX, Ordering::Relaxed);
        let largest = LARGEST.with(Cell::get);
        report.inputs += 1;
        report.largest_alloc = report.largest_alloc.max(largest);

        let mut kinds = Vec::new();
        match result {
            Ok(Ok(())) => {
                report.accepted += 1;
                mutator.accepted(&input);
            }
            Ok(Err(e)) => {
                errors.insert(error_shape(&e.to_string()));
            }
            Err(_) => {
                let msg = LAST_PANIC
                    .with(|p| p.borrow_mut().take())
                    .unwrap_or_else(|| "(no message)".into());
                kinds.push(FailureKind::Panic(msg));
            }
        }
        if dt > cfg.limits.time {
            kinds.push(FailureKind::Slow(dt));
        }
        if largest > cfg.limits.alloc_bytes {
            kinds.push(FailureKind::Alloc(largest));
        }
        for kind in kinds {
            let n = report.failures.len();
            let saved = (n < SAVED_FAILURES)
                .then(|| {
                    let name = format!("failure-{}-{n}.{}", target.name, target.syntax.extension());
                    save(&cfg.out_dir, &name, &input)
                })
                .flatten();
            report.failures.push(Failure {
                kind,
                saved,
                origin: mutator.describe(&origin),
            });
        }
        if dt > report.slowest {
            report.slowest = dt;
            report.slowest_origin = mutator.describe(&origin);
            report.slowest_len = input.len();
            slowest_input.clone_from(&input);
        }
    }
    RUN.with(|r| r.set(std::ptr::null()));
    report.elapsed = t_run.elapsed();
    report.distinct_errors = errors.len();
    stop.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    let name = format!("slowest-{}.{}", target.name, target.syntax.extension());
    report.slowest_saved = save(&cfg.out_dir, &name, &slowest_input);
    report
}
