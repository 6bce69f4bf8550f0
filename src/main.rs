//! The `shadelab` binary: parse, run, print the error once, exit with the documented code
//! (0 ok, 1 a threshold exceeded, 2 usage / input / runtime error).
use std::process::ExitCode;

fn main() -> ExitCode {
    one_malloc_arena();
    // Before any other thread exists: SIGINT/SIGTERM/SIGHUP then clean up (src/cleanup.rs).
    shadelab::cleanup::install();
    match shadelab::cli::run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("shadelab: error: {e}");
            ExitCode::from(shadelab::cli::EXIT_ERROR)
        }
    }
}

/// glibc gives each thread that allocates its own arena, and an arena keeps what it freed:
/// `compare`'s threads (the renderer and two workers, each peaking at a different time, with
/// FLIP's 12 MB float images on the workers) then held each their own peak. One arena
/// shares the freed memory between them: peak RSS of `compare` at 1024x1024 on the fine
/// sphere 543-555 -> 466-496 MB with no more CPU time (docs/history/). The large blocks are
/// taken and freed a few times per method, so the lock costs nothing measurable.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn one_malloc_arena() {
    use std::ffi::c_int;
    extern "C" {
        fn mallopt(param: c_int, value: c_int) -> c_int;
    }
    /// glibc malloc.h
    const M_ARENA_MAX: c_int = -8;
    // SAFETY: glibc's mallopt takes two ints and only sets a tuning parameter; it is called
    // before any other thread exists. A refusal (return 0) leaves the default, which is fine.
    unsafe {
        mallopt(M_ARENA_MAX, 1);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn one_malloc_arena() {}
