//! Compiler workers (src/workers/): on every family set up, a warm worker's figures equal a
//! fresh child's, bit for bit; a worker that hangs is stopped at its deadline, one killed in the
//! middle of a request fails that request alone and the next one succeeds, one past its memory
//! cap is stopped; idle workers beyond the bound go, the least recently used first; kill -9 of
//! `isa` leaves no worker running.
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use shadelab::child::Spawn;
use shadelab::isa::{self, ChildRequest, IsaReport, Precision};
use shadelab::workers::{Limits, Pool};

use crate::hostile::{children_seen, kill_and_check_children_gone, running};
use crate::isa::families_ready;
use crate::store::{same_figures, set_up_families};

fn exe() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_shadelab"))
}

/// isa.json of `shadelab isa` with one child per request (`SHADELAB_NO_WORKERS=1`), with its
/// disassembly read back from the files it lists.
fn fresh_children(families: &[String], methods: &str, out: &Path) -> IsaReport {
    let status = std::process::Command::new(exe())
        .args([
            "isa",
            "--no-cache",
            "-q",
            "--methods",
            methods,
            "--families",
        ])
        .arg(families.join(","))
        .arg("--out")
        .arg(out)
        .env("SHADELAB_NO_WORKERS", "1")
        .status()
        .unwrap();
    assert!(status.success());
    let mut r = isa::files::read(&out.join("isa.json")).unwrap();
    let listed = serde_json::to_value(&r).unwrap()["asm"].clone();
    r.disassembly = listed
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let p = p.as_str().unwrap().to_string();
            let text = std::fs::read_to_string(out.join(&p)).unwrap();
            (p, text)
        })
        .collect();
    r
}

/// On every family set up, the workers' figures (a first request, then the same request on
/// the warm workers) equal those of one fresh child per family; teeth: one statistic changed
/// is told apart.
#[test]
fn workers_give_a_fresh_childs_figures_on_every_family() {
    let families = set_up_families("workers::workers_give_a_fresh_childs_figures_on_every_family");
    if families.is_empty() {
        return;
    }
    let methods = ["gouraud", "phong_exact"];
    let dir = tempfile::tempdir().unwrap();
    let fresh = fresh_children(&families, &methods.join(","), dir.path());
    let opts = isa::IsaOptions {
        methods: methods
            .iter()
            .map(|m| shadelab::method::find(m).unwrap())
            .collect(),
        families: families.clone(),
        driver_files: None,
        scene: None,
        exe: exe(),
        precision: Precision::F32,
        probes: Vec::new(),
        store: None,
    };
    let first = isa::run(&opts, &|_| {}).unwrap();
    let warm = isa::run(&opts, &|_| {}).unwrap();
    assert!(!fresh.supported().is_empty(), "{:#?}", fresh.families);
    assert_eq!(first.supported(), fresh.supported());
    same_figures(&fresh, &first).unwrap();
    same_figures(&fresh, &warm).unwrap();
    let mut doctored = warm.clone();
    let row = doctored.results.first_mut().unwrap();
    let v = row.statistics.values_mut().next().unwrap();
    *v += 1.0;
    assert!(
        same_figures(&fresh, &doctored).is_err(),
        "a changed figure went unnoticed"
    );
}

/// The request and the worker environment of `family` (under the driver's first name for the chip).
fn family_request(family: &str, methods: &[&str]) -> (Spawn, ChildRequest) {
    let f = isa::families(&[family.to_string()]).unwrap()[0];
    let setup = f.vendor.setup_for(f.chip, None).unwrap();
    let name = f.vendor.driver_chips(f.chip, &setup)[0].clone();
    let spawn = Spawn {
        exe: exe(),
        driver_env: f.vendor.child_env(&name, &setup, None).unwrap(),
        method_files: Vec::new(),
        show_stderr: false,
    };
    let req = ChildRequest {
        family: f.id(),
        methods: methods.iter().map(|m| m.to_string()).collect(),
        scene: None,
        kernel_counts: isa::KERNEL_COUNTS,
        probes: Vec::new(),
        precision: Precision::F32,
        draws_only: false,
    };
    (spawn, req)
}

/// Every method of the table: a request of a second or more on any family.
fn all_methods() -> Vec<&'static str> {
    shadelab::method::METHODS.iter().map(|m| m.name).collect()
}

const FAMILY: &str = "amd:navi21";

fn ready(test: &str) -> bool {
    families_ready(test, &[FAMILY], "SHADELAB_REQUIRE_VENDORS")
}

/// A worker that never answers (a program that sleeps, in a worker's place) is stopped at the
/// deadline with a reason that says so, within two seconds of it; the pool then serves the next
/// request. The deadline (4 s) is the one both requests run under: the next one starts a cold
/// worker, which took over a second on a loaded 2-core CI machine.
#[test]
fn a_worker_that_hangs_is_stopped_at_its_deadline_and_the_next_request_is_served() {
    if !ready("workers::a_worker_that_hangs_is_stopped_at_its_deadline") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let hang = dir.path().join("hang.sh");
    std::fs::write(&hang, "#!/bin/sh\nexec sleep 60\n").unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&hang, std::fs::Permissions::from_mode(0o755)).unwrap();
    let pool = Pool::new(Limits {
        deadline: Duration::from_secs(4),
        ..Limits::default()
    });
    let (spawn, req) = family_request(FAMILY, &["phong_exact"]);
    let hung = Spawn {
        exe: hang,
        ..spawn.clone()
    };
    let start = Instant::now();
    let f = pool.call(&hung, &req, dir.path(), "hang").unwrap_err();
    let took = start.elapsed();
    assert!(f.stopped, "{f}");
    assert!(
        f.why.contains("no reply in 4.0 s: the worker was stopped"),
        "{f}"
    );
    assert!(
        (Duration::from_secs(4)..Duration::from_secs(6)).contains(&took),
        "{took:?}"
    );
    let r = pool.call(&spawn, &req, dir.path(), "next").unwrap();
    assert!(!r.compiled.is_empty());
    assert_eq!(pool.started(), 2);
}

/// A worker killed (SIGKILL) in the middle of a request fails that request with how it ended,
/// as stopped (not the driver's answer); the next request starts a new worker and succeeds.
/// One killed while idle is replaced before the next request is sent.
#[test]
fn a_worker_killed_mid_request_fails_that_request_and_the_next_succeeds() {
    if !ready("workers::a_worker_killed_mid_request_fails_that_request") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let pool = Pool::new(Limits::default());
    let (spawn, small) = family_request(FAMILY, &["phong_exact"]);
    let (_, big) = family_request(FAMILY, &all_methods());
    pool.call(&spawn, &small, dir.path(), "warm").unwrap();
    let pid = pool.idle_pids()[0];
    let killer = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(100));
        // SAFETY: a signal to a process this test started.
        unsafe { libc::kill(pid as libc::pid_t, libc::SIGKILL) };
    });
    let f = pool.call(&spawn, &big, dir.path(), "big").unwrap_err();
    killer.join().unwrap();
    assert!(f.stopped, "{f}");
    assert!(f.why.contains("killed by signal 9 (SIGKILL)"), "{f}");
    let r = pool.call(&spawn, &small, dir.path(), "after").unwrap();
    assert_eq!(
        r.compiled
            .iter()
            .filter(|c| c.method == "phong_exact")
            .count(),
        3
    );
    assert_eq!(pool.started(), 2);
    // killed idle: replaced, and the request succeeds
    let idle = pool.idle_pids()[0];
    // SAFETY: as above.
    unsafe { libc::kill(idle as libc::pid_t, libc::SIGKILL) };
    std::thread::sleep(Duration::from_millis(100));
    pool.call(&spawn, &small, dir.path(), "replaced").unwrap();
    assert_eq!(pool.started(), 3);
}

/// A worker past its memory cap is stopped, the request failing with its size and the cap.
#[test]
fn a_worker_past_its_memory_cap_is_stopped() {
    if !ready("workers::a_worker_past_its_memory_cap_is_stopped") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let pool = Pool::new(Limits {
        memory: 1 << 20,
        ..Limits::default()
    });
    let (spawn, big) = family_request(FAMILY, &all_methods());
    let f = pool.call(&spawn, &big, dir.path(), "big").unwrap_err();
    assert!(f.stopped, "{f}");
    assert!(f.why.contains("past the cap of 1 MiB"), "{f}");
    assert!(pool.idle_pids().is_empty());
}

/// Idle workers beyond the bound are stopped, the least recently used first.
#[test]
fn idle_workers_beyond_the_bound_go_least_recently_used_first() {
    let other = "intel:tgl";
    if !families_ready(
        "workers::idle_workers_beyond_the_bound_go_least_recently_used_first",
        &[FAMILY, other],
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let pool = Pool::new(Limits {
        max_idle: 1,
        ..Limits::default()
    });
    let (a, ra) = family_request(FAMILY, &["phong_exact"]);
    let (b, rb) = family_request(other, &["phong_exact"]);
    pool.call(&a, &ra, dir.path(), "a").unwrap();
    let first = pool.idle_pids();
    pool.call(&b, &rb, dir.path(), "b").unwrap();
    let second = pool.idle_pids();
    assert_eq!((first.len(), second.len()), (1, 1));
    assert_ne!(first, second, "the older worker stays");
    std::thread::sleep(Duration::from_millis(100));
    assert!(!running(first[0]), "the stopped worker still runs");
    pool.stop_idle();
}

/// kill -9 of `isa` while its workers compile leaves none of them running.
#[test]
fn a_killed_isa_leaves_no_worker_running() {
    if !ready("workers::a_killed_isa_leaves_no_worker_running") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut isa = std::process::Command::new(exe())
        .args(["isa", "--no-cache", "-q", "--out"])
        .arg(dir.path().join("out"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let workers = children_seen(&mut isa, "child --worker", Duration::from_secs(120));
    kill_and_check_children_gone(&mut isa, &workers);
}
