//! Our SPIR-V as GLSL 4.30 for OpenGL drivers, or as GLSL ES for OpenGL ES drivers, by the
//! `spirv-cross` program (Debian package spirv-cross): the specialization constants get the
//! draw's values through the `SPIRV_CROSS_CONSTANT_ID_<n>` macros spirv-cross leaves for them
//! (it uses the SPIR-V's defaults otherwise).
//!
//! GLSL ES has no float16 type that Mesa's OpenGL ES drivers accept: float16 is spelt
//! `mediump` there, and drivers with float16 arithmetic (panfrost, freedreno) compile mediump
//! arithmetic in 16 bits (Mesa's lower_precision). [`es_precision`] makes float32 programs
//! `highp` throughout and turns a float16 program's `float16_t`/`f16vec*`/`f16mat*` into
//! `mediump` declarations and conversions, so that the same operations are 16-bit.
use std::io::Write;
use std::process::{Command, Stdio};

use crate::error::{Error, Result};

/// GLSL 4.30 (core) of `spirv`, with each `(constant_id, value)` of `spec` the program has
/// set, and the ids it set; `label` names the program in errors.
pub fn from_spirv(label: &str, spirv: &[u8], spec: &[(u32, u32)]) -> Result<(String, Vec<u32>)> {
    let text = cross(label, spirv, &["--version", "430", "--no-es"])?;
    Ok(specialize(&text, spec))
}

/// GLSL ES `version` (100, 300, 310, 320) of `spirv`, specialized as [`from_spirv`], with
/// float32 `highp` throughout, and a float16 program's 16-bit types as `mediump`
/// ([`es_precision`]).
pub fn from_spirv_es(
    label: &str,
    spirv: &[u8],
    spec: &[(u32, u32)],
    version: u32,
) -> Result<(String, Vec<u32>)> {
    if version == 100 {
        return Ok(specialize(&essl100(label, spirv)?, spec));
    }
    let v = version.to_string();
    let text = es_precision(&cross(label, spirv, &["--es", "--version", &v])?);
    Ok(specialize(&text, spec))
}

/// ESSL 1.00 (OpenGL ES 2.0), which links varyings by name, not location, and has no flat
/// interpolation nor a second colour output: the interface variables named after their
/// location (`v_<n>` for varyings, `a_<n>` for vertex attributes, from the ESSL 3.10
/// translation's `layout(location = n)`), `flat` varyings smooth, the colour output alone.
fn essl100(label: &str, spirv: &[u8]) -> Result<String> {
    let es310 = cross(label, spirv, &["--es", "--version", "310"])?;
    let vertex = es310.contains("gl_Position");
    let mut args: Vec<String> = ["--es", "--version", "100"].map(String::from).to_vec();
    for line in es310.lines() {
        let Some(rest) = line.trim().strip_prefix("layout(location = ") else {
            continue;
        };
        let Some((loc, decl)) = rest.split_once(')') else {
            continue;
        };
        let dir = if decl.contains(" in ") {
            "in"
        } else if decl.contains(" out ") {
            "out"
        } else {
            continue;
        };
        let name = match (vertex, dir) {
            (true, "in") => format!("a_{loc}"),
            (false, "out") => continue,
            _ => format!("v_{loc}"),
        };
        args.extend([
            "--rename-interface-variable".into(),
            dir.into(),
            loc.into(),
            name,
        ]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let text = es_precision(&cross(label, spirv, &args)?);
    let text = text
        .lines()
        .map(|l| match l.strip_prefix("flat varying ") {
            Some(rest) => format!("varying {rest}\n"),
            None => format!("{l}\n"),
        })
        .collect::<String>();
    Ok(colour_output_alone(&text))
}

/// ESSL 1.00 without EXT_draw_buffers (VC4, Mali-450): the writes to outputs other than
/// `gl_FragData[0]`, and the extension spirv-cross asks for them, dropped.
pub fn colour_output_alone(glsl: &str) -> String {
    glsl.lines()
        .filter(|l| {
            let t = l.trim();
            let other_output = t.starts_with("gl_FragData[") && !t.starts_with("gl_FragData[0]");
            t != "#extension GL_EXT_draw_buffers : require" && !other_output
        })
        .map(|l| format!("{l}\n"))
        .collect()
}

/// The GLSL ES version of an OpenGL ES context's version (3.2: 320, 3.1: 310, 3.0: 300, 2.0:
/// 100).
pub fn es_version(es: (u32, u32)) -> u32 {
    match es {
        (2, _) => 100,
        (major, minor) => major * 100 + minor * 10,
    }
}

/// spirv-cross on `spirv` with `args`, its output.
fn cross(label: &str, spirv: &[u8], args: &[&str]) -> Result<String> {
    let mut cmd = Command::new("spirv-cross");
    crate::cleanup::die_with_parent(&mut cmd);
    let mut child = cmd
        .args(args)
        .arg("-")
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
    String::from_utf8(out.stdout)
        .map_err(|e| Error::Shader(format!("{label}: spirv-cross wrote non-UTF-8: {e}")))
}

/// The 16-bit float types of GLSL and their 32-bit spelling.
const F16_TYPES: [(&str, &str); 7] = [
    ("float16_t", "float"),
    ("f16vec2", "vec2"),
    ("f16vec3", "vec3"),
    ("f16vec4", "vec4"),
    ("f16mat2", "mat2"),
    ("f16mat3", "mat3"),
    ("f16mat4", "mat4"),
];

/// GLSL ES from spirv-cross with float32 `highp` by default (spirv-cross declares
/// `precision mediump float`, which drivers with float16 would compile in 16 bits) and the
/// float16 types as `mediump`: a declaration `f16vec3 x` becomes `mediump vec3 x`, a
/// conversion `f16vec3(e)` becomes `_mp_vec3(vec3(e))` (a function returning mediump, so the
/// value is rounded to mediump where the float16 program converts), a literal `1.5hf` becomes
/// `1.5`; the extension block spirv-cross guards float16 with is dropped.
pub fn es_precision(glsl: &str) -> String {
    let mut lines: Vec<&str> = Vec::new();
    let mut skipping = false;
    for line in glsl.lines() {
        let t = line.trim();
        if t.starts_with("#if defined(GL_AMD_gpu_shader_half_float)") {
            skipping = true;
            continue;
        }
        if skipping {
            skipping = t != "#endif";
            continue;
        }
        lines.push(line);
    }
    let f16 = glsl.contains("f16") || glsl.contains("float16_t");
    // The helpers go after the directives that must come first (#version, #extension).
    let head = lines
        .iter()
        .rposition(|l| l.starts_with("#version") || l.starts_with("#extension"))
        .map_or(0, |i| i + 1);
    let mut body = String::new();
    for (i, line) in lines.iter().enumerate() {
        if i == head && f16 {
            for (_, t) in &F16_TYPES[..] {
                body += &format!("mediump {t} _mp_{t}(mediump {t} x) {{ return x; }}\n");
            }
        }
        if line.trim() == "precision mediump float;" {
            body += "precision highp float;\n";
            continue;
        }
        body += &mediump_types(line);
        body.push('\n');
    }
    body
}

/// One line of [`es_precision`] with the float16 types and literals rewritten.
fn mediump_types(line: &str) -> String {
    let chars: Vec<char> = line.chars().collect();
    let mut out = String::with_capacity(line.len() + 16);
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if !(c.is_ascii_alphanumeric() || c == '_' || c == '.') {
            out.push(c);
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len()
            && (chars[i].is_ascii_alphanumeric() || chars[i] == '_' || chars[i] == '.')
        {
            i += 1;
        }
        let word: String = chars[start..i].iter().collect();
        if word.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
            if let Some(n) = word.strip_suffix("hf") {
                out += n;
            } else {
                out += &word;
            }
            continue;
        }
        let Some(&(_, t)) = F16_TYPES.iter().find(|(f, _)| *f == word) else {
            out += &word;
            continue;
        };
        let mut j = i;
        while j < chars.len() && chars[j] == ' ' {
            j += 1;
        }
        if j < chars.len() && chars[j] == '[' {
            // An array constructor `float16_t[4](...)`: its elements carry their precision.
            out += t;
        } else if j < chars.len() && chars[j] == '(' {
            // A conversion: wrap the constructor and its arguments.
            let mut depth = 0;
            let mut k = j;
            while k < chars.len() {
                match chars[k] {
                    '(' => depth += 1,
                    ')' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    _ => {}
                }
                k += 1;
            }
            let inner: String = chars[j + 1..k.min(chars.len())].iter().collect();
            let inner = mediump_types(&inner);
            out += &format!("_mp_{t}({t}({inner}))");
            i = (k + 1).min(chars.len());
        } else {
            out += &format!("mediump {t}");
        }
    }
    out
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

/// Whether spirv-cross's `glsl` has any specialization constant (a program that has none, a
/// kernel that reads no light or material as `isa --calibrate`'s, depends on none of the
/// draw's values: [`check_all_set`] does not apply).
pub fn has_constants(glsl: &str) -> bool {
    glsl.contains("#define SPIRV_CROSS_CONSTANT_ID_")
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

    #[test]
    fn essl100_keeps_the_colour_output_alone() {
        let src = "#version 100\n#extension GL_EXT_draw_buffers : require\nvoid main()\n{\n    \
            gl_FragData[1] = vec4(n, 1.0);\n    gl_FragData[0] = vec4(c, 1.0);\n}\n";
        let out = colour_output_alone(src);
        assert!(
            !out.contains("draw_buffers") && !out.contains("gl_FragData[1]"),
            "{out}"
        );
        assert!(
            out.contains("    gl_FragData[0] = vec4(c, 1.0);\n"),
            "{out}"
        );
    }

    #[test]
    fn float16_becomes_mediump_and_float32_highp() {
        let src = "#version 310 es\n#if defined(GL_AMD_gpu_shader_half_float)\n\
            #extension GL_AMD_gpu_shader_half_float : require\n#else\n#error No FP16.\n#endif\n\
            precision mediump float;\nprecision highp int;\n\
            void main()\n{\n    f16vec3 _174 = normalize(f16vec3(_124));\n\
            float16_t _207 = max(dot(_174, f16vec3(a.xyz, float16_t(b))), 0.5hf);\n}\n";
        let out = es_precision(src);
        assert!(!out.contains("GL_AMD") && !out.contains("#error"), "{out}");
        assert!(out.contains("precision highp float;"), "{out}");
        assert!(
            out.contains("mediump vec3 _174 = normalize(_mp_vec3(vec3(_124)));"),
            "{out}"
        );
        assert!(
            out.contains(
                "mediump float _207 = max(dot(_174, _mp_vec3(vec3(a.xyz, _mp_float(float(b))))), 0.5);"
            ),
            "{out}"
        );
        assert!(out.contains("mediump vec3 _mp_vec3(mediump vec3 x) { return x; }"));
        // A float32 program: highp by default, nothing else changed, no helpers.
        let f32 = "#version 310 es\nprecision mediump float;\nvoid main()\n{\n    highp vec3 a = normalize(b);\n}\n";
        let out = es_precision(f32);
        assert!(
            out.contains("precision highp float;") && !out.contains("_mp_"),
            "{out}"
        );
        assert!(out.contains("highp vec3 a = normalize(b);"));
        assert_eq!(
            mediump_types("x = float16_t[2](float16_t(0.5), a);"),
            "x = float[2](_mp_float(float(0.5)), a);"
        );
        // Teeth: `f16vec3x` is another identifier, not the type.
        assert_eq!(mediump_types("f16vec3x = y;"), "f16vec3x = y;");
    }

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
        // A program without any constant has none to set.
        assert!(!has_constants("#version 430\nvoid main() {}\n"));
        assert!(has_constants(GLSL));
    }
}
