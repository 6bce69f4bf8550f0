//! Vulkan drivers found the way the Vulkan loader finds them: their ICD manifests, matched by
//! the library a manifest names (`libvulkan_radeon.so`), never by the manifest's file name,
//! which differs between Mesa releases (`radeon_icd.x86_64.json` in Mesa 22.3,
//! `radeon_icd.json` in Mesa 25) and between architectures.
//!
//! The folders are the loader's, in its order (Khronos Vulkan-Loader,
//! docs/LoaderDriverInterface.md, "Driver Discovery on Linux"): the files and folders of
//! `VK_DRIVER_FILES` (its older name `VK_ICD_FILENAMES`) and `VK_ADD_DRIVER_FILES`, then
//! `icd.d` under `$XDG_CONFIG_HOME` (`~/.config`), `$XDG_CONFIG_DIRS` (`/etc/xdg`), `/etc`,
//! `$XDG_DATA_HOME` (`~/.local/share`) and `$XDG_DATA_DIRS` (`/usr/local/share:/usr/share`),
//! each followed by `vulkan/icd.d`. Where two manifests name the same library (an i386 and an
//! x86-64 one of a multiarch system), the one whose library is of this process's
//! architecture wins: a manifest with an absolute `library_path` must name an existing ELF
//! file of this machine; a bare name is left to the dynamic linker, as the loader does.
use std::path::{Path, PathBuf};

/// One ICD manifest: where it is and the driver library it names.
#[derive(Debug, Clone, PartialEq)]
pub struct Manifest {
    pub path: PathBuf,
    /// `ICD.library_path` as written (absolute, relative to the manifest, or a bare name).
    pub library_path: String,
    /// `ICD.api_version`, e.g. "1.3.230" (Mesa 22.3.6), "1.4.305" (Mesa 25.0.7).
    pub api_version: String,
}

impl Manifest {
    /// The library's file name: `libvulkan_radeon.so`.
    pub fn library_name(&self) -> &str {
        self.library_path
            .rsplit('/')
            .next()
            .unwrap_or(&self.library_path)
    }

    /// Reads a manifest; `None` for a file that is not an ICD manifest.
    pub fn read(path: &Path) -> Option<Manifest> {
        let text = std::fs::read_to_string(path).ok()?;
        let v: serde_json::Value = serde_json::from_str(&text).ok()?;
        let icd = v.get("ICD")?;
        Some(Manifest {
            path: path.to_path_buf(),
            library_path: icd.get("library_path")?.as_str()?.to_string(),
            api_version: icd
                .get("api_version")
                .and_then(|a| a.as_str())
                .unwrap_or("")
                .to_string(),
        })
    }

    /// Whether the library can be this process's: a bare name (the dynamic linker's to find),
    /// or a path (relative to the manifest's folder) to an ELF file of this architecture.
    pub fn usable(&self) -> bool {
        if !self.library_path.contains('/') {
            return true;
        }
        let lib = self
            .path
            .parent()
            .unwrap_or(Path::new("/"))
            .join(&self.library_path);
        elf_machine(&lib).is_some_and(|m| Some(m) == own_machine())
    }
}

/// The loader's search list: (environment files and folders, then the standard folders).
pub fn search_paths() -> Vec<PathBuf> {
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    let home = var("HOME").map(PathBuf::from);
    let mut paths: Vec<PathBuf> = Vec::new();
    for k in ["VK_DRIVER_FILES", "VK_ICD_FILENAMES", "VK_ADD_DRIVER_FILES"] {
        if let Some(v) = var(k) {
            paths.extend(std::env::split_paths(&v));
        }
    }
    let under = |base: Option<PathBuf>| base.map(|b| b.join("vulkan").join("icd.d"));
    let list = |v: Option<String>, default: &str| -> Vec<PathBuf> {
        std::env::split_paths(&v.unwrap_or_else(|| default.into()))
            .filter(|p| !p.as_os_str().is_empty())
            .collect()
    };
    paths.extend(under(
        var("XDG_CONFIG_HOME")
            .map(PathBuf::from)
            .or_else(|| home.as_ref().map(|h| h.join(".config"))),
    ));
    for d in list(var("XDG_CONFIG_DIRS"), "/etc/xdg") {
        paths.extend(under(Some(d)));
    }
    paths.extend(under(Some(PathBuf::from("/etc"))));
    paths.extend(under(
        var("XDG_DATA_HOME")
            .map(PathBuf::from)
            .or_else(|| home.as_ref().map(|h| h.join(".local/share"))),
    ));
    for d in list(var("XDG_DATA_DIRS"), "/usr/local/share:/usr/share") {
        paths.extend(under(Some(d)));
    }
    let mut seen = Vec::new();
    for p in paths {
        if !seen.contains(&p) {
            seen.push(p);
        }
    }
    seen
}

/// Every manifest of `paths` (a file, or a folder's `*.json` in name order).
pub fn manifests_in(paths: &[PathBuf]) -> Vec<Manifest> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_file() {
            out.extend(Manifest::read(p));
        } else if let Ok(rd) = std::fs::read_dir(p) {
            let mut files: Vec<PathBuf> = rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.extension().is_some_and(|x| x == "json"))
                .collect();
            files.sort();
            out.extend(files.iter().filter_map(|f| Manifest::read(f)));
        }
    }
    out
}

/// The manifest of the driver whose library is `library` (`libvulkan_radeon.so`), found by
/// the loader's rules; an error says what was searched and the likely cause.
pub fn find_driver(library: &str, package: &str) -> Result<Manifest, String> {
    find_driver_in(&search_paths(), library, package)
}

/// [`find_driver`] over `paths`.
pub fn find_driver_in(paths: &[PathBuf], library: &str, package: &str) -> Result<Manifest, String> {
    let named: Vec<Manifest> = manifests_in(paths)
        .into_iter()
        .filter(|m| m.library_name() == library)
        .collect();
    if let Some(m) = named.iter().find(|m| m.usable()) {
        return Ok(m.clone());
    }
    let searched: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    if let Some(m) = named.first() {
        return Err(format!(
            "{} names {}, which is not a library of this machine ({})",
            m.path.display(),
            m.library_path,
            std::env::consts::ARCH
        ));
    }
    let pinned = ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"]
        .iter()
        .find(|k| std::env::var_os(k).is_some_and(|v| !v.is_empty()));
    let cause = if let Some(lib) = library_on_system(library) {
        format!(
            "the driver {} is installed but no ICD manifest names it: the manifest was removed \
             or is outside the loader's folders{}",
            lib.display(),
            pinned.map_or(String::new(), |k| format!(" ({k} is set)"))
        )
    } else {
        format!("install {package} (scripts/install-deps.sh run)")
    };
    Err(format!(
        "no Vulkan ICD manifest names {library} in {}: {cause}",
        searched.join(", ")
    ))
}

/// `library` (a file name such as `libEGL.so.1`) in a folder of the dynamic linker's cache
/// (`ldconfig -p`), of this machine's architecture, where there is one.
pub fn library_on_system(library: &str) -> Option<PathBuf> {
    let out = std::process::Command::new("ldconfig")
        .arg("-p")
        .output()
        .or_else(|_| {
            std::process::Command::new("/sbin/ldconfig")
                .arg("-p")
                .output()
        })
        .ok()?;
    String::from_utf8_lossy(&out.stdout).lines().find_map(|l| {
        let (name, path) = l.trim().split_once(" => ")?;
        let name = name.split_whitespace().next()?;
        (name == library || name.starts_with(&format!("{library}.")))
            .then(|| PathBuf::from(path.trim()))
            .filter(|p| elf_machine(p) == own_machine())
    })
}

/// The ELF `e_machine` of a file, `None` for anything that is not ELF.
fn elf_machine(path: &Path) -> Option<u16> {
    use std::io::Read;
    let mut head = [0u8; 20];
    std::fs::File::open(path).ok()?.read_exact(&mut head).ok()?;
    if &head[..4] != b"\x7fELF" {
        return None;
    }
    let bytes = [head[18], head[19]];
    Some(if head[5] == 2 {
        u16::from_be_bytes(bytes)
    } else {
        u16::from_le_bytes(bytes)
    })
}

/// This process's ELF machine, read from its own executable.
fn own_machine() -> Option<u16> {
    std::env::current_exe().ok().and_then(|e| elf_machine(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(path: &Path, library: &str) {
        std::fs::write(
            path,
            format!(
                "{{\"ICD\": {{\"api_version\": \"1.4.305\", \"library_path\": \"{library}\"}}, \
                 \"file_format_version\": \"1.0.1\"}}"
            ),
        )
        .unwrap();
    }

    #[test]
    fn a_driver_is_found_by_its_library_whatever_the_manifest_is_called() {
        let dir = tempfile::tempdir().unwrap();
        let icd = dir.path().join("icd.d");
        std::fs::create_dir(&icd).unwrap();
        // Mesa 25's names (no architecture infix), bare library names.
        write(&icd.join("radeon_icd.json"), "libvulkan_radeon.so");
        write(&icd.join("intel_icd.json"), "libvulkan_intel.so");
        // An absolute path of this executable: a library of this machine's architecture.
        let exe = std::env::current_exe().unwrap();
        write(&icd.join("odd_name.json"), &exe.display().to_string());
        std::fs::write(icd.join("not_a_manifest.json"), "{}").unwrap();
        let paths = vec![icd.clone()];
        let m = find_driver_in(&paths, "libvulkan_radeon.so", "mesa-vulkan-drivers").unwrap();
        assert_eq!(m.path, icd.join("radeon_icd.json"));
        assert_eq!(m.api_version, "1.4.305");
        let m = find_driver_in(&paths, "libvulkan_intel.so", "mesa-vulkan-drivers").unwrap();
        assert_eq!(m.path, icd.join("intel_icd.json"));
        let own = exe.file_name().unwrap().to_string_lossy().into_owned();
        let m = find_driver_in(&paths, &own, "x").unwrap();
        assert_eq!(m.path, icd.join("odd_name.json"));
        // Teeth: a library no manifest names is not found, and says what was searched.
        let why = find_driver_in(&paths, "libvulkan_lvp.so", "mesa-vulkan-drivers")
            .err()
            .unwrap_or_default();
        assert!(
            why.contains("no Vulkan ICD manifest names libvulkan_lvp.so"),
            "{why}"
        );
        assert!(why.contains(&icd.display().to_string()), "{why}");
    }

    #[test]
    fn a_manifest_of_another_architecture_is_passed_over() {
        let dir = tempfile::tempdir().unwrap();
        // A file that exists but is no ELF library of this machine (an i386 one would be
        // refused the same way: its e_machine differs).
        let foreign = dir.path().join("libvulkan_radeon.so");
        std::fs::write(
            &foreign,
            b"\x7fELF\x01\x01\x01\0\0\0\0\0\0\0\0\0\x03\0\x03\0",
        )
        .unwrap();
        write(
            &dir.path().join("radeon_icd.i686.json"),
            &foreign.display().to_string(),
        );
        let paths = vec![dir.path().to_path_buf()];
        let why = find_driver_in(&paths, "libvulkan_radeon.so", "mesa-vulkan-drivers")
            .err()
            .unwrap_or_default();
        assert!(why.contains("not a library of this machine"), "{why}");
        // With one of this machine beside it, that one is chosen.
        let own = dir.path().join("own");
        std::fs::create_dir(&own).unwrap();
        let lib = own.join("libvulkan_radeon.so");
        std::os::unix::fs::symlink(std::env::current_exe().unwrap(), &lib).unwrap();
        write(
            &dir.path().join("radeon_icd.x86.json"),
            &lib.display().to_string(),
        );
        let m = find_driver_in(&paths, "libvulkan_radeon.so", "x").unwrap();
        assert_eq!(m.path, dir.path().join("radeon_icd.x86.json"));
    }

    #[test]
    fn the_search_follows_the_loaders_folders() {
        let paths = search_paths();
        // The standard system folders are searched whatever the environment (XDG_DATA_DIRS
        // unset means /usr/local/share:/usr/share).
        assert!(
            paths.iter().any(|p| p.ends_with("vulkan/icd.d")),
            "{paths:?}"
        );
        assert!(
            paths.contains(&PathBuf::from("/etc/vulkan/icd.d")),
            "{paths:?}"
        );
    }
}
