//! `shadelab corpus` and `merge` through the built binary: three shards merged give the same
//! per-mesh files as one unsharded run, byte for byte; merge refuses a missing, a duplicated
//! and a mismatched shard (exit 2 naming it); a corrupt OBJ is recorded and the rest completes;
//! a restarted shard keeps what it finished and redoes a changed mesh; the Slurm example's job
//! array on a single-node Slurm started on localhost (docs/examples/corpus-slurm.sh).
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use crate::support::{self, assert_schema, read_json, run};

/// Few methods at a small size: the figures are exercised, not the methods.
const METHODS: &str = "gouraud,phong_exact,newton_raphson,slerp";
const SIZE: &str = "48x48";

/// A corpus of two shared models (one in a subfolder) and a corrupt OBJ, in a temp folder.
fn small_corpus() -> Option<tempfile::TempDir> {
    let models = support::models_dir()?;
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(d.path().join("sub")).unwrap();
    std::fs::copy(models.join("suzanne.obj"), d.path().join("suzanne.obj")).unwrap();
    std::fs::copy(models.join("teapot.obj"), d.path().join("sub/teapot.obj")).unwrap();
    std::fs::write(
        d.path().join("broken.obj"),
        "v 0 0 0\nv nonsense\nf 1 2 3\n",
    )
    .unwrap();
    Some(d)
}

fn corpus(dir: &Path, out: &Path, extra: &[&str]) -> (i32, String, String) {
    corpus_at(dir, out, SIZE, extra)
}

fn corpus_at(dir: &Path, out: &Path, size: &str, extra: &[&str]) -> (i32, String, String) {
    let (d, o) = (dir.to_str().unwrap(), out.to_str().unwrap());
    let mut args = vec![
        "corpus",
        d,
        "--out",
        o,
        "--size",
        size,
        "--methods",
        METHODS,
    ];
    args.push("--no-isa");
    args.extend_from_slice(extra);
    run(&args)
}

fn merge(shards: &[&Path], out: &Path) -> (i32, String, String) {
    let mut args = vec!["merge".to_string()];
    args.extend(shards.iter().map(|p| p.display().to_string()));
    args.extend(["--out".to_string(), out.display().to_string()]);
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    run(&a)
}

/// Every file under `dir`/meshes, relative path and bytes, sorted.
fn mesh_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v = Vec::new();
    let meshes = dir.join("meshes");
    for e in std::fs::read_dir(&meshes).unwrap() {
        let p = e.unwrap().path().join("result.json");
        let rel = p.strip_prefix(dir).unwrap().display().to_string();
        v.push((rel, std::fs::read(&p).unwrap()));
    }
    v.sort();
    v
}

#[test]
fn shards_merge_to_the_unsharded_run() {
    let Some(c) = small_corpus() else { return };
    let t = tempfile::tempdir().unwrap();
    let (one, merged1, merged3) = (
        t.path().join("one"),
        t.path().join("m1"),
        t.path().join("m3"),
    );
    let (code, _, err) = corpus(c.path(), &one, &[]);
    assert_eq!(code, 1, "a failed mesh makes the exit code 1: {err}");
    assert!(err.contains("shard 1/1 (from none)"), "{err}");
    let shards: Vec<PathBuf> = (1..=3).map(|k| t.path().join(format!("s{k}"))).collect();
    for (k, s) in shards.iter().enumerate() {
        let (code, _, err) = corpus(c.path(), s, &["--shard", &format!("{}/3", k + 1)]);
        assert!(code == 0 || code == 1, "{err}");
        assert!(
            err.contains(&format!("shard {}/3 (from --shard)", k + 1)),
            "{err}"
        );
    }
    let refs: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    let (code, _, err) = merge(&refs, &merged3);
    assert_eq!(code, 1, "merge exits 1 when a mesh failed: {err}");
    assert_eq!(merge(&[&one], &merged1).0, 1);
    let (a, b) = (mesh_files(&merged1), mesh_files(&merged3));
    assert_eq!(a.len(), 3);
    assert!(a == b, "per-mesh results differ between 1 and 3 shards");
    // The corrupt OBJ is recorded with its error; the others have figures.
    let broken = read_json(merged3.join("meshes/broken.obj/result.json"));
    assert_eq!(broken["status"], "failed");
    let e = broken["error"].as_str().unwrap();
    assert!(
        e.starts_with("broken.obj:2:"),
        "the error names the mesh and line: {e}"
    );
    let ok = read_json(merged3.join("meshes/sub__teapot.obj/result.json"));
    assert_eq!(ok["summary"]["methods"].as_array().unwrap().len(), 4);
    // The tables are the same too, and match their schemas (with teeth).
    let (j1, j3) = (
        read_json(merged1.join("corpus.json")),
        read_json(merged3.join("corpus.json")),
    );
    assert_eq!(j1["methods"], j3["methods"]);
    assert_eq!(j1["answer"], j3["answer"]);
    assert_eq!(j3["failed"][0]["id"], "broken.obj");
    assert_schema(
        &j3,
        "docs/corpus.schema.json",
        "/methods/0",
        "distributions",
    );
    assert_schema(&j3, "docs/corpus.schema.json", "/answer", "cells");
    // The answer part has the report's fields (one implementation): answer.json's schema.
    assert_schema(
        &j3["answer"],
        "docs/answer.schema.json",
        "/checks/0",
        "meets",
    );
    let m = read_json(shards[0].join("manifest.json"));
    assert_schema(&m, "docs/corpus-manifest.schema.json", "", "config_hash");
    for f in ["corpus.csv", "index.html"] {
        let text = std::fs::read_to_string(merged3.join(f)).unwrap();
        assert!(text.contains("newton_raphson"), "{f}");
    }
    // Teeth: another size gives other per-mesh bytes.
    let other = t.path().join("other");
    assert_eq!(corpus_at(c.path(), &other, "40x40", &[]).0, 1);
    assert!(mesh_files(&other) != mesh_files(&one));
}

#[test]
fn merge_refuses_missing_duplicated_and_mismatched_shards() {
    let Some(c) = small_corpus() else { return };
    let t = tempfile::tempdir().unwrap();
    let s: Vec<PathBuf> = (1..=3).map(|k| t.path().join(format!("s{k}"))).collect();
    for (k, d) in s.iter().enumerate() {
        corpus(c.path(), d, &["--shard", &format!("{}/3", k + 1)]);
    }
    let out = t.path().join("m");
    let (code, _, err) = merge(&[&s[0], &s[2]], &out);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("shard 2/3 missing"), "{err}");
    let (code, _, err) = merge(&[&s[0], &s[1], &s[1], &s[2]], &out);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("shard 2/3 given twice"), "{err}");
    let odd = t.path().join("odd");
    assert!(corpus_at(c.path(), &odd, "40x40", &["--shard", "2/3"]).0 <= 1);
    let (code, _, err) = merge(&[&s[0], &odd, &s[2]], &out);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&odd.display().to_string()) && err.contains("width"),
        "{err}"
    );
    let (code, _, err) = merge(&[&s[0], t.path(), &s[2]], &out);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no manifest.json"), "{err}");
    // The three right ones merge.
    assert!(merge(&[&s[2], &s[0], &s[1]], &out).0 <= 1);
}

#[test]
fn a_restarted_shard_keeps_what_it_finished() {
    let Some(c) = small_corpus() else { return };
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("o");
    corpus(c.path(), &out, &[]);
    let suz = out.join("meshes/suzanne.obj/result.json");
    let before = std::fs::metadata(&suz).unwrap().modified().unwrap();
    // Change the teapot's content: it is done again, suzanne is kept, broken retried.
    let mut teapot = std::fs::read(c.path().join("sub/teapot.obj")).unwrap();
    teapot.extend_from_slice(b"\n# changed\n");
    std::fs::write(c.path().join("sub/teapot.obj"), teapot).unwrap();
    let (code, _, err) = corpus(c.path(), &out, &[]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("suzanne.obj kept (finished earlier)"), "{err}");
    assert!(
        err.contains("sub/teapot.obj ok in"),
        "the changed mesh is redone: {err}"
    );
    assert!(err.contains("broken.obj failed"), "{err}");
    assert_eq!(std::fs::metadata(&suz).unwrap().modified().unwrap(), before);
}

/// The daemons of a single-node Slurm on localhost, stopped by their process ids on drop.
struct Slurm {
    dir: tempfile::TempDir,
    children: Vec<Child>,
}

impl Drop for Slurm {
    fn drop(&mut self) {
        for c in self.children.iter_mut().rev() {
            let _ = Command::new("kill").arg(c.id().to_string()).status();
            let _ = c.wait();
        }
    }
}

/// Whether this machine can run Slurm; `None` with a SKIPPED line, or a failure under
/// SHADELAB_REQUIRE_SLURM=1 (which .ci/run sets).
fn slurm_available() -> Option<()> {
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let root = Command::new("id")
        .arg("-u")
        .output()
        .map(|o| o.stdout == b"0\n")
        .unwrap_or(false);
    let tools = [
        "munged",
        "mungekey",
        "slurmctld",
        "slurmd",
        "sbatch",
        "squeue",
    ]
    .iter()
    .all(|t| {
        Command::new("sh")
            .args(["-c", &format!("command -v {t}")])
            .stdout(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    });
    if root && tools {
        return Some(());
    }
    let why = if root {
        "no slurm-wlm/munge (scripts/install-deps.sh test installs them)"
    } else {
        "not root"
    };
    if std::env::var("SHADELAB_REQUIRE_SLURM").as_deref() == Ok("1") {
        panic!("{test}: SHADELAB_REQUIRE_SLURM=1 but {why}");
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED: {test}: {why}");
    None
}

fn spawn(slurm: &mut Slurm, cmd: &mut Command) {
    let log = std::fs::File::create(
        slurm
            .dir
            .path()
            .join(format!("log{}.txt", slurm.children.len())),
    )
    .unwrap();
    let child = cmd
        .stdout(log.try_clone().unwrap())
        .stderr(log)
        .spawn()
        .expect("start a daemon");
    slurm.children.push(child);
}

/// munged, slurmctld and slurmd in the foreground under a scratch folder (TOOLCHAIN.md).
fn start_slurm() -> Slurm {
    let mut s = Slurm {
        dir: tempfile::tempdir().unwrap(),
        children: Vec::new(),
    };
    let d = s.dir.path().to_path_buf();
    for sub in ["munge", "spool", "state"] {
        std::fs::create_dir_all(d.join(sub)).unwrap();
    }
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(d.join("munge"), std::fs::Permissions::from_mode(0o711)).unwrap();
    let key = d.join("munge.key");
    assert!(Command::new("mungekey")
        .arg("--create")
        .arg(format!("--keyfile={}", key.display()))
        .status()
        .unwrap()
        .success());
    let socket = d.join("munge/munge.socket.2");
    let p = |x: &str| d.join(x).display().to_string();
    spawn(
        &mut s,
        Command::new("munged")
            .args(["-F", "--force"])
            .arg(format!("--key-file={}", key.display()))
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--pid-file={}", p("munged.pid")))
            .arg(format!("--seed-file={}", p("munged.seed")))
            .arg(format!("--log-file={}", p("munged.log"))),
    );
    let host = String::from_utf8(Command::new("hostname").output().unwrap().stdout)
        .unwrap()
        .trim()
        .to_string();
    let node =
        String::from_utf8(Command::new("slurmd").arg("-C").output().unwrap().stdout).unwrap();
    let node = node
        .lines()
        .next()
        .unwrap()
        .split(" UpTime")
        .next()
        .unwrap()
        .to_string();
    // Ports of their own (a Slurm already on 6817/6818 would make slurmctld exit), and a short
    // message timeout: a daemon that is down fails sinfo in seconds, not Slurm's default ten.
    let (ctld_port, d_port) = (free_port(), free_port());
    let conf = format!(
        "ClusterName=shadelab\nSlurmctldHost={host}(127.0.0.1)\nSlurmUser=root\nSlurmdUser=root\n\
         SlurmctldPort={ctld_port}\nSlurmdPort={d_port}\nMessageTimeout=3\n\
         AuthType=auth/munge\nAuthInfo=socket={sock}\nProctrackType=proctrack/linuxproc\n\
         TaskPlugin=task/none\nAccountingStorageType=accounting_storage/none\n\
         JobAcctGatherType=jobacct_gather/none\nMailProg=/bin/true\nSelectType=select/cons_tres\n\
         SelectTypeParameters=CR_Core\nStateSaveLocation={state}\nSlurmdSpoolDir={spool}\n\
         SlurmctldPidFile={cpid}\nSlurmdPidFile={dpid}\nSlurmctldLogFile={clog}\nSlurmdLogFile={dlog}\n\
         {node} NodeAddr=127.0.0.1 State=UNKNOWN\nPartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
        sock = socket.display(), state = p("state"), spool = p("spool"), cpid = p("slurmctld.pid"),
        dpid = p("slurmd.pid"), clog = p("slurmctld.log"), dlog = p("slurmd.log"),
    );
    std::fs::write(d.join("slurm.conf"), conf).unwrap();
    // The job needs no cgroups (linuxproc, task/none), but slurmd from Slurm 24 on sets up its
    // cgroup plugin anyway and exits where the cgroup tree is not one it knows (a chroot, a
    // container, a hybrid v1/v2 host): "Unable to initialize cgroup plugin". CgroupPlugin=disabled
    // exists from Slurm 24.05 on (cgroup.conf(5) of 24.05, absent from 23.11's).
    if slurm_version() >= (24, 5) {
        std::fs::write(d.join("cgroup.conf"), "CgroupPlugin=disabled\n").unwrap();
    }
    for _ in 0..50 {
        if socket.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let conf = d.join("slurm.conf");
    spawn(
        &mut s,
        Command::new("slurmctld")
            .args(["-D", "-i"])
            .env("SLURM_CONF", &conf),
    );
    spawn(
        &mut s,
        Command::new("slurmd")
            .args(["-D", "-N", &host])
            .env("SLURM_CONF", &conf),
    );
    // Up in about 1 s here (TOOLCHAIN.md); a daemon that exits fails at once with its log, a
    // node not idle within 60 s with the logs.
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while std::time::Instant::now() < deadline {
        if let Some(why) = daemon_exited(&mut s) {
            panic!("{why}");
        }
        let o = Command::new("sinfo")
            .args(["-h", "-o", "%t"])
            .env("SLURM_CONF", &conf)
            .output()
            .unwrap();
        if String::from_utf8_lossy(&o.stdout).trim() == "idle" {
            return s;
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    panic!(
        "the Slurm node was not idle within 60 s; logs in {}:\n{}",
        d.display(),
        log_tails(&d)
    );
}

/// Slurm's (major, minor) version, from `slurmd -V` ("slurm 22.05.8", "slurm-wlm 24.11.5").
fn slurm_version() -> (u32, u32) {
    let out = Command::new("slurmd")
        .arg("-V")
        .output()
        .expect("run slurmd -V");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    parse_slurm_version(&text).unwrap_or_else(|| panic!("slurmd -V printed {text:?}"))
}

fn parse_slurm_version(text: &str) -> Option<(u32, u32)> {
    let v = text.split_whitespace().nth(1)?;
    let mut parts = v.split('.');
    Some((parts.next()?.parse().ok()?, parts.next()?.parse().ok()?))
}

#[test]
fn slurm_versions_are_read_from_both_package_names() {
    assert_eq!(parse_slurm_version("slurm 22.05.8\n"), Some((22, 5)));
    assert_eq!(parse_slurm_version("slurm-wlm 24.11.5\n"), Some((24, 11)));
    assert!(parse_slurm_version("slurm-wlm 24.11.5") >= Some((24, 5)));
    // Teeth: 23.11 is older than 24.05, and text without a version is none.
    assert!(parse_slurm_version("slurm 23.11.4") < Some((24, 5)));
    assert_eq!(parse_slurm_version("slurmd: command not found"), None);
}

/// A port free on 127.0.0.1 now (the kernel's pick).
fn free_port() -> u16 {
    let l = std::net::TcpListener::bind("127.0.0.1:0").expect("bind a free port");
    l.local_addr().unwrap().port()
}

/// The last lines of every log of the scratch folder `d`.
fn log_tails(d: &std::path::Path) -> String {
    let mut out = String::new();
    let mut logs: Vec<_> = std::fs::read_dir(d)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    logs.sort();
    for p in logs.iter().filter(|p| p.to_string_lossy().contains("log")) {
        let text = std::fs::read_to_string(p).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        let tail = lines[lines.len().saturating_sub(5)..].join("\n");
        out += &format!("{}:\n{tail}\n", p.display());
    }
    out
}

/// Which daemon (munged, slurmctld, slurmd) has exited, with its status and the logs.
fn daemon_exited(s: &mut Slurm) -> Option<String> {
    let names = ["munged", "slurmctld", "slurmd"];
    for (name, child) in names.iter().zip(s.children.iter_mut()) {
        if let Ok(Some(status)) = child.try_wait() {
            return Some(format!(
                "{name} exited ({status}) before the node was idle:\n{}",
                log_tails(s.dir.path())
            ));
        }
    }
    None
}

#[test]
fn the_slurm_example_runs_a_job_array_and_merges() {
    if slurm_available().is_none() {
        return;
    }
    let Some(c) = small_corpus() else { return };
    let slurm = start_slurm();
    let conf = slurm.dir.path().join("slurm.conf");
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("slurm");
    let o = Command::new(support::root().join("docs/examples/corpus-slurm.sh"))
        .args([c.path(), &out])
        .arg("3")
        .env("SLURM_CONF", &conf)
        .env("SHADELAB", env!("CARGO_BIN_EXE_shadelab"))
        .env("SHADELAB_SIZE", SIZE)
        .env("SHADELAB_METHODS", METHODS)
        .env("SHADELAB_CORPUS_ARGS", "--no-isa")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let jobs: Vec<String> = text
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1))
        .map(String::from)
        .collect();
    assert_eq!(jobs.len(), 2, "{text}");
    let start = std::time::Instant::now();
    loop {
        let q = Command::new("squeue")
            .args(["-h", "-j", &jobs.join(",")])
            .env("SLURM_CONF", &conf)
            .output()
            .unwrap();
        if String::from_utf8_lossy(&q.stdout).trim().is_empty() {
            break;
        }
        assert!(
            start.elapsed().as_secs() < 300,
            "the jobs did not end in 300 s: {}",
            String::from_utf8_lossy(&q.stdout)
        );
        std::thread::sleep(std::time::Duration::from_millis(500));
    }
    let merged = out.join("merged");
    assert!(
        merged.join("corpus.json").is_file(),
        "no merge output; logs in {}",
        out.display()
    );
    for k in 1..=3 {
        let m = read_json(out.join(format!("shard-{k}/manifest.json")));
        assert_eq!(
            m["shard"]["source"],
            "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT"
        );
        assert_eq!(m["shard"]["k"], k);
    }
    let one = t.path().join("one");
    corpus(c.path(), &one, &[]);
    let m1 = t.path().join("m1");
    merge(&[&one], &m1);
    assert!(
        mesh_files(&merged) == mesh_files(&m1),
        "Slurm's merged figures differ from an unsharded run"
    );
    drop(slurm);
}

/// The Slurm start fails fast with the cause: a daemon that exited (a port taken, a bad
/// configuration) is named with its log at the next poll, never waited on for minutes; one
/// still running is not.
#[test]
fn a_slurm_daemon_that_exits_is_reported_at_once() {
    let mut s = Slurm {
        dir: tempfile::tempdir().unwrap(),
        children: Vec::new(),
    };
    spawn(&mut s, Command::new("sleep").arg("30"));
    std::thread::sleep(std::time::Duration::from_millis(100));
    assert_eq!(daemon_exited(&mut s), None);
    spawn(
        &mut s,
        Command::new("sh").args(["-c", "echo 'bind: Address already in use'; exit 1"]),
    );
    let start = std::time::Instant::now();
    let why = loop {
        if let Some(why) = daemon_exited(&mut s) {
            break why;
        }
        assert!(start.elapsed().as_secs() < 10, "the exit was not seen");
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    assert!(why.starts_with("slurmctld exited"), "{why}");
    assert!(why.contains("Address already in use"), "{why}");
    let p = free_port();
    assert!(std::net::TcpListener::bind(("127.0.0.1", p)).is_ok(), "{p}");
}
