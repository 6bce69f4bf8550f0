//! One protocol for every child process shadelab starts (bench's fresh-process runs, `isa`'s
//! one process per GPU family): the parent writes one typed request ([`Envelope`], schema
//! [`SCHEMA_VERSION`]) to a file and starts `shadelab child FILE`; the child reads it, does
//! the [`Job`], and writes one typed [`Reply`] to the file the request names. Nothing else passes
//! between them: no shadelab state in environment variables (the request holds it, the user's
//! method files included); only what a driver reads when it loads (`RADV_FORCE_FAMILY`,
//! `LP_NUM_THREADS`, a drm-shim's `LD_PRELOAD`) is set by the parent at spawn, from the request's
//! `driver_env`.
//!
//! A child that fails writes its error as the reply; one that dies (a driver's SIGFPE) writes
//! none, and the parent says how it ended with the tail of its stderr. Either way the parent's
//! error names the job and keeps the request file, so `shadelab child FILE` runs it again.
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use base64::Engine;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::error::{Error, Result};

/// Bytes, written in JSON as standard base64 (RFC 4648): SPIR-V in a frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bytes(pub Vec<u8>);

impl Serialize for Bytes {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(&base64::engine::general_purpose::STANDARD.encode(&self.0))
    }
}

impl<'de> Deserialize<'de> for Bytes {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Bytes, D::Error> {
        let text = String::deserialize(d)?;
        base64::engine::general_purpose::STANDARD
            .decode(text.as_bytes())
            .map(Bytes)
            .map_err(serde::de::Error::custom)
    }
}

/// Version of the request and reply files.
pub const SCHEMA_VERSION: u32 = 1;
/// Lines of a dead child's stderr kept in the parent's error.
const STDERR_TAIL_LINES: usize = 6;

/// A job a child can do: its request (this type) and its reply.
pub trait Job: Serialize + DeserializeOwned {
    /// The job's name in the envelope (`bench_run`, `isa_family`).
    const NAME: &'static str;
    type Reply: Serialize + DeserializeOwned;
}

/// The request file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Envelope<T> {
    pub schema_version: u32,
    /// [`Job::NAME`].
    pub job: String,
    /// Where the child writes its [`Reply`].
    pub reply: PathBuf,
    /// Environment a driver reads when it loads, set by the parent when it starts the child.
    #[serde(default)]
    pub driver_env: Vec<(String, String)>,
    /// The user's method files (`--method-file`), registered by the child before anything.
    #[serde(default)]
    pub method_files: Vec<PathBuf>,
    /// What the child tells on stderr: the parent's `log` level (its `-v`/`-q`), e.g. `WARN`.
    #[serde(default = "default_log_level")]
    pub log_level: String,
    pub request: T,
}

fn default_log_level() -> String {
    log::LevelFilter::Info.to_string()
}

/// The reply file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Reply<R> {
    Done {
        reply: R,
    },
    /// The job ran and failed: its own answer to this request (a chip without float16).
    Failed {
        error: String,
    },
    /// The child refused the request's inputs before its job ran (a method file that does not
    /// load): nothing of the job, the driver's or the compiler's, was tried.
    Refused {
        error: String,
    },
}

/// How a parent starts a child.
#[derive(Debug, Clone)]
pub struct Spawn {
    /// The shadelab binary.
    pub exe: PathBuf,
    pub driver_env: Vec<(String, String)>,
    pub method_files: Vec<PathBuf>,
    /// Whether the child's stderr goes to the parent's terminal (progress of a long job) or
    /// is kept for the error message of a child that dies.
    pub show_stderr: bool,
}

/// Why a child gave no reply.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    pub job: &'static str,
    /// What happened: the child's own error, or how it ended.
    pub why: String,
    /// The request file, kept: `shadelab child FILE` runs it again.
    pub request: PathBuf,
    /// Whether the child itself replied with the error (a refusal it decided: the same request
    /// is refused again), as opposed to a child that died, could not start or wrote no
    /// readable reply.
    pub replied: bool,
    /// Whether the child refused the request's inputs before its job ran ([`Reply::Refused`]):
    /// what failed is the input, never the driver.
    pub refused_input: bool,
    /// Whether the parent stopped it (a worker past its deadline or memory cap,
    /// [`crate::workers::Limits`]): what failed is the time or memory it took, not the job.
    pub stopped: bool,
}

impl Failure {
    /// A failure of job `job` whose request file is `request`: the child did not reply
    /// (the flags say otherwise where it did).
    pub fn new(job: &'static str, why: String, request: PathBuf) -> Failure {
        Failure {
            job,
            why,
            request,
            replied: false,
            refused_input: false,
            stopped: false,
        }
    }
}

impl<R> Reply<R> {
    /// The reply as a result: a failure (by `failure`) flagged as the child's own answer
    /// ([`Reply::Failed`]) or as its inputs refused ([`Reply::Refused`]).
    pub fn into_result(
        self,
        failure: &dyn Fn(String) -> Failure,
    ) -> std::result::Result<R, Failure> {
        match self {
            Reply::Done { reply } => Ok(reply),
            Reply::Failed { error } => Err(Failure {
                replied: true,
                ..failure(error)
            }),
            Reply::Refused { error } => Err(Failure {
                refused_input: true,
                ..failure(error)
            }),
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "child {} failed: {} (request: {}; `shadelab child {}` runs it again)",
            self.job,
            self.why,
            self.request.display(),
            self.request.display()
        )
    }
}

/// Runs `request` in a child started by `spawn`, in folder `dir` (its request and reply files
/// are `<dir>/<name>.request.json` and `.reply.json`), and returns the reply.
pub fn call<J: Job>(
    spawn: &Spawn,
    request: &J,
    dir: &Path,
    name: &str,
) -> std::result::Result<J::Reply, Failure> {
    let path = dir.join(format!("{name}.request.json"));
    let failure = |why: String| Failure::new(J::NAME, why, path.clone());
    let reply = dir.join(format!("{name}.reply.json"));
    write_request(spawn, request, &path, &reply).map_err(|e| failure(e.to_string()))?;
    let _ = std::fs::remove_file(&reply);
    let mut cmd = Command::new(&spawn.exe);
    crate::cleanup::die_with_parent(&mut cmd);
    cmd.arg("child")
        .arg(&path)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(if spawn.show_stderr {
            Stdio::inherit()
        } else {
            Stdio::piped()
        });
    for (k, v) in &spawn.driver_env {
        cmd.env(k, v);
    }
    let child = cmd
        .spawn()
        .map_err(|e| failure(format!("cannot start {}: {e}", spawn.exe.display())))?;
    // Killed by a signal's cleanup while it runs; with this process on SIGKILL.
    let _running = crate::cleanup::child(child.id());
    let out = child
        .wait_with_output()
        .map_err(|e| failure(format!("waiting for {}: {e}", spawn.exe.display())))?;
    match std::fs::read(&reply) {
        Ok(b) => match serde_json::from_slice::<Reply<J::Reply>>(&b) {
            Ok(r) => r.into_result(&failure),
            Err(e) => Err(failure(format!("its reply is not readable: {e}"))),
        },
        Err(_) => Err(failure(ended(out.status, &out.stderr, spawn.show_stderr))),
    }
}

/// Writes the request file of `request` for `spawn` at `path` (its reply to go to `reply`):
/// what `shadelab child FILE` runs.
pub fn write_request<J: Job>(spawn: &Spawn, request: &J, path: &Path, reply: &Path) -> Result<()> {
    let envelope = Envelope {
        schema_version: SCHEMA_VERSION,
        job: J::NAME.into(),
        reply: reply.to_path_buf(),
        driver_env: spawn.driver_env.clone(),
        method_files: spawn.method_files.clone(),
        log_level: log::max_level().to_string(),
        request,
    };
    let bytes = serde_json::to_vec_pretty(&envelope)
        .map_err(|e| Error::output(path.display().to_string(), format!("cannot encode: {e}")))?;
    crate::output::write_bytes_atomic(path, &bytes)
}

/// "no reply, killed by signal 8 (SIGFPE)" or "no reply, exit code 2".
pub fn how_it_ended(status: std::process::ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(c), _) => format!("no reply, exit code {c}"),
        (None, Some(s)) => format!("no reply, killed by signal {s}{}", signal_name(s)),
        (None, None) => format!("no reply, {status}"),
    }
}

/// "killed by signal 8 (SIGFPE)" or "exit code 2", then the last lines of stderr (or where
/// they went).
fn ended(status: std::process::ExitStatus, stderr: &[u8], shown: bool) -> String {
    let how = how_it_ended(status);
    if shown {
        return format!("{how}; its messages are above");
    }
    let text = String::from_utf8_lossy(stderr);
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    let tail = lines[lines.len().saturating_sub(STDERR_TAIL_LINES)..].join(" | ");
    if tail.is_empty() {
        how
    } else {
        format!("{how}; stderr: {tail}")
    }
}

fn signal_name(s: i32) -> &'static str {
    match s {
        4 => " (SIGILL)",
        6 => " (SIGABRT)",
        8 => " (SIGFPE)",
        9 => " (SIGKILL)",
        11 => " (SIGSEGV)",
        _ => "",
    }
}

/// The child's side: the request file at `path`, its job not yet read.
pub fn read(path: &Path) -> Result<Envelope<serde_json::Value>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let env: Envelope<serde_json::Value> = serde_json::from_slice(&bytes)
        .map_err(|e| Error::input(path, None, format!("not a child request: {e}")))?;
    if env.schema_version != SCHEMA_VERSION {
        return Err(Error::input(
            path,
            None,
            format!(
                "a request of schema version {} (this shadelab reads {SCHEMA_VERSION})",
                env.schema_version
            ),
        ));
    }
    Ok(env)
}

/// The child's side: decodes the request of `env` as job `J`, runs `work` on it and writes
/// the reply (its error too, as the reply: the parent reports it).
/// Answers the request of `env` with [`Reply::Refused`]: its inputs (`error`) were refused
/// before its job ran.
pub fn refuse<T>(env: &Envelope<T>, error: &Error) -> Result<()> {
    let reply = serde_json::to_vec(&Reply::<()>::Refused {
        error: error.to_string(),
    })
    .map_err(|e| Error::output("the child's reply", e))?;
    crate::output::write_bytes_atomic(&env.reply, &reply)
}

pub fn serve<J: Job>(
    env: Envelope<serde_json::Value>,
    work: impl FnOnce(J) -> Result<J::Reply>,
) -> Result<()> {
    let outcome = serde_json::from_value::<J>(env.request)
        .map_err(|e| Error::Usage(format!("child {}: not its request: {e}", J::NAME)))
        .and_then(work);
    let reply = match &outcome {
        Ok(r) => serde_json::to_vec(&Reply::Done { reply: r }),
        Err(e) => serde_json::to_vec(&Reply::<J::Reply>::Failed {
            error: e.to_string(),
        }),
    }
    .map_err(|e| Error::output("the child's reply", e))?;
    crate::output::write_bytes_atomic(&env.reply, &reply)?;
    outcome.map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Serialize, Deserialize, PartialEq)]
    struct Echo {
        text: String,
    }

    impl Job for Echo {
        const NAME: &'static str = "echo";
        type Reply = String;
    }

    fn envelope(dir: &Path, request: serde_json::Value) -> Envelope<serde_json::Value> {
        Envelope {
            schema_version: SCHEMA_VERSION,
            job: "echo".into(),
            reply: dir.join("r.json"),
            driver_env: Vec::new(),
            method_files: Vec::new(),
            log_level: default_log_level(),
            request,
        }
    }

    /// The child writes its reply, or its error as the reply; a request of another schema
    /// version or of another shape is refused.
    #[test]
    fn a_child_replies_with_its_result_or_its_error() {
        let dir = tempfile::tempdir().unwrap();
        let env = envelope(dir.path(), serde_json::json!({"text": "hi"}));
        serve::<Echo>(env.clone(), |e| Ok(e.text.to_uppercase())).unwrap();
        let r: Reply<String> =
            serde_json::from_slice(&std::fs::read(dir.path().join("r.json")).unwrap()).unwrap();
        assert!(matches!(r, Reply::Done { reply } if reply == "HI"));
        let err = serve::<Echo>(env, |_| Err(Error::Usage("no".into())));
        assert!(err.is_err());
        let r: Reply<String> =
            serde_json::from_slice(&std::fs::read(dir.path().join("r.json")).unwrap()).unwrap();
        assert!(matches!(r, Reply::Failed { error } if error.contains("no")));
        // Teeth: another shape is not this job's request.
        let wrong = envelope(dir.path(), serde_json::json!({"txt": 1}));
        assert!(serve::<Echo>(wrong, |e| Ok(e.text)).is_err());
        let path = dir.path().join("q.json");
        let mut v = serde_json::to_value(envelope(dir.path(), serde_json::json!({}))).unwrap();
        v["schema_version"] = serde_json::json!(SCHEMA_VERSION + 1);
        std::fs::write(&path, v.to_string()).unwrap();
        assert!(read(&path)
            .unwrap_err()
            .to_string()
            .contains("schema version"));
    }

    /// Bytes go through JSON as base64 unchanged; text that is not base64 is refused.
    #[test]
    fn bytes_round_trip_through_json_as_base64() {
        let b = Bytes((0..=255u8).collect());
        let json = serde_json::to_string(&b).unwrap();
        assert!(json.starts_with("\"AAECAwQF"), "{json}");
        assert_eq!(serde_json::from_str::<Bytes>(&json).unwrap(), b);
        assert!(serde_json::from_str::<Bytes>("\"not base64!\"").is_err());
    }

    /// A child that dies without a reply is reported with how it ended and its request.
    #[test]
    fn a_dead_child_is_reported_with_its_request() {
        let dir = tempfile::tempdir().unwrap();
        let spawn = Spawn {
            exe: PathBuf::from("/bin/false"),
            driver_env: Vec::new(),
            method_files: Vec::new(),
            show_stderr: false,
        };
        let e = call(&spawn, &Echo { text: "x".into() }, dir.path(), "one").unwrap_err();
        assert_eq!(e.job, "echo");
        assert!(e.why.contains("exit code 1"), "{}", e.why);
        assert!(e.request.is_file(), "the request is kept");
        assert!(e.to_string().contains("shadelab child"), "{e}");
    }
}
