//! The library's one error type. Every variant maps to exit code 2 (usage, input or runtime
//! error); exit code 1 (a threshold exceeded) is not an error and never travels through here.
use std::path::PathBuf;

/// Result alias used across the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong, with enough context to say what, where and how to fix it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input file (scene, OBJ, ...): names the file and, where known, the 1-based line.
    #[error("{}: {message}", location(path, *line))]
    Input {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
    /// A file could not be read or written (with what to do for a full disk, a read-only
    /// filesystem or a missing permission).
    #[error("{}: {source}{}", path.display(), io_hint(source))]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A command-line value that makes no sense (bad size, unknown method, ...).
    #[error("{0}")]
    Usage(String),
    /// A Vulkan call returned an error; `call` names the entry point.
    #[error("Vulkan call {call} failed: {result}")]
    Vulkan {
        call: &'static str,
        /// The `VkResult` code's name, e.g. `ERROR_OUT_OF_HOST_MEMORY`.
        result: String,
    },
    /// No usable Vulkan loader / device / layer, with a hint how to get one.
    #[error("{0}")]
    Device(String),
    /// Shader compilation or SPIR-V problems.
    #[error("{0}")]
    Shader(String),
    /// An output could not be produced (serialising JSON, drawing a chart or heatmap);
    /// `what` names the output.
    #[error("cannot write {what}: {message}")]
    Output { what: String, message: String },
    /// A broken internal invariant (a worker thread panicked, a pass returned nothing): a bug
    /// in shadelab, never the user's input.
    #[error("internal error (please report): {0}")]
    Internal(String),
}

/// What to do about the I/O errors a user can fix, also when an encoder wrapped them (its
/// message keeps the system's "(os error N)").
fn io_hint(e: &std::io::Error) -> &'static str {
    use std::io::ErrorKind as K;
    let text = e.to_string();
    let is = |kind: K, code: i32| e.kind() == kind || text.contains(&format!("(os error {code})"));
    // Linux's ENOSPC, EROFS, EACCES (asm-generic/errno-base.h)
    if is(K::StorageFull, 28) {
        ": the disk is full; free space or write elsewhere"
    } else if is(K::ReadOnlyFilesystem, 30) {
        ": the filesystem is read-only; write elsewhere"
    } else if is(K::PermissionDenied, 13) {
        ": no permission; write elsewhere or change the folder's permissions"
    } else {
        ""
    }
}

fn location(path: &std::path::Path, line: Option<usize>) -> String {
    match line {
        Some(l) => format!("{}:{l}", path.display()),
        None => path.display().to_string(),
    }
}

impl Error {
    /// An input error at `path`, optionally at a 1-based `line`.
    pub fn input(
        path: impl Into<PathBuf>,
        line: Option<usize>,
        message: impl Into<String>,
    ) -> Self {
        Error::Input {
            path: path.into(),
            line,
            message: message.into(),
        }
    }

    /// An output named `what` that could not be produced.
    pub fn output(what: impl Into<String>, message: impl std::fmt::Display) -> Self {
        Error::Output {
            what: what.into(),
            message: message.to_string(),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_error_names_file_and_line() {
        let e = Error::input("a/b.obj", Some(12), "bad vertex");
        assert_eq!(e.to_string(), "a/b.obj:12: bad vertex");
        let e = Error::input("a/b.obj", None, "empty mesh");
        assert_eq!(e.to_string(), "a/b.obj: empty mesh");
    }

    #[test]
    fn io_errors_say_what_to_do_when_the_user_can() {
        let e = |code| Error::io("out/x.png", std::io::Error::from_raw_os_error(code)).to_string();
        assert!(
            e(28).ends_with(": the disk is full; free space or write elsewhere"),
            "{}",
            e(28)
        );
        assert!(e(30).contains("read-only; write elsewhere"), "{}", e(30));
        assert!(e(13).contains("no permission"), "{}", e(13));
        assert_eq!(e(2), "out/x.png: No such file or directory (os error 2)");
        // wrapped by an encoder, as the PNG writer's are
        let wrapped = std::io::Error::other(std::io::Error::from_raw_os_error(28));
        assert!(Error::io("x.png", wrapped)
            .to_string()
            .contains("the disk is full"));
    }

    #[test]
    fn output_and_internal_errors_say_what_failed() {
        let e = Error::output("pareto.png", "the font is missing");
        assert_eq!(
            e.to_string(),
            "cannot write pareto.png: the font is missing"
        );
        let e = Error::Internal("a compare worker panicked".into());
        assert_eq!(
            e.to_string(),
            "internal error (please report): a compare worker panicked"
        );
    }
}
