//! What a run leaves behind, and who removes it. A run makes temporary files (each output is
//! written beside its place and renamed, [`TempFile`]) and temporary folders (the request and
//! reply files of its child processes, [`TempDir`]), and starts children. All three are
//! registered here while they exist:
//!
//! - on a normal end or an error, their guards remove them (drop);
//! - on SIGINT, SIGTERM or SIGHUP ([`install`]: the signals are blocked in every thread and
//!   taken by one thread with `sigwait`, so the handling is ordinary code), the children are
//!   killed, the temporary files and folders removed, a line says so, and the process exits
//!   128 + the signal (130 for Ctrl-C, 143 for SIGTERM);
//! - on SIGKILL nothing of the run can act: its children die with it (each is started with
//!   `PR_SET_PDEATHSIG` = SIGKILL, [`die_with_parent`]), and the next run removes what it left
//!   ([`sweep_temp_dir`] at start, [`sweep_once`] in each folder it writes): every temporary
//!   name carries its run's pid and start time in clock ticks after boot
//!   (`.shadelab-<pid>.<ticks>-<n>.tmp`, `$TMPDIR/shadelab-<job>-<pid>.<ticks>-<n>/`), and one
//!   whose run is gone (no such process, or a process of another start: a reused pid) is
//!   removed. The start is the kernel's own count, never compared with a wall clock: a clock
//!   stepped while a run goes on (a virtual machine resumed, NTP) does not make it look gone.
//!   A name without the start (written by an older shadelab) is judged by its file's time.
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, SystemTime};

/// Temporary files and folders that exist now.
static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Children running now (pids).
static CHILDREN: Mutex<Vec<u32>> = Mutex::new(Vec::new());
/// Folders already swept by this process.
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);
/// The number in the next temporary name.
static NEXT: AtomicU64 = AtomicU64::new(0);

/// The prefix of temporary files (`.shadelab-<pid>-<n>.tmp`).
pub const FILE_PREFIX: &str = ".shadelab-";
/// The prefix of temporary folders in the system's temporary folder
/// (`shadelab-<job>-<pid>-<n>`).
pub const DIR_PREFIX: &str = "shadelab-";
/// A kept temporary folder (a failed child's request, for `shadelab child FILE`) holds this
/// file; sweeps leave it.
pub const KEPT: &str = "KEPT";

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

fn next_name() -> u64 {
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// This run in a temporary name: `<pid>.<ticks>` (its start, [`start_ticks`]), or `<pid>`
/// alone where /proc cannot tell the start.
fn owner() -> String {
    let pid = std::process::id();
    match start_ticks(pid) {
        Some(t) => format!("{pid}.{t}"),
        None => pid.to_string(),
    }
}

/// A temporary file of this run, registered until it is renamed into place or dropped
/// (removed).
pub struct TempFile {
    path: PathBuf,
    file: Option<std::fs::File>,
}

impl TempFile {
    /// Creates `.shadelab-<pid>.<ticks>-<n>.tmp` in `dir`. The creation and the registration happen
    /// under the registry's lock, so a signal's cleanup (which holds it until the process
    /// exits) never misses a file created at the same moment.
    pub fn create_in(dir: &Path) -> std::io::Result<TempFile> {
        let mut temps = lock(&TEMPS);
        loop {
            let path = dir.join(format!("{FILE_PREFIX}{}-{}.tmp", owner(), next_name()));
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(file) => {
                    temps.push(path.clone());
                    return Ok(TempFile {
                        path,
                        file: Some(file),
                    });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The open file.
    pub fn file(&mut self) -> &mut std::fs::File {
        self.file
            .as_mut()
            .expect("a temporary file is open until persisted")
    }

    /// Renames the file to `to` (atomically, on the same filesystem) and forgets it.
    pub fn persist(mut self, to: &Path) -> std::io::Result<()> {
        self.file = None;
        std::fs::rename(&self.path, to)?;
        forget(&self.path);
        self.path = PathBuf::new();
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.path.as_os_str().is_empty() {
            self.file = None;
            let _ = std::fs::remove_file(&self.path);
            forget(&self.path);
        }
    }
}

fn forget(path: &Path) {
    lock(&TEMPS).retain(|p| p != path);
}

/// A temporary folder of this run in the system's temporary folder, registered until it is
/// dropped (removed with what it holds) or kept.
pub struct TempDir {
    path: PathBuf,
}

impl TempDir {
    /// Creates `$TMPDIR/shadelab-<job>-<pid>.<ticks>-<n>/`.
    pub fn new(job: &str) -> std::io::Result<TempDir> {
        let base = std::env::temp_dir();
        let mut temps = lock(&TEMPS);
        loop {
            let path = base.join(format!("{DIR_PREFIX}{job}-{}-{}", owner(), next_name()));
            match std::fs::create_dir(&path) {
                Ok(()) => {
                    temps.push(path.clone());
                    return Ok(TempDir { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Leaves the folder in place (marked [`KEPT`], which sweeps leave alone) and returns it.
    pub fn keep(mut self) -> PathBuf {
        let _ = std::fs::write(
            self.path.join(KEPT),
            "kept by shadelab: a failed child's request\n",
        );
        forget(&self.path);
        std::mem::take(&mut self.path)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if !self.path.as_os_str().is_empty() {
            let _ = std::fs::remove_dir_all(&self.path);
            forget(&self.path);
        }
    }
}

/// A child process of this run, registered while it runs.
pub struct ChildGuard(u32);

/// Registers the running child `pid` (killed by a signal's cleanup) until the guard drops.
pub fn child(pid: u32) -> ChildGuard {
    lock(&CHILDREN).push(pid);
    ChildGuard(pid)
}

impl Drop for ChildGuard {
    fn drop(&mut self) {
        lock(&CHILDREN).retain(|&p| p != self.0);
    }
}

/// Makes a child of `cmd` die with this process: `PR_SET_PDEATHSIG` = SIGKILL in the child
/// before it runs (Linux), and an immediate exit when this process is already gone by then.
/// (The signal follows the thread that started the child; every caller waits for its child on
/// that thread.)
pub fn die_with_parent(cmd: &mut std::process::Command) {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        let parent = std::process::id() as libc::pid_t;
        // SAFETY: between fork and exec the closure calls only async-signal-safe system calls
        // (prctl, getppid, _exit) and allocates nothing.
        unsafe {
            cmd.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL as libc::c_ulong) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                if libc::getppid() != parent {
                    libc::_exit(1);
                }
                Ok(())
            });
        }
    }
}

/// The signals a run cleans up after, with their names.
const SIGNALS: [(libc::c_int, &str); 3] = [
    (libc::SIGINT, "SIGINT"),
    (libc::SIGTERM, "SIGTERM"),
    (libc::SIGHUP, "SIGHUP"),
];

/// Takes SIGINT, SIGTERM and SIGHUP away from their default (an exit that leaves temporary
/// files and children behind): blocked in this thread and so in every thread started after
/// (call it first, before any other thread exists), and waited for by one thread of its own,
/// which cleans up and exits 128 + the signal. A signal ignored when the process starts stays
/// ignored. Children start with an empty signal mask (the standard library resets it).
pub fn install() {
    // SAFETY: sigset_t and sigaction are plain data; the calls only read the dispositions,
    // fill the set and set this thread's mask.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for (s, _) in SIGNALS {
            // A signal ignored by whoever started us (nohup, a shell's background job) stays
            // ignored.
            let mut old: libc::sigaction = std::mem::zeroed();
            let ignored = libc::sigaction(s, std::ptr::null(), &mut old) == 0
                && old.sa_sigaction == libc::SIG_IGN;
            if !ignored {
                libc::sigaddset(&mut set, s);
            }
        }
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        set
    };
    let spawned = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || loop {
            let mut sig: libc::c_int = 0;
            // SAFETY: `set` is an initialised signal set; sig is written by sigwait.
            if unsafe { libc::sigwait(&set, &mut sig) } == 0 {
                on_signal(sig);
            }
        });
    if spawned.is_err() {
        // No thread to take them: let the signals act as before rather than never.
        // SAFETY: as above.
        unsafe {
            libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
        }
    }
}

/// Kills the children, removes the temporary files and folders, says so, exits 128 + `sig`.
/// The registry stays locked until the exit: nothing new is registered (or created) after the
/// snapshot.
fn on_signal(sig: libc::c_int) -> ! {
    let temps = lock(&TEMPS);
    let children = lock(&CHILDREN);
    for &pid in children.iter() {
        // SAFETY: a plain system call on a pid this process started and still waits for.
        unsafe {
            libc::kill(pid as libc::pid_t, libc::SIGKILL);
        }
    }
    let mut removed = 0;
    for p in temps.iter() {
        let gone = if p.is_dir() {
            std::fs::remove_dir_all(p)
        } else {
            std::fs::remove_file(p)
        };
        removed += usize::from(gone.is_ok());
    }
    let name = SIGNALS
        .iter()
        .find(|(s, _)| *s == sig)
        .map_or("a signal", |(_, n)| n);
    let code = 128 + sig;
    eprintln!(
        "shadelab: stopped by {name}: {} child process(es) killed, {removed} temporary file(s) \
         and folder(s) removed; the outputs written so far are complete files, the run is not \
         (exit {code})",
        children.len()
    );
    // SAFETY: _exit ends the process at once, without running exit handlers that could wait on
    // a lock another thread holds.
    unsafe { libc::_exit(code) }
}

/// When `pid` started, in clock ticks after boot (/proc/PID/stat's field 22, proc(5)); None
/// where it cannot be read. The kernel's count: no wall clock enters it.
fn start_ticks(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command's ')' start at field 3.
    stat.rsplit_once(')')?
        .1
        .split_whitespace()
        .nth(19)?
        .parse()
        .ok()
}

/// When `pid` started, as a wall-clock time (boot time plus [`start_ticks`]); only for names
/// without the start, whose file's time is all there is to compare.
fn started(pid: u32) -> Option<SystemTime> {
    let ticks = start_ticks(pid)?;
    let boot: u64 = std::fs::read_to_string("/proc/stat")
        .ok()?
        .lines()
        .find_map(|l| l.strip_prefix("btime ")?.trim().parse().ok())?;
    // SAFETY: sysconf reads a constant of the system.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    let hz = u64::try_from(hz).ok().filter(|&h| h > 0)?;
    Some(
        SystemTime::UNIX_EPOCH
            + Duration::from_secs(boot)
            + Duration::from_millis(ticks * 1000 / hz),
    )
}

fn exists(pid: u32) -> bool {
    // SAFETY: signal 0 only asks whether the process exists.
    let sent = unsafe { libc::kill(pid as libc::pid_t, 0) };
    sent == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// Whether the run of process `pid` may still own a file last written at `modified`: the
/// process exists, and did not start after the file was written (a reused pid). For names
/// without the start only: a clock stepped since the file was written misjudges it.
fn owner_alive(pid: u32, modified: SystemTime) -> bool {
    // the start time has a clock tick's resolution and the boot time a second's
    exists(pid) && started(pid).is_none_or(|s| s <= modified + Duration::from_secs(2))
}

/// A temporary name's run: its pid and, in names that carry it, its start in clock ticks.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Owner {
    pid: u32,
    start: Option<u64>,
}

impl Owner {
    /// Whether the run may still own a file last written at `modified`: the process of the
    /// name's pid exists with the name's start (or, for a name without it, [`owner_alive`]).
    fn alive(self, modified: SystemTime) -> bool {
        match self.start {
            Some(t) => exists(self.pid) && start_ticks(self.pid).is_none_or(|s| s == t),
            None => owner_alive(self.pid, modified),
        }
    }
}

/// The run in a temporary name: `.shadelab-<pid>[.<ticks>]-<n>.tmp` or
/// `shadelab-<job>-<pid>[.<ticks>]-<n>`.
fn owner_of(name: &str) -> Option<Owner> {
    let rest = if let Some(r) = name.strip_prefix(FILE_PREFIX) {
        r.strip_suffix(".tmp")?
    } else {
        let r = name.strip_prefix(DIR_PREFIX)?;
        r.split_once('-')?.1
    };
    let (who, n) = rest.split_once('-')?;
    n.parse::<u64>().ok()?;
    let (pid, start) = match who.split_once('.') {
        Some((pid, t)) => (pid, Some(t.parse().ok()?)),
        None => (who, None),
    };
    Some(Owner {
        pid: pid.parse().ok()?,
        start,
    })
}

/// Removes from `dir` the temporary files (or, in the system's temporary folder, folders) of
/// runs that are gone; returns how many. Quiet: a file another process removes first is no
/// error.
pub fn sweep(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(owner) = name.to_str().and_then(owner_of) else {
            continue;
        };
        let Ok(meta) = e.metadata() else { continue };
        let modified = meta.modified().unwrap_or(SystemTime::UNIX_EPOCH);
        if owner.pid == std::process::id() || owner.alive(modified) {
            continue;
        }
        let path = e.path();
        let gone = if meta.is_dir() {
            if path.join(KEPT).exists() {
                continue;
            }
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
        removed += usize::from(gone.is_ok());
    }
    removed
}

/// [`sweep`] of `dir` and the folders below it, [`TREE_DEPTH`] deep: a run's output folder
/// when the run starts (a killed run may have been writing anywhere below it). Returns how
/// many were removed.
pub fn sweep_tree(dir: &Path) -> usize {
    fn walk(dir: &Path, depth: usize) -> usize {
        let mut removed = sweep(dir);
        if depth == 0 {
            return removed;
        }
        if let Ok(entries) = std::fs::read_dir(dir) {
            for e in entries.flatten() {
                // not through symbolic links: only what a run wrote
                if e.file_type().is_ok_and(|t| t.is_dir()) {
                    removed += walk(&e.path(), depth - 1);
                }
            }
        }
        removed
    }
    lock(&SWEPT)
        .get_or_insert_with(HashSet::new)
        .insert(std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf()));
    walk(dir, TREE_DEPTH)
}

/// How deep [`sweep_tree`] looks: a report's deepest outputs are 3 folders down
/// (scenes/<scene>/<method>/), a corpus's 3 (meshes/<id>/bench/).
pub const TREE_DEPTH: usize = 4;

/// [`sweep`] of `dir`, once per process.
pub fn sweep_once(dir: &Path) {
    let key = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
    let first = lock(&SWEPT).get_or_insert_with(HashSet::new).insert(key);
    if first {
        sweep(dir);
    }
}

/// [`sweep`] of the system's temporary folder: the request and reply folders of killed runs.
pub fn sweep_temp_dir() -> usize {
    sweep(&std::env::temp_dir())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pid no process has: a child that has exited and been waited for.
    fn dead_pid() -> u32 {
        let mut c = std::process::Command::new("true").spawn().unwrap();
        let pid = c.id();
        c.wait().unwrap();
        pid
    }

    /// Sets `path`'s modification time to 1970 (as a wall clock stepped forward would make
    /// every file look).
    fn filetime_epoch(path: &Path) {
        let f = std::fs::File::options().write(true).open(path).unwrap();
        f.set_modified(SystemTime::UNIX_EPOCH).unwrap();
    }

    /// Temporary names carry their run's pid; a sweep removes those of runs that are gone and
    /// keeps this run's, a live run's, kept folders and every other file.
    #[test]
    fn a_sweep_removes_what_dead_runs_left() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let dead = dead_pid();
        let mine = TempFile::create_in(d).unwrap();
        let name = mine
            .path()
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .to_string();
        let me = owner_of(&name).unwrap();
        assert_eq!(me.pid, std::process::id(), "{name}");
        assert_eq!(me.start, start_ticks(me.pid), "{name}");
        let stale = d.join(format!(".shadelab-{dead}-7.tmp"));
        std::fs::write(&stale, vec![0u8; 1000]).unwrap();
        let stale_dir = d.join(format!("shadelab-isa-{dead}-3"));
        std::fs::create_dir(&stale_dir).unwrap();
        std::fs::write(stale_dir.join("f.request.json"), "{}").unwrap();
        let kept = d.join(format!("shadelab-bench-{dead}-4"));
        std::fs::create_dir(&kept).unwrap();
        std::fs::write(kept.join(KEPT), "").unwrap();
        // pid 1 is alive and started long before this file: kept
        let live = d.join(".shadelab-1-0.tmp");
        std::fs::write(&live, "").unwrap();
        let other = d.join(".shadelab-notes.tmp");
        std::fs::write(&other, "").unwrap();
        assert_eq!(sweep(d), 2);
        assert!(!stale.exists() && !stale_dir.exists());
        assert!(mine.path().exists() && kept.exists() && live.exists() && other.exists());
        // Teeth: a process that started after the file was written does not own it.
        assert!(owner_alive(1, SystemTime::now()));
        assert!(!owner_alive(1, SystemTime::UNIX_EPOCH));
        assert!(!owner_alive(dead, SystemTime::now()));
        // A name with the start: alive whatever the file's time (a clock stepped since), and
        // gone for another start of the same pid (reused) or no process.
        let one = start_ticks(1).unwrap();
        let at = |start| Owner {
            pid: 1,
            start: Some(start),
        };
        assert!(at(one).alive(SystemTime::UNIX_EPOCH));
        assert!(!at(one + 1).alive(SystemTime::now()));
        let gone = Owner {
            pid: dead,
            start: Some(one),
        };
        assert!(!gone.alive(SystemTime::now()));
        let reused = d.join(format!("shadelab-isa-1.{}-5", one + 1));
        std::fs::create_dir(&reused).unwrap();
        let owned = d.join(format!(".shadelab-1.{one}-6.tmp"));
        std::fs::write(&owned, "").unwrap();
        filetime_epoch(&owned);
        assert_eq!(sweep(d), 1, "the reused pid's folder only");
        assert!(!reused.exists() && owned.exists());
        std::fs::remove_file(&owned).unwrap();
        drop(mine);
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 3, "dropped: removed");
    }

    /// A temporary folder and file are registered while they exist (a signal's cleanup
    /// removes what is registered) and forgotten once gone or kept.
    #[test]
    fn temporaries_are_registered_while_they_exist() {
        let registered = |p: &Path| lock(&TEMPS).iter().any(|t| t == p);
        let d = TempDir::new("test").unwrap();
        let p = d.path().to_path_buf();
        assert!(registered(&p) && p.is_dir());
        let mut f = TempFile::create_in(&p).unwrap();
        use std::io::Write;
        f.file().write_all(b"x").unwrap();
        let fp = f.path().to_path_buf();
        assert!(registered(&fp));
        f.persist(&p.join("done")).unwrap();
        assert!(!registered(&fp) && p.join("done").is_file());
        drop(d);
        assert!(!registered(&p) && !p.exists());
        let k = TempDir::new("test").unwrap().keep();
        assert!(k.join(KEPT).is_file() && !registered(&k));
        std::fs::remove_dir_all(k).unwrap();
    }
}
