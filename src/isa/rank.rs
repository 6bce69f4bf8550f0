//! How the static cost agrees with other measures: Spearman's rank correlation between a
//! family's ranking statistic (AMD: inverse throughput) of one kernel evaluation and
//! lavapipe's isolated cost (bench.json), per family.
use crate::isa::request::RowKind;
use serde::{Deserialize, Serialize};

use super::table::{find_row, Row};
use crate::error::{Error, Result};

/// The measure compared with lavapipe's isolated cost, for a family ranked by `key`.
pub fn measure(key: &str) -> String {
    format!("{key} of one kernel evaluation vs bench.json isolated_ns_per_eval")
}

/// Per family of `families` ((row key, its ranking statistic's key): the compiled ones),
/// Spearman's rho between one kernel evaluation's ranking statistic in `rows` and bench.json's
/// `isolated_ns_per_eval`, over the methods both have.
pub fn against_bench(
    rows: &[Row],
    families: &[(&str, String)],
    bench: &serde_json::Value,
) -> Result<Vec<Correlation>> {
    let methods = bench["methods"].as_array().ok_or_else(|| {
        Error::Usage("--bench: no `methods` list: not a bench.json of `shadelab bench`".into())
    })?;
    let isolated: Vec<(&str, f64)> = methods
        .iter()
        .filter_map(|m| Some((m["name"].as_str()?, m["isolated_ns_per_eval"].as_f64()?)))
        .collect();
    Ok(families
        .iter()
        .map(|&(f, ref key)| {
            let (a, b): (Vec<f64>, Vec<f64>) = isolated
                .iter()
                .filter_map(|&(m, ns)| {
                    let row = find_row(rows, f, m, "compute", RowKind::Evaluation)?;
                    Some((*row.statistics.get(key)?, ns))
                })
                .unzip();
            Correlation {
                family: f.to_string(),
                measure: measure(key),
                methods: a.len(),
                spearman: spearman(&a, &b),
            }
        })
        .collect())
}

/// One family's agreement with lavapipe's isolated cost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Correlation {
    pub family: String,
    /// The static measure compared ("inverse_throughput of one kernel evaluation").
    pub measure: String,
    pub methods: usize,
    /// Spearman's rho over the methods both have; `None` with fewer than 3 methods or a
    /// constant ranking.
    pub spearman: Option<f64>,
}

/// Ranks (1-based) with ties sharing their mean rank.
pub fn ranks(values: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..values.len()).collect();
    idx.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut out = vec![0.0; values.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && values[idx[j + 1]] == values[idx[i]] {
            j += 1;
        }
        let mean = (i + j) as f64 / 2.0 + 1.0;
        for &k in &idx[i..=j] {
            out[k] = mean;
        }
        i = j + 1;
    }
    out
}

/// Spearman's rho: Pearson's correlation of the ranks (ties at mean rank). `None` for fewer
/// than 3 pairs, unequal lengths, a non-finite value, or a constant side.
pub fn spearman(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() != b.len() || a.len() < 3 || a.iter().chain(b).any(|v| !v.is_finite()) {
        return None;
    }
    let (ra, rb) = (ranks(a), ranks(b));
    let n = ra.len() as f64;
    let (ma, mb) = (ra.iter().sum::<f64>() / n, rb.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in ra.iter().zip(&rb) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    if saa == 0.0 || sbb == 0.0 {
        return None;
    }
    Some(sab / (saa * sbb).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_share_ties() {
        assert_eq!(ranks(&[10.0, 30.0, 20.0, 20.0]), vec![1.0, 4.0, 2.5, 2.5]);
    }

    #[test]
    fn spearman_of_monotone_and_reversed() {
        let a = [1.0, 2.0, 3.0, 4.0, 5.0];
        // Monotone but not linear: rho is exactly 1 (Pearson's r would not be).
        let b = [1.0, 4.0, 9.0, 100.0, 1000.0];
        assert_eq!(spearman(&a, &b), Some(1.0));
        let rev: Vec<f64> = b.iter().rev().copied().collect();
        assert_eq!(spearman(&a, &rev), Some(-1.0));
        // Teeth: one swapped pair lowers it: 1 - 6*2/(5*24) = 0.9.
        let swapped = [1.0, 9.0, 4.0, 100.0, 1000.0];
        let r = spearman(&a, &swapped).unwrap();
        assert!((r - 0.9).abs() < 1e-12, "{r}");
    }

    #[test]
    fn spearman_refuses_what_it_cannot_rank() {
        assert_eq!(spearman(&[1.0, 2.0], &[1.0, 2.0]), None);
        assert_eq!(spearman(&[1.0, 2.0, 3.0], &[5.0, 5.0, 5.0]), None);
        assert_eq!(spearman(&[1.0, f64::NAN, 3.0], &[1.0, 2.0, 3.0]), None);
    }
}
