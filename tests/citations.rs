//! Every source the tool cites can be opened from a clone of the repository: each
//! `docs/formulas.md#<anchor>` in the sources, the shaders, the docs and the README names a heading
//! of docs/formulas.md (GitHub's anchors), every method's citation and claim in the table (what
//! `shadelab list --json`, bench, stress and the report print) names one, and no text cites a file
//! that is not in the repository (the project's working notes or the supplied paper texts by
//! line). Each check is a function over (path, text) pairs, so the teeth tests can feed it a tree
//! that breaks it.
use std::path::{Path, PathBuf};

use shadelab::report::formulas::{anchors, cited};

use crate::support::root;

/// The folders and files whose text is checked (sources, shaders, docs, scripts, tests).
const CHECKED: &[&str] = &[
    "src",
    "glsl",
    "docs",
    "tests",
    "scripts",
    "examples",
    "README.md",
    "Makefile",
    "build.rs",
];

/// Citations of what a clone does not have: the project's working notes (kept outside the
/// repository) and line numbers of the supplied paper texts. Spelt in pieces so that this file
/// does not cite them itself.
fn outside_sources() -> Vec<String> {
    let notes = ["FORMULAS", ".md"].concat();
    let mut v = vec![notes];
    for n in ["0", "2", "4"] {
        v.push(["S00", n].concat());
    }
    v.push(["seed file", " and line"].concat());
    v.push(["seed file", "/line"].concat());
    v.push(["the seed", " lines"].concat());
    v
}

/// Every text file under the checked paths, as (path relative to the root, text).
fn tree() -> Vec<(PathBuf, String)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    for c in CHECKED {
        let p = root().join(c);
        if p.is_dir() {
            walk(&p, &mut files);
        } else if p.is_file() {
            files.push(p);
        }
    }
    files
        .into_iter()
        .filter_map(|p| {
            let text = std::fs::read_to_string(&p).ok()?;
            Some((p.strip_prefix(root()).unwrap().to_path_buf(), text))
        })
        .collect()
}

/// The anchors `text` names as `formulas.md#<anchor>`: `docs/formulas.md#<anchor>` in the tool's
/// texts, a relative Markdown link `](formulas.md#<anchor>)` in docs/ (an anchor is a run of
/// letters, digits, `_` and `-`; a placeholder such as `<anchor>` is none).
fn anchors_named(text: &str) -> Vec<&str> {
    const LINK: &str = "](formulas.md#";
    let mut out = cited(text);
    let mut rest = text;
    while let Some(i) = rest.find(LINK) {
        let after = &rest[i + LINK.len()..];
        let end = after
            .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '-'))
            .unwrap_or(after.len());
        if end > 0 {
            out.push(&after[..end]);
        }
        rest = &after[end..];
    }
    out
}

/// Each `formulas.md#<anchor>` of `files` that `page` (the text of docs/formulas.md) lacks, as
/// "path: #anchor"; also each `[text](#anchor)` inside the page that it lacks.
fn unresolved(page: &str, files: &[(PathBuf, String)]) -> Vec<String> {
    let have = anchors(page);
    let mut bad = Vec::new();
    for (path, text) in files {
        for a in anchors_named(text) {
            if !have.iter().any(|h| h == a) {
                bad.push(format!("{}: #{a}", path.display()));
            }
        }
    }
    let mut rest = page;
    while let Some(i) = rest.find("](#") {
        let after = &rest[i + 3..];
        let end = after.find(')').unwrap_or(after.len());
        if !have.iter().any(|h| h == &after[..end]) {
            bad.push(format!("docs/formulas.md: #{}", &after[..end]));
        }
        rest = &after[end..];
    }
    bad
}

/// Each citation of a source outside the repository in `files`, as "path:line: text". The
/// paper texts may be named once, in docs/formulas.md, where it says which papers they are.
fn outside_citations(files: &[(PathBuf, String)]) -> Vec<String> {
    let forbidden = outside_sources();
    let mut bad = Vec::new();
    for (path, text) in files {
        let page = path == Path::new("docs/formulas.md");
        for (n, line) in text.lines().enumerate() {
            for f in &forbidden {
                let word = line.match_indices(f.as_str()).any(|(i, _)| {
                    let next = line[i + f.len()..].chars().next();
                    !next.is_some_and(|c| c.is_ascii_alphanumeric())
                });
                if word && !(page && f.starts_with("S00")) {
                    bad.push(format!("{}:{}: {f}", path.display(), n + 1));
                }
            }
        }
    }
    bad
}

fn formulas_page() -> String {
    std::fs::read_to_string(root().join("docs/formulas.md")).unwrap()
}

#[test]
fn every_cited_anchor_is_a_heading_of_docs_formulas_md() {
    let files = tree();
    let cites: usize = files.iter().map(|(_, t)| anchors_named(t).len()).sum();
    assert!(
        cites > 200,
        "only {cites} citations found: is the scan broken?"
    );
    let bad = unresolved(&formulas_page(), &files);
    assert!(
        bad.is_empty(),
        "citations with no heading in docs/formulas.md:\n{}",
        bad.join("\n")
    );
}

#[test]
fn nothing_cites_a_source_outside_the_repository() {
    let bad = outside_citations(&tree());
    assert!(
        bad.is_empty(),
        "citations of files a clone lacks:\n{}",
        bad.join("\n")
    );
}

#[test]
fn every_method_and_claim_of_the_table_cites_a_section_of_the_page() {
    let have = anchors(&formulas_page());
    let resolves = |what: &str, text: &str| {
        let named = cited(text);
        assert!(!named.is_empty(), "{what} cites no section: {text:?}");
        for a in named {
            assert!(
                have.iter().any(|h| h == a),
                "{what}: no heading #{a} in docs/formulas.md"
            );
        }
    };
    for m in shadelab::method::METHODS {
        resolves(&format!("{} citation", m.name), m.citation);
        for c in m.claims {
            resolves(&format!("{} claim", m.name), c.claim);
        }
    }
}

#[test]
fn the_checks_fail_on_a_wrong_anchor_and_on_an_outside_citation() {
    // The citations below are spelt in pieces, so that the scan of this file does not see them.
    let (tool, doc) = ("docs/formulas.md", "](formulas.md");
    let page = "# Top\n## Mikami square root\nsee [top](#top)\n";
    let good = vec![(
        PathBuf::from("src/a.rs"),
        format!("// ({tool}#mikami-square-root), [t{doc}#top)"),
    )];
    assert_eq!(unresolved(page, &good), Vec::<String>::new());
    assert_eq!(outside_citations(&good), Vec::<String>::new());
    // teeth: a misspelt anchor, one in a docs link, one inside the page itself
    let wrong = vec![(
        PathBuf::from("src/a.rs"),
        format!("// ({tool}#mikami-sqrt) and [t{doc}#nowhere)"),
    )];
    assert_eq!(
        unresolved(page, &wrong),
        ["src/a.rs: #mikami-sqrt", "src/a.rs: #nowhere"]
    );
    assert_eq!(
        unresolved("# Top\n[x](#gone)\n", &[]),
        ["docs/formulas.md: #gone"]
    );
    // teeth: the working notes and a paper text by line, named outside the page
    let notes = ["FORMULAS", ".md 2.8"].concat();
    let seed = ["(S00", "0 l.74)"].concat();
    let outside = vec![
        (PathBuf::from("src/b.rs"), format!("// {notes}\n// {seed}")),
        (
            PathBuf::from("docs/formulas.md"),
            format!("{seed}\n{notes}"),
        ),
    ];
    assert_eq!(
        outside_citations(&outside),
        [
            format!("src/b.rs:1: {}", ["FORMULAS", ".md"].concat()),
            format!("src/b.rs:2: {}", ["S00", "0"].concat()),
            format!("docs/formulas.md:2: {}", ["FORMULAS", ".md"].concat()),
        ]
    );
    // a method name in snake case is not a citation
    let ident = vec![(
        PathBuf::from("src/c.rs"),
        "fn as_printed_in_s004() {}".to_string(),
    )];
    assert_eq!(outside_citations(&ident), Vec::<String>::new());
}
