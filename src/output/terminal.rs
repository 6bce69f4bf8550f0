//! What the terminal shows: the library reports progress and notes through `log`'s macros
//! (`log::info!` for a job's progress, `log::debug!` for detail, `log::warn!` for what the user
//! must read), and the binary installs [`Terminal`] with the level its command and `-v`/`-q`
//! ask for. A job run inside another (bench inside `report`) then stays as quiet as the outer
//! command wants, and a child process gets its parent's level in its request (src/child.rs).
//!
//! Lines go to stderr as they are, one per record (stdout is kept for a command's result, such
//! as the report's path). While a progress bar is drawn ([`show_bar`]), a line is printed above
//! it rather than through it: the logger suspends the bar for the line, so nothing may log
//! inside the bar's own `suspend` (it holds the bar's lock: a deadlock).
use std::io::Write as _;
use std::sync::Mutex;

/// The logger of the `shadelab` binary.
pub struct Terminal {
    bar: Mutex<Option<indicatif::ProgressBar>>,
}

static TERMINAL: Terminal = Terminal {
    bar: Mutex::new(None),
};

impl log::Log for Terminal {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::max_level()
    }

    fn log(&self, record: &log::Record) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let line = match record.level() {
            log::Level::Warn | log::Level::Error => format!("shadelab: warning: {}", record.args()),
            _ => record.args().to_string(),
        };
        let bar = self.bar.lock().ok().and_then(|b| b.clone());
        match bar {
            Some(b) if !b.is_hidden() && !b.is_finished() => b.suspend(|| eprintln_ok(&line)),
            _ => eprintln_ok(&line),
        }
    }

    fn flush(&self) {
        let _ = std::io::stderr().flush();
    }
}

/// Writes one line to stderr; a closed stderr (a reader that went away) is not an error.
fn eprintln_ok(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// Installs the terminal logger (once per process; later calls only change the level) and
/// shows records up to `level`.
pub fn init(level: log::LevelFilter) {
    // Err means a logger is already installed (a second call, or a test harness's): keep it.
    let _ = log::set_logger(&TERMINAL);
    log::set_max_level(level);
}

/// Lines logged while `bar` is drawn go above it; `None` when the bar is done.
pub fn show_bar(bar: Option<indicatif::ProgressBar>) {
    if let Ok(mut b) = TERMINAL.bar.lock() {
        *b = bar;
    }
}

/// The level of a command: `base` (what the command shows by default) raised by each `-v` and
/// lowered by each `-q`, from errors only (`Error`) to everything (`Trace`).
pub fn level(base: log::LevelFilter, verbose: u8, quiet: u8) -> log::LevelFilter {
    const ORDER: [log::LevelFilter; 5] = [
        log::LevelFilter::Error,
        log::LevelFilter::Warn,
        log::LevelFilter::Info,
        log::LevelFilter::Debug,
        log::LevelFilter::Trace,
    ];
    let at = ORDER.iter().position(|l| *l == base).unwrap_or(2) as i32;
    let i = (at + i32::from(verbose) - i32::from(quiet)).clamp(0, ORDER.len() as i32 - 1);
    ORDER[i as usize]
}

#[cfg(test)]
mod tests {
    use super::*;
    use log::LevelFilter::*;

    #[test]
    fn each_v_shows_more_and_each_q_less_within_the_levels() {
        assert_eq!(level(Info, 0, 0), Info);
        assert_eq!(level(Warn, 1, 0), Info);
        assert_eq!(level(Warn, 2, 0), Debug);
        assert_eq!(level(Info, 0, 1), Warn);
        assert_eq!(level(Info, 9, 0), Trace);
        // never below errors: -q cannot hide why a command failed
        assert_eq!(level(Info, 0, 9), Error);
        assert_ne!(level(Warn, 1, 0), Warn);
    }
}
