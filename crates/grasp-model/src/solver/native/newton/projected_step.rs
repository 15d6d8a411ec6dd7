//! The Newton step when every finger's compliance is the FFT operator: the free directions of
//! all fingers and the equality rows solved at once by projected preconditioned conjugate
//! gradients (Gould, Hribar and Nocedal, "On the solution of equality constrained quadratic
//! programming problems arising in optimization", SIAM J. Sci. Comput. 23, 2001, algorithm
//! II with residual update), one operator product per finger and iteration.
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
use crate::solver::native::parallel_vectors::{dot, each_chunk, max_abs};

use super::free_operator::FreeOperator;
use super::linearisation::FingerLinearisation;
use super::newton_step::{finish_finger, fixed_part, FingerHalf, Step, StepSpace, SCHUR_CUTOFF};
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

/// A vector of `len` zeros, from `block`'s kept vectors.
fn zeroed(block: &FingerBlockData, len: usize) -> Vec<f64> {
    let mut v = block.work.take(len);
    each_chunk(&mut v, |_, c| c.fill(0.0));
    v
}

fn dot_split(a: &Split, b: &Split) -> f64 {
    a.iter().zip(b).map(|(x, y)| dot(x, y)).sum()
}

/// `x <- x + alpha y`, per finger.
fn add_scaled(x: &mut Split, alpha: f64, y: &Split) {
    for (xi, yi) in x.iter_mut().zip(y) {
        each_chunk(xi, |s, c| {
            c.iter_mut()
                .zip(&yi[s..])
                .for_each(|(a, b)| *a += alpha * b)
        });
    }
}

impl<'a> Projected<'a> {
    /// The projection at `lins`, its operators made in the storage of `spare` (the last
    /// step's).
    fn new(
        blocks: &'a [FingerBlockData],
        lins: &[FingerLinearisation],
        m: usize,
        spare: Vec<FreeOperator>,
    ) -> Self {
        let mut spare = spare.into_iter();
        let ops: Vec<FreeOperator> = blocks
            .iter()
            .zip(lins)
            .map(|(b, l)| FreeOperator::reusing(b, &l.free, spare.next().unwrap_or_default()))
            .collect();
        let et: Vec<_> = blocks
            .iter()
            .zip(lins)
            .map(|(b, l)| FreeOperator::equality_columns(b, &l.free))
            .collect();
        let y: Vec<Vec<Vec<f64>>> = (0..ops.len())
            .map(|i| {
                let cols = &et[i];
                cols.iter()
                    .map(|col| {
                        let mut out = zeroed(&blocks[i], col.len());
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

    /// `f(i, out_i)` for every finger `i`, the fingers on all cores when there are several
    /// (each finger's arithmetic is the same on any thread: the result does not depend on the
    /// threads).
    fn per_finger(&self, out: &mut Split, f: impl Fn(usize, &mut [f64]) + Sync + Send) {
        if self.ops.len() > 1 {
            use rayon::prelude::*;
            out.par_iter_mut().enumerate().for_each(|(i, o)| f(i, o));
        } else {
            out.iter_mut().enumerate().for_each(|(i, o)| f(i, o));
        }
    }

    /// `z = G^-1 v`.
    fn precondition(&self, v: &Split, z: &mut Split) {
        self.per_finger(z, |i, z| {
            self.ops[i].precondition(&self.blocks[i], &v[i], z)
        });
    }

    /// `out = M v`.
    fn apply(&self, v: &Split, out: &mut Split) {
        self.per_finger(out, |i, o| self.ops[i].apply(&self.blocks[i], &v[i], o));
    }

    /// Zero vectors, one per finger, from the fingers' kept vectors.
    fn zeros(&self) -> Split {
        (self.blocks.iter().zip(&self.ops))
            .map(|(b, o)| zeroed(b, o.len()))
            .collect()
    }

    /// Keeps the vectors of `v` for the fingers' next use (this step's or the next one's).
    fn keep(&self, v: Split) {
        self.blocks.iter().zip(v).for_each(|(b, x)| b.work.give(x));
    }

    /// Keeps the step's columns (`Et'` and `G^-1 Et'`) for the next step, and hands back
    /// its operators (whose storage the next step's reuse).
    fn keep_columns(self) -> Vec<FreeOperator> {
        for (b, (et, y)) in self.blocks.iter().zip(self.et.into_iter().zip(self.y)) {
            et.into_iter().chain(y).for_each(|c| b.work.give(c));
        }
        self.ops
    }

    /// `out += scale cols w` per finger (`cols`: `et` or `y`), in one pass.
    fn add_columns(cols: &[Vec<Vec<f64>>], w: &DVector<f64>, scale: f64, out: &mut Split) {
        for (c, o) in cols.iter().zip(out.iter_mut()) {
            each_chunk(o, |s, chunk| {
                for (col, &wr) in c.iter().zip(w.iter()).filter(|(_, wr)| **wr != 0.0) {
                    let f = scale * wr;
                    chunk
                        .iter_mut()
                        .zip(&col[s..])
                        .for_each(|(x, v)| *x += f * v);
                }
            });
        }
    }

    /// Projects the residual `v` in place (`v <- v - A' w`), writes `g = G^-1 v` and returns
    /// `w`.
    fn project(&self, v: &mut Split, g: &mut Split) -> DVector<f64> {
        self.precondition(v, g);
        let w = &self.k_plus * self.a_times(g);
        Self::add_columns(&self.et, &w, -1.0, v);
        Self::add_columns(&self.y, &w, -1.0, g);
        w
    }

    /// `xi_0 = G^-1 A' K^+ c`.
    fn particular(&self, c: &DVector<f64>) -> Split {
        let w = &self.k_plus * c;
        let mut xi = self.zeros();
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

/// Where projected conjugate gradients stop: when the projected residual falls to `relative`
/// of its start, or its largest entry to `floor` (force units of the scaled program, 0 for
/// none).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CgStop {
    /// Relative accuracy (of the residual's start).
    pub relative: f64,
    /// Absolute floor of the residual's largest entry.
    pub floor: f64,
}

/// Projected conjugate gradients from `xi`, until the projected residual falls to
/// `stop.relative` of its start or its largest entry to `stop.floor`: returns `xi` and `dlambda`
/// (`None` when the residual did not fall to [`CG_ACCEPTABLE`] of its start (or `relative`
/// when that is larger) or to `floor`, or is not finite) and the iterations. The vectors are
/// allocated once, before the iterations.
fn solve(
    p: &Projected,
    r: &Split,
    mut xi: Split,
    stop: CgStop,
) -> (Option<(Split, DVector<f64>)>, u32) {
    let CgStop { relative, floor } = stop;
    let mut res = p.zeros();
    p.apply(&xi, &mut res);
    add_scaled(&mut res, -1.0, r);
    let (mut g, mut g_new, mut md) = (p.zeros(), p.zeros(), p.zeros());
    let mut lambda = p.project(&mut res, &mut g);
    let mut rg = dot_split(&res, &g);
    if !rg.is_finite() {
        return (None, 0);
    }
    let start = rg.max(0.0).sqrt();
    let mut d = p.zeros();
    for (di, gi) in d.iter_mut().zip(&g) {
        each_chunk(di, |s, c| {
            c.iter_mut().zip(&gi[s..]).for_each(|(x, y)| *x = -y)
        });
    }
    let n: usize = xi.iter().map(Vec::len).sum();
    let max = CG_ITERATIONS_PER_ROOT * ((n as f64).sqrt().ceil() as usize).max(1);
    let mut its = 0;
    let small = |res: &Split| res.iter().all(|v| max_abs(v) <= floor);
    let mut below_floor = small(&res);
    while rg.max(0.0).sqrt() > relative * start && !below_floor && its < max {
        its += 1;
        p.apply(&d, &mut md);
        let dmd = dot_split(&d, &md);
        if dmd.is_nan() || dmd <= 0.0 {
            break;
        }
        let alpha = rg / dmd;
        add_scaled(&mut xi, alpha, &d);
        add_scaled(&mut res, alpha, &md);
        lambda += p.project(&mut res, &mut g_new);
        let rg_new = dot_split(&res, &g_new);
        if !rg_new.is_finite() {
            return (None, its as u32);
        }
        below_floor = small(&res);
        let beta = rg_new / rg;
        std::mem::swap(&mut g, &mut g_new);
        rg = rg_new;
        for (di, gi) in d.iter_mut().zip(&g) {
            each_chunk(di, |s, c| {
                c.iter_mut()
                    .zip(&gi[s..])
                    .for_each(|(x, y)| *x = -y + beta * *x)
            });
        }
    }
    [res, g, g_new, md, d].into_iter().for_each(|v| p.keep(v));
    let reached = rg.max(0.0).sqrt();
    let enough = CG_ACCEPTABLE.max(relative) * start;
    let converged = reached.is_finite() && (reached <= enough || below_floor);
    let done = converged || start == 0.0;
    (done.then(|| (xi, -lambda)), its as u32)
}

/// The Newton step at the linearisations `lins` (one per finger, every finger an FFT one)
/// with equality residual `e_res = E x - e`, its free rows solved to `relative` (at least
/// [`CG_TOLERANCE`]) of their start or to `floor` (force units of the scaled program, 0 for
/// none): an inexact Newton step when `relative` is above [`CG_TOLERANCE`]. `None` when the
/// conjugate gradients fail. The step and its operators are made in the storage `space`
/// keeps (the last step's), and the operators left there for the next.
pub(crate) fn projected_step(
    blocks: &[FingerBlockData],
    lins: &[FingerLinearisation],
    e_res: &[f64],
    space: &mut StepSpace,
    counts: &mut Counts,
    stop: CgStop,
) -> Option<Step> {
    let m = e_res.len();
    let mut halves: Vec<FingerHalf> = blocks
        .iter()
        .zip(lins)
        .map(|(b, l)| fixed_part(b, l))
        .collect();
    let mut rhs = DVector::from_column_slice(e_res);
    for h in &halves {
        rhs += DVector::from_column_slice(&h.e_z);
    }
    let p = Projected::new(blocks, lins, m, std::mem::take(&mut space.ops));
    counts.factorisations += blocks.len() as u32;
    let unreachable = &p.k_null * &rhs;
    let xi0 = p.particular(&(-&rhs));
    let r: Split = halves
        .iter_mut()
        .map(|h| std::mem::take(&mut h.g))
        .collect();
    let stop = CgStop {
        relative: stop.relative.max(CG_TOLERANCE),
        ..stop
    };
    let (solved, its) = solve(&p, &r, xi0, stop);
    p.keep(r);
    counts.inner_iterations += its;
    let Some((xi, dlambda)) = solved else {
        space.ops = p.keep_columns();
        return None;
    };
    let mut step = Step::reusing(space.step.take(), space.unknowns, &dlambda, &unreachable);
    for (((block, lin), half), x) in blocks.iter().zip(lins).zip(halves).zip(&xi) {
        finish_finger(block, lin, half.z, x, &mut step);
    }
    p.keep(xi);
    space.ops = p.keep_columns();
    Some(step)
}
