//! The architecture of src/lib.rs, checked on the source tree: layers point one way, `ash` lives
//! only in src/gpu/vk, clap only in src/cli, no production file and no production function is
//! too long (comments, strings and `#[cfg(test)]` items told apart by a small lexer, not by the
//! first `#[cfg(test)]` line). Each check is a function over (path, text) pairs, so the teeth
//! tests below can feed it a tree that breaks it.
use std::path::{Path, PathBuf};

/// No ring between the files of one module, with its teeth.
mod rings;

/// The layers of src/lib.rs, top first. A module may use modules of its own or a lower layer;
/// within a layer, dependencies must not form a cycle.
const LAYERS: &[&[&str]] = &[
    &["main", "cli"],
    &["report", "corpus", "explore"],
    &[
        "compare", "bench", "verify", "stress", "plan", "isa", "prove", "costs", "tune",
    ],
    &["analysis", "truth", "cases", "cost", "auto", "workers"],
    &["gpu", "software", "engine"],
    &["scene", "frame"],
    &["method", "geometry"],
    &[
        "output", "error", "child", "cleanup", "memory", "parallel", "testutil", "lib",
    ],
];

/// A production file longer than this (its `#[cfg(test)]` items left out) is a file to split.
const MAX_PRODUCTION_LINES: usize = 800;

/// A production function longer than this, from its `fn` line to its closing brace, is a
/// function to split.
const MAX_FUNCTION_LINES: usize = 120;

/// Functions over [`MAX_FUNCTION_LINES`] still waiting for their split, as (path under src/,
/// fn name). Each must still be over the limit: once its split is merged,
/// `no_production_function_is_too_long` fails until its entry is removed, so the list can only
/// shrink, and must end empty.
const PENDING_SPLIT: &[(&str, &str)] = &[];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The top-level module a file under src/ belongs to: `src/gpu/vk/mod.rs` -> `gpu`.
fn module_of(path: &Path) -> String {
    let first = path
        .components()
        .next()
        .unwrap()
        .as_os_str()
        .to_string_lossy();
    first.trim_end_matches(".rs").to_string()
}

/// Every `crate::NAME` a text mentions, outside comments.
fn uses(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            let name: String = rest[i + 7..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push(name);
            }
            rest = &rest[i + 7..];
        }
        // `use crate::{a, b::c}` names several modules at once.
        if let Some(i) = code.find("crate::{") {
            let inner = &code[i + 8..];
            for part in inner.split([',', '}']) {
                let name: String = part
                    .trim()
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    out.push(name);
                }
            }
        }
    }
    out
}

/// Layer violations and dependency cycles among top-level modules.
fn layer_violations(files: &[(PathBuf, String)]) -> Vec<String> {
    let mut bad = Vec::new();
    let mut edges = std::collections::BTreeSet::new();
    for (path, text) in files {
        let from = module_of(path);
        let Some(lf) = layer_of(&from) else {
            bad.push(format!(
                "{}: module `{from}` is in no layer of LAYERS",
                path.display()
            ));
            continue;
        };
        for to in uses(text) {
            if to == from || to == "self" || to == "super" {
                continue;
            }
            match layer_of(&to) {
                None => bad.push(format!(
                    "{}: uses `crate::{to}`, in no layer",
                    path.display()
                )),
                Some(lt) if lt < lf => bad.push(format!(
                    "{}: `{from}` (layer {lf}) uses `{to}` (layer {lt}, above it)",
                    path.display()
                )),
                Some(_) => {
                    edges.insert((from.clone(), to));
                }
            }
        }
    }
    for (a, b) in &edges {
        if edges.contains(&(b.clone(), a.clone())) && a < b {
            bad.push(format!("cycle: `{a}` and `{b}` use each other"));
        }
    }
    bad
}

/// Files outside `allowed` (a path prefix) that name `needle` in code.
fn named_outside(files: &[(PathBuf, String)], needle: &str, allowed: &str) -> Vec<String> {
    files
        .iter()
        .filter(|(p, _)| !p.starts_with(allowed))
        .flat_map(|(p, text)| {
            text.lines().enumerate().filter_map(move |(i, l)| {
                let code = l.split("//").next().unwrap_or("");
                code.contains(needle)
                    .then(|| format!("{}:{}: {}", p.display(), i + 1, l.trim()))
            })
        })
        .collect()
}

/// `text` with the contents of comments, strings and character literals blanked to spaces
/// (newlines kept), so that braces, `fn` and `#[cfg(test)]` are seen only in code.
fn code_only(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let blank = |out: &mut String, ch: char| out.push(if ch == '\n' { '\n' } else { ' ' });
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    // The hashes of a raw string opening at `i` (r"..", r#".."#, br".."), if one does.
    let raw = |i: usize| {
        let j = i + if c[i] == 'b' { 2 } else { 1 };
        let opens = c[i] == 'r' || (c[i] == 'b' && c.get(i + 1) == Some(&'r'));
        let hashes = c.iter().skip(j).take_while(|&&h| h == '#').count();
        (opens && c.get(j + hashes) == Some(&'"')).then_some((j + hashes + 1, hashes))
    };
    // b'x': a byte literal, whose quote follows an identifier's letter.
    let byte_prefix = |i: usize| c[i - 1] == 'b' && (i < 2 || !ident(c[i - 2]));
    let mut i = 0;
    while i < c.len() {
        let after_ident = i > 0 && ident(c[i - 1]);
        if c[i] == '/' && c.get(i + 1) == Some(&'/') {
            while i < c.len() && c[i] != '\n' {
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if c[i] == '/' && c.get(i + 1) == Some(&'*') {
            // Block comments nest.
            let mut depth = 0;
            while i < c.len() {
                let two = (c[i], c.get(i + 1).copied().unwrap_or(' '));
                if two == ('/', '*') || two == ('*', '/') {
                    depth += if two.0 == '/' { 1 } else { -1 };
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
        } else if let Some((body, hashes)) = (!after_ident).then(|| raw(i)).flatten() {
            (i..body).for_each(|k| out.push(c[k]));
            i = body;
            let closes = |k: usize| c[k] == '"' && (1..=hashes).all(|h| c.get(k + h) == Some(&'#'));
            while i < c.len() && !closes(i) {
                blank(&mut out, c[i]);
                i += 1;
            }
            (i..(i + 1 + hashes).min(c.len())).for_each(|k| out.push(c[k]));
            i += 1 + hashes;
        } else if c[i] == '"' {
            out.push('"');
            i += 1;
            while i < c.len() && c[i] != '"' {
                let n = if c[i] == '\\' { 2 } else { 1 };
                (i..(i + n).min(c.len())).for_each(|k| blank(&mut out, c[k]));
                i += n;
            }
            if i < c.len() {
                out.push('"');
            }
            i += 1;
        } else if c[i] == '\'' && (!after_ident || byte_prefix(i)) {
            // A character literal ('{', '\n', '\u{7d}') is blanked; a lifetime ('a) is kept.
            let end = if c.get(i + 1) == Some(&'\\') {
                c.iter()
                    .skip(i + 2)
                    .position(|&x| x == '\'')
                    .map(|p| i + 2 + p)
            } else {
                (c.get(i + 2) == Some(&'\'')).then_some(i + 2)
            };
            out.push('\'');
            if let Some(end) = end {
                (i + 1..end).for_each(|k| blank(&mut out, c[k]));
                out.push('\'');
                i = end;
            }
            i += 1;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// Where the item starting at `from` of `code` (from [`code_only`]) ends: its `;` outside
/// brackets, or the `}` matching its first `{` outside brackets. The bool says it had a body.
fn item_end(code: &[char], from: usize) -> Option<(usize, bool)> {
    let mut brackets = 0i32;
    let mut i = from;
    while i < code.len() {
        match code[i] {
            '(' | '[' => brackets += 1,
            ')' | ']' => brackets -= 1,
            ';' if brackets == 0 => return Some((i, false)),
            '{' if brackets == 0 => {
                let mut depth = 0i32;
                for (k, &ch) in code.iter().enumerate().skip(i) {
                    depth += i32::from(ch == '{') - i32::from(ch == '}');
                    if depth == 0 {
                        return Some((k, true));
                    }
                }
                return None;
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// The line (0-based) of each char of `code`.
fn line_of(code: &[char]) -> Vec<usize> {
    let mut line = 0;
    code.iter()
        .map(|&ch| {
            let l = line;
            line += usize::from(ch == '\n');
            l
        })
        .collect()
}

/// Per line of a file: whether it belongs to an item under `#[cfg(test)]` (a `mod tests { .. }`,
/// a test helper, or the line `mod tests;` itself, whose file is judged on its own).
fn test_lines(text: &str) -> Vec<bool> {
    let code: Vec<char> = code_only(text).chars().collect();
    let lines = line_of(&code);
    let mut mask = vec![false; text.lines().count()];
    let s: String = code.iter().collect();
    for (at, _) in s.match_indices("#[cfg(test)]") {
        let from = s[..at].chars().count();
        let Some((end, _)) = item_end(&code, from + "#[cfg(test)]".len()) else {
            continue;
        };
        for m in mask.iter_mut().take(lines[end] + 1).skip(lines[from]) {
            *m = true;
        }
    }
    mask
}

/// Files of tests, not production: every tests.rs, every file under `#![cfg(test)]`, and every
/// module its parent declares under `#[cfg(test)]` (src/testutil.rs), with the folder of such a
/// module (src/geometry/tests/). A file is a test file when it is one or lies in one.
fn test_files(files: &[(PathBuf, String)]) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = files
        .iter()
        .filter(|(p, _)| p.file_name().is_some_and(|f| f == "tests.rs"))
        .map(|(p, _)| p.clone())
        .collect();
    for (p, text) in files {
        let dir = match p.file_name().and_then(|f| f.to_str()) {
            Some("lib.rs" | "main.rs" | "mod.rs") => p.parent().unwrap().to_path_buf(),
            _ => p.with_extension(""),
        };
        let code = code_only(text);
        if code.contains("#![cfg(test)]") {
            out.push(p.clone());
        }
        let lines: Vec<&str> = code.lines().collect();
        for (i, l) in lines.iter().enumerate() {
            if l.trim() != "#[cfg(test)]" {
                continue;
            }
            let Some(next) = lines.get(i + 1) else {
                continue;
            };
            let decl = next
                .trim()
                .trim_start_matches("pub ")
                .trim_start_matches("pub(crate) ");
            if let Some(name) = decl.strip_prefix("mod ").and_then(|d| d.strip_suffix(';')) {
                // NAME.rs, or the folder NAME/ (its mod.rs and the modules it declares).
                out.push(dir.join(format!("{name}.rs")));
                out.push(dir.join(name));
            }
        }
    }
    out
}

/// Whether `p` is, or lies in a folder of, [`test_files`].
fn is_test_file(tests: &[PathBuf], p: &Path) -> bool {
    tests.iter().any(|t| p.starts_with(t))
}

/// Production files (tests' files and test items left out) that spell `needle` in their code.
fn production_files_naming(files: &[(PathBuf, String)], needle: &str) -> Vec<String> {
    let tests = test_files(files);
    files
        .iter()
        .filter(|(p, _)| !is_test_file(&tests, p))
        .filter(|(_, text)| {
            let mask = test_lines(text);
            text.lines()
                .zip(mask)
                .any(|(l, test)| !test && l.split("//").next().unwrap_or("").contains(needle))
        })
        .map(|(p, _)| p.display().to_string())
        .collect()
}

/// Production files (tests' files left out) longer than [`MAX_PRODUCTION_LINES`], counting every
/// line but those of items under `#[cfg(test)]`: a `mod tests;` at the top hides nothing.
fn long_files(files: &[(PathBuf, String)]) -> Vec<String> {
    let tests = test_files(files);
    files
        .iter()
        .filter(|(p, _)| !is_test_file(&tests, p))
        .filter_map(|(p, text)| {
            let n = test_lines(text).iter().filter(|&&t| !t).count();
            (n > MAX_PRODUCTION_LINES).then(|| format!("{}: {n} lines", p.display()))
        })
        .collect()
}

/// Every production function longer than [`MAX_FUNCTION_LINES`] (from the `fn` line to its
/// closing brace), as (path, name, lines); functions under `#[cfg(test)]` and in tests' files
/// are left out.
fn long_functions(files: &[(PathBuf, String)]) -> Vec<(String, String, usize)> {
    let tests = test_files(files);
    let mut out = Vec::new();
    for (p, text) in files.iter().filter(|(p, _)| !is_test_file(&tests, p)) {
        let mask = test_lines(text);
        let code: Vec<char> = code_only(text).chars().collect();
        let lines = line_of(&code);
        let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
        for i in 0..code.len().saturating_sub(3) {
            let word = code[i] == 'f' && code[i + 1] == 'n' && code[i + 2].is_whitespace();
            if !word || (i > 0 && ident(code[i - 1])) || mask[lines[i]] {
                continue;
            }
            let rest = code[i + 2..].iter().skip_while(|c| c.is_whitespace());
            let name: String = rest.take_while(|&&c| ident(c)).collect();
            if name.is_empty() {
                continue; // a `fn (..)` pointer type
            }
            if let Some((end, true)) = item_end(&code, i + 2) {
                let n = lines[end] - lines[i] + 1;
                if n > MAX_FUNCTION_LINES {
                    out.push((p.display().to_string(), name, n));
                }
            }
        }
    }
    out
}

/// What the function-length check reports: long functions not in `pending`, and entries of
/// `pending` that are no longer long (split: take them off the list).
fn function_verdicts(long: &[(String, String, usize)], pending: &[(&str, &str)]) -> Vec<String> {
    let mut bad: Vec<String> = long
        .iter()
        .filter(|(p, n, _)| !pending.contains(&(p.as_str(), n.as_str())))
        .map(|(p, n, l)| format!("{p}: fn {n} is {l} lines (over {MAX_FUNCTION_LINES})"))
        .collect();
    for &(p, n) in pending {
        if !long.iter().any(|(lp, ln, _)| lp == p && ln == n) {
            bad.push(format!(
                "{p}: fn {n} is in PENDING_SPLIT but no longer over {MAX_FUNCTION_LINES} lines: \
                 take it off the list"
            ));
        }
    }
    bad
}

/// Every .rs file under src/, as (path relative to src/, text).
fn source_tree() -> Vec<(PathBuf, String)> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<(PathBuf, String)>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                out.push((p.strip_prefix(root).unwrap().to_path_buf(), text));
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = Vec::new();
    walk(&root, &root, &mut out);
    assert!(out.len() > 20, "found only {} files under src/", out.len());
    out
}

fn tree(files: &[(&str, &str)]) -> Vec<(PathBuf, String)> {
    files
        .iter()
        .map(|(p, t)| (PathBuf::from(p), t.to_string()))
        .collect()
}

#[test]
fn layers_point_one_way() {
    let bad = layer_violations(&source_tree());
    assert!(bad.is_empty(), "layer violations:\n{}", bad.join("\n"));
}

#[test]
fn ash_only_in_gpu_vk_and_clap_only_in_cli() {
    let files = source_tree();
    let mut bad = named_outside(&files, "ash::", "gpu/vk");
    bad.extend(named_outside(&files, "use ash", "gpu/vk"));
    bad.extend(named_outside(&files, "clap::", "cli"));
    bad.extend(named_outside(&files, "use clap", "cli"));
    assert!(bad.is_empty(), "outside their folder:\n{}", bad.join("\n"));
}

/// The reference's identity lives in the method table: its name is spelled as a string only
/// there (the constant every other file uses, `method::PHONG_EXACT`, which names its row); the
/// other references' (unnormalised, slerp, vertex-lit) only in their rows
/// (`method::phong_unnormalized()` and the like find them by their properties), and so are the
/// names of the rows production code once picked by name (newton_raphson, flat).
#[test]
fn the_reference_is_named_in_the_method_table_alone() {
    let mut named = production_files_naming(&source_tree(), "\"phong_exact\"");
    named.sort();
    assert_eq!(named, ["method/table.rs"]);
    // the other references, found by their properties, are spelled in their rows alone
    for name in [
        "phong_unnormalized",
        "slerp",
        "gouraud",
        "newton_raphson",
        "flat",
    ] {
        let named = production_files_naming(&source_tree(), &format!("\"{name}\""));
        assert_eq!(named, ["method/table.rs"], "{name}");
    }
    // Teeth: a second file spelling it is found; a test item spelling it is not.
    let t = tree(&[
        ("bench/x.rs", "let r = \"phong_exact\";\n"),
        (
            "bench/y.rs",
            "#[cfg(test)]\nmod tests {\n    const R: &str = \"phong_exact\";\n}\n",
        ),
    ]);
    assert_eq!(
        production_files_naming(&t, "\"phong_exact\""),
        ["bench/x.rs"]
    );
}

#[test]
fn no_production_file_is_too_long() {
    let bad = long_files(&source_tree());
    assert!(bad.is_empty(), "split these files:\n{}", bad.join("\n"));
}

#[test]
fn no_production_function_is_too_long() {
    let bad = function_verdicts(&long_functions(&source_tree()), PENDING_SPLIT);
    assert!(bad.is_empty(), "split these functions:\n{}", bad.join("\n"));
}

/// Teeth: each check flags a tree that breaks it, and passes the same tree mended.
#[test]
fn the_layout_checks_fail_on_a_broken_tree() {
    let upward = tree(&[("gpu/renderer.rs", "use crate::compare::Summary;\n")]);
    assert_eq!(
        layer_violations(&upward).len(),
        1,
        "{:?}",
        layer_violations(&upward)
    );
    let grouped = tree(&[("scene/mod.rs", "use crate::{geometry, truth::Truth};\n")]);
    let v = layer_violations(&grouped);
    assert!(v.len() == 1 && v[0].contains("`truth`"), "{v:?}");
    let cycle = tree(&[
        ("compare/mod.rs", "use crate::bench::X;\n"),
        ("bench/mod.rs", "use crate::compare::Y;\n"),
    ]);
    assert!(layer_violations(&cycle)
        .iter()
        .any(|v| v.starts_with("cycle")));
    let unknown = tree(&[("render.rs", "fn f() {}\n")]);
    assert_eq!(layer_violations(&unknown).len(), 1);
    let fine = tree(&[
        (
            "cli/mod.rs",
            "use crate::compare::X; // crate::nothing in a comment\n",
        ),
        (
            "compare/mod.rs",
            "use crate::gpu::{Renderer};\nuse crate::frame::Frame;\n",
        ),
    ]);
    assert_eq!(layer_violations(&fine), Vec::<String>::new());

    let ash = tree(&[("gpu/renderer.rs", "let f = ash::vk::Format::UNDEFINED;\n")]);
    assert_eq!(named_outside(&ash, "ash::", "gpu/vk").len(), 1);
    let ash_ok = tree(&[("gpu/vk/conv.rs", "let f = ash::vk::Format::UNDEFINED;\n")]);
    assert!(named_outside(&ash_ok, "ash::", "gpu/vk").is_empty());

    let long = "fn f() {}\n".repeat(MAX_PRODUCTION_LINES + 1);
    assert_eq!(long_files(&tree(&[("geometry/obj.rs", &long)])).len(), 1);
}

/// Teeth of the file-length check: a `mod tests;` at the top of a long file hides nothing (the
/// loophole that counted src/bench/mod.rs as 22 lines), while test code is not counted.
#[test]
fn the_file_length_check_counts_whole_production_files() {
    let body = "fn f() {}\n".repeat(900);
    let hidden = format!("//! A module.\n#[cfg(test)]\nmod tests;\n{body}");
    let v = long_files(&tree(&[("bench/mod.rs", &hidden)]));
    assert_eq!(v.len(), 1, "{v:?}");
    let n: usize = v[0]
        .split(": ")
        .nth(1)
        .and_then(|s| s.strip_suffix(" lines"))
        .unwrap()
        .parse()
        .unwrap();
    assert!(n >= 900, "counted {n}");
    // An inline test module, a tests.rs and a module declared under #[cfg(test)] are tests.
    let inline = format!("fn g() {{}}\n#[cfg(test)]\nmod tests {{\n{body}}}\n");
    let declared = "#[cfg(test)]\nmod testutil;\npub mod output;\n";
    let files = tree(&[
        ("bench/mod.rs", &inline),
        ("bench/tests.rs", &body),
        ("lib.rs", declared),
        ("testutil.rs", &body),
        ("output/mod.rs", "fn h() {}\n"),
    ]);
    assert_eq!(long_files(&files), Vec::<String>::new());
    let folder = tree(&[
        (
            "geometry/mod.rs",
            "#[cfg(test)]\nmod tests;\npub mod obj;\n",
        ),
        ("geometry/tests/mod.rs", "mod loading;\n"),
        ("geometry/tests/loading.rs", &body),
        ("geometry/obj.rs", "fn h() {}\n"),
    ]);
    assert_eq!(long_files(&folder), Vec::<String>::new());
    let v = long_files(&tree(&[
        (
            "geometry/mod.rs",
            "#[cfg(test)]\nmod tests;\npub mod obj;\n",
        ),
        ("geometry/obj.rs", &body),
    ]));
    assert_eq!(v.len(), 1, "{v:?}");
    // ... but the same text as a production module is counted.
    let v = long_files(&tree(&[("lib.rs", declared), ("output/mod.rs", &body)]));
    assert_eq!(v.len(), 1, "{v:?}");
    // A brace in a string, a char or a comment does not end the test module early.
    let tricky = format!(
        "#[cfg(test)]\nmod tests {{\n    const A: &str = \"}}\";\n    const B: char = '}}';\n    // }}\n    const C: &str = r#\"}}\"#;\n{body}}}\nfn after() {{}}\n"
    );
    assert_eq!(
        long_files(&tree(&[("a.rs", &tricky)])),
        Vec::<String>::new()
    );
}

/// A synthetic function of `n` lines from its `fn` line to its closing brace, with braces in a
/// string, a char, a raw string and a comment that must not end it early.
fn function_of(n: usize) -> String {
    assert!(n >= 6);
    let mut s = String::from("pub fn long(x: [u8; 4]) -> usize {\n");
    s += "    let s = \"}\"; let c = '}'; let r = r#\"}\"#; // }\n";
    s += "    let _ = (s, c, r, '\\'', b'}');\n";
    s += &"    let _ = x.len();\n".repeat(n - 5);
    s += "    0\n}\n";
    s
}

/// Teeth of the function-length check: a function of 121 lines fails, one of 120 passes, test
/// code and tests' files are left out, and PENDING_SPLIT fails once an entry is split.
#[test]
fn the_function_length_check_fails_on_a_long_function() {
    let at = |n: usize| format!("//! A file.\nuse std::fmt;\n\n/// Doc.\n{}", function_of(n));
    assert_eq!(at(121).lines().count(), 4 + 121);
    let long = long_functions(&tree(&[("geometry/obj.rs", &at(121))]));
    assert_eq!(
        long,
        vec![("geometry/obj.rs".to_string(), "long".to_string(), 121)]
    );
    assert!(long_functions(&tree(&[("geometry/obj.rs", &at(120))])).is_empty());
    // A trait's declaration without a body, a fn pointer type, and a short fn after it.
    let decl = format!(
        "trait T {{\n    fn short(&self);\n}}\ntype F = fn(u8) -> u8;\n{}",
        function_of(121)
    );
    assert_eq!(long_functions(&tree(&[("a.rs", &decl)]))[0].2, 121);
    // Under #[cfg(test)] or in a tests.rs it is test code.
    let in_tests = format!("#[cfg(test)]\nmod tests {{\n{}}}\n", function_of(200));
    let files = tree(&[("a.rs", &in_tests), ("b/tests.rs", &function_of(200))]);
    assert!(long_functions(&files).is_empty());

    let long = long_functions(&tree(&[("cli/mod.rs", &at(121).replace("long", "run"))]));
    assert!(function_verdicts(&long, &[]).len() == 1);
    assert!(function_verdicts(&long, &[("cli/mod.rs", "run")]).is_empty());
    // Split: the entry is stale and the check says so.
    let split = long_functions(&tree(&[("cli/mod.rs", &at(120).replace("long", "run"))]));
    let v = function_verdicts(&split, &[("cli/mod.rs", "run")]);
    assert!(v.len() == 1 && v[0].contains("take it off"), "{v:?}");
}

/// What names one distribution's or one architecture's files: a multiarch triplet folder, an
/// ICD manifest's architecture infix, a fixed library folder. Such names are found at run time
/// (the Vulkan loader's rules in src/gpu/icd.rs, the dynamic linker's cache) or at build time
/// (pkg-config and the C compiler's search folders in build.rs), never spelt.
const DISTRIBUTION_NAMES: &[&str] = &[
    "-linux-gnu",
    ".x86_64.json",
    ".i686.json",
    ".aarch64.json",
    "/usr/lib/x86_64",
    "/usr/lib/aarch64",
    "/usr/lib/i386",
    "/usr/lib64",
];

/// Production lines (test items and test files left out, comments cut) that spell one of
/// [`DISTRIBUTION_NAMES`], as `path:line: text`.
fn distribution_names(files: &[(PathBuf, String)]) -> Vec<String> {
    let tests = test_files(files);
    let mut out = Vec::new();
    for (p, text) in files.iter().filter(|(p, _)| !is_test_file(&tests, p)) {
        for (i, (l, test)) in text.lines().zip(test_lines(text)).enumerate() {
            let code = l.split("//").next().unwrap_or("");
            if !test && DISTRIBUTION_NAMES.iter().any(|n| code.contains(n)) {
                out.push(format!("{}:{}: {}", p.display(), i + 1, l.trim()));
            }
        }
    }
    out
}

/// build.rs and src/ hold no path or file name of one distribution or architecture (Debian's
/// `x86_64-linux-gnu`, Mesa 22.3's `radeon_icd.x86_64.json`): the same source builds and runs
/// on Debian 12 and 13 and would on arm64.
#[test]
fn no_distribution_or_architecture_is_spelt() {
    let mut files = source_tree();
    let build = Path::new(env!("CARGO_MANIFEST_DIR")).join("build.rs");
    files.push((
        PathBuf::from("../build.rs"),
        std::fs::read_to_string(&build).unwrap(),
    ));
    let bad = distribution_names(&files);
    assert!(bad.is_empty(), "found, not spelt:\n{}", bad.join("\n"));
    // Teeth: main's hard-coded names are caught; the same words in a comment or a test are not.
    let t = tree(&[
        (
            "isa/mod.rs",
            "pub const F: &str = \"/usr/share/vulkan/icd.d/radeon_icd.x86_64.json\";\n",
        ),
        (
            "../build.rs",
            "    println!(\"cargo:rustc-link-search=native=/usr/lib/x86_64-linux-gnu\");\n",
        ),
        (
            "isa/route/mod.rs",
            "let egl = \"/usr/lib64/libEGL.so.1\";\n",
        ),
        ("gpu/icd.rs", "//! Mesa 22.3 names radeon_icd.x86_64.json\n"),
        (
            "gpu/x.rs",
            "#[cfg(test)]\nmod tests {\n    const M: &str = \"radeon_icd.i686.json\";\n}\n",
        ),
    ]);
    let bad = distribution_names(&t);
    assert_eq!(bad.len(), 3, "{bad:?}");
    assert!(bad[0].starts_with("isa/mod.rs:1:"), "{bad:?}");
}
