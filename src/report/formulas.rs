//! The report's copy of docs/formulas.md, the page every citation of the tool points to
//! (`docs/formulas.md#<anchor>`), so that a citation in the report is a link that opens offline.
//!
//! The page is the Markdown rendered as HTML (pulldown-cmark), each heading with its GitHub-style
//! anchor as `id` (the anchor a citation names, the one GitHub renders). [`cite`] turns the
//! citations in a text into links to it.
use super::html::esc;

/// docs/formulas.md, built into the binary.
pub const SOURCE: &str = include_str!("../../docs/formulas.md");

/// The page's file name, beside index.html.
pub const PAGE: &str = "formulas.html";

/// How the tool's texts cite a section of the page.
pub const CITATION_PREFIX: &str = "docs/formulas.md#";

/// GitHub's anchor of a Markdown heading: lower case; letters, digits, `_`, `-` and spaces kept,
/// everything else dropped; spaces become `-`. (Duplicates get `-1`, `-2`, ... in
/// [`sections`].)
pub fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// One heading of the page and the text under it.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    pub level: usize,
    pub heading: String,
    pub anchor: String,
    pub body: String,
}

/// The headings of `markdown` (outside code fences) with their anchors and the text up to the
/// next heading; the text before the first heading is dropped.
pub fn sections(markdown: &str) -> Vec<Section> {
    let mut out: Vec<Section> = Vec::new();
    let mut fence = false;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
        }
        let hashes = line.chars().take_while(|c| *c == '#').count();
        let heading = (!fence && (1..=6).contains(&hashes))
            .then(|| line[hashes..].strip_prefix(' '))
            .flatten();
        match (heading, out.last_mut()) {
            (Some(h), _) => {
                let h = h.trim().trim_end_matches('#').trim().to_string();
                let base = slug(&h);
                let taken = out.iter().filter(|s| slug(&s.heading) == base).count();
                let anchor = match taken {
                    0 => base,
                    n => format!("{base}-{n}"),
                };
                out.push(Section {
                    level: hashes,
                    heading: h,
                    anchor,
                    body: String::new(),
                });
            }
            (None, Some(s)) => {
                s.body.push_str(line);
                s.body.push('\n');
            }
            (None, None) => {}
        }
    }
    out
}

/// The anchors of `markdown`, in page order.
pub fn anchors(markdown: &str) -> Vec<String> {
    sections(markdown).into_iter().map(|s| s.anchor).collect()
}

/// The length of the anchor at the start of `s`: its run of letters, digits, `_` and `-`.
fn anchor_len(s: &str) -> usize {
    s.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '-'))
        .unwrap_or(s.len())
}

/// Every `docs/formulas.md#<anchor>` that `text` names: the anchor is the run of letters, digits,
/// `_` and `-` after the `#` (none, as in this sentence's placeholder, is no citation).
pub fn cited(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find(CITATION_PREFIX) {
        let after = &rest[i + CITATION_PREFIX.len()..];
        let end = anchor_len(after);
        if end > 0 {
            out.push(&after[..end]);
        }
        rest = &after[end..];
    }
    out
}

/// `text` escaped for HTML, each `docs/formulas.md#<anchor>` in it a link to the anchor of the
/// report's copy of the page ([`PAGE`], beside index.html).
pub fn cite(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find(CITATION_PREFIX) {
        out += &esc(&rest[..i]);
        let after = &rest[i + CITATION_PREFIX.len()..];
        let anchor = &after[..anchor_len(after)];
        out += &match anchor {
            "" => esc(CITATION_PREFIX),
            a => format!(
                "<a href=\"{PAGE}#{}\">{}</a>",
                esc(a),
                esc(&format!("{CITATION_PREFIX}{a}"))
            ),
        };
        rest = &after[anchor.len()..];
    }
    out + &esc(rest)
}

/// The report's copy of `markdown` (docs/formulas.md) as one HTML page, rendered as Markdown
/// (tables, emphasis, code, lists; GitHub's extensions for tables and strikethrough), each
/// heading with the anchor [`sections`] gives it, so `formulas.html#<anchor>` opens where
/// GitHub's rendering of docs/formulas.md would. Raw HTML in the source is escaped, never passed
/// through.
pub fn page(markdown: &str) -> String {
    use pulldown_cmark::{Event, Options, Parser, Tag};
    let mut h = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>shadelab: formulas and sources</title>\
         <link rel=\"stylesheet\" href=\"report.css\"></head><body><header><p>\
         <a href=\"index.html\">back to the report</a>. This page is docs/formulas.md of \
         shadelab, the page the report's citations name.</p></header><main class=\"formulas\">",
    );
    // The anchors in page order: the parser's headings are the same ones, in the same order
    // (both skip fenced code), which the test below checks against the ids of the page.
    let mut anchors = sections(markdown).into_iter().map(|s| s.anchor);
    let options = Options::ENABLE_TABLES | Options::ENABLE_STRIKETHROUGH;
    let events = Parser::new_ext(markdown, options).map(|e| match e {
        Event::Start(Tag::Heading {
            level,
            classes,
            attrs,
            ..
        }) => Event::Start(Tag::Heading {
            level,
            id: anchors.next().map(Into::into),
            classes,
            attrs,
        }),
        Event::Html(t) | Event::InlineHtml(t) => Event::Text(t),
        other => other,
    });
    pulldown_cmark::html::push_html(&mut h, events);
    h + "</main></body></html>\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs_are_githubs() {
        assert_eq!(slug("Lyon, Taylor form"), "lyon-taylor-form");
        assert_eq!(
            slug("Digital segments: error bounds"),
            "digital-segments-error-bounds"
        );
        assert_eq!(
            slug("Hast-Barrera-Bengtsson half vector"),
            "hast-barrera-bengtsson-half-vector"
        );
        assert_eq!(slug("`k_newton` and 2.4"), "k_newton-and-24");
        // punctuation is dropped, not replaced; every space is a hyphen
        assert_eq!(slug("a.b  c"), "ab--c");
        assert_ne!(slug("Lyon Taylor form"), slug("Lyon Taylor"));
    }

    #[test]
    fn sections_skip_code_fences_and_number_duplicates() {
        let md = "intro\n# A\ntext\n```\n# not a heading\n```\n## A\n### B c\nmore\n";
        let s = sections(md);
        let a: Vec<_> = s.iter().map(|s| s.anchor.as_str()).collect();
        assert_eq!(a, ["a", "a-1", "b-c"]);
        assert!(s[0].body.contains("# not a heading"));
        assert_eq!(s[2].body, "more\n");
    }

    #[test]
    fn cite_links_every_citation_and_escapes_the_rest() {
        let t = "x < 1 (docs/formulas.md#mikami-square-root), docs/formulas.md#dichotomy.";
        assert_eq!(cited(t), ["mikami-square-root", "dichotomy"]);
        let h = cite(t);
        assert_eq!(
            h,
            "x &lt; 1 (<a href=\"formulas.html#mikami-square-root\">\
             docs/formulas.md#mikami-square-root</a>), <a href=\"formulas.html#dichotomy\">\
             docs/formulas.md#dichotomy</a>."
        );
        assert_eq!(cite("no citation & more"), "no citation &amp; more");
    }

    #[test]
    fn the_page_has_an_id_per_heading_and_links_within_it() {
        let html = page("# Top\nsee [below](#the-end) & <x>\n## The end\n");
        assert!(html.contains("<h1 id=\"top\">Top</h1>"), "{html}");
        assert!(html.contains("<h2 id=\"the-end\">The end</h2>"), "{html}");
        assert!(
            html.contains("see <a href=\"#the-end\">below</a> &amp; &lt;x&gt;"),
            "{html}"
        );
        let ids = crate::report::links::attribute_values(&page(SOURCE), "id");
        assert_eq!(ids, anchors(SOURCE));
    }

    #[test]
    fn the_page_is_rendered_markdown_not_its_source() {
        let md = "# T\n| a | b |\n|---|---|\n| **x** | `y` |\n\n- item\n\n```\n# code\n```\n";
        let html = page(md);
        assert!(html.contains("<table>"), "{html}");
        assert!(html.contains("<strong>x</strong>"), "{html}");
        assert!(html.contains("<code>y</code>"), "{html}");
        assert!(html.contains("<li>item</li>"), "{html}");
        // a fenced line that looks like a heading stays code and takes no anchor
        assert!(html.contains("<pre><code># code"), "{html}");
        assert!(!html.contains("|---|"), "{html}");
        // raw HTML in the source is text, never markup
        assert!(page("a <script>x</script>").contains("&lt;script&gt;"));
        // and docs/formulas.md itself: its tables and emphasis are rendered, none left as source
        let full = page(SOURCE);
        assert!(
            full.contains("<table>") && full.contains("<strong>"),
            "{}",
            &full[..400]
        );
        assert!(
            !full.contains("\n|---") && !full.contains("**"),
            "raw Markdown left"
        );
    }
}
