//! Who compiles a family, as data that changes whenever the compiler could: the route's
//! driver and API ([`super::route::Compiler`]), the environment the route gives its child
//! (driver selection, preloaded shim, chip variable), and a build id of every file that
//! environment loads: size and modification time of the shims, the Vulkan ICD manifests and
//! the driver libraries they name, an OpenGL route's `<dri>_dri.so`, EGL and spirv-cross.
//! A rebuilt or upgraded route (another Mesa) changes one of them, so the store
//! ([`super::store`]) misses instead of answering with another compiler's figures. The Mesa
//! version itself is what the child reads from the driver; it is a consequence of those files,
//! not an input, and isa.json records it beside the identity.
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

/// One file a route loads: its path, size and modification time (nanoseconds since the
/// epoch). Hashing the files themselves (hundreds of MB of drivers) would cost seconds per
/// run; a rebuild or a package upgrade changes the stamp.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileStamp {
    pub path: String,
    pub size: u64,
    pub mtime_ns: i128,
}

impl FileStamp {
    /// The stamp of `path`, `None` when it is not a readable file.
    pub fn of(path: &Path) -> Option<FileStamp> {
        let meta = std::fs::metadata(path).ok()?;
        if !meta.is_file() {
            return None;
        }
        let mtime_ns = meta
            .modified()
            .ok()
            .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
            .map_or(0, |d| d.as_nanos() as i128);
        Some(FileStamp {
            path: path.display().to_string(),
            size: meta.len(),
            mtime_ns,
        })
    }
}

/// A family's compiler identity: everything about the route that can change what its
/// compiler prints for the same program.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CompilerIdentity {
    /// "RADV (ACO)", "ANV (brw)", ...
    pub driver: String,
    /// "Vulkan", "OpenGL", "OpenGL ES".
    pub api: String,
    /// The child's environment as the route sets it (sorted by name).
    pub env: Vec<(String, String)>,
    /// The files that environment loads (sorted by path).
    pub files: Vec<FileStamp>,
}

impl CompilerIdentity {
    /// The identity of the compiler `driver` (through `api`) run with the child environment
    /// `env`, which loads `files` (the route's
    /// [`Vendor::compiler_files`](super::route::Vendor::compiler_files)).
    pub fn new(
        driver: &str,
        api: &str,
        env: &[(String, String)],
        mut files: Vec<FileStamp>,
    ) -> CompilerIdentity {
        let mut env = env.to_vec();
        env.sort();
        files.sort_by(|a, b| a.path.cmp(&b.path));
        files.dedup();
        CompilerIdentity {
            driver: driver.into(),
            api: api.into(),
            env,
            files,
        }
    }

    /// SHA-256 of the identity (hex): what isa.json shows as the family's `compiler_id`.
    pub fn digest(&self) -> String {
        let bytes = serde_json::to_vec(self).unwrap_or_default();
        hex(&Sha256::digest(&bytes))
    }
}

/// The files the environment `env` makes a child load: every existing absolute path among its
/// values (`:`-separated lists included; a folder: the files directly in it), the library a
/// Vulkan ICD manifest names, and for an OpenGL route (`MESA_LOADER_DRIVER_OVERRIDE`) the
/// `<dri>_dri.so` it forces, EGL and, for an OpenGL route (`opengl`: our SPIR-V translated to
/// GLSL), spirv-cross. The default of
/// [`Vendor::compiler_files`](super::route::Vendor::compiler_files).
pub fn files_of_env(env: &[(String, String)], opengl: bool) -> Vec<FileStamp> {
    let mut out = Vec::new();
    for (_, value) in env {
        for part in value.split(':').filter(|p| p.starts_with('/')) {
            let path = Path::new(part);
            if path.is_dir() {
                out.extend(files_in(path));
                continue;
            }
            out.extend(FileStamp::of(path));
            if part.ends_with(".json") {
                out.extend(manifest_library(path).as_deref().and_then(FileStamp::of));
            }
        }
    }
    if let Some((_, dri)) = env.iter().find(|(k, _)| k == "MESA_LOADER_DRIVER_OVERRIDE") {
        let file = format!("{dri}_dri.so");
        let mut dirs: Vec<PathBuf> = env
            .iter()
            .find(|(k, _)| k == "LIBGL_DRIVERS_PATH")
            .map(|(_, v)| std::env::split_paths(v).collect())
            .or_else(|| {
                std::env::var_os("LIBGL_DRIVERS_PATH").map(|v| std::env::split_paths(&v).collect())
            })
            .unwrap_or_default();
        if let Some(egl) = system_egl() {
            out.extend(FileStamp::of(egl));
            dirs.extend(egl.parent().map(|d| d.join("dri")));
        }
        out.extend(dirs.iter().find_map(|d| FileStamp::of(&d.join(&file))));
    }
    if opengl {
        out.extend(on_path("spirv-cross").as_deref().and_then(FileStamp::of));
    }
    out
}

/// The files directly in `dir` (a library folder an environment points at).
fn files_in(dir: &Path) -> Vec<FileStamp> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    rd.filter_map(|e| FileStamp::of(&e.ok()?.path())).collect()
}

/// The `library_path` of a Vulkan ICD manifest, resolved as the loader does: relative to the
/// manifest's folder when it holds a `/`, else a name in the dynamic linker's cache.
fn manifest_library(manifest: &Path) -> Option<PathBuf> {
    let text = std::fs::read_to_string(manifest).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let lib = v.get("ICD")?.get("library_path")?.as_str()?;
    let p = Path::new(lib);
    if p.is_absolute() {
        Some(p.to_path_buf())
    } else if lib.contains('/') {
        Some(manifest.parent()?.join(p))
    } else {
        crate::gpu::icd::library_on_system(lib)
    }
}

/// The system's libEGL.so.1, looked up once per process (ldconfig is a child process).
fn system_egl() -> Option<&'static Path> {
    static EGL: OnceLock<Option<PathBuf>> = OnceLock::new();
    EGL.get_or_init(|| crate::gpu::icd::library_on_system("libEGL.so.1"))
        .as_deref()
}

/// `program` on PATH.
fn on_path(program: &str) -> Option<PathBuf> {
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 of the file at `path` (hex), read now.
pub fn file_sha256(path: &Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut f = std::fs::File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = f.read(&mut buf)?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
    }
    Ok(hex(&hasher.finalize()))
}

/// [`file_sha256`] of the shadelab binary whose children compile (the SPIR-V built into it
/// and the code that builds the pipelines), once per path and process: a running binary is
/// not rewritten under its own feet (a rebuild replaces the file, and the next process sees it).
pub fn exe_sha256(path: &Path) -> std::io::Result<String> {
    use std::collections::HashMap;
    use std::sync::Mutex;
    static DONE: OnceLock<Mutex<HashMap<PathBuf, String>>> = OnceLock::new();
    let done = DONE.get_or_init(Default::default);
    if let Some(h) = done.lock().ok().and_then(|d| d.get(path).cloned()) {
        return Ok(h);
    }
    let h = file_sha256(path)?;
    if let Ok(mut d) = done.lock() {
        d.insert(path.to_path_buf(), h.clone());
    }
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rebuilt_shim_changes_the_identity() {
        let dir = tempfile::tempdir().unwrap();
        let shim = dir.path().join("libshim.so");
        std::fs::write(&shim, b"one").unwrap();
        let env = vec![("LD_PRELOAD".to_string(), shim.display().to_string())];
        let id = |env: &[(String, String)]| {
            CompilerIdentity::new("RADV (ACO)", "Vulkan", env, files_of_env(env, false))
        };
        let a = id(&env);
        assert_eq!(a.files.len(), 1, "{a:?}");
        assert_eq!(a, id(&env));
        // Teeth: another size (a rebuilt shim) is another identity.
        std::fs::write(&shim, b"other").unwrap();
        let b = id(&env);
        assert_ne!(a.digest(), b.digest());
        // So is another chip variable.
        let mut env2 = env.clone();
        env2.push(("RADV_FORCE_FAMILY".into(), "navi10".into()));
        assert_ne!(b.digest(), id(&env2).digest());
    }

    #[test]
    fn a_manifest_brings_its_library() {
        let dir = tempfile::tempdir().unwrap();
        let lib = dir.path().join("libvulkan_x.so");
        std::fs::write(&lib, b"elf").unwrap();
        let icd = dir.path().join("x.json");
        std::fs::write(
            &icd,
            r#"{"file_format_version":"1.0.0","ICD":{"library_path":"./libvulkan_x.so"}}"#,
        )
        .unwrap();
        let env = vec![("VK_DRIVER_FILES".to_string(), icd.display().to_string())];
        let files = files_of_env(&env, false);
        assert_eq!(files.len(), 2, "{files:?}");
        assert!(files[1].path.ends_with("libvulkan_x.so"), "{files:?}");
    }
}
