//! The compile store: what a child of `shadelab isa` replied ([`ChildReport`]: the statistics
//! the compiler printed and the disassembly), kept under a key that is the SHA-256 of
//! everything that can change that reply ([`KeyMaterial`]): the store's and the child
//! protocol's schema versions, the shadelab binary (the SPIR-V built into it and the code that
//! builds the pipelines), the request (family, methods, precision, kernel counts, scene,
//! probes), the bytes of every file the request names (method files, probes, a scene and the
//! files it names), the driver's name for the chip and the route's compiler identity
//! ([`CompilerIdentity`]: driver, API, environment, build ids of its files). The same SPIR-V
//! compiled by the same compiler gives the same statistics (tests/isa.rs checks exactly that),
//! so a hit is the reply a child would give, in milliseconds instead of seconds.
//!
//! Invariants: an entry is written once, whole, by rename ([`crate::output::write_bytes_atomic`]),
//! so concurrent processes (Slurm shards on a shared file system) never read half of one; each
//! entry carries the SHA-256 and length of its body and its full key material, checked on
//! every read: a corrupt, truncated or foreign entry is reported, removed and compiled again,
//! never used. Only replies are stored (a child's own refusal too: float16 on a chip without it);
//! everything derived from them (rows, ratios, rankings) is computed after the store, as for a
//! fresh reply. A child that died or gave no reply is not stored: it is asked again. The store is bounded ([`DEFAULT_MAX_BYTES`]): when a
//! write takes it over, the least recently used entries (modification time, refreshed on every
//! hit) go first, down to nine tenths of the bound.
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::SystemTime;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::identity::{exe_sha256, file_sha256, hex, CompilerIdentity};
use super::request::{ChildReport, ChildRequest};
use crate::error::{Error, Result};

/// Version of the entries' layout and of what goes into a key: a change of either is a miss.
pub const STORE_SCHEMA: u32 = 2;
/// The first bytes of every entry.
const MAGIC: &str = "shadelab-store";
/// The file name ending of an entry.
const SUFFIX: &str = ".entry";
/// The bound the store is kept under after each write (2 GiB: a report's two precisions on
/// every family take about 0.1 GB with their disassembly, so the bound keeps a dozen builds'
/// worth; `shadelab cache --max-size` sets another).
pub const DEFAULT_MAX_BYTES: u64 = 2 << 30;
/// Environment variable: the store's folder instead of the user's cache.
pub const ENV_DIR: &str = "SHADELAB_STORE";
/// Environment variable: `1` compiles every family now (as `--no-cache`).
pub const ENV_OFF: &str = "SHADELAB_NO_CACHE";

static DISABLED: AtomicBool = AtomicBool::new(false);

/// Turns the store off for this process (`--no-cache`): every family is compiled now and
/// nothing is written.
pub fn disable() {
    DISABLED.store(true, Ordering::Relaxed);
}

/// Whether this process uses the store: not after [`disable`], nor with `SHADELAB_NO_CACHE`
/// set to anything but `0` or empty.
pub fn enabled() -> bool {
    let off = std::env::var(ENV_OFF).is_ok_and(|v| !v.is_empty() && v != "0");
    !DISABLED.load(Ordering::Relaxed) && !off
}

/// The store's folder: `$SHADELAB_STORE`, else `$XDG_CACHE_HOME/shadelab/store`, else
/// `~/.cache/shadelab/store` (beside the routes' builds).
pub fn default_dir() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os(ENV_DIR).filter(|v| !v.is_empty()) {
        return Some(PathBuf::from(d));
    }
    Some(super::route::cache_dir()?.parent()?.join("store"))
}

/// The store this process uses, `None` when it is off ([`enabled`]) or there is no cache
/// folder.
pub fn default_store() -> Option<Store> {
    enabled().then(default_dir).flatten().map(Store::at)
}

/// Whether a family's figures were compiled by a child now or read from the store.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    Compiled,
    FromStore,
}

/// Everything that can change a child's reply; its SHA-256 is the entry's key.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KeyMaterial {
    pub store_schema: u32,
    pub child_schema: u32,
    /// SHA-256 of the shadelab binary that runs the children.
    pub shadelab: String,
    /// The name the driver is given for the chip (AMD's gfx1100 or navi31).
    pub driver_chip: String,
    pub compiler: CompilerIdentity,
    /// The request as the child gets it.
    pub request: serde_json::Value,
    /// SHA-256 of every file the request names, in order: method files, probes, the scene
    /// and the files it names.
    pub inputs: Vec<String>,
}

impl KeyMaterial {
    /// The material of `req` compiled by `exe` under the driver name `driver_chip` with the
    /// compiler `compiler`; the user's method files are `method_files`. An unreadable input
    /// is an error (the child reports it; nothing is stored).
    pub fn new(
        exe: &Path,
        req: &ChildRequest,
        method_files: &[PathBuf],
        driver_chip: &str,
        compiler: CompilerIdentity,
    ) -> std::io::Result<KeyMaterial> {
        // Contents, not paths: a method file written again elsewhere (tune's candidates in
        // another output folder) with the same bytes is the same program; its name is the
        // request's method id.
        let mut inputs = Vec::new();
        for p in method_files.iter().chain(&req.probes) {
            inputs.push(file_sha256(p)?);
        }
        if let Some(scene) = &req.scene {
            inputs.push(file_sha256(scene)?);
            for p in files_named_by(scene) {
                inputs.push(file_sha256(&p)?);
            }
        }
        let mut request = serde_json::to_value(req).map_err(std::io::Error::other)?;
        // A probe's name is its method id; the folder it lies in changes nothing.
        request["probes"] = req
            .probes
            .iter()
            .map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect::<Vec<_>>()
            .into();
        Ok(KeyMaterial {
            store_schema: STORE_SCHEMA,
            child_schema: crate::child::SCHEMA_VERSION,
            shadelab: exe_sha256(exe)?,
            driver_chip: driver_chip.into(),
            compiler,
            request,
            inputs,
        })
    }

    /// SHA-256 (hex) of the material: the entry's file name.
    pub fn key(&self) -> String {
        hex(&Sha256::digest(
            serde_json::to_vec(self).unwrap_or_default(),
        ))
    }

    /// The family the request asks for.
    pub fn family(&self) -> &str {
        self.request
            .get("family")
            .and_then(|f| f.as_str())
            .unwrap_or("?")
    }
}

/// Every existing file a scene file's TOML names by a string (its mesh), relative to the
/// scene's folder: a changed mesh is another key.
fn files_named_by(scene: &Path) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read_to_string(scene) else {
        return Vec::new();
    };
    let Ok(v) = text.parse::<toml::Table>() else {
        return Vec::new();
    };
    let dir = scene.parent().unwrap_or(Path::new("."));
    let mut out = Vec::new();
    let mut stack: Vec<toml::Value> = v.into_iter().map(|(_, v)| v).collect();
    while let Some(v) = stack.pop() {
        match v {
            toml::Value::String(s) => {
                let p = dir.join(&s);
                if !s.is_empty() && p.is_file() {
                    out.push(p);
                }
            }
            toml::Value::Array(a) => stack.extend(a),
            toml::Value::Table(t) => stack.extend(t.into_iter().map(|(_, v)| v)),
            _ => {}
        }
    }
    out.sort();
    out.dedup();
    out
}

/// What a child answered: its reply, or the error it replied with (a refusal it decided: the
/// driver does not compile float16 on that chip, or does not start on it).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stored {
    Compiled(ChildReport),
    Refused(String),
}

/// One stored answer with the material of its key.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Entry {
    pub material: KeyMaterial,
    pub stored: Stored,
}

impl Entry {
    /// The reply, for an entry of a compile.
    pub fn reply(&self) -> Option<&ChildReport> {
        match &self.stored {
            Stored::Compiled(r) => Some(r),
            Stored::Refused(_) => None,
        }
    }

    /// [`Entry::reply`], mutable.
    pub fn reply_mut(&mut self) -> Option<&mut ChildReport> {
        match &mut self.stored {
            Stored::Compiled(r) => Some(r),
            Stored::Refused(_) => None,
        }
    }
}

/// An entry's bytes: a header line `shadelab-store <schema> <sha256 of body> <body length>`,
/// then the body (the entry as JSON).
pub fn encode(entry: &Entry) -> Result<Vec<u8>> {
    let body = serde_json::to_vec(entry).map_err(|e| Error::output("a store entry", e))?;
    let mut out = format!(
        "{MAGIC} {STORE_SCHEMA} {} {}\n",
        hex(&Sha256::digest(&body)),
        body.len()
    )
    .into_bytes();
    out.extend_from_slice(&body);
    Ok(out)
}

/// The longest header line an entry has (the magic, the schema, 64 hex digits and a length,
/// with room to spare): more bytes without a newline is no entry.
const MAX_HEADER: usize = 160;
/// The largest entry read (256 MiB, an eighth of [`DEFAULT_MAX_BYTES`]; a report's largest
/// reply, every method with its disassembly on one family, is a few MB): a larger file is not
/// read, whatever its header says.
pub const MAX_ENTRY_BYTES: u64 = DEFAULT_MAX_BYTES / 8;

/// The header line of an entry (without its newline): the checksum and length of the body it
/// announces, or what is wrong with it.
fn decode_header(header: &[u8]) -> std::result::Result<(&str, u64), String> {
    let header = std::str::from_utf8(header).map_err(|_| "a header that is not text")?;
    let parts: Vec<&str> = header.split(' ').collect();
    let [magic, schema, sum, len] = parts[..] else {
        return Err(format!(
            "header `{header}` is not `{MAGIC} SCHEMA SHA256 LENGTH`"
        ));
    };
    if magic != MAGIC || schema != STORE_SCHEMA.to_string() {
        return Err(format!(
            "header `{header}`: not an entry of store schema {STORE_SCHEMA}"
        ));
    }
    let len = len
        .parse::<u64>()
        .map_err(|_| format!("header `{header}`: its length is not a number"))?;
    Ok((sum, len))
}

/// The entry of `bytes`, or what is wrong with them.
pub fn decode(bytes: &[u8]) -> std::result::Result<Entry, String> {
    let nl = bytes
        .iter()
        .take(MAX_HEADER + 1)
        .position(|&b| b == b'\n')
        .ok_or("no header line")?;
    let (sum, len) = decode_header(&bytes[..nl])?;
    let body = &bytes[nl + 1..];
    if len != body.len() as u64 {
        return Err(format!(
            "truncated: the header says {len} bytes, the body has {}",
            body.len()
        ));
    }
    if hex(&Sha256::digest(body)) != sum {
        return Err("its checksum does not match its body".into());
    }
    serde_json::from_slice(body).map_err(|e| format!("its body is not an entry: {e}"))
}

/// The bytes of the entry file at `path`, read only when it can be one: a regular file (not a
/// link, a device, a FIFO or a folder: a link to /dev/zero was read until the kernel killed
/// the process) of at most [`MAX_ENTRY_BYTES`], whose header is read first and whose length is
/// the one the header announces. `Ok(None)`: no such file (another process removed it).
/// `Err`: why the file is no entry, without reading more of it.
pub fn read_entry(path: &Path) -> std::result::Result<Option<Vec<u8>>, String> {
    use std::io::Read;
    use std::os::unix::fs::OpenOptionsExt;
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("cannot be read: {e}")),
    };
    let regular = |m: &std::fs::Metadata| -> std::result::Result<(), String> {
        if !m.file_type().is_file() {
            return Err(format!(
                "not a regular file ({}): an entry is one, written by shadelab",
                kind_of(m.file_type())
            ));
        }
        if m.len() > MAX_ENTRY_BYTES {
            return Err(format!(
                "{} bytes, more than an entry may hold ({MAX_ENTRY_BYTES})",
                m.len()
            ));
        }
        Ok(())
    };
    regular(&meta)?;
    // O_NOFOLLOW and O_NONBLOCK: what is opened is what was checked, and a FIFO put there
    // meanwhile does not block the open; the opened file is checked again.
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
        .open(path);
    let mut file = match file {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("cannot be opened: {e}")),
    };
    let meta = file
        .metadata()
        .map_err(|e| format!("cannot be read: {e}"))?;
    regular(&meta)?;
    let mut head = Vec::with_capacity(MAX_HEADER + 1);
    (&mut file)
        .take(MAX_HEADER as u64 + 1)
        .read_to_end(&mut head)
        .map_err(|e| format!("cannot be read: {e}"))?;
    let nl = head
        .iter()
        .position(|&b| b == b'\n')
        .ok_or("no header line")?;
    let (_, len) = decode_header(&head[..nl])?;
    let whole = nl as u64 + 1 + len;
    if whole != meta.len() {
        return Err(format!(
            "truncated: the header says {len} bytes, the body has {}",
            meta.len().saturating_sub(nl as u64 + 1)
        ));
    }
    let mut bytes = head;
    bytes.reserve(whole as usize - bytes.len());
    file.take(whole - bytes.len() as u64)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot be read: {e}"))?;
    Ok(Some(bytes))
}

/// What a file that is not a regular one is, in words.
fn kind_of(t: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_symlink() {
        "a symbolic link"
    } else if t.is_dir() {
        "a folder"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a file"
    }
}

/// Removes the entry file at `path`: `Ok` when it is gone (or another process removed it
/// first), else why it is still there (a read-only store).
fn remove_entry(path: &Path) -> std::result::Result<(), String> {
    match std::fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e.to_string()),
    }
}

/// One entry as `shadelab cache` lists it.
#[derive(Debug, Clone)]
pub struct EntryFile {
    pub path: PathBuf,
    pub size: u64,
    /// Last written or read from (the least recently used goes first).
    pub used: SystemTime,
}

/// What [`Store::verify`] found.
#[derive(Debug, Default)]
pub struct Verified {
    /// The entries that decode, under their own key.
    pub sound: Vec<Entry>,
    /// Each entry that did not, removed: its path and why.
    pub removed: Vec<(PathBuf, String)>,
    /// Each entry that did not and could not be removed (a read-only store): its path, why it
    /// is no entry, and why it is still there.
    pub kept: Vec<(PathBuf, String, String)>,
}

/// What [`Store::prune_to`] did.
#[derive(Debug, Default)]
pub struct Pruned {
    /// Entries removed, and their bytes.
    pub removed: usize,
    pub freed: u64,
    /// Each entry that was to go and could not be removed (a read-only store): its path and
    /// why.
    pub kept: Vec<(PathBuf, String)>,
}

/// A store in a folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Store {
    dir: PathBuf,
}

impl Store {
    /// The store in `dir` (created on the first write).
    pub fn at(dir: impl Into<PathBuf>) -> Store {
        Store { dir: dir.into() }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The file of key `key`.
    pub fn path_of(&self, key: &str) -> PathBuf {
        self.dir.join(format!("{key}{SUFFIX}"))
    }

    /// The answer stored for `m`, if any. A corrupt entry (or one whose material is not `m`'s)
    /// is warned about, removed, and a miss; a hit refreshes the entry's time (LRU).
    pub fn get(&self, m: &KeyMaterial) -> Option<Stored> {
        let path = self.path_of(&m.key());
        let why = match read_entry(&path).map(|b| b.map(|b| decode(&b))) {
            Ok(None) => return None,
            Ok(Some(Ok(e))) if e.material == *m => {
                touch(&path);
                return Some(e.stored);
            }
            Ok(Some(Ok(_))) => "its key material is another compile's".to_string(),
            Ok(Some(Err(why))) | Err(why) => why,
        };
        let what = match remove_entry(&path) {
            Ok(()) => "removed".to_string(),
            Err(e) => format!("could not be removed ({e}), left as it is"),
        };
        log::warn!(
            "compile store: {} ({}): {why}; {what}; compiling again",
            path.display(),
            m.family()
        );
        None
    }

    /// Stores `stored` under `m` (atomically: written whole, then renamed; not synced, since a
    /// read checks every entry), then keeps the
    /// store under [`DEFAULT_MAX_BYTES`] ([`Store::keep_bounded`]).
    pub fn put(&self, m: &KeyMaterial, stored: Stored) -> Result<()> {
        let bytes = encode(&Entry {
            material: m.clone(),
            stored,
        })?;
        // Renamed whole but not synced one by one (a job writes thousands: 3.6 ms per fsync):
        // an entry a crash left short or empty fails its checksum on read and is compiled again.
        crate::output::write_atomic_as(
            &self.path_of(&m.key()),
            crate::output::Durability::Batched,
            |w| w.write_all(&bytes),
        )?;
        self.keep_bounded(bytes.len() as u64, DEFAULT_MAX_BYTES)
    }

    /// After a write of `written` bytes: the store's size as this process counts it (the folder
    /// listed once, then what this process wrote added), and when that passes `max_bytes`, the
    /// least recently used entries removed down to nine tenths of it (and the count made
    /// again). Listing the folder after every write made a report's thousands of writes
    /// quadratic in the store's entries.
    fn keep_bounded(&self, written: u64, max_bytes: u64) -> Result<()> {
        static COUNTED: std::sync::Mutex<Vec<(PathBuf, u64)>> = std::sync::Mutex::new(Vec::new());
        let mut counted = COUNTED.lock().unwrap_or_else(|e| e.into_inner());
        let total = match counted.iter_mut().find(|(dir, _)| *dir == self.dir) {
            Some((_, bytes)) => {
                *bytes += written;
                *bytes
            }
            None => {
                let bytes = self.entries()?.iter().map(|e| e.size).sum();
                counted.push((self.dir.clone(), bytes));
                bytes
            }
        };
        if total > max_bytes {
            self.prune_to(max_bytes / 10 * 9)?;
            let bytes = self.entries()?.iter().map(|e| e.size).sum();
            if let Some((_, b)) = counted.iter_mut().find(|(dir, _)| *dir == self.dir) {
                *b = bytes;
            }
        }
        Ok(())
    }

    /// Every entry file, least recently used first; none when the folder does not exist.
    pub fn entries(&self) -> Result<Vec<EntryFile>> {
        let rd = match std::fs::read_dir(&self.dir) {
            Ok(rd) => rd,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(e) => return Err(Error::io(&self.dir, e)),
        };
        let mut out: Vec<EntryFile> = rd
            .filter_map(|e| {
                let e = e.ok()?;
                let path = e.path();
                if !path.to_str()?.ends_with(SUFFIX) {
                    return None;
                }
                let meta = e.metadata().ok()?;
                Some(EntryFile {
                    path,
                    size: meta.len(),
                    used: meta.modified().ok()?,
                })
            })
            .collect();
        out.sort_by_key(|e| e.used);
        Ok(out)
    }

    /// Removes the least recently used entries until the store holds at most `max_bytes`;
    /// returns (entries removed, bytes freed). An entry another process removed first counts
    /// as removed by neither.
    pub fn prune_to(&self, max_bytes: u64) -> Result<Pruned> {
        let entries = self.entries()?;
        let mut total: u64 = entries.iter().map(|e| e.size).sum();
        let mut done = Pruned::default();
        for e in entries {
            if total <= max_bytes {
                break;
            }
            total -= e.size;
            match std::fs::remove_file(&e.path) {
                Ok(()) => {
                    done.removed += 1;
                    done.freed += e.size;
                }
                Err(x) if x.kind() == std::io::ErrorKind::NotFound => {}
                Err(x) => done.kept.push((e.path, x.to_string())),
            }
        }
        Ok(done)
    }

    /// Reads every entry and removes those that do not decode ([`Verified`]: the sound
    /// entries, those removed and those that could not be).
    pub fn verify(&self) -> Result<Verified> {
        let mut v = Verified::default();
        for e in self.entries()? {
            let name_ok = |x: &Entry| {
                e.path.file_name().and_then(|n| n.to_str())
                    == Some(&format!("{}{SUFFIX}", x.material.key()))
            };
            let why = match read_entry(&e.path).map(|b| b.map(|b| decode(&b))) {
                Ok(None) => continue, // removed by another process meanwhile
                Ok(Some(Ok(x))) if name_ok(&x) => {
                    v.sound.push(x);
                    continue;
                }
                Ok(Some(Ok(_))) => "stored under another key".to_string(),
                Ok(Some(Err(why))) | Err(why) => why,
            };
            match remove_entry(&e.path) {
                Ok(()) => v.removed.push((e.path, why)),
                Err(kept) => v.kept.push((e.path, why, kept)),
            }
        }
        Ok(v)
    }
}

/// Marks `path` as just used (its modification time: the LRU order of [`Store::prune_to`]);
/// a store on a read-only file system just keeps its order.
fn touch(path: &Path) {
    if let Ok(f) = std::fs::OpenOptions::new().append(true).open(path) {
        let _ = f.set_modified(SystemTime::now());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(family: &str) -> KeyMaterial {
        KeyMaterial {
            store_schema: STORE_SCHEMA,
            child_schema: 1,
            shadelab: "0".repeat(64),
            driver_chip: "navi21".into(),
            compiler: CompilerIdentity {
                driver: "RADV (ACO)".into(),
                api: "Vulkan".into(),
                env: vec![("RADV_FORCE_FAMILY".into(), "navi21".into())],
                files: Vec::new(),
            },
            request: serde_json::json!({ "family": family }),
            inputs: Vec::new(),
        }
    }

    fn reply(family: &str) -> ChildReport {
        ChildReport {
            family: family.into(),
            device_name: "AMD RADV NAVI21".into(),
            driver_name: "radv".into(),
            driver_info: "Mesa 22.3.6".into(),
            api_version: "1.3.230".into(),
            compiled: Vec::new(),
            elapsed_ms: 812.0,
            float16: Some(true),
            skipped: Vec::new(),
        }
    }

    #[test]
    fn an_entry_comes_back_and_a_corrupt_one_is_removed() {
        let dir = tempfile::tempdir().unwrap();
        let s = Store::at(dir.path());
        let m = material("amd:navi21");
        assert!(s.get(&m).is_none());
        s.put(&m, Stored::Compiled(reply("amd:navi21"))).unwrap();
        let Some(Stored::Compiled(r)) = s.get(&m) else {
            panic!("no reply")
        };
        assert_eq!(r.elapsed_ms, 812.0);
        // Teeth: one flipped byte of the body is detected; the entry is gone.
        let p = s.path_of(&m.key());
        let mut bytes = std::fs::read(&p).unwrap();
        let last = bytes.len() - 3;
        bytes[last] ^= 1;
        std::fs::write(&p, &bytes).unwrap();
        assert!(s.get(&m).is_none());
        assert!(!p.exists());
        // A truncated one too.
        s.put(&m, Stored::Compiled(reply("amd:navi21"))).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
        assert!(decode(&std::fs::read(&p).unwrap())
            .unwrap_err()
            .contains("truncated"));
        assert!(s.get(&m).is_none());
        // An empty one (what a crash can leave of an entry renamed before its bytes reached the
        // disk: entries are not synced one by one).
        s.put(&m, Stored::Compiled(reply("amd:navi21"))).unwrap();
        std::fs::write(&p, b"").unwrap();
        assert!(s.get(&m).is_none());
        assert!(!p.exists());
    }

    /// An entry that never ends is not read: a link to /dev/zero took `isa` to 22.9 GB until
    /// the kernel killed it. A link, a FIFO (which would block the read) or a folder is no
    /// entry, nor a file past [`MAX_ENTRY_BYTES`] or one longer than its header says: each is
    /// refused from its metadata and header, at once, and removed.
    #[test]
    fn an_entry_that_is_no_regular_file_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let s = Store::at(dir.path());
        let m = material("amd:navi21");
        let p = s.path_of(&m.key());
        let refused = |what: &str, want: &str| {
            let start = std::time::Instant::now();
            let why = read_entry(&p).unwrap_err();
            assert!(why.contains(want), "{what}: {why}");
            assert!(s.get(&m).is_none(), "{what}");
            assert!(std::fs::symlink_metadata(&p).is_err(), "{what} left behind");
            assert!(
                start.elapsed().as_secs() < 5,
                "{what}: {:?}",
                start.elapsed()
            );
        };
        std::os::unix::fs::symlink("/dev/zero", &p).unwrap();
        refused("a link to /dev/zero", "a symbolic link");
        // a link to a sound entry is no entry either: what is read is what was checked
        s.put(&material("amd:tahiti"), Stored::Refused("x".into()))
            .unwrap();
        std::os::unix::fs::symlink(s.path_of(&material("amd:tahiti").key()), &p).unwrap();
        refused("a link to an entry", "a symbolic link");
        let c = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path; mkfifo only creates the node.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        refused("a FIFO", "a FIFO");
        // more bytes than the header announces (a body padded with zeros): not read past them
        s.put(&m, Stored::Refused("x".into())).unwrap();
        let mut bytes = std::fs::read(&p).unwrap();
        bytes.extend_from_slice(&[0; 4096]);
        std::fs::write(&p, &bytes).unwrap();
        refused("a padded entry", "truncated: the header says");
        // past the bound, whatever the header says (a sparse file: no disk used)
        std::fs::File::create(&p)
            .unwrap()
            .set_len(MAX_ENTRY_BYTES + 1)
            .unwrap();
        refused("a huge file", "more than an entry may hold");
        // a header line that never ends
        std::fs::write(&p, vec![b'x'; 10_000]).unwrap();
        refused("no header line", "no header line");
        // and a sound entry still reads
        s.put(&m, Stored::Refused("x".into())).unwrap();
        assert!(s.get(&m).is_some());
    }

    /// An entry that cannot be removed (here a folder where an entry would be, which even root
    /// cannot `unlink`; a read-only store is the common case) is said to be still there:
    /// `verify` and `prune_to` listed it as removed, or said nothing.
    #[test]
    fn an_entry_that_cannot_be_removed_is_said_to_be_kept() {
        let dir = tempfile::tempdir().unwrap();
        let s = Store::at(dir.path());
        s.put(&material("amd:navi21"), Stored::Refused("x".into()))
            .unwrap();
        let stuck = dir.path().join(format!("{}{SUFFIX}", "f".repeat(64)));
        std::fs::create_dir(&stuck).unwrap();
        std::fs::write(stuck.join("inside"), b"x").unwrap();
        let v = s.verify().unwrap();
        assert_eq!((v.sound.len(), v.removed.len(), v.kept.len()), (1, 0, 1));
        assert_eq!(v.kept[0].0, stuck);
        assert!(v.kept[0].1.contains("a folder"), "{:?}", v.kept);
        // the store's own entry goes, the folder stays and is said to
        let done = s.prune_to(0).unwrap();
        assert_eq!((done.removed, done.kept.len()), (1, 1));
        assert!(stuck.exists());
        // teeth: a removable bad entry is removed, not kept
        std::fs::remove_dir_all(&stuck).unwrap();
        std::fs::write(&stuck, b"junk").unwrap();
        let v = s.verify().unwrap();
        assert_eq!((v.removed.len(), v.kept.len()), (1, 0));
        assert!(!stuck.exists());
    }

    #[test]
    fn another_compiler_is_another_key() {
        let a = material("amd:navi21");
        let mut b = a.clone();
        b.compiler.env.push(("LD_PRELOAD".into(), "/x.so".into()));
        assert_ne!(a.key(), b.key());
        let mut c = a.clone();
        c.shadelab = "1".repeat(64);
        assert_ne!(a.key(), c.key());
        // An entry renamed to another key is never another key's answer.
        let dir = tempfile::tempdir().unwrap();
        let s = Store::at(dir.path());
        s.put(&a, Stored::Refused("no float16".into())).unwrap();
        assert!(matches!(s.get(&a), Some(Stored::Refused(w)) if w == "no float16"));
        std::fs::rename(s.path_of(&a.key()), s.path_of(&b.key())).unwrap();
        assert!(s.get(&b).is_none());
    }

    #[test]
    fn pruning_removes_the_least_recently_used_first() {
        let dir = tempfile::tempdir().unwrap();
        let s = Store::at(dir.path());
        let (a, b) = (material("amd:tahiti"), material("amd:navi10"));
        s.put(&a, Stored::Compiled(reply("amd:tahiti"))).unwrap();
        s.put(&b, Stored::Compiled(reply("amd:navi10"))).unwrap();
        let old = SystemTime::now() - std::time::Duration::from_secs(3600);
        let f = std::fs::OpenOptions::new()
            .append(true)
            .open(s.path_of(&a.key()))
            .unwrap();
        f.set_modified(old).unwrap();
        let f = std::fs::OpenOptions::new()
            .append(true)
            .open(s.path_of(&b.key()))
            .unwrap();
        f.set_modified(old - std::time::Duration::from_secs(60))
            .unwrap();
        // a hit makes `b` the most recently used
        assert!(s.get(&b).is_some());
        let one = s.entries().unwrap()[0].size;
        assert_eq!(s.prune_to(one + one / 2).unwrap().removed, 1);
        assert!(s.get(&a).is_none() && s.get(&b).is_some());
        assert_eq!(s.prune_to(0).unwrap().removed, 1);
        assert!(s.entries().unwrap().is_empty());
    }

    /// The bound is kept from a count made once per process: writes below it list nothing,
    /// a write past it removes the least recently used entries down to nine tenths of it.
    #[test]
    fn writes_past_the_bound_remove_the_oldest_down_to_nine_tenths() {
        let dir = tempfile::tempdir().unwrap();
        let s = Store::at(dir.path());
        let now = SystemTime::now();
        for i in 0..5u64 {
            let path = s.path_of(&format!("k{i}"));
            std::fs::write(&path, [b'x'; 100]).unwrap();
            let f = std::fs::OpenOptions::new()
                .append(true)
                .open(&path)
                .unwrap();
            f.set_modified(now - std::time::Duration::from_secs(100 - i))
                .unwrap();
        }
        let names = |s: &Store| -> Vec<String> {
            let mut v: Vec<String> = (s.entries().unwrap().iter())
                .map(|e| e.path.file_name().unwrap().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        };
        // 500 bytes under a bound of 500: nothing goes
        s.keep_bounded(0, 500).unwrap();
        assert_eq!(names(&s).len(), 5);
        // one more entry of 100 bytes written (600 > 500): down to 450, the two oldest go
        std::fs::write(s.path_of("k5"), [b'x'; 100]).unwrap();
        s.keep_bounded(100, 500).unwrap();
        assert_eq!(names(&s), ["k2.entry", "k3.entry", "k4.entry", "k5.entry"]);
    }

    #[test]
    fn a_scene_names_its_mesh() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.obj"), "v 0 0 0\n").unwrap();
        let scene = dir.path().join("s.toml");
        std::fs::write(&scene, "[mesh]\nfile = \"m.obj\"\nname = \"none\"\n").unwrap();
        assert_eq!(files_named_by(&scene), vec![dir.path().join("m.obj")]);
    }
}
