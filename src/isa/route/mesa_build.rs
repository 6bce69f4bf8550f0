//! What the routes built by `make compilers` share (scripts/build-compilers.sh: Mesa 25.0.7
//! from Debian's source package in the user's cache, its `compilers.env` naming the files):
//! the set-up check, the environment of a Vulkan child on a drm-shim (Turnip, ANV 25.0.7,
//! Honeykrisp) and
//! of an OpenGL ES child (panfrost, lima, v3d, vc4 on their shims, with the build's own EGL
//! and OpenGL ES libraries first on the library path), and the shader-db lines these
//! compilers send as KHR_debug messages ("MESA_SHADER_FRAGMENT shader: 59 inst, 2 threads,
//! ..., 0:0 spills:fills").
use super::Setup;

/// The command that sets these routes up.
pub const SETUP_COMMAND: &str = "make compilers";

/// The set-up of `compilers.env` with every key of `keys` present.
pub fn setup(keys: &[&str]) -> Result<Setup, String> {
    let setup = super::read_env("compilers")?;
    for k in keys {
        setup.get(k)?;
    }
    Ok(setup)
}

/// A Vulkan child's environment: the ICD of `icd_key` alone, the shim of `shim_key`
/// preloaded, the chip variable, no shader cache.
pub fn vulkan_env(
    setup: &Setup,
    icd_key: &str,
    shim_key: &str,
    chip_vars: &[(&str, String)],
) -> Result<Vec<(String, String)>, String> {
    let icd = setup.get(icd_key)?;
    let mut env = vec![
        ("LD_PRELOAD".to_string(), setup.get(shim_key)?.to_string()),
        ("VK_DRIVER_FILES".into(), icd.into()),
        ("VK_ICD_FILENAMES".into(), icd.into()),
        ("NODEVICE_SELECT".into(), "1".into()),
        ("MESA_SHADER_CACHE_DISABLE".into(), "true".into()),
    ];
    env.extend(chip_vars.iter().map(|(k, v)| (k.to_string(), v.clone())));
    Ok(env)
}

/// An OpenGL ES child's environment: the build's EGL and OpenGL ES libraries (`GLES_LIB`)
/// first on the library path, the shim of `shim_key` preloaded, Mesa's `driver` forced on the
/// surfaceless platform, the driver's own variables (chip, shader-db switch), no shader cache
/// (a cached shader reports no statistics).
pub fn gles_env(
    setup: &Setup,
    shim_key: &str,
    driver: &str,
    vars: &[(&str, String)],
) -> Result<Vec<(String, String)>, String> {
    let mut env = vec![
        ("LD_PRELOAD".to_string(), setup.get(shim_key)?.to_string()),
        ("LD_LIBRARY_PATH".into(), setup.get("GLES_LIB")?.into()),
        ("MESA_LOADER_DRIVER_OVERRIDE".into(), driver.into()),
        ("EGL_PLATFORM".into(), "surfaceless".into()),
        ("MESA_SHADER_CACHE_DISABLE".into(), "true".into()),
        ("MESA_GLSL_CACHE_DISABLE".into(), "true".into()),
    ];
    env.extend(vars.iter().map(|(k, v)| (k.to_string(), v.clone())));
    Ok(env)
}

/// The stage and statistics of a shader-db line "<STAGE> shader: <n> <name>, ...,
/// <spills>:<fills> spills:fills" (names as snake_case keys; "max-temps" is `max_temps`), or
/// `None` for another message. Stages: MESA_SHADER_FRAGMENT `fragment`, _VERTEX `vertex`,
/// _COMPUTE `compute`; Valhall's IDVS position shader (MESA_SHADER_POSITION) is the vertex
/// stage's; the others (blend, Valhall's varying shader, VC4's coordinate shader) `None`.
pub fn parse_shader_db(message: &str) -> Option<(String, Vec<(String, f64)>)> {
    let (stage, rest) = message.trim().split_once(" shader: ")?;
    let stage = match stage.trim() {
        "MESA_SHADER_FRAGMENT" => "fragment",
        "MESA_SHADER_VERTEX" | "MESA_SHADER_POSITION" => "vertex",
        "MESA_SHADER_COMPUTE" => "compute",
        _ => return None,
    };
    let mut stats = Vec::new();
    for part in rest.split(',') {
        let (value, name) = part.trim().split_once(' ')?;
        if let (Some((a, b)), Some((na, nb))) = (value.split_once(':'), name.split_once(':')) {
            stats.push((crate::isa::table::key(na), a.parse().ok()?));
            stats.push((crate::isa::table::key(nb), b.parse().ok()?));
        } else {
            stats.push((crate::isa::table::key(name), value.parse().ok()?));
        }
    }
    (!stats.is_empty()).then(|| (stage.to_string(), stats))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shader_db_lines_parse() {
        let (stage, stats) = parse_shader_db(
            "MESA_SHADER_FRAGMENT shader: 68 inst, 7.000000 cycles, 1.062500 fma, 0.25 cvt, \
             0.5 sfu, 0.375 v, 0.000000 t, 7.000000 ls, 9 quadwords, 2 threads, 0 loops, \
             0:0 spills:fills",
        )
        .unwrap();
        assert_eq!(stage, "fragment");
        let get = |k: &str| stats.iter().find(|(n, _)| n == k).map(|(_, v)| *v);
        assert_eq!(get("inst"), Some(68.0));
        assert_eq!(get("ls"), Some(7.0));
        assert_eq!(get("spills"), Some(0.0));
        assert_eq!(get("fills"), Some(0.0));
        let (_, stats) = parse_shader_db(
            "MESA_SHADER_VERTEX shader: 20 inst, 2 threads, 0 loops, 12 uniforms, 9 max-temps, \
             0:0 spills:fills, 1 sfu-stalls, 21 inst-and-stalls, 4 nops",
        )
        .unwrap();
        assert!(stats.contains(&("max_temps".into(), 9.0)));
        assert!(stats.contains(&("inst_and_stalls".into(), 21.0)));
        // Teeth: other messages, other stages and malformed figures give nothing.
        assert!(parse_shader_db("GLSL IR for shader 3").is_none());
        assert!(parse_shader_db("MESA_SHADER_BLEND shader: 5 inst").is_none());
        assert!(parse_shader_db("MESA_SHADER_COORD shader: 5 inst").is_none());
        assert!(parse_shader_db("MESA_SHADER_FRAGMENT shader: many inst").is_none());
    }
}
