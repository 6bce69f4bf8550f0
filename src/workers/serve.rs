//! The worker's side (`shadelab child --worker`): requests read from stdin, one [`Frame`] per
//! line, each answered with one [`Reply`] line on the reply pipe, until stdin closes (the
//! parent is gone or stopped it). The reply pipe is the process's stdout as it started; stdout
//! itself is then the stderr, so that whatever a driver prints cannot break a reply.
use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::os::fd::FromRawFd;

use super::protocol::{CheckedFile, Frame, MethodVersion};
use crate::child::Reply;
use crate::error::{Error, Result};

/// What a worker keeps between requests: every method version it was sent, and which version
/// of each id is registered now.
#[derive(Default)]
struct Methods {
    sent: HashMap<String, CheckedFile>,
    active: HashMap<String, String>,
}

impl Methods {
    /// Makes each of `wanted` the registered version of its id.
    fn activate(&mut self, new: Vec<CheckedFile>, wanted: &[MethodVersion]) -> Result<()> {
        for c in new {
            self.sent.insert(c.sha256.clone(), c);
        }
        for m in wanted {
            if self.active.get(&m.name) == Some(&m.sha256) {
                continue;
            }
            let c = self.sent.get(&m.sha256).ok_or_else(|| {
                Error::Internal(format!(
                    "the parent asked for {} at {} without sending it",
                    m.name, m.sha256
                ))
            })?;
            c.adopt()?;
            self.active.insert(m.name.clone(), m.sha256.clone());
        }
        Ok(())
    }
}

/// Serves requests until stdin closes: `job(name, request)` does each one.
pub fn serve(job: &dyn Fn(&str, serde_json::Value) -> Result<serde_json::Value>) -> Result<()> {
    let mut replies = reply_pipe()?;
    let mut methods = Methods::default();
    let stdin = std::io::stdin().lock();
    for line in stdin.lines() {
        let line = line.map_err(|e| Error::io("the worker's stdin", e))?;
        let reply = match super::protocol::decode::<Frame<serde_json::Value>>(&line, "a frame") {
            Err(e) => Reply::Refused {
                error: e.to_string(),
            },
            Ok(frame) => {
                if let Ok(level) = frame.log_level.parse() {
                    log::set_max_level(level);
                }
                match methods.activate(frame.new_methods, &frame.methods) {
                    Err(e) => Reply::Refused {
                        error: e.to_string(),
                    },
                    Ok(()) => match job(&frame.job, frame.request) {
                        Ok(reply) => Reply::Done { reply },
                        Err(e) => Reply::Failed {
                            error: e.to_string(),
                        },
                    },
                }
            }
        };
        let mut bytes =
            serde_json::to_vec(&reply).map_err(|e| Error::output("the worker's reply", e))?;
        bytes.push(b'\n');
        replies
            .write_all(&bytes)
            .and_then(|()| replies.flush())
            .map_err(|e| Error::io("the worker's reply pipe", e))?;
    }
    Ok(())
}

/// The process's stdout as it started, for replies alone; stdout becomes a copy of stderr.
fn reply_pipe() -> Result<std::fs::File> {
    // SAFETY: dup and dup2 on the standard descriptors, before any thread of this process
    // writes to stdout; the duplicate is owned by the File from here on.
    unsafe {
        let fd = libc::dup(libc::STDOUT_FILENO);
        if fd < 0 || libc::dup2(libc::STDERR_FILENO, libc::STDOUT_FILENO) < 0 {
            return Err(Error::io(
                "the worker's stdout",
                std::io::Error::last_os_error(),
            ));
        }
        Ok(std::fs::File::from_raw_fd(fd))
    }
}
