//! The methods a server was sent as text: each distinct source becomes a method file of the
//! server's temporary folder (`edit_<12 hex digits of its SHA-256>.glsl`) registered as
//! `--method-file` registers one ([`crate::gpu::shaders::register_user`]: parsed, a tuned
//! line proven, its programs compiled to SPIR-V), so that render and cost treat it as any
//! user method, in the workers too. The same source twice is the same method; a source that
//! does not compile gives its errors by line.
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};
use crate::method::Method;

/// The longest source accepted, bytes.
pub const SOURCE_BYTES: usize = 64 * 1024;
/// Distinct edits a server keeps (a registered method stays for the process's life: its
/// programs are a few hundred kilobytes).
pub const MAX_EDITS: usize = 256;

/// One compile error of an edit: its line in the source (none when the message has none).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SourceError {
    pub line: Option<usize>,
    pub message: String,
}

/// Why an edit is not a method.
#[derive(Debug)]
pub enum Refused {
    /// Its text: errors by line (HTTP 422).
    Source(Vec<SourceError>),
    /// Too long or too many edits (HTTP 413).
    TooLarge(String),
    /// Anything else (HTTP 500).
    Internal(Error),
}

/// The edits of one server.
pub struct Edits {
    dir: PathBuf,
    /// SHA-256 of a source to its method's name, or to its errors.
    known: Mutex<HashMap<String, std::result::Result<&'static str, Vec<SourceError>>>>,
}

impl Edits {
    /// Whether `m` is one of these edits (its file lies under their folder), not a method of
    /// the table or of `--method-file`.
    pub fn holds(&self, m: &crate::method::Method) -> bool {
        crate::method::user::of(m).is_some_and(|u| Path::new(&u.path).starts_with(&self.dir))
    }

    /// Edits written under `dir` (the server's temporary folder).
    pub fn new(dir: &Path) -> Result<Edits> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        Ok(Edits {
            dir: dir.to_path_buf(),
            known: Mutex::new(HashMap::new()),
        })
    }

    /// The method of `source`, registered on first sight.
    pub fn method(&self, source: &str) -> std::result::Result<&'static Method, Refused> {
        if source.len() > SOURCE_BYTES {
            return Err(Refused::TooLarge(format!(
                "a method's source is at most {SOURCE_BYTES} bytes; this one is {}",
                source.len()
            )));
        }
        let sha: String = Sha256::digest(source.as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        let mut known = self
            .known
            .lock()
            .map_err(|_| Refused::Internal(Error::Internal("explore: edits poisoned".into())))?;
        if let Some(k) = known.get(&sha) {
            return match k {
                Ok(name) => crate::method::find(name).map_err(Refused::Internal),
                Err(errors) => Err(Refused::Source(errors.clone())),
            };
        }
        if known.len() >= MAX_EDITS {
            return Err(Refused::TooLarge(format!(
                "this server keeps {MAX_EDITS} edited methods, all used: restart `shadelab \
                 explore`"
            )));
        }
        let name = format!("edit_{}", &sha[..12]);
        let path = self.dir.join(format!("{name}.glsl"));
        std::fs::write(&path, source).map_err(|e| Refused::Internal(Error::io(&path, e)))?;
        let paths = [path.clone()];
        let registered = crate::tune::check::check_files(&paths)
            .and_then(|()| crate::gpu::shaders::register_user(&paths));
        match registered {
            Ok(()) => {
                let m = crate::method::find(&name).map_err(Refused::Internal)?;
                known.insert(sha, Ok(m.name));
                Ok(m)
            }
            Err(Error::Usage(message)) | Err(Error::Shader(message)) => {
                let errors = by_line(&path, &message);
                known.insert(sha, Err(errors.clone()));
                let _ = std::fs::remove_file(&path);
                Err(Refused::Source(errors))
            }
            Err(other) => {
                let _ = std::fs::remove_file(&path);
                Err(Refused::Internal(other))
            }
        }
    }
}

/// A check's message as errors by line: shaderc's `PATH:LINE: error: ...` lines of the edit's
/// file (its path dropped: the user never saw it), else the whole message without a line.
pub fn by_line(path: &Path, message: &str) -> Vec<SourceError> {
    let prefix = format!("{}:", path.display());
    let mut out: Vec<SourceError> = message
        .lines()
        .filter_map(|l| {
            let rest = l.trim().strip_prefix(&prefix)?;
            let (line, text) = rest.split_once(':')?;
            let line: usize = line.trim().parse().ok()?;
            Some(SourceError {
                line: Some(line),
                message: text.trim().to_string(),
            })
        })
        .collect();
    if out.is_empty() {
        let text = message.replace(&path.display().to_string(), "the method");
        let line = line_in(&text);
        out.push(SourceError {
            line,
            message: text.trim().to_string(),
        });
    }
    out
}

/// The line a message names ("... line 3: ..." or "make line 2 ..."), if any.
fn line_in(text: &str) -> Option<usize> {
    let at = text.find("line ")?;
    let digits: String = text[at + 5..]
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shaderc_lines_become_lines_and_other_messages_keep_theirs() {
        let p = Path::new("/tmp/x/edit_0.glsl");
        let m = "/tmp/x/edit_0.glsl does not compile:\n/tmp/x/edit_0.glsl:4: error: 'y' : undeclared identifier\n/tmp/x/edit_0.glsl:6: error: '' : compilation terminated\n2 errors generated.";
        let e = by_line(p, m);
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].line, Some(4));
        assert!(
            e[0].message.contains("'y' : undeclared identifier"),
            "{e:?}"
        );
        assert_eq!(e[1].line, Some(6));
        let u = by_line(p, "/tmp/x/edit_0.glsl: reads `vBary`, ...; make line 2 `// shadelab-inputs: barycentrics`");
        assert_eq!(u.len(), 1);
        assert_eq!(u[0].line, Some(2));
        assert!(!u[0].message.contains("/tmp/x"), "{u:?}");
        let none = by_line(p, "something else");
        assert_eq!(none[0].line, None);
    }
}
