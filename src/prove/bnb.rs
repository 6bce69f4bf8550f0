//! Branch-and-bound over a box of inputs: the box with the largest proven upper bound is split
//! in two along its widest side (measured against the root's), each half bounded again and a
//! real point inside it evaluated, until the largest upper bound is within the tolerance of the
//! best value found at a real point, or the boxes or seconds it may spend run out. Every box ever
//! bounded counts in `boxes`.
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::time::Instant;

use super::interval::Interval;

/// An absolute allowance below which upper and found count as equal (fractions; far below any
/// float32 rounding): a metric that is exactly 0 (a scalar method's angle error) is proven
/// within tolerance when its bound is <= this.
pub const ATOL: f64 = 1e-12;

/// A box of the domain: (angle between the vertex normals in degrees, position t along the
/// edge from N0 to N1, weight s of the third corner).
pub type Cell = [Interval; 3];

/// A point of the domain (theta degrees, t, s).
pub type Point = [f64; 3];

/// How hard a branch-and-bound searches: its stopping rule, and the boxes and seconds it may
/// spend (its effort; the error budgets are what its results are judged against).
#[derive(Debug, Clone, Copy)]
pub struct Effort {
    /// Stop when upper <= found * (1 + tolerance) + atol.
    pub tolerance: f64,
    /// The absolute allowance ([`ATOL`] for a reported metric).
    pub atol: f64,
    pub max_boxes: usize,
    pub max_seconds: f64,
}

/// What a branch-and-bound proved and found.
#[derive(Debug, Clone, Copy)]
pub struct Outcome {
    /// No point of the root box has a larger value (NaN never: an unbounded box gives +inf).
    pub proven_upper: f64,
    /// The largest value at a real point (a lower bound of the maximum); NaN when a real point
    /// gave a non-finite value.
    pub found: f64,
    /// Where `found` was reached.
    pub found_at: Option<Point>,
    pub boxes: usize,
    pub seconds: f64,
    /// Stopped by the tolerance (false: by its effort's limit).
    pub converged: bool,
}

impl Outcome {
    /// `proven_upper - found`.
    pub fn gap(&self) -> f64 {
        self.proven_upper - self.found
    }

    /// The gap relative to `found` (0 when both are within [`ATOL`] of 0).
    pub fn relative_gap(&self) -> f64 {
        if self.gap() <= ATOL {
            0.0
        } else {
            self.gap() / self.found
        }
    }
}

struct Entry {
    upper: f64,
    cell: Cell,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.upper.total_cmp(&o.upper) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        self.upper.total_cmp(&o.upper)
    }
}

/// An upper bound as a number the heap can order: NaN (nothing proven) is +inf.
fn bounded(u: f64) -> f64 {
    if u.is_nan() {
        f64::INFINITY
    } else {
        u
    }
}

/// The centre of a cell and, for the angle, its upper end (the worst case of most methods
/// grows with the angle).
fn probes(c: &Cell) -> [Point; 2] {
    let mid = [c[0].mid(), c[1].mid(), c[2].mid()];
    [mid, [c[0].hi, mid[1], mid[2]]]
}

/// The best real point so far.
struct Best {
    found: f64,
    at: Option<Point>,
    non_finite: bool,
}

impl Default for Best {
    fn default() -> Self {
        Best {
            found: f64::NEG_INFINITY,
            at: None,
            non_finite: false,
        }
    }
}

impl Best {
    /// Evaluates `p`; a non-finite value is kept (it ends the search: a failure, never "no
    /// error").
    fn try_point(&mut self, p: &Point, value: &impl Fn(&Point) -> Option<f64>) {
        if self.non_finite {
            return;
        }
        if let Some(v) = value(p) {
            if !v.is_finite() {
                self.non_finite = true;
                self.at = Some(*p);
            } else if v > self.found {
                self.found = v;
                self.at = Some(*p);
            }
        }
    }
}

/// Maximises over `root`: `upper(cell)` bounds the value over a cell, `value(point)` is the
/// value at a real point (None: the point is not one the method can be evaluated at).
pub fn maximise(
    root: Cell,
    effort: Effort,
    upper: impl Fn(&Cell) -> f64,
    value: impl Fn(&Point) -> Option<f64>,
) -> Outcome {
    let start = Instant::now();
    let scale = root.map(|i| if i.width() > 0.0 { i.width() } else { 1.0 });
    let mut best = Best::default();
    let mut heap = BinaryHeap::new();
    heap.push(Entry {
        upper: bounded(upper(&root)),
        cell: root,
    });
    for p in probes(&root) {
        best.try_point(&p, &value);
    }
    let mut boxes = 1;
    let (proven_upper, converged) = loop {
        let top = heap.pop().expect("the heap holds the root's pieces");
        if best.non_finite {
            break (f64::INFINITY, true);
        }
        if top.upper <= best.found.max(0.0) * (1.0 + effort.tolerance) + effort.atol {
            break (top.upper, true);
        }
        if boxes >= effort.max_boxes || start.elapsed().as_secs_f64() >= effort.max_seconds {
            break (top.upper, false);
        }
        let axis = (0..3)
            .max_by(|&a, &b| {
                (top.cell[a].width() / scale[a]).total_cmp(&(top.cell[b].width() / scale[b]))
            })
            .unwrap_or(0);
        let (lo, hi) = top.cell[axis].split();
        for half in [lo, hi] {
            let mut cell = top.cell;
            cell[axis] = half;
            boxes += 1;
            for p in probes(&cell) {
                best.try_point(&p, &value);
            }
            heap.push(Entry {
                upper: bounded(upper(&cell)),
                cell,
            });
        }
    };
    Outcome {
        proven_upper,
        found: if best.non_finite {
            f64::NAN
        } else {
            best.found
        },
        found_at: best.at,
        boxes,
        seconds: start.elapsed().as_secs_f64(),
        converged,
    }
}
