//! HTML of the report, the pieces every part of the page shares: [`esc`] (every piece of text
//! passes through it), numbers in table cells ([`number`], [`num_td`]), the anchor of a
//! method's section ([`method_anchor`]) and images with their dimensions ([`figure`]). Every
//! link is relative to DIR; the tables are plain HTML (readable without JavaScript);
//! `report.js` only adds sorting and the viewer.

/// Escapes text for HTML content and double- or single-quoted attribute values.
pub fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            _ => o.push(c),
        }
    }
    o
}

/// A number for a table cell: (the sort key in `data-v`, the text shown). `None` is "n/a"
/// (does not apply, or null in the job's JSON) with an empty key; non-finite values are shown as
/// `inf`, `-inf`, `NaN` (keys `Infinity`, `-Infinity`, `NaN`, which JavaScript's `Number`
/// parses).
pub fn number(x: Option<f64>) -> (String, String) {
    let Some(x) = x else {
        return (String::new(), "n/a".into());
    };
    if x.is_nan() {
        return ("NaN".into(), "NaN".into());
    }
    if x.is_infinite() {
        let s = if x > 0.0 { "" } else { "-" };
        return (format!("{s}Infinity"), format!("{s}inf"));
    }
    let text = if x == x.trunc() && x.abs() < 1e9 {
        format!("{x:.0}")
    } else if (1e-3..1e5).contains(&x.abs()) {
        let digits = (3 - x.abs().log10().floor() as i32).clamp(0, 6) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    };
    (format!("{x:e}"), text)
}

pub(crate) fn num_td(x: Option<f64>) -> String {
    let (k, t) = number(x);
    let class = match t.as_str() {
        "n/a" => " class=\"na\"",
        "inf" | "-inf" | "NaN" => " class=\"nonfinite\"",
        _ => "",
    };
    format!("<td data-v=\"{}\"{class}>{}</td>", esc(&k), esc(&t))
}

/// The HTML id of a method's section in a scene. Every id of a scene starts with `scene-`,
/// every id of the stress section with `stress-`, so no scene name can collide with another id.
pub fn method_anchor(scene: &str, method: &str) -> String {
    format!("scene-{scene}--{method}")
}

/// Dimensions of an image (by its path relative to DIR), when readable.
pub type Dims<'a> = &'a dyn Fn(&str) -> Option<(u32, u32)>;

fn img(src: &str, alt: &str, class: &str, dims: Dims) -> String {
    let size = dims(src)
        .map(|(w, h)| format!(" width=\"{w}\" height=\"{h}\""))
        .unwrap_or_default();
    format!(
        "<img src=\"{}\" alt=\"{}\" class=\"{}\"{size} loading=\"lazy\">",
        esc(src),
        esc(alt),
        esc(class)
    )
}

pub(super) fn figure(src: &str, caption: &str, class: &str, dims: Dims) -> String {
    format!(
        "<figure>{}<figcaption>{}</figcaption></figure>",
        img(src, caption, class, dims),
        esc(caption)
    )
}
