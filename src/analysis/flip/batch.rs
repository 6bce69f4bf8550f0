//! One output row of FLIP at a time, in passes over the row: the arithmetic between the libm
//! calls runs over contiguous arrays (struct of arrays, no call per pixel, so LLVM vectorises
//! it), and the libm calls (`powf`: the three cube roots of a side, the three powers of a FLIP
//! value) run as tight scalar loops over the wanted pixels only.
//!
//! Every pixel goes through exactly the operations of nv-flip's per-pixel code in the same
//! order ([`super::kernel`]'s `side_at` and `flip_value`, kept as the tests' oracle): only the
//! order of the loops changes (pass by pass over the row instead of pixel by pixel), and a
//! vector `add`/`mul`/`div`/`sqrt`/`max`/`min` rounds each lane exactly as the scalar
//! instruction does (no FMA: Rust never contracts `a * b + c`). A pass over the row's computed
//! columns also computes the pixels that are not wanted (in a needed block); their values are
//! never read, and the libm passes skip them.

use std::ops::Range;

use super::color::{
    clamp01, mat, Params, DELTA_CUBE, FACTOR, GPT, GQC, GQF, ILLUMINANT, INV_ILLUMINANT,
    RGB_TO_XYZ, TERM, XYZ_TO_RGB,
};

/// One output row's sides over the filtered area's columns (index `i`: image column
/// `area.x0 + i`), struct of arrays, with the scratch rows of the passes.
pub(crate) struct SideRow {
    /// The column ranges whose vertical sums were computed (the needed blocks, clipped to the
    /// area's width): the vector passes run over these.
    pub(crate) spans: Vec<Range<usize>>,
    /// The wanted columns, as ascending disjoint runs, all within `spans`: the libm passes
    /// run over these, column by column.
    pub(crate) wanted: Vec<Range<usize>>,
    /// Lab after Hunt, edge and point value of each column (valid at the wanted ones).
    pub(crate) lab: [Vec<f32>; 3],
    pub(crate) edge: Vec<f32>,
    pub(crate) point: Vec<f32>,
    /// Scratch: XYZ over the illuminant, then its cube roots (sides); HyAB distance, feature
    /// base, colour and feature power (FLIP values).
    scratch: [Vec<f32>; 6],
}

impl SideRow {
    /// A row `n` columns wide.
    pub(crate) fn new(n: usize) -> SideRow {
        let row = || vec![0.0f32; n];
        SideRow {
            spans: Vec::new(),
            wanted: Vec::new(),
            lab: [row(), row(), row()],
            edge: row(),
            point: row(),
            scratch: [(); 6].map(|_| row()),
        }
    }

    /// The row's sides from the vertical sums `acc` (YCx x, y, Cz x, y, dx, ddx, dy, ddy) over
    /// `spans`: `side_at` of every wanted column.
    pub(crate) fn compute(&mut self, acc: &[Vec<f32>; 8]) {
        let [v0, v1, v2, c0, c1, c2] = &mut self.scratch;
        for s in &self.spans {
            let n = s.len();
            let a: [&[f32]; 8] = std::array::from_fn(|c| &acc[c][s.clone()][..n]);
            let (v0, v1, v2) = (&mut v0[s.clone()], &mut v1[s.clone()], &mut v2[s.clone()]);
            let (edge, point) = (&mut self.edge[s.clone()], &mut self.point[s.clone()]);
            to_lab_input([v0, v1, v2], a, [edge, point]);
        }
        // the cube roots, wanted pixels only (libm)
        let third = std::hint::black_box(1.0f32 / 3.0);
        for (v, c) in [(&*v0, &mut *c0), (&*v1, &mut *c1), (&*v2, &mut *c2)] {
            for run in &self.wanted {
                for i in run.clone() {
                    if v[i] > DELTA_CUBE {
                        c[i] = v[i].powf(third);
                    }
                }
            }
        }
        for s in &self.spans {
            let v = [&v0[s.clone()], &v1[s.clone()], &v2[s.clone()]];
            let c = [&c0[s.clone()], &c1[s.clone()], &c2[s.clone()]];
            let [l0, l1, l2] = &mut self.lab;
            lab_hunt(
                v,
                c,
                [&mut l0[s.clone()], &mut l1[s.clone()], &mut l2[s.clone()]],
            );
        }
    }

    /// The row's FLIP values against the reference's `sides` from pixel `at` on (the row's
    /// first column): `flip_value` of every wanted column, written to `map[i]`.
    pub(crate) fn flip(&mut self, p: &Params, reference: &SidePlanes, at: usize, map: &mut [f32]) {
        let [hy, base, color, feature, _, _] = &mut self.scratch;
        for s in &self.spans {
            let r = s.start + at..s.end + at;
            let ref_lab = [0, 1, 2].map(|c| &reference.lab[c][r.clone()]);
            let test_lab = [0, 1, 2].map(|c| &self.lab[c][s.clone()]);
            let features = [
                &reference.edge[r.clone()],
                &reference.point[r.clone()],
                &self.edge[s.clone()],
                &self.point[s.clone()],
            ];
            distances(
                ref_lab,
                test_lab,
                features,
                &mut hy[s.clone()],
                &mut base[s.clone()],
            );
        }
        // the exponents hidden from the optimiser, as in `flip_value`: `powf(x, 0.5)` must stay
        // glibc's powf, not become sqrt
        let (gqc, gqf) = (std::hint::black_box(GQC), std::hint::black_box(GQF));
        for run in &self.wanted {
            for i in run.clone() {
                color[i] = hy[i].powf(gqc);
                feature[i] = base[i].powf(gqf);
            }
        }
        for s in &self.spans {
            rescale(p, &mut color[s.clone()]);
        }
        for run in &self.wanted {
            for i in run.clone() {
                map[i] = color[i].powf(1.0 - feature[i]);
            }
        }
    }
}

/// Per pixel, `side_at` up to `xyz_to_lab`'s cube roots: YCxCz to XYZ to linear RGB, clamped,
/// to XYZ over the illuminant (`v`); and the edge and point values.
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn to_lab_input(v: [&mut [f32]; 3], a: [&[f32]; 8], [edge, point]: [&mut [f32]; 2]) {
    let [v0, v1, v2] = v;
    let n = v0.len();
    let (v1, v2, edge, point) = (&mut v1[..n], &mut v2[..n], &mut edge[..n], &mut point[..n]);
    let a = a.map(|a| &a[..n]);
    for k in 0..n {
        // color3::YCxCz2XYZ
        let yy = (a[0][k] + 16.0) / 116.0;
        let (cx, cz) = (a[1][k] / 500.0, (a[2][k] + a[3][k]) / 200.0);
        let xyz = [
            (yy + cx) * ILLUMINANT[0],
            yy * ILLUMINANT[1],
            (yy - cz) * ILLUMINANT[2],
        ];
        let m = mat(&XYZ_TO_RGB, xyz);
        let rgb = [clamp01(m[0]), clamp01(m[1]), clamp01(m[2])];
        let xyz = mat(&RGB_TO_XYZ, rgb);
        v0[k] = xyz[0] * INV_ILLUMINANT[0];
        v1[k] = xyz[1] * INV_ILLUMINANT[1];
        v2[k] = xyz[2] * INV_ILLUMINANT[2];
        let (dx, ddx, dy, ddy) = (a[4][k], a[5][k], a[6][k], a[7][k]);
        edge[k] = (dx * dx + dy * dy).sqrt();
        point[k] = (ddx * ddx + ddy * ddy).sqrt();
    }
}

/// Per pixel, the rest of `xyz_to_lab` (the cube root `c` where `v > DELTA_CUBE`, else the
/// linear part) and `hunt`.
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn lab_hunt(v: [&[f32]; 3], c: [&[f32]; 3], lab: [&mut [f32]; 3]) {
    let [l0, l1, l2] = lab;
    let n = l0.len();
    let (l1, l2) = (&mut l1[..n], &mut l2[..n]);
    let (v, c) = (v.map(|v| &v[..n]), c.map(|c| &c[..n]));
    for k in 0..n {
        // both branches read, one chosen: a select LLVM vectorises (the values are the same)
        let f = |j: usize| {
            let (v, c) = (v[j][k], c[j][k]);
            let linear = FACTOR * v + TERM;
            if v > DELTA_CUBE {
                c
            } else {
                linear
            }
        };
        let (f0, f1, f2) = (f(0), f(1), f(2));
        let lab = [116.0 * f1 - 16.0, 500.0 * (f0 - f1), 200.0 * (f1 - f2)];
        l0[k] = lab[0];
        l1[k] = 0.01 * lab[0] * lab[1];
        l2[k] = 0.01 * lab[0] * lab[2];
    }
}

/// Per pixel, `flip_value`'s HyAB distance of the two Labs and the base of the feature power.
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn distances(
    r: [&[f32]; 3],
    t: [&[f32]; 3],
    features: [&[f32]; 4],
    hy: &mut [f32],
    base: &mut [f32],
) {
    let n = hy.len();
    let base = &mut base[..n];
    let (r, t, f) = (
        r.map(|v| &v[..n]),
        t.map(|v| &v[..n]),
        features.map(|v| &v[..n]),
    );
    let normalization = 1.0 / 2.0f32.sqrt();
    for k in 0..n {
        let (da, db) = (r[1][k] - t[1][k], r[2][k] - t[2][k]);
        hy[k] = (r[0][k] - t[0][k]).abs() + (da * da + db * db).sqrt();
        let edge = (f[0][k] - f[2][k]).abs();
        let point = (f[1][k] - f[3][k]).abs();
        base[k] = normalization * if edge > point { edge } else { point };
    }
}

/// Per pixel, `flip_value`'s mapping of the colour difference's power to [0, 1].
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn rescale(p: &Params, color: &mut [f32]) {
    for c in color {
        *c = if *c < p.pccmax {
            *c * (GPT / p.pccmax)
        } else {
            GPT + ((*c - p.pccmax) / (p.cmax - p.pccmax)) * (1.0 - GPT)
        };
    }
}

/// The reference's sides over the whole image, struct of arrays (row-major planes).
pub(crate) struct SidePlanes {
    pub(crate) lab: [Vec<f32>; 3],
    pub(crate) edge: Vec<f32>,
    pub(crate) point: Vec<f32>,
}

impl SidePlanes {
    /// Planes of `n` pixels.
    pub(crate) fn new(n: usize) -> SidePlanes {
        let plane = || vec![0.0f32; n];
        SidePlanes {
            lab: [plane(), plane(), plane()],
            edge: plane(),
            point: plane(),
        }
    }

    /// Stores the first `n` columns of `row` at pixel `at` on.
    pub(crate) fn store(&mut self, at: usize, n: usize, row: &SideRow) {
        for (p, r) in self.lab.iter_mut().zip(&row.lab) {
            p[at..at + n].copy_from_slice(&r[..n]);
        }
        self.edge[at..at + n].copy_from_slice(&row.edge[..n]);
        self.point[at..at + n].copy_from_slice(&row.point[..n]);
    }
}

#[cfg(test)]
mod tests {
    use super::super::color::{flip_value, side_at, Side};
    use super::*;

    /// Vertical sums as the filters give them: Y from below black to above white (both sides
    /// of `DELTA_CUBE` after the clamp), chroma of both signs, small feature sums.
    fn sums(rng: &mut fastrand::Rng, n: usize) -> [Vec<f32>; 8] {
        std::array::from_fn(|c| {
            (0..n)
                .map(|_| match c {
                    0 => rng.f32() * 130.0 - 20.0,
                    1..=3 => (rng.f32() - 0.5) * 120.0,
                    _ => (rng.f32() - 0.5) * 0.6,
                })
                .collect()
        })
    }

    fn side_bits(s: &Side) -> [u32; 5] {
        [s.lab[0], s.lab[1], s.lab[2], s.edge, s.point].map(f32::to_bits)
    }

    /// The batched row (sides, then FLIP values against a reference row) against the
    /// per-pixel oracle `side_at` / `flip_value`, bit for bit at every wanted column; returns
    /// the first column that differs.
    fn first_difference(
        acc: &[Vec<f32>; 8],
        oracle_acc: &[Vec<f32>; 8],
        reference_acc: &[Vec<f32>; 8],
        spans: &[Range<usize>],
        wanted: &[usize],
    ) -> Option<usize> {
        let p = Params::new(67.0);
        let n = acc[0].len();
        let mut reference = SidePlanes::new(n + 5);
        let mut row = SideRow::new(n);
        row.spans.push(0..n);
        row.wanted.push(0..n);
        row.compute(reference_acc);
        reference.store(5, n, &row);
        row.spans = spans.to_vec();
        row.wanted = as_runs(wanted);
        row.compute(acc);
        let mut map = vec![f32::NAN; n];
        row.flip(&p, &reference, 5, &mut map);
        wanted.iter().copied().find(|&i| {
            let (t, r) = (side_at(oracle_acc, i), side_at(reference_acc, i));
            let got = Side {
                lab: [row.lab[0][i], row.lab[1][i], row.lab[2][i]],
                edge: row.edge[i],
                point: row.point[i],
            };
            side_bits(&got) != side_bits(&t) || map[i].to_bits() != flip_value(&p, &r, &t).to_bits()
        })
    }

    /// Ascending columns as runs of consecutive ones.
    fn as_runs(columns: &[usize]) -> Vec<Range<usize>> {
        let mut runs: Vec<Range<usize>> = Vec::new();
        for &i in columns {
            match runs.last_mut() {
                Some(r) if r.end == i => r.end += 1,
                _ => runs.push(i..i + 1),
            }
        }
        runs
    }

    /// Random sums over rows of several widths, spans with gaps and a random subset of their
    /// columns wanted: the batched passes give the oracle's bits. Teeth: one feature sum
    /// 0.01 off at a wanted column is found.
    #[test]
    fn batched_rows_are_the_per_pixel_code_bit_for_bit() {
        let mut rng = fastrand::Rng::with_seed(28);
        for n in [1usize, 7, 32, 33, 100, 300] {
            for share in [0.2, 0.7, 1.0] {
                let acc = sums(&mut rng, n);
                let reference_acc = sums(&mut rng, n);
                let spans = if n > 40 {
                    vec![0..5, 12..32, 35..n - 1]
                } else {
                    std::iter::once(0..n.min(3)).collect()
                };
                let wanted: Vec<usize> = spans
                    .iter()
                    .flat_map(|s| s.clone())
                    .filter(|_| rng.f64() < share)
                    .collect();
                let diff = first_difference(&acc, &acc, &reference_acc, &spans, &wanted);
                assert_eq!(diff, None, "{n} columns, share {share}");
                if let Some(&i) = wanted.get(wanted.len() / 2) {
                    let mut off = acc.clone();
                    off[4][i] += 0.01;
                    let diff = first_difference(&off, &acc, &reference_acc, &spans, &wanted);
                    assert_eq!(diff, Some(i), "{n} columns, share {share}");
                }
            }
        }
    }
}
