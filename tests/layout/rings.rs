//! No ring between the files of one module: within a folder of src/ (a module), its files and
//! subfolders (its submodules; a `NAME.rs` with a folder `NAME/` is one) must not import each
//! other in a circle, directly or through others. What both sides of a ring need goes to a
//! leaf of its own. The module's own file (`mod.rs`) declares the others and is not one of
//! them; rings between top-level modules are `layers_point_one_way`'s. Imports are read from
//! production code only (comments, strings and `#[cfg(test)]` items left out): every
//! `crate::..`, `super::..` and `self::..` path, `use` groups included.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use super::{code_only, is_test_file, source_tree, test_files, test_lines, tree};

/// Rings still waiting to be broken, as (module folder under src/, its files in the ring,
/// sorted). Each must still be a ring: once it is broken, `no_ring_between_files_of_a_module`
/// fails until its entry is removed, so the list can only shrink.
const PENDING_RINGS: &[(&str, &[&str])] = &[
    // method/tuned.rs (a tuned file's line) and method/user.rs (a user method file) read each
    // other; the next part of this work, which may change tuned.rs, breaks it.
    ("method", &["tuned", "user"]),
];

/// The module path of a file under src/: `report/front/matrix.rs` -> [report, front, matrix],
/// `report/mod.rs` -> [report], `lib.rs` -> [].
fn module_path(p: &Path) -> Vec<String> {
    let mut parts: Vec<String> = p
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// Every path (its segments after `crate`, `super` or `self`) that `code` names, `use` groups
/// opened: `use super::{a, b::{c, d}}` names `super::a`, `super::b::c`, `super::b::d`.
fn paths(code: &[char]) -> Vec<Vec<String>> {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let word_at = |i: usize| -> (String, usize) {
        let w: String = code[i..].iter().take_while(|&&c| ident(c)).collect();
        let n = w.chars().count();
        (w, i + n)
    };
    let skip_ws = |mut i: usize| {
        while i < code.len() && code[i].is_whitespace() {
            i += 1;
        }
        i
    };
    let sep_at = |i: usize| code.get(i) == Some(&':') && code.get(i + 1) == Some(&':');
    // The paths of the use tree at `i` with segments `prefix`; returns where it ends.
    fn tree_at(
        code: &[char],
        i: usize,
        prefix: Vec<String>,
        out: &mut Vec<Vec<String>>,
        word_at: &dyn Fn(usize) -> (String, usize),
        skip_ws: &dyn Fn(usize) -> usize,
        sep_at: &dyn Fn(usize) -> bool,
    ) -> usize {
        let mut i = skip_ws(i);
        let mut segs = prefix;
        loop {
            if code.get(i) == Some(&'{') {
                i += 1;
                loop {
                    i = skip_ws(i);
                    match code.get(i) {
                        Some('}') => return i + 1,
                        Some(',') => i += 1,
                        None => return i,
                        _ => {
                            let end = tree_at(code, i, segs.clone(), out, word_at, skip_ws, sep_at);
                            i = if end == i { i + 1 } else { end };
                        }
                    }
                }
            }
            let (w, end) = word_at(i);
            if w.is_empty() {
                out.push(segs);
                return i;
            }
            segs.push(w);
            i = skip_ws(end);
            if sep_at(i) {
                i = skip_ws(i + 2);
            } else {
                out.push(segs);
                return i;
            }
        }
    }
    let mut out = Vec::new();
    let mut i = 0;
    while i < code.len() {
        let starts = i == 0 || !ident(code[i - 1]);
        let (w, end) = word_at(i);
        if starts && matches!(w.as_str(), "crate" | "super" | "self") && sep_at(end) {
            let e = tree_at(
                code,
                end + 2,
                vec![w],
                &mut out,
                &word_at,
                &skip_ws,
                &sep_at,
            );
            i = e.max(end);
        } else {
            i = if w.is_empty() { i + 1 } else { end };
        }
    }
    out
}

/// `path` (from [`paths`]) named in the module `module`, as an absolute module path.
fn resolve(module: &[String], path: &[String]) -> Vec<String> {
    let mut base: Vec<String> = module.to_vec();
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            rest = &path[1..];
        }
        Some("self") => rest = &path[1..],
        _ => {
            while rest.first().map(String::as_str) == Some("super") {
                base.pop();
                rest = &rest[1..];
            }
        }
    }
    base.extend(rest.iter().cloned());
    base
}

/// Per module folder (below the top level), the imports between its submodules:
/// (folder, from, to) -> the files that import.
fn file_edges(files: &[(PathBuf, String)]) -> BTreeMap<(String, String, String), Vec<String>> {
    let tests = test_files(files);
    let production: Vec<&(PathBuf, String)> = files
        .iter()
        .filter(|(p, _)| !is_test_file(&tests, p) && p != Path::new("main.rs"))
        .collect();
    // the submodules of each folder: its NAME.rs files and NAME/ folders
    let mut children: BTreeSet<(Vec<String>, String)> = BTreeSet::new();
    for (p, _) in &production {
        let m = module_path(p);
        for k in 1..=m.len() {
            children.insert((m[..k - 1].to_vec(), m[k - 1].clone()));
        }
    }
    let mut edges: BTreeMap<(String, String, String), Vec<String>> = BTreeMap::new();
    for (p, text) in &production {
        let module = module_path(p);
        let mask = test_lines(text);
        let code: String = code_only(text)
            .lines()
            .zip(mask.iter().chain(std::iter::repeat(&false)))
            .map(|(l, &test)| if test { String::new() } else { l.to_string() })
            .collect::<Vec<_>>()
            .join("\n");
        let code: Vec<char> = code.chars().collect();
        for path in paths(&code) {
            let target = resolve(&module, &path);
            let n = module
                .iter()
                .zip(&target)
                .take_while(|(a, b)| a == b)
                .count();
            if n == 0 || n >= module.len() || n >= target.len() {
                continue; // the top level, or within one submodule
            }
            let dir = module[..n].to_vec();
            let (from, to) = (&module[n], &target[n]);
            if !children.contains(&(dir.clone(), to.clone())) {
                continue; // an item of the folder's own file (mod.rs), not a submodule
            }
            let files = edges
                .entry((dir.join("/"), from.clone(), to.clone()))
                .or_default();
            let shown = p.display().to_string();
            if !files.contains(&shown) {
                files.push(shown);
            }
        }
    }
    edges
}

/// The rings between files of one module, as (folder, sorted members): the groups of more than
/// one submodule that reach each other.
fn rings(files: &[(PathBuf, String)]) -> Vec<(String, Vec<String>)> {
    let edges = file_edges(files);
    let mut by_dir: BTreeMap<&str, BTreeMap<&str, Vec<&str>>> = BTreeMap::new();
    for (dir, from, to) in edges.keys() {
        by_dir
            .entry(dir)
            .or_default()
            .entry(from)
            .or_default()
            .push(to);
    }
    let mut out = Vec::new();
    for (dir, graph) in by_dir {
        let nodes: BTreeSet<&str> = graph
            .iter()
            .flat_map(|(a, bs)| std::iter::once(*a).chain(bs.iter().copied()))
            .collect();
        // Reachability closure: a ring is a set of nodes that reach each other (the graphs
        // are a few dozen files, so the quadratic closure is plenty).
        let reach = |from: &str| -> BTreeSet<&str> {
            let mut seen = BTreeSet::new();
            let mut stack = vec![from];
            while let Some(n) = stack.pop() {
                for &m in graph.get(n).map(Vec::as_slice).unwrap_or(&[]) {
                    if seen.insert(m) {
                        stack.push(m);
                    }
                }
            }
            seen
        };
        let reaches: BTreeMap<&str, BTreeSet<&str>> =
            nodes.iter().map(|&n| (n, reach(n))).collect();
        let mut done: BTreeSet<&str> = BTreeSet::new();
        for &n in &nodes {
            if done.contains(n) || !reaches[n].contains(n) {
                continue;
            }
            let group: Vec<String> = nodes
                .iter()
                .filter(|&&m| reaches[n].contains(m) && reaches[m].contains(n))
                .map(|m| m.to_string())
                .collect();
            done.extend(nodes.iter().filter(|m| group.iter().any(|g| g == *m)));
            out.push((dir.to_string(), group));
        }
    }
    out
}

/// What the check reports: rings not in `pending` (with the imports that make them), and
/// entries of `pending` that are no longer rings.
fn ring_verdicts(files: &[(PathBuf, String)], pending: &[(&str, &[&str])]) -> Vec<String> {
    let found = rings(files);
    let edges = file_edges(files);
    let mut bad = Vec::new();
    for (dir, members) in &found {
        if pending
            .iter()
            .any(|(d, m)| d == dir && m.iter().copied().eq(members.iter().map(String::as_str)))
        {
            continue;
        }
        let imports: Vec<String> = edges
            .iter()
            .filter(|((d, a, b), _)| d == dir && members.contains(a) && members.contains(b))
            .map(|((_, a, b), files)| format!("{a} -> {b} ({})", files.join(", ")))
            .collect();
        bad.push(format!(
            "src/{dir}: {} import each other in a ring: {}; move what both sides need to a \
             leaf of its own",
            members.join(", "),
            imports.join("; ")
        ));
    }
    for (dir, members) in pending {
        if !found
            .iter()
            .any(|(d, m)| d == dir && m.iter().map(String::as_str).eq(members.iter().copied()))
        {
            bad.push(format!(
                "src/{dir}: {} is in PENDING_RINGS but no longer a ring: take it off the list",
                members.join(", ")
            ));
        }
    }
    bad
}

#[test]
fn no_ring_between_files_of_a_module() {
    let bad = ring_verdicts(&source_tree(), PENDING_RINGS);
    assert!(bad.is_empty(), "rings between files:\n{}", bad.join("\n"));
}

/// Teeth: a made-up module whose files import each other in a ring (directly, through a third
/// file, through a `use` group, from a nested folder) fails; the same module with the shared
/// item in a leaf passes; test code, comments, strings and the module's own file make no ring;
/// a pending ring that is broken must leave the list.
#[test]
fn the_ring_check_fails_on_a_ring_between_files() {
    let two = tree(&[
        ("report/mod.rs", "pub mod a;\npub mod b;\nuse a::X;\n"),
        ("report/a.rs", "use super::b::Y;\npub struct X;\n"),
        ("report/b.rs", "use crate::report::a::X;\npub struct Y;\n"),
    ]);
    assert_eq!(
        rings(&two),
        [("report".to_string(), vec!["a".into(), "b".into()])]
    );
    let v = ring_verdicts(&two, &[]);
    assert!(
        v.len() == 1 && v[0].contains("a -> b (report/a.rs)") && v[0].contains("b -> a"),
        "{v:?}"
    );
    // Through a third file, a use group and a nested folder (front.rs + front/claims.rs).
    let three = tree(&[
        ("isa/a.rs", "use super::{b::One, c};\n"),
        ("isa/b.rs", "pub fn f() { super::front::g() }\n"),
        ("isa/front.rs", "pub mod claims;\n"),
        ("isa/front/claims.rs", "use super::super::a::Z;\n"),
        (
            "isa/c.rs",
            "// crate::isa::a in a comment\nconst S: &str = \"super::a::x\";\n",
        ),
    ]);
    assert_eq!(
        rings(&three),
        [(
            "isa".to_string(),
            vec!["a".into(), "b".into(), "front".into()]
        )]
    );
    // Mended: what both need in a leaf; test code and the folder's own file make no ring.
    let mended = tree(&[
        (
            "report/mod.rs",
            "pub mod a;\npub mod b;\npub mod leaf;\nuse a::X;\n",
        ),
        ("report/a.rs", "use super::leaf::Y;\npub struct X;\n"),
        (
            "report/b.rs",
            "use super::leaf::Y;\n#[cfg(test)]\nmod tests {\n    use super::super::a::X;\n}\n",
        ),
        ("report/leaf.rs", "pub struct Y;\nuse super::Shared;\n"),
        ("report/tests.rs", "use super::a::X;\nuse super::b::*;\n"),
    ]);
    assert_eq!(rings(&mended), Vec::<(String, Vec<String>)>::new());
    assert_eq!(ring_verdicts(&mended, &[]), Vec::<String>::new());
    // The pending list: a ring on it passes, a broken one must leave it.
    assert_eq!(
        ring_verdicts(&two, &[("report", &["a", "b"])]),
        Vec::<String>::new()
    );
    let stale = ring_verdicts(&mended, &[("report", &["a", "b"])]);
    assert!(
        stale.len() == 1 && stale[0].contains("take it off"),
        "{stale:?}"
    );
}
