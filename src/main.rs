//! The `shadelab` binary: parse, run, print the error once, exit with the documented code
//! (0 ok, 1 a threshold exceeded, 2 usage / input / runtime error).
use std::process::ExitCode;

fn main() -> ExitCode {
    match shadelab::cli::run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("shadelab: error: {e}");
            ExitCode::from(shadelab::cli::EXIT_ERROR)
        }
    }
}
