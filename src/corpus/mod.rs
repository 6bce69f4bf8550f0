//! `shadelab corpus` and `shadelab merge`: a mesh corpus in deterministic shards, each mesh
//! compared as `compare --mesh` does, the shards merged and checked into one set of tables.
//!
//! This module owns what the shards agree on: the list of meshes of a corpus (a folder walked
//! for mesh files ([`crate::geometry::mesh_files`]), or a list file), each mesh's id (its relative path, sanitised), the stable hash
//! that puts a mesh in shard K of N (as cargo-nextest's `hash:K/N`, 1-based), the shard taken
//! from `--shard` or the environment of a CI matrix / Slurm job array, the configuration and
//! its hash. [`run`] runs one shard, [`merge`] checks and merges shards, [`tables`] computes
//! the corpus tables and writes them (docs/corpus.md, docs/corpus*.schema.json).
pub mod merge;
pub mod run;
pub mod tables;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};

/// Version of the corpus files (manifest.json, meshes/<id>/result.json, corpus.json).
pub const SCHEMA_VERSION: u32 = 1;

/// One mesh of the corpus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mesh {
    /// Stable id: the relative path, sanitised ([`mesh_id`]); the folder under meshes/.
    pub id: String,
    /// The path as given, relative to the corpus folder (or as written in the list file).
    pub rel: String,
    /// Where the file is read from.
    pub path: PathBuf,
}

/// The id of a mesh whose relative path is `rel`: `/` and `\` become `__`, every character
/// outside `[A-Za-z0-9._-]` becomes `_`, and a leading `.` becomes `_` (no hidden folders).
pub fn mesh_id(rel: &str) -> String {
    let mut id = String::with_capacity(rel.len());
    for c in rel.chars() {
        match c {
            '/' | '\\' => id.push_str("__"),
            c if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') => id.push(c),
            _ => id.push('_'),
        }
    }
    if id.starts_with('.') || id.is_empty() {
        id.insert(0, '_');
    }
    id
}

/// FNV-1a, 64 bits: the stable hash of a mesh id (the same on every machine and release; the
/// standard library's hasher is neither).
pub fn stable_hash(s: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.as_bytes() {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The 1-based shard of `n` that the mesh `id` belongs to.
pub fn shard_of(id: &str, n: usize) -> usize {
    (stable_hash(id) % n.max(1) as u64) as usize + 1
}

/// The SHA-256 of a file's bytes, as lowercase hex.
pub fn content_hash(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    Ok(hex(&Sha256::digest(&bytes)))
}

/// The SHA-256 of a string, as lowercase hex.
pub fn text_hash(s: &str) -> String {
    hex(&Sha256::digest(s.as_bytes()))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Every mesh file under `dir` ([`crate::geometry::mesh_files`]: recursive, hidden entries and
/// `skip` left out), sorted by relative path.
pub fn list_dir(dir: &Path, skip: Option<&Path>) -> Result<Vec<Mesh>> {
    let files = crate::geometry::mesh_files(dir, crate::geometry::Depth::Recursive, skip)?;
    let meshes = files
        .into_iter()
        .map(|path| {
            let rel = path
                .strip_prefix(dir)
                .unwrap_or(&path)
                .to_string_lossy()
                .replace('\\', "/");
            Mesh {
                id: mesh_id(&rel),
                rel,
                path,
            }
        })
        .collect();
    finish(meshes)
}

/// The meshes of a list file: one path a line (blank lines and `#` comments skipped), relative
/// to the list file's folder unless absolute; the id is made from the line as written.
pub fn list_file(file: &Path) -> Result<Vec<Mesh>> {
    let text = std::fs::read_to_string(file).map_err(|e| Error::io(file, e))?;
    let base = file.parent().unwrap_or(Path::new("."));
    let meshes = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| Mesh {
            id: mesh_id(l.trim_start_matches("./")),
            rel: l.to_string(),
            path: base.join(l),
        })
        .collect();
    finish(meshes)
}

/// Sorts by relative path and refuses an empty corpus or two meshes with the same id.
fn finish(mut meshes: Vec<Mesh>) -> Result<Vec<Mesh>> {
    meshes.sort_by(|a, b| a.rel.cmp(&b.rel));
    if meshes.is_empty() {
        return Err(Error::Usage("corpus: no mesh file listed".into()));
    }
    for w in meshes.windows(2) {
        if w[0].rel == w[1].rel {
            return Err(Error::Usage(format!(
                "corpus: {} is listed twice",
                w[0].rel
            )));
        }
    }
    let mut ids: Vec<(&str, &str)> = meshes.iter().map(|m| (&*m.id, &*m.rel)).collect();
    ids.sort();
    for w in ids.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(Error::Usage(format!(
                "corpus: {} and {} have the same id {} (rename one)",
                w[0].1, w[1].1, w[0].0
            )));
        }
    }
    Ok(meshes)
}

/// Shard K of N (1-based) and where it came from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
    /// `--shard`, `CI_NODE_INDEX/CI_NODE_TOTAL`, `SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT`
    /// or `none` (the whole corpus).
    pub source: String,
}

impl Shard {
    /// `K/N`, 1 <= K <= N.
    pub fn parse(s: &str, source: &str) -> Result<Shard> {
        let bad = || {
            Error::Usage(format!(
                "{source}: expected K/N with 1 <= K <= N (1-based), got {s:?}"
            ))
        };
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard {
            k,
            n,
            source: source.into(),
        })
    }

    /// The shard of `--shard`, else of GitLab's `CI_NODE_INDEX`/`CI_NODE_TOTAL` (1-based), else
    /// of a Slurm job array (`SLURM_ARRAY_TASK_ID` counted from `SLURM_ARRAY_TASK_MIN`, of
    /// `SLURM_ARRAY_TASK_COUNT`; the range must have step 1), else the whole corpus.
    pub fn resolve(flag: Option<&str>, env: &dyn Fn(&str) -> Option<String>) -> Result<Shard> {
        if let Some(s) = flag {
            return Shard::parse(s, "--shard");
        }
        if let (Some(k), Some(n)) = (env("CI_NODE_INDEX"), env("CI_NODE_TOTAL")) {
            return Shard::parse(&format!("{k}/{n}"), "CI_NODE_INDEX/CI_NODE_TOTAL");
        }
        if let (Some(id), Some(n)) = (env("SLURM_ARRAY_TASK_ID"), env("SLURM_ARRAY_TASK_COUNT")) {
            let src = "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT";
            let num = |name: &str, v: &str| {
                v.trim()
                    .parse::<usize>()
                    .map_err(|_| Error::Usage(format!("{src}: {name}={v:?} is not a whole number")))
            };
            let step = env("SLURM_ARRAY_TASK_STEP").unwrap_or_else(|| "1".into());
            if num("SLURM_ARRAY_TASK_STEP", &step)? != 1 {
                return Err(Error::Usage(format!(
                    "{src}: the array's step is {step}; give --array a range with step 1 \
                     (such as 1-4 or 0-3), or pass --shard K/N"
                )));
            }
            let id = num("SLURM_ARRAY_TASK_ID", &id)?;
            let min = match env("SLURM_ARRAY_TASK_MIN") {
                Some(m) => num("SLURM_ARRAY_TASK_MIN", &m)?,
                None => 1,
            };
            let k = (id + 1).saturating_sub(min);
            return Shard::parse(&format!("{k}/{}", num("SLURM_ARRAY_TASK_COUNT", &n)?), src);
        }
        Ok(Shard {
            k: 1,
            n: 1,
            source: "none".into(),
        })
    }

    /// Whether the mesh `id` is in this shard.
    pub fn holds(&self, id: &str) -> bool {
        shard_of(id, self.n) == self.k
    }
}

/// What every shard of one corpus must share (its hash is compared by `merge`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// shadelab's version (figures may change between releases).
    pub version: String,
    pub compare_schema_version: u32,
    pub methods: Vec<String>,
    pub width: u32,
    pub height: u32,
    pub precision: crate::method::Precision,
    /// compare's `pixels_above_threshold` threshold.
    pub threshold: f64,
    /// `--bench`: the runs of bench (None: no timing).
    pub bench_runs: Option<usize>,
    /// `--images`: compare's PNGs written per mesh.
    pub images: bool,
}

impl Config {
    /// The SHA-256 of the configuration's JSON (field order fixed by the struct).
    pub fn hash(&self) -> String {
        text_hash(&serde_json::to_string(self).unwrap_or_default())
    }
}

#[cfg(test)]
mod tests;
