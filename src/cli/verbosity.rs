//! `-v` / `-q`: how much a command tells on stderr ([`crate::output::terminal`]).
use clap::Args;

use super::Command;

/// The global verbosity flags.
#[derive(Args, Debug, Clone, Copy)]
pub(super) struct Verbosity {
    /// Tell more on stderr (repeatable): `report -v` shows each job's progress and every cell
    /// of the answer, `-vv` the detail.
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,
    /// Tell less on stderr (repeatable): warnings only, then errors only.
    #[arg(short, long, action = clap::ArgAction::Count, global = true, conflicts_with = "verbose")]
    quiet: u8,
}

impl Verbosity {
    /// Installs the terminal logger at the level `command` shows by default, moved by the flags.
    /// `report` runs a dozen jobs and answers in a few lines: its jobs' progress is behind `-v`
    /// (its own steps are on its progress bar); every other command shows its progress.
    pub(super) fn init(self, command: &Command) {
        let base = match command {
            Command::Report(_) | Command::Demo(_) => log::LevelFilter::Warn,
            _ => log::LevelFilter::Info,
        };
        crate::output::terminal::init(crate::output::terminal::level(
            base,
            self.verbose,
            self.quiet,
        ));
    }
}
