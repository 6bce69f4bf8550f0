//! A link checker for the report (no browser needed): every `href` and `src` of a page must be
//! a relative path to an existing file (resolved from the page's folder; with a `#fragment` into
//! another HTML page, an `id` that page has) or an `#id` of the page itself. Anything that would reach the network (`http:`, `https:`, `//host`, any other scheme)
//! is reported too: the report must work from file:// with no network.
use std::path::Path;

use crate::error::{Error, Result};

/// Undoes [`super::html::esc`] and the numeric entities an attribute value may hold.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        let after = &rest[i..];
        let Some(end) = after.find(';') else {
            out.push_str(after);
            return out;
        };
        let entity = &after[1..end];
        let c = match entity {
            "amp" => Some('&'),
            "lt" => Some('<'),
            "gt" => Some('>'),
            "quot" => Some('"'),
            "apos" => Some('\''),
            e if e.starts_with("#x") => u32::from_str_radix(&e[2..], 16)
                .ok()
                .and_then(char::from_u32),
            e if e.starts_with('#') => e[1..].parse().ok().and_then(char::from_u32),
            _ => None,
        };
        match c {
            Some(c) => {
                out.push(c);
                rest = &after[end + 1..];
            }
            None => {
                out.push('&');
                rest = &after[1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// Decodes `%XX` escapes of a URL path.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            if let Some(Ok(v)) = s.get(i + 1..i + 3).map(|h| u8::from_str_radix(h, 16)) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The values of attribute `name` (double- or single-quoted) in `html`, unescaped.
pub fn attribute_values(html: &str, name: &str) -> Vec<String> {
    let mut out = Vec::new();
    let lower = html.to_ascii_lowercase();
    let needle = format!("{name}=");
    let mut from = 0;
    while let Some(i) = lower[from..].find(&needle) {
        let at = from + i;
        from = at + needle.len();
        // A whole attribute name: preceded by whitespace (not `data-src=` or `xhref=`).
        if at == 0 || !lower.as_bytes()[at - 1].is_ascii_whitespace() {
            continue;
        }
        let rest = &html[from..];
        let Some(q) = rest.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            continue;
        };
        if let Some(end) = rest[1..].find(q) {
            out.push(unescape(&rest[1..1 + end]));
        }
    }
    out
}

/// Every `href`/`src` of `html` that does not resolve: a missing file under `dir`, an `#id`
/// the page lacks (this page, or another HTML page under `dir` it links into), or anything
/// pointing outside (a scheme, `//host`, an absolute path, `..`).
/// Each entry says which attribute value failed and why.
pub fn broken_in(html: &str, dir: &Path) -> Vec<String> {
    let ids = attribute_values(html, "id");
    let mut bad = Vec::new();
    for attr in ["href", "src"] {
        for v in attribute_values(html, attr) {
            let (path, frag) = match v.split_once('#') {
                Some((p, f)) => (p, Some(f)),
                None => (v.as_str(), None),
            };
            let path = path.split('?').next().unwrap_or("");
            if path.is_empty() {
                match frag {
                    Some(f) if ids.iter().any(|i| i == f) => {}
                    Some(f) => bad.push(format!("{attr}=\"{v}\": no element with id \"{f}\"")),
                    None => bad.push(format!("{attr}=\"{v}\": empty link")),
                }
                continue;
            }
            let scheme = path
                .split_once(':')
                .is_some_and(|(s, _)| !s.contains('/') && !s.is_empty());
            if scheme || path.starts_with('/') || path.starts_with('\\') {
                bad.push(format!(
                    "{attr}=\"{v}\": not a relative path (the report must work offline)"
                ));
                continue;
            }
            let decoded = percent_decode(path);
            if decoded.split(['/', '\\']).any(|c| c == "..") {
                bad.push(format!("{attr}=\"{v}\": leaves the report's folder"));
                continue;
            }
            let target = dir.join(&decoded);
            if !target.is_file() {
                bad.push(format!("{attr}=\"{v}\": no file {}", target.display()));
            } else if let Some(f) = frag.filter(|_| is_html(&target)) {
                let text = std::fs::read_to_string(&target).unwrap_or_default();
                if !attribute_values(&text, "id").iter().any(|i| i == f) {
                    bad.push(format!(
                        "{attr}=\"{v}\": {} has no element with id \"{f}\"",
                        target.display()
                    ));
                }
            }
        }
    }
    bad
}

/// Whether `path` names an HTML page (whose ids a `#fragment` can name).
fn is_html(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"))
}

/// [`broken_in`] for the page at `path` (links resolved from its folder).
pub fn broken_links(path: &Path) -> Result<Vec<String>> {
    let html = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    Ok(broken_in(&html, dir))
}
