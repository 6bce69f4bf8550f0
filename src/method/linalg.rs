//! Small dense linear algebra shared by the fits (Remez exchange in `method::scanline_checks`
//! and `tune::remez`).

/// Gaussian elimination with partial pivoting of an augmented matrix; None when singular.
pub fn gauss(m: &mut [Vec<f64>]) -> Option<Vec<f64>> {
    let n = m.len();
    for c in 0..n {
        let p = (c..n).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        m.swap(c, p);
        if m[c][c] == 0.0 || !m[c][c].is_finite() {
            return None;
        }
        let pivot = m[c].clone();
        for row in m.iter_mut().skip(c + 1) {
            let k = row[c] / pivot[c];
            for (x, p) in row[c..].iter_mut().zip(&pivot[c..]) {
                *x -= k * p;
            }
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|j| m[r][j] * x[j]).sum();
        x[r] = (m[r][n] - s) / m[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}
