//! What passes between a parent and a compiler worker: one [`Frame`] per request on the
//! worker's stdin and one [`crate::child::Reply`] per request on its reply pipe, each a line of
//! JSON. A frame carries the user methods the request uses as the parent checked and compiled
//! them ([`CheckedFile`]), each sent once per worker and named by its SHA-256 after that.
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::gpu::shaders::RuntimePrograms;
use crate::method::user::UserMethod;

/// A user method file as its parent read, checked (a tuned file's proof) and compiled it: what
/// a worker registers in place of reading the file ([`CheckedFile::adopt`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckedFile {
    /// The method's id (the file's stem).
    pub name: String,
    /// The file, absolute.
    pub path: PathBuf,
    /// SHA-256 of the file's bytes, hex: the version of the method.
    pub sha256: String,
    /// The file's text (without a byte-order mark), as the programs were compiled from it.
    pub text: String,
    pub programs: RuntimePrograms,
}

impl CheckedFile {
    /// What this process registered of `u`.
    pub fn of(u: &UserMethod) -> Result<CheckedFile> {
        Ok(CheckedFile {
            name: u.name.to_string(),
            path: PathBuf::from(&u.path),
            sha256: u.sha256.clone(),
            text: u.source.clone(),
            programs: crate::gpu::shaders::runtime_programs(u.name)?,
        })
    }

    /// Registers the method and its programs in this process, in place of a method of the
    /// same id.
    pub fn adopt(&self) -> Result<()> {
        let u = crate::method::user::adopt(&self.path, &self.sha256, &self.text)?;
        crate::gpu::shaders::adopt_programs(u.name, &self.programs)
    }
}

/// A method a request uses: its id and version.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct MethodVersion {
    pub name: String,
    pub sha256: String,
}

/// One request to a worker.
#[derive(Debug, Serialize, Deserialize)]
pub struct Frame<T> {
    /// [`crate::child::Job::NAME`].
    pub job: String,
    /// What the worker tells on stderr while it runs this request: the parent's `log` level.
    pub log_level: String,
    /// The methods this worker was not sent before, whole.
    pub new_methods: Vec<CheckedFile>,
    /// Every user method the request uses, at its version: the worker makes each of them the
    /// registered one before the job runs.
    pub methods: Vec<MethodVersion>,
    pub request: T,
}

/// Reads one line of JSON as a `T`, naming `what` in the error.
pub fn decode<T: serde::de::DeserializeOwned>(line: &str, what: &str) -> Result<T> {
    serde_json::from_str(line).map_err(|e| Error::Usage(format!("{what}: not readable: {e}")))
}
