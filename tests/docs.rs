//! The documentation agrees with the tool and with itself, checked on its text:
//! - every count of methods, GPU families, a vendor's families, vendors and float16 guards in
//!   README.md, ARCHITECTURE.md and docs/*.md is the count the library has (the method table,
//!   the isa vendor registry); docs/history/ is a record and keeps the counts of its day;
//! - every path the pages name exists (each entry of docs/layout.md and each file its
//!   description names; elsewhere, every path from a top-level folder of the repository);
//! - every link between the pages resolves to a file and, with `#anchor`, to a heading or an
//!   `<a id>` of that page (the figures' rows are linked that way);
//! - no page outside docs/history/ speaks of how the tool was made (the project's process words);
//! - code fences open and close on lines of their own.
//!
//! Each check is a function over (path, text) pairs, so the teeth tests feed it text that breaks
//! it.
use std::path::{Path, PathBuf};

use shadelab::isa::route::{default_family_ids, VENDORS};
use shadelab::method::METHODS;
use shadelab::report::formulas::anchors;

use crate::support::root;

/// The counts the library has, and the nouns that name them.
struct Counts {
    /// The method table (`shadelab list`).
    methods: usize,
    /// The float16 guards among them (their rows cite docs/formulas.md#float16-guards).
    guards: usize,
    /// Every default family of every vendor (`shadelab isa --families all`).
    families: usize,
    /// The vendors, with each one's default families: (lower-case name, count).
    vendors: Vec<(String, usize)>,
}

fn counts() -> Counts {
    let guards = METHODS
        .iter()
        .filter(|m| m.citation.contains("#float16-guards"))
        .count();
    Counts {
        methods: METHODS.len(),
        guards,
        families: default_family_ids().len(),
        vendors: VENDORS
            .iter()
            .map(|v| (v.name().to_lowercase(), v.default_chips().len()))
            .collect(),
    }
}

/// Words that make "N methods" (or families, vendors) a part rather than the whole when they
/// follow the noun ("the 10 methods that scale the normal") or precede the number ("more than
/// 8 methods", "the 27 other ...").
const PART_AFTER: &[&str] = &[
    "that", "which", "whose", "it", "they", "covered", "skipped", "compiled", "where", "out",
];
const PART_BEFORE: &[&str] = &["than", "most", "least", "other", "first", "last", "these"];

/// A number written in digits or as a word up to twenty.
fn number(word: &str) -> Option<usize> {
    const WORDS: &[&str] = &[
        "zero",
        "one",
        "two",
        "three",
        "four",
        "five",
        "six",
        "seven",
        "eight",
        "nine",
        "ten",
        "eleven",
        "twelve",
        "thirteen",
        "fourteen",
        "fifteen",
        "sixteen",
        "seventeen",
        "eighteen",
        "nineteen",
        "twenty",
    ];
    word.parse()
        .ok()
        .or_else(|| WORDS.iter().position(|w| *w == word))
}

/// The words of `text`, lower case, without the punctuation around and inside them
/// (`method(s)` is `methods`, `` `37` `` is `37`; a decimal point stays, so `2.0` is no count),
/// each with its 1-based line.
fn words(text: &str) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        for w in line.split(|c: char| c.is_whitespace() || c == '|' || c == '/') {
            let w: String = w
                .chars()
                .filter(|c| c.is_alphanumeric() || "_-.".contains(*c))
                .collect::<String>()
                .trim_matches('.')
                .to_lowercase();
            if !w.is_empty() {
                out.push((w, i + 1));
            }
        }
    }
    out
}

/// Each count of `text` that disagrees with `c`, as "path:line: N noun (the tool has M)".
fn wrong_counts(c: &Counts, files: &[(PathBuf, String)]) -> Vec<String> {
    let mut bad = Vec::new();
    for (path, text) in files {
        let w = words(text);
        let at = |i: usize| w.get(i).map_or("", |(s, _)| s.as_str());
        for (i, (word, line)) in w.iter().enumerate() {
            let Some(n) = number(word) else { continue };
            let (noun, len, expected) = match (at(i + 1), at(i + 2)) {
                ("methods", _) if at(i + 2) == "from" && at(i + 4) == "papers" => {
                    ("methods from the papers", 4, c.methods - c.guards)
                }
                ("methods", _) => ("methods", 1, c.methods),
                ("guards", _) => ("guards", 1, c.guards),
                ("gpu", "families") | ("families", _) => (
                    "GPU families",
                    1 + (at(i + 1) == "gpu") as usize,
                    c.families,
                ),
                ("vendors", _) => ("vendors", 1, c.vendors.len()),
                (v, "families") => match c.vendors.iter().find(|(name, _)| name == v) {
                    Some((_, k)) => ("families of that vendor", 2, *k),
                    None => continue,
                },
                _ => continue,
            };
            let part = PART_AFTER.contains(&at(i + 1 + len))
                || (i > 0 && PART_BEFORE.contains(&at(i - 1)));
            if n != expected && !part {
                let shown = (i..=i + len).map(at).collect::<Vec<_>>().join(" ");
                bad.push(format!(
                    "{}:{line}: \"{shown}\" ({noun}: the tool has {expected})",
                    path.display()
                ));
            }
        }
    }
    bad
}

/// The user documentation: README.md, ARCHITECTURE.md and docs/*.md (not docs/history/).
fn user_docs() -> Vec<(PathBuf, String)> {
    let mut paths = vec![root().join("README.md"), root().join("ARCHITECTURE.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    paths.extend(docs);
    read(paths)
}

/// Every Markdown page, docs/history/ included (their links must resolve too).
fn every_page() -> Vec<(PathBuf, String)> {
    let mut pages = user_docs();
    let mut hist: Vec<PathBuf> = std::fs::read_dir(root().join("docs/history"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    hist.sort();
    pages.extend(read(hist));
    pages
}

fn read(paths: Vec<PathBuf>) -> Vec<(PathBuf, String)> {
    paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{p:?}: {e}"));
            (p.strip_prefix(root()).unwrap().to_path_buf(), text)
        })
        .collect()
}

#[test]
fn every_count_in_the_docs_is_the_tools() {
    let c = counts();
    // The counts this test reads, so that a change of the table or the registry is seen here.
    assert!(
        c.methods > c.guards && c.guards > 0,
        "{} {}",
        c.methods,
        c.guards
    );
    assert_eq!(
        c.families,
        c.vendors.iter().map(|(_, n)| n).sum::<usize>(),
        "families"
    );
    let bad = wrong_counts(&c, &user_docs());
    assert!(
        bad.is_empty(),
        "counts that disagree with the tool:\n{}",
        bad.join("\n")
    );
}

#[test]
fn a_wrong_count_fails_and_a_part_passes() {
    let c = Counts {
        methods: 37,
        guards: 2,
        families: 36,
        vendors: vec![("amd".into(), 6), ("intel".into(), 9)],
    };
    let page = |s: &str| vec![(PathBuf::from("made-up.md"), s.to_string())];
    for wrong in [
        "shadelab implements 35 methods.",
        "all **35** methods at 1024x1024",
        "on six families (tahiti, ...)",
        "the 19 GPU families of AMD",
        "37 methods x 9 AMD families",
        "of 3 vendors",
        "three guards",
        "36 methods from the papers",
    ] {
        let bad = wrong_counts(&c, &page(wrong));
        assert_eq!(bad.len(), 1, "{wrong:?}: {bad:?}");
        assert!(bad[0].starts_with("made-up.md:1:"), "{bad:?}");
    }
    for right in [
        "37 methods, 36 GPU families of 2 vendors",
        "35 methods from the papers and two guards: 37 methods",
        "the 10 methods that scale the normal; never more than 8 methods per panel",
        "6 AMD families and 9 Intel families; the 12 Intel, NVIDIA and TeraScale families",
        "compiled, 19 method(s) skipped",
    ] {
        let bad = wrong_counts(&c, &page(right));
        assert!(bad.is_empty(), "{right:?}: {bad:?}");
    }
}

/// A word that names a path: without the punctuation a sentence puts around it (backticks,
/// brackets, a trailing full stop or `'s`); `None` for a pattern (`*`, `<name>`, `{a,b}`).
fn path_word(w: &str) -> Option<&str> {
    let punct = |c: char| "`()[],;:\"".contains(c);
    let w = w
        .trim_matches(punct)
        .trim_end_matches('.')
        .trim_matches(punct);
    let w = w.strip_suffix("'s").unwrap_or(w).trim_end_matches('.');
    let plain = w
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || "_./-".contains(c));
    (plain && !w.is_empty()).then_some(w)
}

/// The folders at the top of the repository that a path in the docs starts with.
const TOP: &[&str] = &[
    "src/",
    "tests/",
    "scripts/",
    "glsl/",
    "docs/",
    "scenes/",
    "spirv/",
    "examples/",
    ".ci/",
];

/// Paths of Mesa's source tree that docs/isa.md cites (Intel's compiler, in Mesa, not here).
const MESA_TREE: &str = "src/intel/";

/// The paths `text` names, each as the places it may be (relative to the root): in the code
/// block of a layout page (`layout`), each entry's first word, and each file or folder name of
/// its description, relative to the entry's folder or to the root; everywhere, each word that
/// starts with a top-level folder ([`MESA_TREE`] left out). As (line, candidates).
fn named_paths(text: &str, layout: bool) -> Vec<(usize, Vec<PathBuf>)> {
    let mut out = Vec::new();
    let mut fence = false;
    let mut dir: Option<PathBuf> = None;
    let is_file = |w: &str| {
        w.ends_with('/')
            || [
                ".rs", ".glsl", ".comp", ".css", ".js", ".md", ".sh", ".json", ".toml",
            ]
            .iter()
            .any(|x| w.ends_with(x))
    };
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            dir = None;
            continue;
        }
        let in_layout = layout && fence;
        if in_layout && !line.starts_with(' ') {
            let first = line.split_whitespace().next().unwrap_or("");
            dir = (first.contains('/') || first.contains('.')).then(|| {
                out.push((i + 1, vec![PathBuf::from(first)]));
                let p = PathBuf::from(first);
                if first.ends_with('/') {
                    p
                } else {
                    p.parent().map(Path::to_path_buf).unwrap_or_default()
                }
            });
            if dir.is_none() {
                continue;
            }
        }
        let skip_first = in_layout && !line.starts_with(' ');
        for w in line.split_whitespace().skip(skip_first as usize) {
            let Some(w) = path_word(w) else { continue };
            if TOP.iter().any(|t| w.starts_with(t)) && !w.starts_with(MESA_TREE) {
                out.push((i + 1, vec![PathBuf::from(w)]));
            } else if let (true, Some(d)) = (in_layout && is_file(w), &dir) {
                out.push((i + 1, vec![d.join(w), PathBuf::from(w)]));
            }
        }
    }
    out
}

/// Each path of `files` that exists in none of its places under `root`, as "path:line: name".
fn missing_paths(root: &Path, files: &[(PathBuf, String)]) -> Vec<String> {
    let mut bad = Vec::new();
    for (path, text) in files {
        let layout = path.ends_with("docs/layout.md");
        for (line, places) in named_paths(text, layout) {
            if !places.iter().any(|p| root.join(p).exists()) {
                bad.push(format!(
                    "{}:{line}: {}",
                    path.display(),
                    places[0].display()
                ));
            }
        }
    }
    bad
}

#[test]
fn every_path_the_docs_name_exists() {
    let pages = user_docs();
    let named: usize = pages
        .iter()
        .map(|(p, t)| named_paths(t, p.ends_with("docs/layout.md")).len())
        .sum();
    assert!(
        named > 100,
        "only {named} paths found: the parser lost them"
    );
    let bad = missing_paths(root(), &pages);
    assert!(
        bad.is_empty(),
        "paths that do not exist:\n{}",
        bad.join("\n")
    );
}

#[test]
fn a_path_that_is_gone_fails() {
    let layout = "```\nsrc/software/      the engine: raster (raster.rs), twins (formulas.rs)\n\
                  src/nowhere/       gone\n                   (and gone.rs)\n```\n";
    let arch =
        "Files: `src/method/table.rs` and `src/method/gone.rs`, then glsl/methods/<name>.glsl \
                (tests/software.rs). Mesa's src/intel/compiler/brw_fs.cpp is Mesa's.";
    let files = vec![
        (PathBuf::from("docs/layout.md"), layout.to_string()),
        (PathBuf::from("ARCHITECTURE.md"), arch.to_string()),
    ];
    let bad = missing_paths(root(), &files);
    assert_eq!(
        bad,
        [
            "docs/layout.md:2: src/software/formulas.rs",
            "docs/layout.md:3: src/nowhere/",
            "docs/layout.md:4: src/nowhere/gone.rs",
            "ARCHITECTURE.md:1: src/method/gone.rs",
            "ARCHITECTURE.md:1: tests/software.rs",
        ],
        "{bad:?}"
    );
}

/// The targets of the Markdown links of `text` (`](target)`), with their lines; web links and
/// mail are left out.
fn links(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut rest = line;
        while let Some(k) = rest.find("](") {
            let after = &rest[k + 2..];
            let end = after.find(')').unwrap_or(after.len());
            let target = after[..end].split_whitespace().next().unwrap_or("");
            if !target.contains("://") && !target.starts_with("mailto:") {
                out.push((i + 1, target));
            }
            rest = &after[end..];
        }
    }
    out
}

/// The anchors of a page: its headings' (GitHub's rule) and its `<a id="...">`s.
fn page_anchors(text: &str) -> Vec<String> {
    let mut out = anchors(text);
    let mut rest = text;
    while let Some(k) = rest.find("<a id=\"") {
        let after = &rest[k + 7..];
        let end = after.find('"').unwrap_or(after.len());
        out.push(after[..end].to_string());
        rest = &after[end..];
    }
    out
}

/// `base` joined with `rel`, `..` and `.` resolved.
fn resolve(base: &Path, rel: &str) -> PathBuf {
    let mut out = base.to_path_buf();
    for part in rel.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                out.pop();
            }
            p => out.push(p),
        }
    }
    out
}

/// Each link of `files` whose file is not there (`exists`) or whose `#anchor` is not an anchor of
/// the page it names, as "path:line: target". A page's text is taken from `files` when it is
/// there, else read from under `root`.
fn broken_links(
    root: &Path,
    files: &[(PathBuf, String)],
    exists: &dyn Fn(&Path) -> bool,
) -> Vec<String> {
    let mut bad = Vec::new();
    for (path, text) in files {
        let dir = path.parent().unwrap_or(Path::new(""));
        for (line, target) in links(text) {
            let (file, anchor) = target.split_once('#').unwrap_or((target, ""));
            let page = if file.is_empty() {
                path.clone()
            } else {
                resolve(dir, file)
            };
            let ok = exists(&page)
                && (anchor.is_empty()
                    || page.extension().is_none_or(|x| x != "md")
                    || files
                        .iter()
                        .find(|(p, _)| *p == page)
                        .map(|(_, t)| t.clone())
                        .or_else(|| std::fs::read_to_string(root.join(&page)).ok())
                        .is_some_and(|t| page_anchors(&t).iter().any(|a| a == anchor)));
            if !ok {
                bad.push(format!("{}:{line}: {target}", path.display()));
            }
        }
    }
    bad
}

#[test]
fn every_link_between_the_pages_resolves() {
    let pages = every_page();
    let bad = broken_links(root(), &pages, &|p| root().join(p).exists());
    assert!(
        bad.is_empty(),
        "links that do not resolve:\n{}",
        bad.join("\n")
    );
}

#[test]
fn a_link_to_a_missing_page_or_anchor_fails() {
    let a = "See [the row](figures.md#compare-time), [a heading](b.md#the-answer-per-vendor), \
             [here](#local) and [the web](https://example.org/x.md#y).\n\
             Gone: [page](nowhere.md), [row](figures.md#no-such-row), [up](../b.md#the-answer-per-vendor).\n\
             <a id=\"local\"></a>";
    let files = vec![
        (PathBuf::from("docs/a.md"), a.to_string()),
        (
            PathBuf::from("docs/b.md"),
            "# The answer per vendor\n".to_string(),
        ),
        (
            PathBuf::from("docs/figures.md"),
            "| <a id=\"compare-time\"></a>compare | 1 s |\n".to_string(),
        ),
    ];
    let exists = |p: &Path| files.iter().any(|(q, _)| q == p);
    let bad = broken_links(root(), &files, &exists);
    assert_eq!(
        bad,
        [
            "docs/a.md:2: nowhere.md",
            "docs/a.md:2: figures.md#no-such-row",
            "docs/a.md:2: ../b.md#the-answer-per-vendor",
        ]
    );
}

/// Each word of `files` that speaks of how the project works rather than of the tool, as
/// "path:line: words": helpers, briefs, milestones, sessions, issue numbers, "the lead", "this
/// branch", "moved from the README". docs/history/ may (it is the record of that).
fn process_words(files: &[(PathBuf, String)]) -> Vec<String> {
    const ALWAYS: &[&str] = &[
        "helper",
        "helpers",
        "brief",
        "briefs",
        "milestone",
        "milestones",
        "session",
        "sessions",
    ];
    let mut bad = Vec::new();
    for (path, text) in files {
        let w = words(text);
        let at = |i: usize| w.get(i).map_or("", |(s, _)| s.as_str());
        for (i, (word, line)) in w.iter().enumerate() {
            let word = word.as_str();
            let prev = if i > 0 { at(i - 1) } else { "" };
            let next = at(i + 1);
            let hit = ALWAYS.contains(&word)
                || (matches!(word, "issue" | "issues")
                    && next.starts_with(|c: char| c.is_ascii_digit()))
                || (prev == "the" && matches!(word, "lead" | "leads"))
                || (prev == "this" && word == "branch")
                || (word == "moved" && next == "from" && at(i + 3) == "readme");
            if hit {
                bad.push(format!("{}:{}: {} {}", path.display(), line, word, next));
            }
        }
    }
    bad
}

#[test]
fn no_page_speaks_of_how_the_tool_was_made() {
    let bad = process_words(&user_docs());
    assert!(
        bad.is_empty(),
        "say what the tool does (or move the passage to docs/history/):\n{}",
        bad.join("\n")
    );
}

#[test]
fn process_words_fail_and_the_tools_words_pass() {
    let page = |s: &str| vec![(PathBuf::from("made-up.md"), s.to_string())];
    for wrong in [
        "<!-- Moved from the README (issue 24) -->",
        "the lead takes the idle figure",
        "(other helpers building)",
        "the brief's suzanne runs",
        "19 methods of milestone 1",
        "Before: main; after: this branch.",
        "as in the sixth session",
    ] {
        assert!(!process_words(&page(wrong)).is_empty(), "{wrong:?}");
    }
    for right in [
        "interval branch-and-bound; the branches of a shader; an issue slot; issue groups",
        "r600's VLIW issue groups; issue plus stall cycles; a leading zero",
    ] {
        assert!(process_words(&page(right)).is_empty(), "{right:?}");
    }
}

/// Each page of `files` whose code fences do not open and close on lines of their own, as
/// "path:line" (a fence after text on its line leaves the block open, and the rest of the page
/// renders as code) or "path: unclosed".
fn bad_fences(files: &[(PathBuf, String)]) -> Vec<String> {
    let mut bad = Vec::new();
    for (path, text) in files {
        let mut open = false;
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("```") {
                open = !open;
            } else if line.contains("```") {
                bad.push(format!("{}:{}", path.display(), i + 1));
            }
        }
        if open {
            bad.push(format!("{}: unclosed", path.display()));
        }
    }
    bad
}

#[test]
fn code_blocks_close_on_lines_of_their_own() {
    let bad = bad_fences(&every_page());
    assert!(bad.is_empty(), "code fences:\n{}", bad.join("\n"));
}

#[test]
fn a_fence_after_text_fails() {
    let broken = "```toml\n[render]\ninterpolation = \"screen_linear\" # default```\n\nText.\n";
    let bad = bad_fences(&[(PathBuf::from("docs/scenes.md"), broken.into())]);
    assert_eq!(bad, ["docs/scenes.md:3", "docs/scenes.md: unclosed"]);
    let fixed = broken.replace("# default```", "# default\n```");
    assert!(bad_fences(&[(PathBuf::from("docs/scenes.md"), fixed)]).is_empty());
}
