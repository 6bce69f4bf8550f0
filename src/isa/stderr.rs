//! The compiler statistics a Vulkan driver prints on stderr, caught in an `isa` child
//! ([`super::route::Vendor::statistics_on_stderr`]: asahi's Honeykrisp, whose pipeline
//! statistics are a code size and a register count while `AGX_MESA_DEBUG=shaderdb` prints the
//! compiler's cycle model, one "SHADER-DB: <label> - <stage> shader: ..." line per program).
//! [`capture`] points file descriptor 2 at a temporary file while one compile runs, then puts
//! it back; [`merge`] adds each stage's last line to that stage's executable. The child compiles
//! on one thread, so every line printed during a capture is that compile's.
use std::io::{Read, Seek, Write};
use std::os::fd::AsRawFd;

use crate::error::{Error, Result};
use crate::gpu::vk::{Executable, StatValue, Statistic};
use crate::isa::route::Vendor;

/// The process's standard output.
const STDOUT: i32 = 1;
/// The process's standard error.
const STDERR: i32 = 2;

extern "C" {
    // POSIX (unistd.h), in the C library every Rust program on Linux links.
    fn dup(fd: i32) -> i32;
    fn dup2(old: i32, new: i32) -> i32;
    fn close(fd: i32) -> i32;
    // C (stdio.h): with a null stream, flushes every output stream (a driver's `printf`s).
    fn fflush(stream: *mut std::ffi::c_void) -> i32;
}

/// Runs `f` with file descriptor `fd` pointed at a temporary file: its result and what was
/// written to `fd` meanwhile (C's buffered streams flushed first).
fn catch_fd<T>(fd: i32, f: impl FnOnce() -> T) -> Result<(T, String)> {
    let io = |e: std::io::Error| Error::Device(format!("catching the driver's output: {e}"));
    let mut file = tempfile::tempfile().map_err(io)?;
    let flush = || {
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().flush();
        // SAFETY: fflush(NULL) flushes every open output stream of the C library; it reads
        // no pointer of ours.
        unsafe { fflush(std::ptr::null_mut()) };
    };
    flush();
    // SAFETY: dup and dup2 only duplicate descriptors: `fd` (1 or 2) is open for the whole
    // process and `file` outlives both calls; the saved copy is put back and closed below on
    // every path.
    let saved = unsafe { dup(fd) };
    if saved < 0 || unsafe { dup2(file.as_raw_fd(), fd) } < 0 {
        return Err(io(std::io::Error::last_os_error()));
    }
    let out = f();
    flush();
    // SAFETY: `saved` is the descriptor dup returned above, still open; restoring it makes
    // `fd` the original stream again, then the copy is closed.
    let restored = unsafe { dup2(saved, fd) >= 0 && close(saved) == 0 };
    if !restored {
        return Err(io(std::io::Error::last_os_error()));
    }
    let mut text = String::new();
    file.rewind().map_err(io)?;
    file.read_to_string(&mut text).map_err(io)?;
    Ok((out, text))
}

/// Runs `f` with stderr and stdout caught: its result and what was printed on either
/// meanwhile, stderr first (Mesa's `MESA_GLSL=dump` prints its IR on stderr).
pub fn capture_text<T>(f: impl FnOnce() -> T) -> Result<(T, String)> {
    let (inner, text) = catch_fd(STDOUT, || catch_fd(STDERR, f))?;
    let (out, err) = inner?;
    Ok((out, format!("{err}{text}")))
}

/// Runs `f` with stderr caught: its result and the lines printed meanwhile. The lines that
/// `keep` refuses are printed again on the restored stderr (a driver's warning stays visible).
pub fn capture<T>(keep: impl Fn(&str) -> bool, f: impl FnOnce() -> T) -> Result<(T, Vec<String>)> {
    let (out, text) = catch_fd(STDERR, f)?;
    let (kept, others): (Vec<&str>, Vec<&str>) = text.lines().partition(|l| keep(l));
    for l in others {
        eprintln!("{l}");
    }
    Ok((out, kept.into_iter().map(str::to_string).collect()))
}

/// `exes` with, for each executable, the statistics of the last line of `lines` that the
/// vendor reads as its stage's; an error naming the stage when a stage has none (the driver
/// printed nothing for it: nothing is measured).
pub fn merge(
    vendor: &dyn Vendor,
    program: &str,
    mut exes: Vec<Executable>,
    lines: &[String],
) -> Result<Vec<Executable>> {
    let parsed: Vec<(String, Vec<(String, f64)>)> = lines
        .iter()
        .filter_map(|l| vendor.parse_debug_message(l))
        .collect();
    for e in &mut exes {
        let (_, stats) = parsed
            .iter()
            .rev()
            .find(|(stage, _)| *stage == e.stage)
            .ok_or_else(|| {
                Error::Device(format!(
                    "{program}: the driver printed no statistics for the {} shader (lines: \
                     {lines:?})",
                    e.stage
                ))
            })?;
        e.statistics.extend(stats.iter().map(|(name, v)| Statistic {
            name: name.clone(),
            description: "the compiler's shader-db line".into(),
            value: StatValue::Float(*v),
        }));
    }
    Ok(exes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::isa::route::apple::Apple;

    fn exe(stage: &str) -> Executable {
        Executable {
            name: stage.into(),
            description: String::new(),
            stage: stage.into(),
            subgroup_size: 32,
            statistics: Vec::new(),
            representations: Vec::new(),
        }
    }

    #[test]
    fn a_compile_s_stderr_is_caught_and_put_back() {
        // Straight to fd 2, as a driver writes (the test harness captures eprintln! itself);
        // the lines carry a marker, since tests running beside this one write to fd 2 too.
        let say = |l: &str| writeln!(std::io::stderr(), "{l}").unwrap();
        let (v, lines) = capture(
            |l| l.starts_with("SHADER-DB: stderr-test"),
            || {
                say("SHADER-DB: stderr-test - MESA_SHADER_FRAGMENT shader: 5 inst");
                say("stderr-test: a warning that stays visible");
                7
            },
        )
        .unwrap();
        assert_eq!(v, 7);
        assert_eq!(
            lines,
            ["SHADER-DB: stderr-test - MESA_SHADER_FRAGMENT shader: 5 inst"]
        );
        // stderr is stderr again: a second capture sees only its own lines.
        let (_, lines) = capture(
            |l| l.starts_with("SHADER-DB: stderr-test"),
            || say("SHADER-DB: stderr-test second"),
        )
        .unwrap();
        assert_eq!(lines, ["SHADER-DB: stderr-test second"]);
    }

    #[test]
    fn each_stage_takes_its_last_line() {
        let line = |stage: &str, inst: u32| {
            format!(
                "SHADER-DB:  - MESA_SHADER_{stage} shader: {inst} inst, 8 alu, 8 fscib, 2 ic, \
                 96 bytes, 10 regs, 0 uniforms, 0 scratch, 1024 threads, 0 loops, 0:0 \
                 spills:fills"
            )
        };
        let lines = vec![
            line("FRAGMENT", 3),
            line("VERTEX", 11),
            line("FRAGMENT", 42),
        ];
        let exes = merge(&Apple, "p", vec![exe("vertex"), exe("fragment")], &lines).unwrap();
        let inst = |e: &Executable| {
            e.statistics
                .iter()
                .find(|s| s.name == "inst")
                .map(|s| s.value)
        };
        assert_eq!(inst(&exes[0]), Some(StatValue::Float(11.0)));
        assert_eq!(inst(&exes[1]), Some(StatValue::Float(42.0)));
        // Teeth: a stage the driver printed nothing for fails, naming it.
        let why = merge(&Apple, "p", vec![exe("compute")], &lines)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(
            why.contains("no statistics for the compute shader"),
            "{why}"
        );
    }
}
