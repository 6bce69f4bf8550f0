//! `shadelab merge`: reads the shards' folders and checks them before anything is merged: every
//! folder has a manifest of this schema, the same corpus (ids and content hashes), the same
//! configuration (hash) and the same shard count; each shard K of N is given once, none is
//! missing, and each holds exactly its meshes, each with a result of that content and
//! configuration. Any failed check is a usage error (exit 2) naming the folder or shard. Shards
//! from different machines are merged for error (the figures are deterministic) and kept apart,
//! flagged, for time.
use std::path::{Path, PathBuf};

use super::run::{Manifest, MeshResult};
use super::SCHEMA_VERSION;
use crate::error::{Error, Result};

/// A shard folder and its manifest.
pub struct ShardDir {
    pub dir: PathBuf,
    pub manifest: Manifest,
}

/// One mesh as merged: its result, the raw bytes of result.json, its shard's machine and its
/// timing.json.
pub struct Merged {
    pub result: MeshResult,
    pub bytes: Vec<u8>,
    pub machine: String,
    pub timing: serde_json::Value,
}

fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join("manifest.json");
    let bytes = std::fs::read(&path).map_err(|e| {
        Error::Usage(format!(
            "merge: {}: no manifest.json ({e}); is it a finished corpus shard?",
            dir.display()
        ))
    })?;
    let m: Manifest = serde_json::from_slice(&bytes)
        .map_err(|e| Error::input(&path, None, format!("not a corpus manifest: {e}")))?;
    if m.schema_version != SCHEMA_VERSION {
        return Err(Error::Usage(format!(
            "merge: {}: manifest schema {} (this shadelab reads {SCHEMA_VERSION})",
            dir.display(),
            m.schema_version
        )));
    }
    Ok(m)
}

/// Reads and checks the shards; returns them sorted by K.
pub fn check(dirs: &[PathBuf]) -> Result<Vec<ShardDir>> {
    if dirs.is_empty() {
        return Err(Error::Usage("merge: give at least one shard folder".into()));
    }
    let mut shards = Vec::new();
    for d in dirs {
        shards.push(ShardDir {
            dir: d.clone(),
            manifest: read_manifest(d)?,
        });
    }
    let first = &shards[0];
    let name = |s: &ShardDir| s.dir.display().to_string();
    for s in &shards[1..] {
        let (a, b) = (&first.manifest, &s.manifest);
        if a.config_hash != b.config_hash {
            return Err(Error::Usage(format!(
                "merge: {}: its configuration (hash {}) differs from {}'s ({}): {}",
                name(s),
                short(&b.config_hash),
                name(first),
                short(&a.config_hash),
                config_diff(&a.config, &b.config)
            )));
        }
        if a.shard.n != b.shard.n {
            return Err(Error::Usage(format!(
                "merge: {}: shard {}/{}, but {} is one of {}",
                name(s),
                b.shard.k,
                b.shard.n,
                name(first),
                a.shard.n
            )));
        }
        if a.corpus != b.corpus {
            return Err(Error::Usage(format!(
                "merge: {}: its corpus (meshes or their content) differs from {}'s",
                name(s),
                name(first)
            )));
        }
    }
    shards.sort_by_key(|s| s.manifest.shard.k);
    let n = first_n(&shards);
    for w in shards.windows(2) {
        if w[0].manifest.shard.k == w[1].manifest.shard.k {
            return Err(Error::Usage(format!(
                "merge: shard {}/{n} given twice: {} and {}",
                w[0].manifest.shard.k,
                name(&w[0]),
                name(&w[1])
            )));
        }
    }
    let missing: Vec<String> = (1..=n)
        .filter(|k| !shards.iter().any(|s| s.manifest.shard.k == *k))
        .map(|k| format!("{k}/{n}"))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Usage(format!(
            "merge: shard {} missing: the union of the folders given is not the corpus",
            missing.join(", ")
        )));
    }
    for s in &shards {
        check_holdings(s)?;
    }
    Ok(shards)
}

fn first_n(shards: &[ShardDir]) -> usize {
    shards.first().map_or(0, |s| s.manifest.shard.n)
}

fn short(h: &str) -> &str {
    &h[..h.len().min(12)]
}

/// Which fields of two configurations differ.
fn config_diff(a: &super::Config, b: &super::Config) -> String {
    let (a, b) = (
        serde_json::to_value(a).unwrap_or_default(),
        serde_json::to_value(b).unwrap_or_default(),
    );
    let mut diffs = Vec::new();
    if let (Some(a), Some(b)) = (a.as_object(), b.as_object()) {
        for (k, va) in a {
            if b.get(k) != Some(va) {
                diffs.push(format!(
                    "{k} {va} vs {}",
                    b.get(k).unwrap_or(&serde_json::Value::Null)
                ));
            }
        }
    }
    diffs.join("; ")
}

/// A shard holds exactly the meshes of its K, each finished for this content and configuration.
fn check_holdings(s: &ShardDir) -> Result<()> {
    let m = &s.manifest;
    let want: Vec<&str> = m
        .corpus
        .iter()
        .filter(|e| e.shard == m.shard.k)
        .map(|e| e.id.as_str())
        .collect();
    let have: Vec<&str> = m.meshes.iter().map(|e| e.id.as_str()).collect();
    let dir = s.dir.display();
    if want != have {
        let lacks: Vec<&str> = want.iter().filter(|w| !have.contains(w)).copied().collect();
        let extra: Vec<&str> = have.iter().filter(|h| !want.contains(h)).copied().collect();
        return Err(Error::Usage(format!(
            "merge: {dir} (shard {}/{}): lacks [{}], holds others' [{}]",
            m.shard.k,
            m.shard.n,
            lacks.join(", "),
            extra.join(", ")
        )));
    }
    for e in m.corpus.iter().filter(|e| e.shard == m.shard.k) {
        let r = read_result(&s.dir, &e.id)?.0;
        if r.content_hash != e.content_hash || r.config_hash != m.config_hash {
            return Err(Error::Usage(format!(
                "merge: {dir}: meshes/{}/result.json is of another content or configuration",
                e.id
            )));
        }
    }
    Ok(())
}

fn read_result(dir: &Path, id: &str) -> Result<(MeshResult, Vec<u8>)> {
    let path = dir.join("meshes").join(id).join("result.json");
    let bytes = std::fs::read(&path).map_err(|e| {
        Error::Usage(format!(
            "merge: {}: {e} (shard unfinished?)",
            path.display()
        ))
    })?;
    let r = serde_json::from_slice(&bytes)
        .map_err(|e| Error::input(&path, None, format!("not a mesh result: {e}")))?;
    Ok((r, bytes))
}

/// Every mesh of the corpus, in corpus order, from the shard that holds it.
pub fn gather(shards: &[ShardDir]) -> Result<Vec<Merged>> {
    let Some(first) = shards.first() else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for e in &first.manifest.corpus {
        let s = shards
            .iter()
            .find(|s| s.manifest.shard.k == e.shard)
            .ok_or_else(|| Error::Internal(format!("no shard holds {}", e.id)))?;
        let (result, bytes) = read_result(&s.dir, &e.id)?;
        let tpath = s.dir.join("meshes").join(&e.id).join("timing.json");
        let timing = std::fs::read(&tpath)
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok())
            .unwrap_or(serde_json::Value::Null);
        out.push(Merged {
            result,
            bytes,
            machine: s.manifest.machine.key(),
            timing,
        });
    }
    Ok(out)
}
