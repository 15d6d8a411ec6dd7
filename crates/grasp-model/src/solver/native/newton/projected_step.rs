//! The Newton step when every finger's compliance is the FFT operator: the free directions of
//! all fingers and the equality rows solved at once by projected preconditioned conjugate
//! gradients (Gould, Hribar and Nocedal, "On the solution of equality constrained quadratic
//! programming problems arising in optimization", SIAM J. Sci. Comput. 23, 2001, algorithm
//! II with residual update), one operator product per finger and iteration (issue 21).
//!
//! The step solves, over the free directions `xi` of all fingers (`M` block diagonal,
//! [`super::free_operator`]; `A = [Et_1 .. Et_k]`, the equality rows over them):
//!
//! ```text
//!   M xi + A' dlambda = r,        A xi = c = -(E x - e) - sum_i E_i z_i
//! ```
//!
//! the system the Schur-complement path ([`super::newton_step`]) solves with `m + 1` solves in
//! `M` per finger and step; here one conjugate-gradient run does it. With `G` the
//! preconditioner and `K = A G^-1 A'` (`m x m`, from `m` preconditioner applications), a
//! residual `v` is projected as `w = K^+ A G^-1 v`, `v <- v - A' w`, `g = G^-1 v`, which keeps
//! the iterates on `A xi = c` from the particular solution `xi_0 = G^-1 A' K^+ c`; the
//! accumulated `w` is `-dlambda`. `K^+` leaves out the eigendirections below
//! [`super::newton_step`]'s cutoff: rows the free directions cannot move, whose part of the
//! right-hand side is reported as unreachable, as the Schur path does.

use nalgebra::{DMatrix, DVector};

use crate::solver::native::finger_block::FingerBlockData;
use crate::solver::native::native_result::Counts;

use super::free_operator::FreeOperator;
use super::linearisation::FingerLinearisation;
use super::newton_step::{finish_finger, fixed_part, FingerHalf, Step, SCHUR_CUTOFF};
use super::reduced_iterative::{CG_ACCEPTABLE, CG_ITERATIONS_PER_ROOT, CG_TOLERANCE};

/// One vector per finger (its free directions).
type Split = Vec<Vec<f64>>;

/// The fingers' free operators, their equality columns and the projection onto `A xi = 0`.
struct Projected<'a> {
    blocks: &'a [FingerBlockData],
    ops: Vec<FreeOperator>,
    /// Per finger, `Et'` as columns (one per equality row).
    et: Vec<Vec<Vec<f64>>>,
    /// Per finger, `G^-1 Et'` as columns.
    y: Vec<Vec<Vec<f64>>>,
    /// `K^+` over the kept eigendirections, and the projector onto the others.
    k_plus: DMatrix<f64>,
    k_null: DMatrix<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn dot_split(a: &Split, b: &Split) -> f64 {
    a.iter().zip(b).map(|(x, y)| dot(x, y)).sum()
}

impl<'a> Projected<'a> {
    fn new(blocks: &'a [FingerBlockData], lins: &[FingerLinearisation], m: usize) -> Self {
        let ops: Vec<FreeOperator> = blocks
            .iter()
            .zip(lins)
            .map(|(b, l)| FreeOperator::new(b, &l.free))
            .collect();
        let et: Vec<_> = ops
            .iter()
            .zip(blocks)
            .map(|(o, b)| o.equality_columns(b))
            .collect();
        let y: Vec<Vec<Vec<f64>>> = (0..ops.len())
            .map(|i| {
                let cols = &et[i];
                cols.iter()
                    .map(|col| {
                        let mut out = vec![0.0; col.len()];
                        if col.iter().any(|v| *v != 0.0) {
                            ops[i].precondition(&blocks[i], col, &mut out);
                        }
                        out
                    })
                    .collect()
            })
            .collect();
        let k = DMatrix::from_fn(m, m, |r, c| {
            (0..ops.len())
                .map(|i| dot(&et[i][r], &y[i][c]))
                .sum::<f64>()
        });
        let (k_plus, k_null) = pseudo_inverse((&k + k.transpose()) * 0.5);
        Projected {
            blocks,
            ops,
            et,
            y,
            k_plus,
            k_null,
        }
    }

    /// `A v` (length `m`).
    fn a_times(&self, v: &Split) -> DVector<f64> {
        let m = self.k_plus.nrows();
        DVector::from_fn(m, |r, _| {
            self.et
                .iter()
                .zip(v)
                .map(|(e, vi)| dot(&e[r], vi))
                .sum::<f64>()
        })
    }

    /// `f(i)` for every finger `i`, the fingers on all cores when there are several (each
    /// finger's arithmetic is the same on any thread: the result does not depend on the
    /// threads).
    fn per_finger(&self, f: impl Fn(usize) -> Vec<f64> + Sync + Send) -> Split {
        if self.ops.len() > 1 {
            use rayon::prelude::*;
            (0..self.ops.len()).into_par_iter().map(f).collect()
        } else {
            (0..self.ops.len()).map(f).collect()
        }
    }

    /// `G^-1 v`.
    fn precondition(&self, v: &Split) -> Split {
        self.per_finger(|i| {
            let mut z = vec![0.0; v[i].len()];
            self.ops[i].precondition(&self.blocks[i], &v[i], &mut z);
            z
        })
    }

    /// `M v`.
    fn apply(&self, v: &Split) -> Split {
        self.per_finger(|i| {
            let mut out = vec![0.0; v[i].len()];
            self.ops[i].apply(&self.blocks[i], &v[i], &mut out);
            out
        })
    }

    /// `out += cols w` per finger (`cols`: `et` or `y`).
    fn add_columns(cols: &[Vec<Vec<f64>>], w: &DVector<f64>, scale: f64, out: &mut Split) {
        for (c, o) in cols.iter().zip(out.iter_mut()) {
            for (col, &wr) in c.iter().zip(w.iter()) {
                if wr != 0.0 {
                    for (x, v) in o.iter_mut().zip(col) {
                        *x += scale * wr * v;
                    }
                }
            }
        }
    }

    /// Projects the residual `v` in place (`v <- v - A' w`) and returns `g = G^-1 v` and `w`.
    fn project(&self, v: &mut Split) -> (Split, DVector<f64>) {
        let mut g = self.precondition(v);
        let w = &self.k_plus * self.a_times(&g);
        Self::add_columns(&self.et, &w, -1.0, v);
        Self::add_columns(&self.y, &w, -1.0, &mut g);
        (g, w)
    }

    /// `xi_0 = G^-1 A' K^+ c`.
    fn particular(&self, c: &DVector<f64>) -> Split {
        let w = &self.k_plus * c;
        let mut xi: Split = self.ops.iter().map(|o| vec![0.0; o.len()]).collect();
        Self::add_columns(&self.y, &w, 1.0, &mut xi);
        xi
    }
}

/// `K^+` over the eigendirections above [`SCHUR_CUTOFF`] of the largest eigenvalue, and the
/// projector onto the others.
fn pseudo_inverse(k: DMatrix<f64>) -> (DMatrix<f64>, DMatrix<f64>) {
    let m = k.nrows();
    let mut plus = DMatrix::zeros(m, m);
    let mut null = DMatrix::zeros(m, m);
    if m == 0 {
        return (plus, null);
    }
    let eig = nalgebra::SymmetricEigen::new(k);
    let lmax = eig.eigenvalues.iter().cloned().fold(0.0_f64, f64::max);
    for j in 0..m {
        let (l, u) = (eig.eigenvalues[j], eig.eigenvectors.column(j));
        if lmax > 0.0 && l > SCHUR_CUTOFF * lmax {
            plus += u * u.transpose() / l;
        } else {
            null += u * u.transpose();
        }
    }
    (plus, null)
}

/// Projected conjugate gradients from `xi`, until the projected residual falls to
/// [`CG_TOLERANCE`] of its start or its largest entry to `floor`: returns `xi` and `dlambda`
/// (`None` when the residual did not fall to [`CG_ACCEPTABLE`] of its start or to `floor`, or
/// is not finite) and the iterations.
fn solve(
    p: &Projected,
    r: &Split,
    mut xi: Split,
    floor: f64,
) -> (Option<(Split, DVector<f64>)>, u32) {
    let mut res = p.apply(&xi);
    for (v, ri) in res.iter_mut().zip(r) {
        for (x, b) in v.iter_mut().zip(ri) {
            *x -= b;
        }
    }
    let (mut g, mut lambda) = p.project(&mut res);
    let mut rg = dot_split(&res, &g);
    if !rg.is_finite() {
        return (None, 0);
    }
    let start = rg.max(0.0).sqrt();
    let mut d: Split = g.iter().map(|v| v.iter().map(|x| -x).collect()).collect();
    let n: usize = xi.iter().map(Vec::len).sum();
    let max = CG_ITERATIONS_PER_ROOT * ((n as f64).sqrt().ceil() as usize).max(1);
    let mut its = 0;
    let small = |res: &Split| res.iter().flatten().all(|v| v.abs() <= floor);
    let mut below_floor = small(&res);
    while rg.max(0.0).sqrt() > CG_TOLERANCE * start && !below_floor && its < max {
        its += 1;
        let md = p.apply(&d);
        let dmd = dot_split(&d, &md);
        if dmd.is_nan() || dmd <= 0.0 {
            break;
        }
        let alpha = rg / dmd;
        for i in 0..xi.len() {
            for a in 0..xi[i].len() {
                xi[i][a] += alpha * d[i][a];
                res[i][a] += alpha * md[i][a];
            }
        }
        let (g_new, w) = p.project(&mut res);
        lambda += w;
        let rg_new = dot_split(&res, &g_new);
        if !rg_new.is_finite() {
            return (None, its as u32);
        }
        below_floor = small(&res);
        let beta = rg_new / rg;
        (g, rg) = (g_new, rg_new);
        for (di, gi) in d.iter_mut().zip(&g) {
            for (x, y) in di.iter_mut().zip(gi) {
                *x = -y + beta * *x;
            }
        }
    }
    let reached = rg.max(0.0).sqrt();
    let converged = reached.is_finite() && (reached <= CG_ACCEPTABLE * start || below_floor);
    let done = converged || start == 0.0;
    (done.then(|| (xi, -lambda)), its as u32)
}

/// The Newton step at the linearisations `lins` (one per finger, every finger an FFT one)
/// with equality residual `e_res = E x - e`, its free rows solved to [`CG_TOLERANCE`] of
/// their start or to `floor` (force units of the scaled program, 0 for none). `None` when
/// the conjugate gradients fail.
pub(crate) fn projected_step(
    blocks: &[FingerBlockData],
    lins: &[FingerLinearisation],
    e_res: &[f64],
    n: usize,
    counts: &mut Counts,
    floor: f64,
) -> Option<Step> {
    let m = e_res.len();
    let halves: Vec<FingerHalf> = blocks
        .iter()
        .zip(lins)
        .map(|(b, l)| fixed_part(b, l))
        .collect();
    let mut rhs = DVector::from_column_slice(e_res);
    for h in &halves {
        rhs += DVector::from_column_slice(&h.e_z);
    }
    let p = Projected::new(blocks, lins, m);
    counts.factorisations += blocks.len() as u32;
    let unreachable = &p.k_null * &rhs;
    let xi0 = p.particular(&(-&rhs));
    let r: Split = halves.iter().map(|h| h.g.clone()).collect();
    let (solved, its) = solve(&p, &r, xi0, floor);
    counts.inner_iterations += its;
    let (xi, dlambda) = solved?;
    let mut step = Step::new(n, &dlambda, &unreachable);
    for (((block, lin), half), x) in blocks.iter().zip(lins).zip(halves).zip(&xi) {
        finish_finger(block, lin, half.z, x, &mut step);
    }
    Some(step)
}
