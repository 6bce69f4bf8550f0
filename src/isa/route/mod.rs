//! The vendor seam of `shadelab isa`: one [`Vendor`] per compiler route, each in a file of its
//! own ([`amd`], [`intel`], [`nouveau`], [`terascale`], [`qualcomm`], [`arm`], [`broadcom`],
//! [`apple`];
//! the routes built by `make compilers` share [`mesa_build`]) and registered in [`VENDORS`]. A
//! vendor says which families it compiles, how a child compiles them (Vulkan pipeline
//! executable statistics, OpenGL's shader-db statistics through KHR_debug, or a compiler of
//! the route's own outside Mesa: [`Api`]), the
//! child's environment (driver selection, the preloaded drm-shim, the chip variable), which
//! statistic ranks its programs and what it means ([`Ranking`]), who compiled them
//! ([`Compiler`]), how to tell that the route is set up and the command that sets it up.
//!
//! Family ids are spelt `<vendor>:<chip>` everywhere (`amd:navi21`, `intel:tgl`,
//! `nvidia:nv162`, `terascale:cayman`; lower case): in isa.json's rows, the cost models
//! (`isa:amd:navi21`), CSV and HTML. A bare chip name given on the command line means AMD's
//! (`navi21` is `amd:navi21`).
//!
//! Adding a vendor: a file implementing [`Vendor`] and one line in [`VENDORS`].
pub mod amd;
pub mod apple;
pub mod arm;
pub mod broadcom;
pub mod brw_issue;
pub mod intel;
pub mod mesa_build;
pub mod nouveau;
pub mod qualcomm;
pub mod terascale;

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::gpu::vk::Executable;
use crate::isa::request::{ChildReport, ChildRequest};
use crate::isa::throughput;

/// Every vendor `shadelab isa` knows, in the order of its reports.
pub static VENDORS: [&dyn Vendor; 8] = [
    &amd::Amd,
    &intel::Intel,
    &nouveau::Nouveau,
    &terascale::TeraScale,
    &qualcomm::Qualcomm,
    &arm::Arm,
    &broadcom::Broadcom,
    &apple::Apple,
];

/// How a vendor's child compiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Api {
    /// Vulkan pipelines on the device whose name contains `device` (case-insensitive), read
    /// back through VK_KHR_pipeline_executable_properties.
    Vulkan { device: &'static str },
    /// OpenGL programs (our SPIR-V translated to GLSL) in an EGL surfaceless context, the
    /// compiler's statistics read from its KHR_debug messages.
    OpenGl,
    /// As [`Api::OpenGl`] in the newest OpenGL ES context the driver offers (GLSL ES; float16
    /// as `mediump` where the driver computes mediump in 16 bits).
    OpenGlEs,
    /// The route's own compiler, outside Mesa's drivers (an offline compiler it runs on each
    /// program's SPIR-V, a library it loads): the child calls [`Vendor::compile_own`]. Such a
    /// route is its file and one line in [`VENDORS`], like any other; it names the files of
    /// its compiler in [`Vendor::compiler_files`] (the compile store's key).
    Own,
}

/// The statistic that ranks a family's programs: the key in a row's `statistics`, read from
/// the rows of `stage` and `kind` (the timed draw's fragment shader for every vendor).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Ranking {
    pub key: String,
    pub stage: String,
    pub kind: crate::isa::request::RowKind,
    /// "cycles per wave", "cycles per thread", "instructions", "ALU instruction groups".
    pub unit: String,
    /// What the figure is, e.g. "ACO inverse throughput, cycles per wave".
    pub meaning: String,
}

/// Who compiled a family's programs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Compiler {
    /// "RADV (ACO)", "ANV (brw)", "nouveau (nv50 IR codegen)", "r600 (sb)".
    pub driver: String,
    /// "Vulkan" or "OpenGL".
    pub api: String,
    /// The driver's version string as the child read it ("Mesa 22.3.6"); absent for a family
    /// that did not compile.
    pub mesa_version: Option<String>,
    /// Whether it is the compiler the vendor's own Linux driver ships (AMD's RADV, Intel's
    /// ANV), as opposed to Mesa's own compiler for hardware whose vendor ships another one
    /// (NVIDIA's proprietary driver, AMD's Catalyst for TeraScale).
    pub production: bool,
    pub note: String,
}

/// What a set-up route gives its children (read from its `.env` file in the cache, see
/// scripts/setup-vendors.sh), or nothing for a route that needs no set-up.
#[derive(Debug, Clone, Default)]
pub struct Setup {
    pub values: BTreeMap<String, String>,
}

impl Setup {
    /// The value of `key`, or an error naming the file it should be in.
    pub fn get(&self, key: &str) -> Result<&str, String> {
        self.values
            .get(key)
            .map(String::as_str)
            .ok_or_else(|| format!("{key} is not in the set-up file"))
    }
}

/// One compiler route. Implementations are unit structs registered in [`VENDORS`].
pub trait Vendor: Sync {
    /// The prefix of this vendor's family ids: "amd", "intel", "nvidia", "terascale".
    fn prefix(&self) -> &'static str;
    /// How a person names the vendor in a sentence or a table: "AMD", "Broadcom".
    fn name(&self) -> &'static str;
    /// The families compiled by default (chips, without the prefix), oldest first.
    fn default_chips(&self) -> &'static [&'static str];
    /// The chips this route's driver knows by name (lower case), whatever their status: what
    /// `--families` and an `isa:` cost model accept ([`check_chip`], before any child starts;
    /// an unknown name used to reach the driver, which aborted or fell back). Per Mesa version
    /// where the versions differ (AMD's gfx1100 is navi31 from Mesa 25).
    fn known_chips(&self) -> Vec<&'static str>;
    /// Whether `chip` is one of this route's: one of [`Vendor::known_chips`] by default.
    fn knows(&self, chip: &str) -> bool {
        self.known_chips().contains(&chip)
    }
    /// Names this route takes beyond [`Vendor::known_chips`], in words (Arm's raw product
    /// ids), for the message of an unknown chip.
    fn other_chips(&self) -> Option<&'static str> {
        None
    }
    fn api(&self) -> Api;
    fn compiler(&self) -> Compiler;
    fn ranking(&self) -> Ranking;
    /// The statistics every draw row of this vendor carries (docs/isa.schema.json).
    fn required_statistics(&self) -> &'static [&'static str];
    /// Whether the driver compiles float16 arithmetic on `chip`, when known without a child
    /// (the Vulkan routes read it from the device: `None`).
    fn float16(&self, chip: &str) -> Option<bool>;
    /// The route's set-up, or why it is not set up. `driver_files` is the Vulkan ICD
    /// manifest the user asked for (AMD's `--driver-files`).
    fn setup(&self, driver_files: Option<&std::path::Path>) -> Result<Setup, String>;
    /// The command that sets the route up.
    fn setup_command(&self) -> &'static str;
    /// The set-up of `chip` (a vendor whose newer chips need another build: Intel's Meteor
    /// Lake and later need ANV 25.0.7 of `make compilers`); the route's by default.
    fn setup_for(
        &self,
        _chip: &str,
        driver_files: Option<&std::path::Path>,
    ) -> Result<Setup, String> {
        self.setup(driver_files)
    }
    /// The command that sets `chip` up; the route's by default.
    fn setup_command_for(&self, _chip: &str) -> &'static str {
        self.setup_command()
    }
    /// The child's environment for `chip` (driver selection, preloaded shim, chip variable),
    /// set before the child loads any driver.
    fn child_env(
        &self,
        chip: &str,
        setup: &Setup,
        driver_files: Option<&std::path::Path>,
    ) -> Result<Vec<(String, String)>, String>;
    /// The names to give the driver for `chip`, the likeliest first (a driver that renamed a
    /// chip between releases: AMD's `gfx1100`, `navi31` in Mesa 25); the next is tried when the
    /// driver says it does not know one ([`Vendor::unknown_chip`]). `[chip]` by default.
    fn driver_chips(&self, chip: &str, _setup: &Setup) -> Vec<String> {
        vec![chip.to_string()]
    }
    /// Whether a child that failed with `why` failed because the driver does not know the
    /// chip's name (then the next of [`Vendor::driver_chips`] is tried).
    fn unknown_chip(&self, _why: &str) -> bool {
        false
    }
    /// Refuses a device that is not `chip` (a driver that does not know the chip may fall
    /// back to a software renderer silently): `Err(why)`.
    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String>;
    /// The executables of one compiled program on `chip` as rows should see them (Intel: one
    /// per SIMD width merged into one per stage, with its throughput figures); unchanged by
    /// default.
    fn merge_executables(&self, _chip: &str, exes: Vec<Executable>) -> Vec<Executable> {
        exes
    }
    /// The statistics of one KHR_debug message of the OpenGL compiler (or, with
    /// [`Vendor::statistics_on_stderr`], one line the compiler printed): (stage, statistics)
    /// with the driver's own names, or `None` for a message that holds none.
    fn parse_debug_message(&self, _message: &str) -> Option<(String, Vec<(String, f64)>)> {
        None
    }
    /// Compiles everything `req` asks for on `chip` with the route's own compiler, in the child
    /// process that [`Vendor::child_env`] set up: the routes whose [`Api`] is [`Api::Own`].
    /// The others compile through their Mesa driver and leave it: an error.
    fn compile_own(&self, _req: &ChildRequest, _chip: &str) -> crate::error::Result<ChildReport> {
        Err(crate::error::Error::Usage(format!(
            "{}: this route compiles through a Mesa driver ({:?}), it has no compiler of its own",
            self.name(),
            self.api()
        )))
    }
    /// Whether a Vulkan driver prints the compiler's own statistics on stderr (a line per
    /// program, read by [`Vendor::parse_debug_message`]) beyond the few its pipeline
    /// statistics give: the child catches stderr around each compile and adds them to that
    /// program's executables (asahi's Honeykrisp: its cycle model). No by default.
    fn statistics_on_stderr(&self) -> bool {
        false
    }
    /// The throughput model of one row's `stats` on `chip` ([`throughput`]): its figure, the
    /// ranking statistic (written under the ranking key where it is not one of the
    /// compiler's own), and the unit that bounds the program. By default the ranking
    /// statistic as it stands, a single-pipe (issue) model.
    fn model(&self, _chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        throughput::issue(stats, &self.ranking().key)
    }
    /// Whether one FP32 FMA is one unit of this route's model (its ranking counts FMAs): the
    /// calibration then wants its FMA step within 10% of one
    /// ([`crate::isa::calibrate::not_positive`]). No by default.
    fn counts_fmas(&self) -> bool {
        false
    }
    /// The calibration steps `chip`'s compiler fuses into the operations around them, so that
    /// their marginal cost is zero by design, not by a model that prices latency: each ratio
    /// with why, in the compiler's terms (docs/calibration.md says it too). None by default.
    fn fused_steps(&self, _chip: &str) -> &'static [(crate::isa::kernel::Ratio, &'static str)] {
        &[]
    }
    /// The statistics every draw row of this vendor carries beyond
    /// [`Vendor::required_statistics`] (an evaluation's differences do not): the occupancy of
    /// [`Vendor::occupancy_statistics`] by default.
    fn required_draw_statistics(&self) -> &'static [&'static str] {
        use crate::isa::occupancy::{REGISTERS_KEY, WAVES_KEY};
        match self.occupancy_statistics() {
            Some((_, Some(_))) => &[REGISTERS_KEY, WAVES_KEY],
            Some((_, None)) => &[REGISTERS_KEY],
            None => &[],
        }
    }
    /// The compiler's own statistics of a program's registers and of the waves (threads) they
    /// allow, where it states both or the registers alone: what [`Vendor::occupancy`] reads by
    /// default. None by default (no register statistic).
    fn occupancy_statistics(&self) -> Option<(&'static str, Option<&'static str>)> {
        None
    }
    /// The registers a program of `chip` holds and the waves (threads, warps) they let the
    /// family keep resident ([`crate::isa::occupancy`]), out of a draw row's `stats`; `None`
    /// where the compiler reports no registers. By default the figures of
    /// [`Vendor::occupancy_statistics`] as they stand.
    fn occupancy(
        &self,
        _chip: &str,
        stats: &BTreeMap<String, f64>,
    ) -> Option<crate::isa::occupancy::Occupancy> {
        let (registers, waves) = self.occupancy_statistics()?;
        crate::isa::occupancy::stated(stats, registers, waves)
    }
    /// Whether the OpenGL child counts the special-function operations of each program in the
    /// NIR Mesa hands the compiler (`MESA_GLSL=dump`, caught on stderr), as the statistic
    /// [`throughput::SFU_KEY`]: the input of a weighted model where the compiler only counts
    /// and prints no disassembly. No by default.
    fn counts_sfu_ops(&self) -> bool {
        false
    }
    /// The files whose change changes this route's compiler (build id of
    /// [`crate::isa::identity::CompilerIdentity`]), given its child's environment `env`: by
    /// default the shims, manifests, libraries and programs that environment loads
    /// ([`crate::isa::identity::files_of_env`]).
    fn compiler_files(&self, env: &[(String, String)]) -> Vec<crate::isa::identity::FileStamp> {
        let opengl = matches!(self.api(), Api::OpenGl | Api::OpenGlEs);
        crate::isa::identity::files_of_env(env, opengl)
    }
}

/// A family: its vendor and chip.
#[derive(Clone, Copy)]
pub struct Family {
    pub vendor: &'static dyn Vendor,
    pub chip: &'static str,
}

impl std::fmt::Debug for Family {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.id())
    }
}

impl Family {
    /// `<vendor>:<chip>`.
    pub fn id(&self) -> String {
        format!("{}:{}", self.vendor.prefix(), self.chip)
    }
}

/// The vendor and chip of a family id (`intel:tgl`) or a bare AMD chip name (`navi21`); an
/// error names the known prefixes.
pub fn resolve(id: &str) -> Result<(&'static dyn Vendor, String), String> {
    let id = id.trim().to_lowercase();
    let (prefix, chip) = id.split_once(':').unwrap_or(("amd", &id));
    let vendor = VENDORS
        .iter()
        .find(|v| v.prefix() == prefix)
        .ok_or_else(|| {
            let known: Vec<&str> = VENDORS.iter().map(|v| v.prefix()).collect();
            format!(
                "family `{id}`: unknown vendor `{prefix}` (known: {})",
                known.join(", ")
            )
        })?;
    if chip.is_empty() || !chip.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "family `{id}`: a chip name is letters, digits and underscores"
        ));
    }
    Ok((*vendor, chip.to_string()))
}

/// `chip` of `vendor` when the route knows it ([`Vendor::knows`]), else the message naming
/// the chips it knows: "unknown chip 'nonsense' for amd; known: tahiti, ...".
pub fn check_chip(vendor: &dyn Vendor, chip: &str) -> Result<(), String> {
    if vendor.knows(chip) {
        return Ok(());
    }
    Err(format!(
        "unknown chip '{chip}' for {}; known: {}{}",
        vendor.prefix(),
        vendor.known_chips().join(", "),
        vendor
            .other_chips()
            .map_or(String::new(), |o| format!(" ({o})"))
    ))
}

/// The family ids compiled by default: every default chip of every vendor.
pub fn default_family_ids() -> Vec<String> {
    VENDORS
        .iter()
        .flat_map(|v| {
            v.default_chips()
                .iter()
                .map(|c| format!("{}:{c}", v.prefix()))
        })
        .collect()
}

/// The user's cache of set-up routes: `$XDG_CACHE_HOME/shadelab/vendors`, else
/// `~/.cache/shadelab/vendors` (scripts/setup-vendors.sh writes there).
pub fn cache_dir() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("shadelab").join("vendors"))
}

/// Reads `<cache>/<route>.env` (KEY=VALUE lines); every value that is an absolute path must
/// exist. An error says what is missing.
pub fn read_env(route: &str) -> Result<Setup, String> {
    let dir = cache_dir().ok_or("no cache directory (neither XDG_CACHE_HOME nor HOME is set)")?;
    read_env_in(&dir, route)
}

/// [`read_env`] in the cache folder `dir`.
pub fn read_env_in(dir: &std::path::Path, route: &str) -> Result<Setup, String> {
    let path = dir.join(format!("{route}.env"));
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("{} cannot be read ({e})", path.display()))?;
    let mut values = BTreeMap::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let (k, v) = line
            .split_once('=')
            .ok_or_else(|| format!("{}: `{line}` is not KEY=VALUE", path.display()))?;
        if v.starts_with('/') && !std::path::Path::new(v).exists() {
            return Err(format!("{}: {k}={v} does not exist", path.display()));
        }
        values.insert(k.to_string(), v.to_string());
    }
    Ok(Setup { values })
}

/// Whether `program` is on PATH, else why not.
pub fn need_program(program: &str, package: &str) -> Result<(), String> {
    let found = std::env::var_os("PATH")
        .map(|p| std::env::split_paths(&p).any(|d| d.join(program).is_file()))
        .unwrap_or(false);
    if found {
        Ok(())
    } else {
        Err(format!(
            "{program} is not on PATH (Debian package {package})"
        ))
    }
}

/// The set-up of an OpenGL route: the system's EGL and Mesa's `dri` driver, spirv-cross, and
/// the shim `shim_key` of `gl.env` (scripts/setup-vendors.sh gl). EGL is found in the dynamic
/// linker's cache, the driver in the `dri` folder beside it (Mesa's default DRI path,
/// `${libdir}/dri`) or in `LIBGL_DRIVERS_PATH`.
pub fn gl_setup(dri: &str, shim_key: &str) -> Result<Setup, String> {
    let egl = crate::gpu::icd::library_on_system("libEGL.so.1")
        .ok_or("libEGL.so.1 is not in the dynamic linker's cache (Debian package libegl1)")?;
    let file = format!("{dri}_dri.so");
    let mut dirs: Vec<PathBuf> = std::env::var_os("LIBGL_DRIVERS_PATH")
        .map(|v| std::env::split_paths(&v).collect())
        .unwrap_or_default();
    dirs.extend(egl.parent().map(|d| d.join("dri")));
    if !dirs.iter().any(|d| d.join(&file).exists()) {
        let shown: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        return Err(format!(
            "{file} is in none of {} (Debian package libgl1-mesa-dri)",
            shown.join(", ")
        ));
    }
    need_program("spirv-cross", "spirv-cross")?;
    let setup = read_env("gl")?;
    setup.get(shim_key)?;
    Ok(setup)
}

/// The environment of an OpenGL child: the shim preloaded, Mesa's `dri` driver forced on an
/// EGL surfaceless display, the chip variable, no shader cache (a cached shader reports no
/// statistics).
pub fn gl_env(
    setup: &Setup,
    shim_key: &str,
    dri: &str,
    chip_var: (&str, String),
) -> Result<Vec<(String, String)>, String> {
    Ok(vec![
        ("LD_PRELOAD".into(), setup.get(shim_key)?.into()),
        (chip_var.0.into(), chip_var.1),
        ("MESA_LOADER_DRIVER_OVERRIDE".into(), dri.into()),
        ("EGL_PLATFORM".into(), "surfaceless".into()),
        ("MESA_SHADER_CACHE_DISABLE".into(), "true".into()),
        ("MESA_GLSL_CACHE_DISABLE".into(), "true".into()),
    ])
}

/// "key: value, key: value" pairs of a shader-db message, with the numbers parsed.
pub fn shader_db_pairs(text: &str) -> Vec<(String, f64)> {
    text.split(',')
        .filter_map(|part| {
            let part = part.trim();
            let (k, v) = part.split_once(':').or_else(|| {
                // "110 dw": value first, name after.
                let (v, k) = part.split_once(' ')?;
                Some((k, v))
            })?;
            Some((k.trim().to_string(), v.trim().parse().ok()?))
        })
        .collect()
}

/// Refuses Mesa's software renderers: a chip the hardware driver does not know may fall back
/// to one of them without an error.
pub fn refuse_software(device_name: &str) -> Result<(), String> {
    let d = device_name.to_lowercase();
    for soft in ["llvmpipe", "softpipe", "lavapipe", "swrast"] {
        if d.contains(soft) {
            return Err(format!(
                "the driver fell back to a software renderer (`{device_name}`): it does not \
                 know this chip, nothing was measured"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_resolve_with_a_bare_name_meaning_amd() {
        let (v, c) = resolve("navi21").unwrap();
        assert_eq!((v.prefix(), c.as_str()), ("amd", "navi21"));
        let (v, c) = resolve(" Intel:TGL ").unwrap();
        assert_eq!((v.prefix(), c.as_str()), ("intel", "tgl"));
        assert!(resolve("nvidia:nv162").is_ok());
        // Teeth: an unknown vendor and an empty or odd chip are refused.
        let why = resolve("vivante:gc7000").err().unwrap_or_default();
        assert!(why.contains("unknown vendor"), "{why}");
        assert!(resolve("intel:").is_err());
        assert!(resolve("intel:t/gl").is_err());
    }

    /// Every vendor knows its default chips; a chip no route knows is refused with the
    /// vendor's known names (it used to reach the driver: SIGABRT, or "0 compiled", exit 0).
    #[test]
    fn unknown_chips_are_refused_with_the_known_ones() {
        for v in VENDORS {
            for c in v.default_chips() {
                assert!(check_chip(v, c).is_ok(), "{}:{c}", v.prefix());
            }
            let why = check_chip(v, "nonsense").unwrap_err();
            assert!(
                why.starts_with(&format!(
                    "unknown chip 'nonsense' for {}; known: ",
                    v.prefix()
                )) && why.contains(v.default_chips()[0]),
                "{why}"
            );
        }
        let amd = resolve("amd:navi24").unwrap().0;
        // known to RADV 22.3.6 although it dies there (SIGFPE): reported per family, not refused
        assert!(check_chip(amd, "navi24").is_ok());
        assert!(check_chip(amd, "gfx1030").is_err());
        let arm = resolve("arm:g52").unwrap().0;
        assert!(check_chip(arm, "id7212").is_ok() && check_chip(arm, "idzz").is_err());
        let nv = resolve("nvidia:nv162").unwrap().0;
        assert!(check_chip(nv, "nv50").is_ok() && check_chip(nv, "nv1").is_err());
    }

    #[test]
    fn every_vendor_has_its_own_prefix_and_default_families() {
        let ids = default_family_ids();
        for v in VENDORS {
            assert!(!v.default_chips().is_empty(), "{}", v.prefix());
            assert_eq!(
                VENDORS.iter().filter(|w| w.prefix() == v.prefix()).count(),
                1
            );
            // a name a person reads ("Broadcom", not the id's "broadcom"), one per vendor
            assert!(
                v.name().starts_with(|c: char| c.is_ascii_uppercase()),
                "{}: {:?}",
                v.prefix(),
                v.name()
            );
            assert_eq!(VENDORS.iter().filter(|w| w.name() == v.name()).count(), 1);
            let r = v.ranking();
            assert!(
                v.required_statistics().contains(&r.key.as_str()),
                "{}",
                v.prefix()
            );
        }
        for want in [
            "amd:navi21",
            "intel:skl",
            "intel:icl",
            "intel:tgl",
            "intel:adl",
            "intel:dg2",
            "nvidia:nvc0",
            "nvidia:nve4",
            "nvidia:nv117",
            "nvidia:nv134",
            "nvidia:nv162",
            "terascale:cypress",
            "terascale:cayman",
            "intel:mtl",
            "intel:lnl",
            "intel:bmg",
            "intel:ptl",
            "qualcomm:a618",
            "qualcomm:a630",
            "qualcomm:a660",
            "qualcomm:a730",
            "qualcomm:a740",
            "qualcomm:a750",
            "arm:g52",
            "arm:g72",
            "arm:g57",
            "arm:g610",
            "arm:t860",
            "arm:mali450",
            "broadcom:v3d42",
            "broadcom:vc4",
            "apple:g13",
        ] {
            assert!(ids.iter().any(|i| i == want), "{want} not among {ids:?}");
        }
    }

    #[test]
    fn a_route_is_set_up_when_its_env_file_and_files_are_there() {
        let dir = tempfile::tempdir().unwrap();
        let why = read_env_in(dir.path(), "gl").err().unwrap_or_default();
        assert!(why.contains("gl.env cannot be read"), "{why}");
        let shim = dir.path().join("shim.so");
        let env = dir.path().join("gl.env");
        std::fs::write(
            &env,
            format!("NOUVEAU_SHIM={}\nSOURCE=x.deb\n", shim.display()),
        )
        .unwrap();
        // Teeth: a path that does not exist is not set up.
        let why = read_env_in(dir.path(), "gl").err().unwrap_or_default();
        assert!(why.contains("does not exist"), "{why}");
        std::fs::write(&shim, b"").unwrap();
        let setup = read_env_in(dir.path(), "gl").unwrap();
        assert_eq!(setup.get("SOURCE"), Ok("x.deb"));
        assert!(setup.get("RADEON_SHIM").is_err());
        std::fs::write(&env, "no equals sign\n").unwrap();
        assert!(read_env_in(dir.path(), "gl").is_err());
    }

    #[test]
    fn software_renderers_are_refused() {
        assert!(refuse_software("llvmpipe (LLVM 15.0.6, 256 bits)").is_err());
        assert!(refuse_software("NV162").is_ok());
    }
}
