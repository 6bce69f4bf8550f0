//! The papers' claims as one matrix: each claim (method and text, its citation a link to the
//! report's formulas page) against each place that measured it (lavapipe bench per scene, the
//! software engine per scene, stress), each verdict linked to its measurement.
//!
//! The merge rule ([`merge`]): where every place that gave a claim a verdict gives the same one
//! (at least two places), the row shows one cell spanning from the first of those places to the
//! last, saying so, with a link to each measurement; otherwise one cell per place. A place that
//! did not measure the claim, or judged it `not_checked`, gives no verdict: it is never counted
//! as agreeing, and never stops the others from agreeing.
use std::fmt::Write as _;

use super::super::html::esc;
use crate::method::Verdict;

/// Where a claim was measured: an engine (`lavapipe`, `software`, `stress`) and, for the
/// engines that measure per scene, the scene's id.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Place {
    pub engine: String,
    pub scene: Option<String>,
}

impl Place {
    /// Its column heading: `engine: scene`, or the engine alone.
    pub fn name(&self) -> String {
        match &self.scene {
            Some(s) => format!("{}: {s}", self.engine),
            None => self.engine.clone(),
        }
    }
}

/// One claim as measured in one place.
#[derive(Debug, Clone)]
pub struct Measured {
    pub method: String,
    /// The claim's text, citations as `docs/formulas.md#<anchor>`.
    pub claim: String,
    pub place: Place,
    pub verdict: Verdict,
    /// What the verdict rests on: "proven <= x, found y", "found y" or "measured".
    pub basis: String,
    /// Its measurement: the claim's row on the page (`#id`) or a file of the report.
    pub link: String,
    /// What was measured, in words (the link's title).
    pub detail: String,
}

/// One merged cell of a row: every place in `counted` gave `verdict`; the cell spans the
/// place columns `first..=last` (places in between that gave no verdict are named in it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Merge {
    pub verdict: Verdict,
    pub first: usize,
    pub last: usize,
    pub counted: Vec<usize>,
}

/// The verdicts of `place` (one per measurement made there) that are verdicts on the claim:
/// `not_checked` says the measurement was not made.
fn counted_verdicts(place: &[Verdict]) -> impl Iterator<Item = Verdict> + '_ {
    place.iter().copied().filter(|v| *v != Verdict::NotChecked)
}

/// The merge rule on one row, the verdicts of each place column (a place measures a claim once
/// or more, e.g. by frame time and by isolated cost; none where it did not measure it): a
/// [`Merge`] when at least two places gave a verdict and every verdict given is the same, else
/// `None`. A place whose verdicts are all `not_checked`, or which has none, is not counted.
pub fn merge(places: &[Vec<Verdict>]) -> Option<Merge> {
    let counted: Vec<usize> = (0..places.len())
        .filter(|&k| counted_verdicts(&places[k]).next().is_some())
        .collect();
    let verdict = counted_verdicts(&places[*counted.first()?]).next()?;
    let same = counted
        .iter()
        .all(|&k| counted_verdicts(&places[k]).all(|v| v == verdict));
    (counted.len() >= 2 && same).then(|| Merge {
        verdict,
        first: counted[0],
        last: counted[counted.len() - 1],
        counted,
    })
}

/// "lavapipe x6, software x1, stress": the places of `places` per engine, in column order, the
/// count after each engine that measures per scene.
fn engines_counted(places: &[&Place]) -> String {
    let mut groups: Vec<(&str, bool, usize)> = Vec::new();
    for p in places {
        match groups.iter_mut().find(|g| g.0 == p.engine) {
            Some(g) => g.2 += 1,
            None => groups.push((&p.engine, p.scene.is_some(), 1)),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(e, per_scene, n)| match (per_scene, n) {
            (false, 1) => e.to_string(),
            _ => format!("{e} x{n}"),
        })
        .collect();
    parts.join(", ")
}

/// The measurements of one row, per place column (none where the place did not measure it).
type Row<'a> = Vec<Vec<&'a Measured>>;

/// The links to `place`'s measurements: the scene (or "its row") for the first, `(2)`, `(3)`
/// for the others; each with its basis when `basis`, and its figures as the title.
fn links(place: &Place, at: &[&Measured], basis: bool) -> String {
    let mut h = String::new();
    for (n, x) in at.iter().enumerate() {
        let text = match n {
            0 => place.scene.clone().unwrap_or_else(|| "its row".into()),
            n => format!("({})", n + 1),
        };
        let _ = write!(
            h,
            "{}<a href=\"{}\" title=\"{}\">{}</a>",
            if n == 0 { "" } else { " " },
            esc(&x.link),
            esc(&format!("{}: {} ({})", place.name(), x.verdict, x.detail)),
            esc(&text)
        );
        if basis {
            let _ = write!(h, " <small>{}</small>", esc(&x.basis));
        }
    }
    h
}

/// The merged cell of `row` under `m`: the verdict, how many places and which, the basis when
/// every measurement has the same, the places inside the span that gave no verdict, and a link
/// to every measurement.
fn merged_cell(places: &[Place], row: &Row, m: &Merge) -> String {
    let counted: Vec<&Place> = m.counted.iter().map(|&k| &places[k]).collect();
    let v = m.verdict.as_str();
    let mut h = format!(
        "<td class=\"verdict merged v-{v}\" colspan=\"{}\" data-verdict=\"{v}\" \
         data-places=\"{}\"><span class=\"all\">{v} in {} places that measured it ({})</span>",
        m.last - m.first + 1,
        m.counted.len(),
        match m.counted.len() {
            2 => "both".to_string(),
            n => format!("all {n}"),
        },
        esc(&engines_counted(&counted))
    );
    let every = || m.counted.iter().flat_map(|&k| row[k].iter());
    let basis = every().next().map_or("", |x| x.basis.as_str());
    let one_basis = every().all(|x| x.basis == basis);
    if one_basis {
        let _ = write!(h, " <small>{}</small>", esc(basis));
    }
    let gap: Vec<usize> = (m.first..=m.last)
        .filter(|k| !m.counted.contains(k))
        .collect();
    let unmeasured: Vec<&Place> = gap
        .iter()
        .filter(|&&k| row[k].is_empty())
        .map(|&k| &places[k])
        .collect();
    if !unmeasured.is_empty() {
        let _ = write!(
            h,
            " <span class=\"gap\">not measured by {}</span>",
            esc(&engines_counted(&unmeasured))
        );
    }
    h += "<span class=\"links\">";
    let mut engine = "";
    for &k in &m.counted {
        let p = &places[k];
        if p.engine != engine {
            let sep = if engine.is_empty() { "" } else { "; " };
            let _ = write!(h, "{sep}{}: ", esc(&p.engine));
            engine = &p.engine;
        } else {
            h += ", ";
        }
        h += &links(p, &row[k], !one_basis);
    }
    for &k in gap.iter().filter(|&&k| !row[k].is_empty()) {
        let _ = write!(h, "; not checked: {}", links(&places[k], &row[k], false));
    }
    h + "</span></td>"
}

/// One place's cell: each of its verdicts on the claim linked to its measurement, with its
/// basis; `-` where the place did not measure the claim. `data-verdict` lists the verdicts.
fn place_cell(place: &Place, at: &[&Measured]) -> String {
    let p = esc(&place.name());
    if at.is_empty() {
        return format!("<td class=\"na\" data-place=\"{p}\">-</td>");
    }
    let verdicts: Vec<&str> = at.iter().map(|x| x.verdict.as_str()).collect();
    let class = match verdicts.iter().all(|v| *v == verdicts[0]) {
        true => verdicts[0],
        false => "mixed",
    };
    let mut h = format!(
        "<td class=\"verdict v-{class}\" data-verdict=\"{}\" data-place=\"{p}\">",
        verdicts.join(" ")
    );
    for x in at {
        let _ = write!(
            h,
            "<span class=\"one v-{v}\"><a href=\"{}\" title=\"{}\">{v}</a> <small>{}</small></span>",
            esc(&x.link),
            esc(&x.detail),
            esc(&x.basis),
            v = x.verdict.as_str()
        );
    }
    h + "</td>"
}

/// The claims of `measured` as one matrix section: a row per claim (method and text) in
/// method order, a column per place in order of first appearance.
pub fn matrix(measured: &[Measured]) -> String {
    let mut places: Vec<Place> = Vec::new();
    let mut claims: Vec<(&str, &str)> = Vec::new();
    for x in measured {
        if !places.contains(&x.place) {
            places.push(x.place.clone());
        }
        if !claims.contains(&(x.method.as_str(), x.claim.as_str())) {
            claims.push((&x.method, &x.claim));
        }
    }
    claims.sort();
    let mut h = String::from(
        "<section id=\"claims\"><h2>The papers' claims</h2><p>Each claim against each place \
         that measured it; the claim's citation links to its source on the formulas page. Where \
         every place that gave a verdict gives the same one, one cell says so and links to each \
         measurement; otherwise each place's verdicts (one per measure, e.g. frame time and \
         isolated cost) link to their measurement (the claim's row, with what was measured and \
         the rule), with the basis: proven (a proven upper bound beside the value found), found \
         (the worst sampled value only) or measured (not a bound). The table scrolls sideways; \
         the claims stay in view.</p><div class=\"scroll\"><table class=\"matrix\" \
         id=\"claims-matrix\"><thead><tr><th class=\"claim\">claim (method)</th>",
    );
    for p in &places {
        // a line break may fall after `:` or `_`, never inside a word
        let name = esc(&p.name()).replace('_', "_<wbr>");
        let _ = write!(h, "<th class=\"place\">{name}</th>");
    }
    h += "</tr></thead><tbody>";
    for (method, claim) in claims {
        let row: Row = places
            .iter()
            .map(|p| {
                measured
                    .iter()
                    .filter(|x| x.place == *p && x.method == method && x.claim == claim)
                    .collect()
            })
            .collect();
        let _ = write!(
            h,
            "<tr data-method=\"{}\" data-claim=\"{}\"><th scope=\"row\" class=\"claim\">\
             <code class=\"method\">{}</code> {}</th>",
            esc(method),
            esc(claim),
            esc(method),
            super::super::formulas::cite(claim)
        );
        let verdicts: Vec<Vec<Verdict>> = row
            .iter()
            .map(|at| at.iter().map(|x| x.verdict).collect())
            .collect();
        let (first, last) = match merge(&verdicts) {
            Some(m) => {
                let cell = merged_cell(&places, &row, &m);
                (m.first, Some((m.last, cell)))
            }
            None => (places.len(), None),
        };
        for k in 0..first {
            h += &place_cell(&places[k], &row[k]);
        }
        if let Some((last, cell)) = last {
            h += &cell;
            for k in last + 1..places.len() {
                h += &place_cell(&places[k], &row[k]);
            }
        }
        h += "</tr>";
    }
    h + "</tbody></table></div></section>"
}

#[cfg(test)]
mod tests {
    use super::*;
    use Verdict::*;

    fn merged(v: &[&[Verdict]]) -> Option<(Verdict, usize, usize, usize)> {
        let places: Vec<Vec<Verdict>> = v.iter().map(|p| p.to_vec()).collect();
        merge(&places).map(|m| (m.verdict, m.first, m.last, m.counted.len()))
    }

    #[test]
    fn the_merge_rule_counts_only_places_with_a_verdict() {
        // every place agrees: one merged cell over all of them
        assert_eq!(
            merged(&[&[Agrees], &[Agrees], &[Agrees]]),
            Some((Agrees, 0, 2, 3))
        );
        // counter-example: one place differs, no merge
        assert_eq!(merged(&[&[Agrees], &[Inconclusive], &[Agrees]]), None);
        // nor when one measurement of a place differs from its other one
        assert_eq!(merged(&[&[Agrees], &[Agrees, Inconclusive]]), None);
        assert_eq!(
            merged(&[&[Agrees], &[Agrees, Agrees]]),
            Some((Agrees, 0, 1, 2))
        );
        // places without a verdict are not counted, and do not stop the merge
        let gaps: [&[Verdict]; 6] = [&[], &[Partly], &[], &[Partly], &[NotChecked], &[]];
        assert_eq!(merged(&gaps), Some((Partly, 1, 3, 2)));
        assert_eq!(
            merged(&[&[Disagrees, NotChecked], &[Disagrees]]),
            Some((Disagrees, 0, 1, 2))
        );
        // counter-example: a place without a verdict is not counted as agreeing, so one
        // verdict alone is not a merge, nor is none
        assert_eq!(merged(&[&[Agrees], &[], &[NotChecked]]), None);
        assert_eq!(merged(&[&[], &[]]), None);
        assert_eq!(merged(&[]), None);
        // every kind of verdict merges, and differs from every other
        for a in [Agrees, Partly, Disagrees, Inconclusive] {
            assert_eq!(merged(&[&[a], &[a]]), Some((a, 0, 1, 2)));
            for b in [Agrees, Partly, Disagrees, Inconclusive] {
                assert_eq!(merged(&[&[a], &[b]]).is_some(), a == b);
            }
        }
    }

    fn at(engine: &str, scene: Option<&str>, claim: &str, v: Verdict, link: &str) -> Measured {
        Measured {
            method: "m".into(),
            claim: claim.into(),
            place: Place {
                engine: engine.into(),
                scene: scene.map(String::from),
            },
            verdict: v,
            basis: "measured".into(),
            link: link.into(),
            detail: "figures".into(),
        }
    }

    /// The `<tr>` of `claim` in `html`.
    fn row<'a>(html: &'a str, claim: &str) -> &'a str {
        let i = html
            .find(&format!("data-claim=\"{}\"", esc(claim)))
            .unwrap();
        &html[i..i + html[i..].find("</tr>").unwrap()]
    }

    #[test]
    fn the_matrix_merges_agreeing_rows_and_keeps_every_link() {
        let c = "fast (docs/formulas.md#exact-phong)";
        let d = "exact";
        let rows = vec![
            at("lavapipe", Some("a"), c, Agrees, "#ca"),
            at("lavapipe", Some("b"), c, Agrees, "#cb"),
            at("lavapipe", Some("b"), c, Agrees, "#cb2"),
            at("stress", None, c, Agrees, "#cs"),
            at("lavapipe", Some("a"), d, Agrees, "#da"),
            at("lavapipe", Some("b"), d, Disagrees, "#db"),
        ];
        let h = matrix(&rows);
        let (merged, split) = (row(&h, c), row(&h, d));
        assert!(
            merged.contains("colspan=\"3\"")
                && merged.contains("agrees in all 3 places that measured it (lavapipe x2, stress)"),
            "{merged}"
        );
        for link in ["#ca", "#cb", "#cb2", "#cs"] {
            assert!(merged.contains(&format!("href=\"{link}\"")), "{merged}");
        }
        assert!(
            merged.contains("<a href=\"formulas.html#exact-phong\">"),
            "{merged}"
        );
        // counter-example: the row whose places differ has a cell per place, the stress
        // column `-`
        assert!(!split.contains("colspan"), "{split}");
        assert_eq!(split.matches("data-verdict=").count(), 2, "{split}");
        assert!(
            split.contains("<td class=\"na\" data-place=\"stress\">"),
            "{split}"
        );
    }

    #[test]
    fn a_merged_cell_names_the_places_inside_it_that_gave_no_verdict() {
        let rows = vec![
            at("lavapipe", Some("a"), "c", Partly, "#a"),
            at("software", Some("a"), "c", NotChecked, "a.md"),
            at("software", Some("b"), "other", Agrees, "b.md"),
            at("stress", None, "c", Partly, "#s"),
        ];
        let h = matrix(&rows);
        let r = row(&h, "c");
        assert!(r.contains("colspan=\"4\""), "{r}");
        assert!(
            r.contains("partly in both places that measured it (lavapipe x1, stress)"),
            "{r}"
        );
        assert!(r.contains("not measured by software x1"), "{r}");
        assert!(r.contains("not checked: <a href=\"a.md\""), "{r}");
        // a place whose measurements differ shows each, under one cell
        let mixed = matrix(&[
            at("lavapipe", Some("a"), "c", Agrees, "#1"),
            at("lavapipe", Some("a"), "c", Inconclusive, "#2"),
            at("software", Some("a"), "c", Agrees, "#3"),
        ]);
        let r = row(&mixed, "c");
        assert!(!r.contains("colspan"), "{r}");
        assert!(r.contains("data-verdict=\"agrees inconclusive\""), "{r}");
    }
}
