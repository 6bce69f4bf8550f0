//! The answer as text: answer.md (the words first, then the cells that differ, then the full
//! grid) and what `shadelab report` prints (the words and the differing cells in a few lines;
//! every cell with `-v`). Both read [`Answer`]; neither decides anything.
use std::fmt::Write as _;

use super::answer::{ratio_text, Answer};
use super::budget::Budget;
use super::summary::CellRef;
use crate::cost::CostModelId;

/// Columns of the terminal text.
const WIDTH: usize = 100;
/// Groups of differing cells the terminal lists before "and N more".
const TERMINAL_GROUPS: usize = 4;

impl Answer {
    /// A cost model's title from its id.
    fn model_title<'a>(&'a self, id: &'a CostModelId) -> &'a str {
        (self.cost_models.iter())
            .find(|m| m.id == *id)
            .map_or(id.as_str(), |m| m.title.as_str())
    }

    /// The differing cells grouped by (answer, cost model), in cell order: "specular_lut under
    /// lavapipe isolated cost, at every budget" reads better than six lines.
    fn differing_groups(&self) -> Vec<String> {
        let mut groups: Vec<(&CellRef, Vec<&Budget>)> = Vec::new();
        for c in &self.summary.differing {
            match groups.iter_mut().find(|(g, _)| {
                g.cost_model == c.cost_model
                    && g.method == c.method
                    && g.nothing_cheaper == c.nothing_cheaper
            }) {
                Some((_, budgets)) => budgets.push(&c.budget),
                None => groups.push((c, vec![&c.budget])),
            }
        }
        groups
            .into_iter()
            .map(|(c, budgets)| {
                let what = if c.nothing_cheaper {
                    "nothing is cheaper than phong_exact".to_string()
                } else {
                    format!("{} is cheaper", c.method)
                };
                let at = if budgets.len() == self.budgets.len() {
                    "at every budget".to_string()
                } else {
                    let labels: Vec<String> = budgets.iter().map(|b| b.label()).collect();
                    format!("at {}", labels.join(", "))
                };
                format!("under {}: {what} {at}", self.model_title(&c.cost_model))
            })
            .collect()
    }

    /// answer.md: the words, the cells that differ from the common answer, then the grid
    /// (budgets x cost models), what each model is, and every cell as a sentence.
    pub fn markdown(&self) -> String {
        let mut s = String::from("# Which method to use\n\n");
        for w in &self.summary.sentences {
            let _ = writeln!(s, "{w}\n");
        }
        let groups = self.differing_groups();
        if !groups.is_empty() {
            let _ = writeln!(
                s,
                "Cells that differ from the common answer ({}):\n",
                self.summary.differing.len()
            );
            for g in &groups {
                let _ = writeln!(s, "- {g}");
            }
            s += "\n";
        }
        let _ = writeln!(
            s,
            "## Every cell\n\nScenes: {}. Errors: {}. Cost: ratio to phong_exact (below 1 is \
             cheaper), interval in brackets; the runner-up below. Schema: \
             docs/answer.schema.json.\n",
            self.scenes.join(", "),
            self.errors_from
        );
        s += "| cost model |";
        for b in &self.budgets {
            let _ = write!(s, " {} |", b.label());
        }
        s += "\n|---|";
        s += &"---|".repeat(self.budgets.len());
        s += "\n";
        for m in &self.cost_models {
            let _ = write!(s, "| {} |", m.title);
            for b in &self.budgets {
                let Some(c) = self.cell(b, &m.id) else {
                    s += " - |";
                    continue;
                };
                let main = if c.nothing_cheaper {
                    "nothing is cheaper than phong_exact".to_string()
                } else {
                    format!(
                        "[{}](index.html#answer-{}-{}) {}",
                        c.answer.method,
                        b.id(),
                        m.id,
                        ratio_text(&c.answer)
                    )
                };
                let second = c.runner_up.as_ref().map_or(String::new(), |r| {
                    format!("<br>then {} {}", r.method, ratio_text(r))
                });
                let bind = c
                    .binding
                    .as_ref()
                    .map_or(String::new(), |k| format!("<br>decided by {}", k.scene));
                let _ = write!(s, " {main}{second}{bind} |");
            }
            s += "\n";
        }
        s += "\n";
        for m in &self.cost_models {
            let _ = writeln!(s, "- **{}** ({:?}): {}", m.title, m.kind, m.description);
        }
        s += "\n";
        for c in &self.cells {
            let _ = writeln!(s, "- {}", c.text);
        }
        s
    }

    /// Every cell as a line (what `shadelab report -v` adds).
    pub fn lines(&self) -> String {
        let mut s = String::new();
        for c in &self.cells {
            let _ = writeln!(s, "answer: {}", c.text);
        }
        s
    }

    /// What `shadelab report` prints: the words, wrapped, and the cells that differ from the
    /// common answer, grouped (at most [`TERMINAL_GROUPS`] groups, then how many more).
    pub fn terminal(&self) -> String {
        let mut s = String::new();
        for w in &self.summary.sentences {
            s += &wrap(w, WIDTH, "  ");
        }
        let groups = self.differing_groups();
        if !groups.is_empty() {
            let _ = writeln!(
                s,
                "  Cells that differ from the common answer ({}):",
                self.summary.differing.len()
            );
            for g in groups.iter().take(TERMINAL_GROUPS) {
                s += &wrap(g, WIDTH, "  - ");
            }
            if groups.len() > TERMINAL_GROUPS {
                let _ = writeln!(
                    s,
                    "  - and {} more (answer.md)",
                    groups.len() - TERMINAL_GROUPS
                );
            }
        }
        s
    }
}

/// `text` in lines of at most `width` columns (a longer word stands alone), the first prefixed
/// by `first`, the others indented as deep.
fn wrap(text: &str, width: usize, first: &str) -> String {
    let indent = " ".repeat(first.chars().count());
    let mut out = String::new();
    let mut line = first.to_string();
    let mut empty = true;
    for word in text.split_whitespace() {
        let len = line.chars().count();
        if !empty && len + 1 + word.chars().count() > width {
            out += line.trim_end();
            out.push('\n');
            line = indent.clone();
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line += word;
        empty = false;
    }
    out += line.trim_end();
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::wrap;

    #[test]
    fn wrap_keeps_lines_within_the_width_and_every_word() {
        let t = "one two three four five six seven eight nine ten eleven twelve";
        let w = wrap(t, 20, "  ");
        assert!(w.lines().all(|l| l.chars().count() <= 20), "{w}");
        assert!(w.lines().count() > 1);
        let words: Vec<&str> = w.split_whitespace().collect();
        assert_eq!(words.join(" "), t);
        // a word longer than the width stands alone rather than being cut
        let long = "x".repeat(30);
        assert_eq!(wrap(&long, 20, "- "), format!("- {long}\n"));
        assert_ne!(wrap(t, 200, ""), w);
    }
}
