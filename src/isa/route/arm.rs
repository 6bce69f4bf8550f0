//! Arm Mali: Bifrost (G72, G52), Valhall (G57, G610) and Midgard (T860) through Mesa's
//! panfrost OpenGL ES driver, Utgard (Mali-450) through lima, both built by `make compilers`,
//! each on its noop drm-shim (panfrost's takes `PAN_GPU_ID=<hex product id>`; lima's is a
//! Mali-450). OpenGL ES rather than panvk: panvk offers Vulkan 1.0/1.1 only (no dynamic
//! rendering) and reports a code size alone, while the OpenGL ES compilers send their
//! shader-db line as a KHR_debug message: instructions, and on Bifrost and Valhall the cycle
//! estimate of each pipe (Bifrost: arith, texture, vary, ldst; Valhall: fma, cvt, sfu, v, t,
//! ls) with the bound one, whose figure is `cycles`; the row names it as `bound_<pipe>`.
//! float16 is `mediump` in GLSL ES, which panfrost computes in 16 bits on Bifrost and Valhall.
//! The compilers are Mesa's own for Mali; Arm's driver, which phones and boards ship, has
//! another (Arm's Mali Offline Compiler is its static analyser).
use crate::isa::request::RowKind;
use std::collections::BTreeMap;
use std::path::Path;

use super::{mesa_build, Api, Compiler, Ranking, Setup, Vendor};
use crate::isa::throughput;

/// The route through panfrost and lima.
pub struct Arm;

/// Chips and panfrost's product ids (src/panfrost/lib/pan_props.c).
const PANFROST: [(&str, &str); 5] = [
    ("t860", "860"),
    ("g72", "6221"),
    ("g52", "7212"),
    ("g57", "9093"),
    ("g610", "a867"),
];

/// The Utgard chip lima's shim is.
const LIMA: &str = "mali450";

/// The pipes of a shader-db line whose largest figure bounds the program (`cycles`).
const PIPES: [&str; 10] = [
    "arith", "texture", "vary", "ldst", "fma", "cvt", "sfu", "v", "t", "ls",
];

/// The unit of each pipe of [`PIPES`].
const PIPE_UNITS: [(&str, throughput::Unit); 10] = [
    ("arith", throughput::Unit::Arithmetic),
    ("texture", throughput::Unit::Texture),
    ("vary", throughput::Unit::Varying),
    ("ldst", throughput::Unit::LoadStore),
    ("fma", throughput::Unit::Arithmetic),
    ("cvt", throughput::Unit::Arithmetic),
    ("sfu", throughput::Unit::Sfu),
    ("v", throughput::Unit::Varying),
    ("t", throughput::Unit::Texture),
    ("ls", throughput::Unit::LoadStore),
];

/// panfrost's product id for `chip`: a known name, or `id<hex>` for any id.
fn product_id(chip: &str) -> Result<String, String> {
    if let Some(&(_, id)) = PANFROST.iter().find(|(c, _)| *c == chip) {
        return Ok(id.into());
    }
    chip.strip_prefix("id")
        .filter(|h| !h.is_empty() && h.chars().all(|c| c.is_ascii_hexdigit()))
        .map(str::to_string)
        .ok_or_else(|| {
            let known: Vec<&str> = PANFROST.iter().map(|(c, _)| *c).collect();
            format!(
                "`{chip}`: Mali chips are {}, {LIMA}, or id<hex product id>",
                known.join(", ")
            )
        })
}

impl Vendor for Arm {
    fn prefix(&self) -> &'static str {
        "arm"
    }

    fn name(&self) -> &'static str {
        "Arm"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        &["mali450", "t860", "g72", "g52", "g57", "g610"]
    }

    /// The Mali chips named here (panfrost's product ids, lima's Mali-450); any `id<hex>`
    /// product id is taken too.
    fn known_chips(&self) -> Vec<&'static str> {
        std::iter::once(LIMA)
            .chain(PANFROST.iter().map(|(c, _)| *c))
            .collect()
    }

    fn knows(&self, chip: &str) -> bool {
        chip == LIMA || product_id(chip).is_ok()
    }

    fn other_chips(&self) -> Option<&'static str> {
        Some("or id<hex>, a panfrost product id")
    }

    fn api(&self) -> Api {
        Api::OpenGlEs
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "panfrost / lima".into(),
            api: "OpenGL ES".into(),
            mesa_version: None,
            production: false,
            note: "Mesa's open-source compilers for Mali (panfrost's Bifrost/Valhall and \
                   Midgard back-ends, lima's Utgard); Arm's own driver has another compiler"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: throughput::MODEL_KEY.into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "cycles".into(),
            meaning: "Bifrost and Valhall: panfrost's cycles of the bound pipe (Valhall: FMA, \
                      CVT, SFU at a quarter of the FMA rate, varying, texture, load/store; \
                      Bifrost: arithmetic tuples, texture, varying, load/store), the bound one \
                      named; Midgard: bundles, one issued a cycle; Utgard: instruction words, \
                      one issued a cycle; the instruction count `inst` beside it"
                .into(),
        }
    }

    /// Utgard's and Midgard's VLIW words issue the reciprocal beside the addition it carries.
    fn fused_steps(&self, chip: &str) -> &'static [(crate::isa::kernel::Ratio, &'static str)] {
        use crate::isa::kernel::Ratio;
        match chip {
            "mali450" => &[(
                Ratio::Rcp,
                "lima's Utgard fragment processor issues a VLIW instruction with a scalar \
                 special-function slot beside the vector adder: the reciprocal shares the \
                 addition's instruction, so the step costs the addition alone",
            )],
            "t860" => &[(
                Ratio::Rcp,
                "panfrost's Midgard bundles put the reciprocal on the special-function (LUT) \
                 unit in the same bundle as the addition: the step costs the addition alone",
            )],
            _ => &[],
        }
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &["inst", "loops", "spills", "fills", "model_cycles"]
    }

    /// Bifrost and Valhall: the largest of panfrost's per-pipe cycles (its `cycles`);
    /// Midgard: its bundles; Utgard: its instruction words (single-pipe).
    fn model(&self, chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        use throughput::Unit;
        let pipes: Vec<(Unit, f64)> = PIPE_UNITS
            .iter()
            .filter_map(|&(k, u)| Some((u, *stats.get(k)?)))
            .collect();
        if !pipes.is_empty() {
            return throughput::bound(&pipes);
        }
        throughput::issue(stats, if chip == LIMA { "inst" } else { "bundles" })
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        None
    }

    fn setup(&self, _driver_files: Option<&Path>) -> Result<Setup, String> {
        mesa_build::setup(&["GLES_LIB", "PANFROST_SHIM", "LIMA_SHIM"])
    }

    fn setup_command(&self) -> &'static str {
        mesa_build::SETUP_COMMAND
    }

    fn child_env(
        &self,
        chip: &str,
        setup: &Setup,
        _driver_files: Option<&Path>,
    ) -> Result<Vec<(String, String)>, String> {
        if chip == LIMA {
            // lima compiles at the first draw unless told to precompile (at link time, with
            // the default key), and we never draw; its shader-db lines go out regardless.
            return mesa_build::gles_env(
                setup,
                "LIMA_SHIM",
                "lima",
                &[("LIMA_DEBUG", "precompile".into())],
            );
        }
        mesa_build::gles_env(
            setup,
            "PANFROST_SHIM",
            "panfrost",
            &[("PAN_GPU_ID", product_id(chip)?)],
        )
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // panfrost: "Mali-G52 (Panfrost)"; lima: "Mali450".
        let name = device_name.to_lowercase().replace('-', "");
        let want = format!("mali{}", chip.trim_start_matches("mali"));
        if name
            .split(|c: char| !c.is_ascii_alphanumeric())
            .any(|w| w == want)
        {
            Ok(())
        } else {
            Err(format!(
                "the renderer is `{device_name}`, not a Mali {chip}"
            ))
        }
    }

    fn parse_debug_message(&self, message: &str) -> Option<(String, Vec<(String, f64)>)> {
        let (stage, mut stats) = mesa_build::parse_shader_db(message)?;
        let cycles = stats.iter().find(|(k, _)| k == "cycles").map(|(_, v)| *v);
        let bound = stats
            .iter()
            .filter(|(k, _)| PIPES.contains(&k.as_str()))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .cloned();
        if let (Some(c), Some((pipe, v))) = (cycles, bound) {
            if v == c {
                stats.push((format!("bound_{pipe}"), v));
            }
        }
        Some((stage, stats))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_pipe_is_named() {
        let (stage, stats) = Arm
            .parse_debug_message(
                "MESA_SHADER_FRAGMENT shader: 68 inst, 7.000000 cycles, 1.06 fma, 0.25 cvt, \
                 0.5 sfu, 0.375 v, 0.000000 t, 7.000000 ls, 9 quadwords, 2 threads, 0 loops, \
                 0:0 spills:fills",
            )
            .unwrap();
        assert_eq!(stage, "fragment");
        assert!(stats.contains(&("bound_ls".into(), 7.0)), "{stats:?}");
        assert_eq!(
            stats
                .iter()
                .filter(|(k, _)| k.starts_with("bound_"))
                .count(),
            1
        );
        // Midgard and Utgard give no cycles: nothing is named bound.
        let (_, stats) = Arm
            .parse_debug_message(
                "MESA_SHADER_FRAGMENT shader: 43 inst, 20 bundles, 30 quadwords, 6 registers, \
                 2 threads, 0 loops, 0:0 spills:fills",
            )
            .unwrap();
        assert!(!stats.iter().any(|(k, _)| k.starts_with("bound_")));
    }

    #[test]
    fn the_model_is_the_bound_pipe_or_the_issue_count() {
        use throughput::Unit;
        let valhall: BTreeMap<String, f64> = [("fma", 0.44), ("cvt", 0.38), ("sfu", 0.19)]
            .into_iter()
            .chain([("v", 0.5), ("t", 0.0), ("ls", 7.0), ("inst", 66.0)])
            .map(|(k, v)| (k.to_string(), v))
            .collect();
        let m = Arm.model("g57", &valhall).unwrap();
        assert_eq!((m.cycles, m.bound), (7.0, Unit::LoadStore));
        // Teeth: more SFU work than load/store makes the SFU the bound.
        let mut sfu = valhall.clone();
        sfu.insert("sfu".into(), 8.0);
        assert_eq!(Arm.model("g57", &sfu).unwrap().bound, Unit::Sfu);
        let midgard: BTreeMap<String, f64> =
            [("bundles".to_string(), 16.0), ("inst".to_string(), 33.0)].into();
        let m = Arm.model("t860", &midgard).unwrap();
        assert_eq!((m.cycles, m.bound), (16.0, Unit::Issue));
        assert_eq!(Arm.model("mali450", &midgard).unwrap().cycles, 33.0);
        assert!(Arm.model("t860", &BTreeMap::new()).is_none());
    }

    #[test]
    fn chips_and_renderers() {
        assert_eq!(product_id("g610").as_deref(), Ok("a867"));
        assert_eq!(product_id("id7212").as_deref(), Ok("7212"));
        assert!(product_id("g99").is_err());
        assert!(Arm.check_device("g52", "Mali-G52 (Panfrost)").is_ok());
        assert!(Arm.check_device("mali450", "Mali450").is_ok());
        // Teeth: another Mali, a prefix of the name, a software renderer.
        assert!(Arm.check_device("g52", "Mali-G57 (Panfrost)").is_err());
        assert!(Arm.check_device("g5", "Mali-G52 (Panfrost)").is_err());
        assert!(Arm.check_device("g52", "llvmpipe (LLVM 15)").is_err());
    }
}
