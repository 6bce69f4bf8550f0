//! The architecture of src/lib.rs, checked on the source tree: layers point one way, `ash` lives
//! only in src/gpu/vk, clap only in src/cli, no production file is too long. Each check is a
//! function over (path, text) pairs, so the teeth tests below can feed it a tree that breaks it.
use std::path::{Path, PathBuf};

/// The layers of src/lib.rs, top first. A module may use modules of its own or a lower layer;
/// within a layer, dependencies must not form a cycle.
const LAYERS: &[&[&str]] = &[
    &["main", "cli"],
    &["report"],
    &["compare", "bench", "verify", "stress", "plan", "isa"],
    &["analysis", "truth"],
    &["gpu", "software"],
    &["scene", "frame"],
    &["method", "geometry"],
    &["output", "error", "testutil", "lib"],
];

/// Production code (before `#[cfg(test)]`) longer than this is a file to split.
const MAX_PRODUCTION_LINES: usize = 800;

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

fn long_files(files: &[(PathBuf, String)]) -> Vec<String> {
    files
        .iter()
        .filter_map(|(p, text)| {
            let n = text
                .lines()
                .take_while(|l| !l.starts_with("#[cfg(test)]"))
                .count();
            let is_tests = p.file_name().is_some_and(|f| f == "tests.rs");
            (n > MAX_PRODUCTION_LINES && !is_tests).then(|| format!("{}: {n} lines", p.display()))
        })
        .collect()
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

#[test]
fn no_production_file_is_too_long() {
    let bad = long_files(&source_tree());
    assert!(bad.is_empty(), "split these files:\n{}", bad.join("\n"));
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
    let long_with_tests = format!("fn f() {{}}\n#[cfg(test)]\n{long}");
    assert!(long_files(&tree(&[("geometry/obj.rs", &long_with_tests)])).is_empty());
}
