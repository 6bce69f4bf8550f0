//! Our SPIR-V as GLSL 4.30 for OpenGL drivers, by the `spirv-cross` program (Debian package
//! spirv-cross): the specialization constants get the draw's values through the
//! `SPIRV_CROSS_CONSTANT_ID_<n>` macros spirv-cross leaves for them (it uses the SPIR-V's
//! defaults otherwise).
use std::io::Write;
use std::process::{Command, Stdio};

use crate::error::{Error, Result};

/// GLSL 4.30 (core) of `spirv`, with each `(constant_id, value)` of `spec` the program has
/// set, and the ids it set; `label` names the program in errors.
pub fn from_spirv(label: &str, spirv: &[u8], spec: &[(u32, u32)]) -> Result<(String, Vec<u32>)> {
    let mut child = Command::new("spirv-cross")
        .args(["--version", "430", "--no-es", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            Error::Shader(format!(
                "{label}: cannot run spirv-cross ({e}): install the Debian package spirv-cross \
                 (scripts/setup-vendors.sh gl)"
            ))
        })?;
    if let Some(mut stdin) = child.stdin.take() {
        stdin
            .write_all(spirv)
            .map_err(|e| Error::Shader(format!("{label}: writing to spirv-cross: {e}")))?;
    }
    let out = child
        .wait_with_output()
        .map_err(|e| Error::Shader(format!("{label}: spirv-cross: {e}")))?;
    if !out.status.success() {
        return Err(Error::Shader(format!(
            "{label}: spirv-cross failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let text = String::from_utf8(out.stdout)
        .map_err(|e| Error::Shader(format!("{label}: spirv-cross wrote non-UTF-8: {e}")))?;
    Ok(specialize(&text, spec))
}

/// An error unless every constant of `spec` is among `set` (the ids the stages of one program
/// set): a constant no stage has would silently keep nothing of the draw's value.
pub fn check_all_set(label: &str, spec: &[(u32, u32)], set: &[u32]) -> Result<()> {
    match spec.iter().find(|(id, _)| !set.contains(id)) {
        Some((id, _)) => Err(Error::Shader(format!(
            "{label}: no specialization constant {id} in the program"
        ))),
        None => Ok(()),
    }
}

/// Replaces the default of each `#define SPIRV_CROSS_CONSTANT_ID_<n> <default>` by the value
/// of `spec`, in the default's type (`true`/`false`, `5u`, `5`); with the ids replaced.
pub fn specialize(glsl: &str, spec: &[(u32, u32)]) -> (String, Vec<u32>) {
    let mut out = String::with_capacity(glsl.len());
    let mut set = Vec::new();
    for line in glsl.lines() {
        let mut replaced = None;
        if let Some(rest) = line.strip_prefix("#define SPIRV_CROSS_CONSTANT_ID_") {
            let (id, default) = rest.split_once(' ').unwrap_or((rest, ""));
            if let Some(i) = spec.iter().position(|(k, _)| id == k.to_string()) {
                set.push(spec[i].0);
                let v = spec[i].1;
                let value = match default.trim() {
                    "true" | "false" => (if v != 0 { "true" } else { "false" }).to_string(),
                    d if d.ends_with('u') => format!("{v}u"),
                    _ => v.to_string(),
                };
                replaced = Some(format!("#define SPIRV_CROSS_CONSTANT_ID_{id} {value}"));
            }
        }
        out += replaced.as_deref().unwrap_or(line);
        out.push('\n');
    }
    (out, set)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLSL: &str = "#version 430\n#ifndef SPIRV_CROSS_CONSTANT_ID_0\n\
        #define SPIRV_CROSS_CONSTANT_ID_0 1\n#endif\nconst int _48 = SPIRV_CROSS_CONSTANT_ID_0;\n\
        #ifndef SPIRV_CROSS_CONSTANT_ID_2\n#define SPIRV_CROSS_CONSTANT_ID_2 true\n#endif\n";

    #[test]
    fn constants_take_the_draws_values_in_their_type() {
        let (s, set) = specialize(GLSL, &[(0, 3), (2, 0)]);
        assert!(s.contains("#define SPIRV_CROSS_CONSTANT_ID_0 3\n"), "{s}");
        assert!(
            s.contains("#define SPIRV_CROSS_CONSTANT_ID_2 false\n"),
            "{s}"
        );
        assert_eq!(set, [0, 2]);
        assert!(check_all_set("t", &[(0, 3), (2, 0)], &set).is_ok());
        // Teeth: a constant the program lacks is an error, not silently the default.
        let (_, set) = specialize(GLSL, &[(1, 3)]);
        assert!(check_all_set("t", &[(1, 3)], &set).is_err());
    }
}
