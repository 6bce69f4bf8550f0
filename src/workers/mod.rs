//! Compiler workers: one long-lived child per driver environment (a GPU family's driver,
//! drm-shim and chip), which answers request after request of [`crate::child`]'s jobs instead
//! of exiting after one. A family's first request starts its worker; later requests of the run
//! (another precision, another method set, tune's candidates, a server's edits) find it warm:
//! no process start, no driver load, and no method file read, proven or compiled again, for
//! the parent hands every worker the methods as it checked and compiled them
//! ([`protocol::CheckedFile`], each sent once per worker).
//!
//! - At most as many requests compile at once as the machine has cores; idle workers beyond
//!   [`Limits::max_idle`] are stopped, the least recently used first.
//! - A worker that dies, gives no reply within [`Limits::deadline`] or grows past
//!   [`Limits::memory`] is stopped; the request it held fails with what happened
//!   ([`Failure::stopped`] for the last two), and the next request starts a new one. A worker
//!   found dead before a request is replaced before the request is sent.
//! - Workers die with their parent: each exits when its stdin closes, and each is started with
//!   `PR_SET_PDEATHSIG` ([`crate::cleanup::die_with_parent`]) from one thread that lives as long
//!   as the process (the signal follows the thread that started the child).
//!
//! `SHADELAB_NO_WORKERS=1` starts one child per request instead ([`crate::child::call`]): the
//! same figures, bit for bit, which the suite checks on every family set up.
pub mod protocol;
pub mod serve;

use std::collections::{HashSet, VecDeque};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, OnceLock};
use std::time::{Duration, Instant};

use protocol::{CheckedFile, Frame, MethodVersion};

use crate::child::{Failure, Job, Reply, Spawn};

/// Lines of a worker's stderr kept for the error of a request it did not answer.
const STDERR_TAIL_LINES: usize = 6;
/// How often a waiting parent looks at its worker's memory.
const WATCH_EVERY: Duration = Duration::from_millis(100);

/// When a worker is stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// The longest one request may take.
    pub deadline: Duration,
    /// The resident memory a worker may grow to, bytes.
    pub memory: u64,
    /// Idle workers kept; the least recently used beyond it are stopped.
    pub max_idle: usize,
    /// Requests compiling at once.
    pub parallel: usize,
}

impl Default for Limits {
    /// 10 minutes a request (a report's whole method table on the slowest family takes tens of
    /// seconds), 2 GiB a worker, 48 idle (every default family of every vendor), one request
    /// per core.
    fn default() -> Limits {
        Limits {
            deadline: Duration::from_secs(600),
            memory: 2 << 30,
            max_idle: 48,
            parallel: std::thread::available_parallelism().map_or(2, |n| n.get()),
        }
    }
}

/// Requests compiling at once: one per core ([`Limits::parallel`]); what the jobs that feed the
/// workers start as many threads for.
pub fn parallel() -> usize {
    global().limits.parallel.max(1)
}

/// Whether requests go to workers (the default) or to one child each
/// (`SHADELAB_NO_WORKERS=1`).
pub fn enabled() -> bool {
    std::env::var_os("SHADELAB_NO_WORKERS").is_none_or(|v| v.is_empty() || v == "0")
}

/// Runs `request` as [`crate::child::call`] does, on this process's pool of workers unless
/// they are turned off ([`enabled`]).
pub fn call<J: Job>(
    spawn: &Spawn,
    request: &J,
    dir: &Path,
    name: &str,
) -> std::result::Result<J::Reply, Failure> {
    if enabled() {
        global().call(spawn, request, dir, name)
    } else {
        crate::child::call(spawn, request, dir, name)
    }
}

/// The limits [`global`] is made with ([`configure`]; [`Limits::default`] otherwise).
static GLOBAL_LIMITS: OnceLock<Limits> = OnceLock::new();

/// This process's pool.
pub fn global() -> &'static Pool {
    static POOL: OnceLock<Pool> = OnceLock::new();
    POOL.get_or_init(|| Pool::new(GLOBAL_LIMITS.get().copied().unwrap_or_default()))
}

/// Sets the limits of this process's pool (a server's shorter deadline), before its first use
/// (a pool already made keeps its limits); false when configured before.
pub fn configure(limits: Limits) -> bool {
    GLOBAL_LIMITS.set(limits).is_ok()
}

/// What tells two workers apart: the binary and the driver's environment.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct Key {
    exe: PathBuf,
    env: Vec<(String, String)>,
}

/// A running worker.
struct Worker {
    key: Key,
    child: Child,
    stdin: ChildStdin,
    replies: Receiver<std::io::Result<String>>,
    /// The last lines of its stderr since its current request began.
    tail: Arc<Mutex<VecDeque<String>>>,
    /// The method versions (SHA-256) it was sent.
    sent: HashSet<String>,
    /// Requests it answered.
    served: usize,
    used: Instant,
    _registered: crate::cleanup::ChildGuard,
}

impl Worker {
    fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Its resident memory, bytes (0 where /proc cannot tell).
    fn resident(&self) -> u64 {
        resident_bytes(self.pid()).unwrap_or(0)
    }

    /// Stops it and reaps it: how it ended.
    fn stop(mut self) -> std::process::ExitStatus {
        let _ = self.child.kill();
        let status = self.child.wait();
        status.unwrap_or_else(|_| std::os::unix::process::ExitStatusExt::from_raw(0))
    }

    fn tail(&self) -> String {
        let t = self.tail.lock().map(|t| t.clone()).unwrap_or_default();
        t.into_iter().collect::<Vec<_>>().join(" | ")
    }
}

/// Resident memory of process `pid`, bytes (/proc/PID/status `VmRSS`, proc(5)).
fn resident_bytes(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    crate::memory::proc_bytes(&status, "VmRSS:")
}

/// A command for the spawner thread, and where its child goes.
type Order = (Command, Sender<std::io::Result<Child>>);

struct State {
    idle: Vec<Worker>,
    compiling: usize,
    /// Workers started so far.
    started: usize,
}

/// Workers of one process.
pub struct Pool {
    limits: Limits,
    state: Mutex<State>,
    freed: Condvar,
    spawner: Mutex<Sender<Order>>,
}

/// What a request's wait ended with.
enum Waited {
    Reply(String),
    Ended(String),
    Stopped(String),
}

impl Pool {
    pub fn new(limits: Limits) -> Pool {
        let (tx, rx) = mpsc::channel::<Order>();
        // The thread that starts every worker: it lives as long as the process, so that a
        // worker's parent-death signal fires when the process ends, not when a caller's
        // thread does.
        std::thread::Builder::new()
            .name("worker-spawner".into())
            .spawn(move || {
                for (mut cmd, back) in rx {
                    let _ = back.send(cmd.spawn());
                }
            })
            .expect("a thread to start workers");
        Pool {
            limits,
            state: Mutex::new(State {
                idle: Vec::new(),
                compiling: 0,
                started: 0,
            }),
            freed: Condvar::new(),
            spawner: Mutex::new(tx),
        }
    }

    fn state(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The pids of the idle workers.
    pub fn idle_pids(&self) -> Vec<u32> {
        self.state().idle.iter().map(Worker::pid).collect()
    }

    /// How many workers this pool has started.
    pub fn started(&self) -> usize {
        self.state().started
    }

    /// Stops every idle worker.
    pub fn stop_idle(&self) {
        let idle = std::mem::take(&mut self.state().idle);
        for w in idle {
            w.stop();
        }
    }

    /// Runs `request` on a worker of `spawn`'s environment (its request file written under
    /// `dir` as `<name>.request.json`, so that `shadelab child FILE` runs it again).
    pub fn call<J: Job>(
        &self,
        spawn: &Spawn,
        request: &J,
        dir: &Path,
        name: &str,
    ) -> std::result::Result<J::Reply, Failure> {
        let path = dir.join(format!("{name}.request.json"));
        let failure = |why: String| Failure::new(J::NAME, why, path.clone());
        crate::child::write_request(
            spawn,
            request,
            &path,
            &dir.join(format!("{name}.reply.json")),
        )
        .map_err(|e| failure(e.to_string()))?;
        let methods = checked(&spawn.method_files).map_err(|e| Failure {
            refused_input: true,
            ..failure(e.to_string())
        })?;
        let _permit = self.permit();
        let key = Key {
            exe: spawn.exe.clone(),
            env: spawn.driver_env.clone(),
        };
        // A worker found dead when the request is sent (it died idle) is replaced once.
        let mut retried = false;
        loop {
            let mut w = match self.take(&key) {
                Some(w) => w,
                None => self.start(&key, spawn.show_stderr).map_err(&failure)?,
            };
            let fresh = w.served == 0;
            let frame = Frame {
                job: J::NAME.to_string(),
                log_level: log::max_level().to_string(),
                new_methods: methods
                    .iter()
                    .filter(|c| !w.sent.contains(&c.sha256))
                    .cloned()
                    .collect(),
                methods: methods
                    .iter()
                    .map(|c| MethodVersion {
                        name: c.name.clone(),
                        sha256: c.sha256.clone(),
                    })
                    .collect(),
                request,
            };
            let mut line = serde_json::to_vec(&frame)
                .map_err(|e| failure(format!("cannot encode the request: {e}")))?;
            line.push(b'\n');
            if let Ok(mut t) = w.tail.lock() {
                t.clear();
            }
            if let Err(e) = w.stdin.write_all(&line).and_then(|()| w.stdin.flush()) {
                let how = ended(w.stop(), "");
                if !retried && !fresh {
                    retried = true;
                    log::debug!("worker gone before a request ({how}): starting another");
                    continue;
                }
                return Err(failure(format!("the worker took no request ({e}); {how}")));
            }
            w.sent.extend(methods.iter().map(|c| c.sha256.clone()));
            let waited = self.wait(&mut w);
            return self.finish::<J>(w, waited, &failure);
        }
    }

    /// The request's end: `w` back among the idle on a reply, stopped otherwise.
    fn finish<J: Job>(
        &self,
        mut w: Worker,
        waited: Waited,
        failure: &dyn Fn(String) -> Failure,
    ) -> std::result::Result<J::Reply, Failure> {
        match waited {
            Waited::Reply(text) => {
                w.served += 1;
                let reply = protocol::decode::<Reply<J::Reply>>(&text, "the worker's reply");
                self.put_back(w);
                reply
                    .map_err(|e| failure(e.to_string()))
                    .and_then(|r| r.into_result(failure))
            }
            Waited::Ended(why) => {
                let tail = w.tail();
                let status = w.stop();
                let how = ended(status, &tail);
                let how = if why.is_empty() {
                    how
                } else {
                    format!("{how} (its reply pipe: {why})")
                };
                // SIGKILL comes from outside (a user, the OOM killer), never a driver.
                let killed =
                    std::os::unix::process::ExitStatusExt::signal(&status) == Some(libc::SIGKILL);
                Err(Failure {
                    stopped: killed,
                    ..failure(how)
                })
            }
            Waited::Stopped(why) => {
                let tail = w.tail();
                w.stop();
                Err(Failure {
                    stopped: true,
                    ..failure(with_tail(format!("{why}: the worker was stopped"), &tail))
                })
            }
        }
    }

    /// Waits for `w`'s reply within the deadline and the memory cap.
    fn wait(&self, w: &mut Worker) -> Waited {
        let start = Instant::now();
        loop {
            match w.replies.recv_timeout(WATCH_EVERY) {
                Ok(Ok(line)) => return Waited::Reply(line),
                Ok(Err(e)) => return Waited::Ended(e.to_string()),
                Err(RecvTimeoutError::Disconnected) => return Waited::Ended(String::new()),
                Err(RecvTimeoutError::Timeout) => {}
            }
            if start.elapsed() > self.limits.deadline {
                return Waited::Stopped(format!(
                    "no reply in {:.1} s",
                    self.limits.deadline.as_secs_f64()
                ));
            }
            let rss = w.resident();
            if rss > self.limits.memory {
                return Waited::Stopped(format!(
                    "it grew to {} MiB, past the cap of {} MiB",
                    rss >> 20,
                    self.limits.memory >> 20
                ));
            }
        }
    }

    /// A permit to compile: at most [`Limits::parallel`] at once.
    fn permit(&self) -> Permit<'_> {
        let mut s = self.state();
        while s.compiling >= self.limits.parallel.max(1) {
            s = self.freed.wait(s).unwrap_or_else(|e| e.into_inner());
        }
        s.compiling += 1;
        Permit(self)
    }

    /// The most recently used idle worker of `key`.
    fn take(&self, key: &Key) -> Option<Worker> {
        let mut s = self.state();
        let i = s
            .idle
            .iter()
            .enumerate()
            .filter(|(_, w)| w.key == *key)
            .max_by_key(|(_, w)| w.used)?
            .0;
        Some(s.idle.swap_remove(i))
    }

    /// Returns `w` to the idle workers (stopped instead when past the memory cap), and stops
    /// the least recently used beyond [`Limits::max_idle`].
    fn put_back(&self, mut w: Worker) {
        if w.resident() > self.limits.memory {
            w.stop();
            return;
        }
        w.used = Instant::now();
        let extra = {
            let mut s = self.state();
            s.idle.push(w);
            let mut extra = Vec::new();
            while s.idle.len() > self.limits.max_idle {
                let Some((oldest, _)) = s.idle.iter().enumerate().min_by_key(|(_, w)| w.used)
                else {
                    break;
                };
                extra.push(s.idle.swap_remove(oldest));
            }
            extra
        };
        for w in extra {
            w.stop();
        }
    }

    /// Starts a worker of `key` (through the spawner thread).
    fn start(&self, key: &Key, show_stderr: bool) -> std::result::Result<Worker, String> {
        let mut cmd = Command::new(&key.exe);
        crate::cleanup::die_with_parent(&mut cmd);
        cmd.arg("child")
            .arg("--worker")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        for (k, v) in &key.env {
            cmd.env(k, v);
        }
        let (tx, rx) = mpsc::channel();
        let sent = self
            .spawner
            .lock()
            .map_err(|_| "the worker spawner is poisoned".to_string())?
            .send((cmd, tx));
        let child = sent
            .ok()
            .and_then(|()| rx.recv().ok())
            .ok_or_else(|| "the worker spawner is gone".to_string())?
            .map_err(|e| format!("cannot start {}: {e}", key.exe.display()))?;
        let mut child = child;
        let registered = crate::cleanup::child(child.id());
        let (stdin, stdout, stderr) =
            match (child.stdin.take(), child.stdout.take(), child.stderr.take()) {
                (Some(i), Some(o), Some(e)) => (i, o, e),
                _ => return Err("a worker without its pipes".into()),
            };
        let (reply_tx, replies) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                if reply_tx.send(line).is_err() {
                    break;
                }
            }
        });
        let tail = Arc::new(Mutex::new(VecDeque::new()));
        let kept = Arc::clone(&tail);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(|l| l.ok()) {
                if show_stderr {
                    eprintln!("{line}");
                }
                if line.trim().is_empty() {
                    continue;
                }
                if let Ok(mut t) = kept.lock() {
                    if t.len() == STDERR_TAIL_LINES {
                        t.pop_front();
                    }
                    t.push_back(line);
                }
            }
        });
        self.state().started += 1;
        log::debug!("worker {} started", child.id());
        Ok(Worker {
            key: key.clone(),
            child,
            stdin,
            replies,
            tail,
            sent: HashSet::new(),
            served: 0,
            used: Instant::now(),
            _registered: registered,
        })
    }
}

/// A request's place among those compiling at once.
struct Permit<'a>(&'a Pool);

impl Drop for Permit<'_> {
    fn drop(&mut self) {
        self.0.state().compiling -= 1;
        self.0.freed.notify_one();
    }
}

/// How a worker that gave no reply ended: "no reply, killed by signal 9 (SIGKILL)", then its
/// stderr's last lines.
fn ended(status: std::process::ExitStatus, tail: &str) -> String {
    with_tail(crate::child::how_it_ended(status), tail)
}

/// `what`, then "; stderr: " and the worker's last lines of stderr when it wrote any.
fn with_tail(what: String, tail: &str) -> String {
    if tail.is_empty() {
        what
    } else {
        format!("{what}; stderr: {tail}")
    }
}

/// The user method files among `paths` as this process checked and compiled them (every
/// method a request names is registered before: [`crate::method::find`] found it).
fn checked(paths: &[PathBuf]) -> crate::error::Result<Vec<CheckedFile>> {
    if paths.is_empty() {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for f in &crate::method::user::expand(paths)? {
        let abs = std::path::absolute(f).map_err(|e| crate::error::Error::io(f, e))?;
        let u = registered_at(&abs).ok_or_else(|| {
            crate::error::Error::Internal(format!(
                "{}: a request names a method file this process did not register",
                abs.display()
            ))
        })?;
        out.push(CheckedFile::of(u)?);
    }
    Ok(out)
}

fn registered_at(abs: &Path) -> Option<&'static crate::method::user::UserMethod> {
    crate::method::user::registered()
        .into_iter()
        .find(|u| Path::new(&u.path) == abs)
}
