//! The predictor of a warm start: the last few solutions of a program, with the data they
//! answer, combined affinely to the new data.
//!
//! Between hand-off steps only the program's data change (`q`, the equality right-hand side,
//! the cones' `mu` or Tresca radii). While the contact pattern (which elements stick, slip and
//! separate, and their slip directions) stays the same, the KKT point of the program is an
//! affine function of `q`, the right-hand side and the Tresca radii (not of `mu`, which
//! multiplies the normal forces). So when the new data are an affine combination of remembered
//! data, `now = d_K + sum_j c_j (d_j - d_K)` (a ramp: one direction of change; two fingers
//! ramping on different curves: two), the same combination of the remembered solutions is the
//! new solution itself and the solve needs no Newton step. Any remembered point may enter the
//! combination (a coulomb iterate is an exact solution of its own program too; a Clarabel
//! answer only to its tolerance). Where the pattern changes, or `mu` moves, the prediction is
//! only a guess: the native solver starts from whichever of it and the last solution has the
//! smaller residual, so a prediction never changes an answer, only where the search begins.

use nalgebra::{DMatrix, DVector};

use crate::program::cone_program::ConeProgram;
use crate::solver::iterate::Iterate;

/// Largest departure of the new data from the remembered points' affine hull (relative to the
/// data's change) for which a prediction is made: round-off of the schedule's arithmetic.
const ON_LINE: f64 = 1e-9;

/// Singular values of the remembered changes below this fraction of the largest count as
/// zero.
const RANK_CUTOFF: f64 = 1e-8;

/// Largest combination coefficient used: beyond it the remembered points are nearly
/// dependent and the prediction would amplify their round-off.
const LARGEST_COEFFICIENT: f64 = 1e3;

/// Largest magnitude of the data (and of their changes) a prediction is made from: beyond it
/// the squares in the singular value decomposition could overflow (the program's data are
/// scaled to about 1, so only data that are garbage reach it).
const LARGEST_DATUM: f64 = 1e100;

/// Iterations of the singular value decomposition before it gives up (its matrix has at most
/// `KEPT - 1` columns; it converges in a handful).
const SVD_ITERATIONS: usize = 10_000;

/// The program's data that change between solves: `q`, the equality right-hand side, and
/// each block's `mu` or Tresca radii, in that order.
pub(crate) fn data_of(program: &ConeProgram) -> Vec<f64> {
    let mut d = program.q.clone();
    d.extend_from_slice(&program.equality_rhs);
    for b in &program.blocks {
        b.cone.append_data(&mut d);
    }
    d
}

/// Solutions remembered (the affine hull of `KEPT` points has `KEPT - 1` directions of
/// change).
const KEPT: usize = 4;

/// The last [`KEPT`] solutions and the data each answers, oldest first.
#[derive(Debug, Clone, Default)]
pub(crate) struct Trail {
    points: Vec<(Vec<f64>, Iterate)>,
}

impl Trail {
    /// Records a solution of the program with data `data`.
    pub fn push(&mut self, data: Vec<f64>, solution: Iterate) {
        if self.points.len() == KEPT {
            self.points.remove(0);
        }
        self.points.push((data, solution));
    }

    /// The affine combination of the remembered solutions for data `now`, when `now` lies in
    /// the affine hull of their data (and differs from the newest). The newest two points are
    /// tried first, then the newest three, and so on: the fewer and more recent the points,
    /// the likelier they share the new solution's contact pattern.
    pub fn predict(&self, now: &[f64]) -> Option<Iterate> {
        if self.off_every_hull(now) {
            return None;
        }
        (2..=self.points.len())
            .find_map(|k| combination(&self.points[self.points.len() - k..], now))
    }
}

impl Trail {
    /// True when `now` is off the affine hull of all the remembered points' data, hence off
    /// the hull of every newest few of them (a smaller span leaves a larger residual): one
    /// projection instead of one per candidate ([`projection_residual`]), first on every
    /// [`SAMPLED_ROW`]-th datum only, which refuses almost every off-hull change at an eighth
    /// of the cost.
    fn off_every_hull(&self, now: &[f64]) -> bool {
        let Some(((base, _), rest)) = self.points.split_last() else {
            return true;
        };
        let n = base.len();
        if rest.is_empty() || now.len() != n || rest.iter().any(|(d, _)| d.len() != n) {
            return true;
        }
        let norm = now
            .iter()
            .zip(base)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        let limit = OFF_HULL_MARGIN * ON_LINE * norm;
        let residual_on = |stride: usize| {
            let change = |d: &[f64]| -> Vec<f64> {
                let pairs = d.iter().zip(base).step_by(stride);
                pairs.map(|(a, b)| a - b).collect()
            };
            let columns = rest.iter().map(|(d, _)| change(d)).collect();
            projection_residual(columns, &change(now))
        };
        norm.is_finite() && (residual_on(SAMPLED_ROW) > limit || residual_on(1) > limit)
    }
}

/// The stride of the rows [`Trail::off_every_hull`] projects first. Leaving rows out can
/// only shrink the residual (the same combination fits the rows kept at least as well), so
/// what the sample refuses the whole data refuse too: the decision is the full projection's.
const SAMPLED_ROW: usize = 8;

/// The combination of `points` (newest last) whose data give `now`, if there is one.
fn combination(points: &[(Vec<f64>, Iterate)], now: &[f64]) -> Option<Iterate> {
    let ((dk, sk), rest) = points.split_last()?;
    if !rest.iter().all(|(_, s)| same_layout(s, sk)) {
        return None;
    }
    let others: Vec<&[f64]> = rest.iter().map(|(d, _)| d.as_slice()).collect();
    let c = affine_coefficients(dk, &others, now)?;
    let combine = |pick: fn(&Iterate) -> &Vec<f64>| -> Vec<f64> {
        let others: Vec<&[f64]> = rest.iter().map(|(_, s)| pick(s).as_slice()).collect();
        combine(pick(sk), &others, &c)
    };
    Some(Iterate {
        x: combine(|s| &s.x),
        lambda: combine(|s| &s.lambda),
    })
}

/// Coefficients `c` with `now = base + sum_j c_j (others_j - base)` to [`ON_LINE`] of the
/// change `now - base` (least squares over the directions the points span, dropping those
/// below [`RANK_CUTOFF`]); `None` when `now` is off their affine hull, equals `base`, the
/// lengths differ, a coefficient exceeds [`LARGEST_COEFFICIENT`], or the data are not finite
/// or beyond [`LARGEST_DATUM`] (no prediction: the solve starts from the last solution).
pub(crate) fn affine_coefficients(
    base: &[f64],
    others: &[&[f64]],
    now: &[f64],
) -> Option<Vec<f64>> {
    let n = base.len();
    if others.is_empty() || now.len() != n || others.iter().any(|d| d.len() != n) {
        return None;
    }
    let g = DMatrix::from_fn(n, others.len(), |r, j| others[j][r] - base[r]);
    let rhs = DVector::from_iterator(n, now.iter().zip(base).map(|(a, b)| a - b));
    let usable = |v: &f64| v.abs() <= LARGEST_DATUM;
    if !(g.iter().all(usable) && rhs.iter().all(usable)) {
        return None;
    }
    let norm = rhs.norm();
    if norm == 0.0
        || projection_residual(columns_of(&g), rhs.as_slice()) > OFF_HULL_MARGIN * ON_LINE * norm
    {
        return None;
    }
    decomposition_coefficients(g, &rhs)
}

/// The least-squares coefficients of `g c = rhs` by the singular value decomposition,
/// dropping directions below [`RANK_CUTOFF`]; `None` when the residual exceeds [`ON_LINE`]
/// of `|rhs|` or a coefficient is wild.
fn decomposition_coefficients(g: DMatrix<f64>, rhs: &DVector<f64>) -> Option<Vec<f64>> {
    let norm = rhs.norm();
    let svd = g
        .clone()
        .try_svd(true, true, 5.0 * f64::EPSILON, SVD_ITERATIONS)?;
    let largest = svd.singular_values.max();
    let c = svd.solve(rhs, RANK_CUTOFF * largest).ok()?;
    let off = (&g * &c - rhs).norm();
    let wild = c
        .iter()
        .any(|v| !v.is_finite() || v.abs() > LARGEST_COEFFICIENT);
    (off <= ON_LINE * norm && !wild).then(|| c.iter().copied().collect())
}

/// Factor on [`ON_LINE`] above which [`projection_residual`] alone refuses a prediction:
/// beyond round-off of the projection, which is the smallest residual any combination has
/// (the decomposition's, dropping directions, can only leave more).
const OFF_HULL_MARGIN: f64 = 1.001;

/// The distance of `rhs` from the span of `g`'s columns, by modified Gram-Schmidt with one
/// reorthogonalisation (Golub and Van Loan, section 5.2.8): a few dot products, so that the
/// common case of a margin trial or a change of contact pattern, data off the remembered
/// points' hull, is refused before the singular value decomposition.
fn projection_residual(mut columns: Vec<Vec<f64>>, rhs: &[f64]) -> f64 {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let remove = |v: &mut [f64], basis: &[Vec<f64>]| {
        for _ in 0..2 {
            for b in basis {
                let d = dot(b, v);
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= d * y);
            }
        }
    };
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(columns.len());
    for mut q in columns.drain(..) {
        remove(&mut q, &basis);
        let after = dot(&q, &q).sqrt();
        // Every direction is kept, however small: the span is then at least the one the
        // decomposition keeps, so the residual at most its residual (to round-off).
        if after > 0.0 {
            q.iter_mut().for_each(|x| *x /= after);
            basis.push(q);
        }
    }
    let mut r = rhs.to_vec();
    remove(&mut r, &basis);
    dot(&r, &r).sqrt()
}

/// The columns of `g`.
fn columns_of(g: &DMatrix<f64>) -> Vec<Vec<f64>> {
    g.column_iter()
        .map(|c| c.iter().copied().collect())
        .collect()
}

/// `base + sum_j c_j (others_j - base)`.
pub(crate) fn combine(base: &[f64], others: &[&[f64]], c: &[f64]) -> Vec<f64> {
    let mut out = base.to_vec();
    for (o, cj) in others.iter().zip(c) {
        for ((v, x), b) in out.iter_mut().zip(o.iter()).zip(base) {
            *v += cj * (x - b);
        }
    }
    out
}

fn same_layout(a: &Iterate, b: &Iterate) -> bool {
    a.x.len() == b.x.len() && a.lambda.len() == b.lambda.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic draws uniform in `[-0.5, 0.5)` (xorshift64 from `seed`).
    fn uniform_draws(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    fn it(x: &[f64], l: &[f64]) -> Iterate {
        Iterate {
            x: x.to_vec(),
            lambda: l.to_vec(),
        }
    }

    #[test]
    fn data_moving_along_a_line_extrapolate_the_solution_by_the_same_fraction() {
        let mut t = Trail::default();
        t.push(vec![1.0, 2.0], it(&[10.0, 0.0], &[1.0]));
        t.push(vec![1.0, 3.0], it(&[12.0, 1.0], &[2.0]));
        // Half the last change: half the last change of the solution.
        let p = t.predict(&[1.0, 3.5]).unwrap();
        assert!((p.x[0] - 13.0).abs() < 1e-12 && (p.x[1] - 1.5).abs() < 1e-12);
        assert!((p.lambda[0] - 2.5).abs() < 1e-12);
    }

    #[test]
    fn two_directions_of_change_are_followed_when_three_points_span_them() {
        // The solution is affine in the data: x = A d + b, here x = (d0 + 2 d1, d0 - d1).
        let sol = |d: &[f64]| it(&[d[0] + 2.0 * d[1], d[0] - d[1]], &[d[0]]);
        let mut t = Trail::default();
        for d in [[0.0, 0.0], [1.0, 0.5], [1.5, 2.0]] {
            t.push(d.to_vec(), sol(&d));
        }
        let now = [3.0, 2.5];
        let p = t.predict(&now).unwrap();
        let exact = sol(&now);
        for (a, b) in
            p.x.iter()
                .zip(&exact.x)
                .chain(p.lambda.iter().zip(&exact.lambda))
        {
            assert!((a - b).abs() < 1e-12, "{p:?} vs {exact:?}");
        }
    }

    /// Data that are not finite or beyond any program's (an overflowed load, say) give no
    /// prediction (and no panic of the decomposition), whichever point holds them.
    #[test]
    fn no_prediction_from_data_that_are_not_finite_or_huge() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e305, -1e200] {
            let mut t = Trail::default();
            t.push(vec![1.0, 2.0], it(&[10.0, 0.0], &[1.0]));
            t.push(vec![1.0, 3.0], it(&[12.0, 1.0], &[2.0]));
            assert!(t.predict(&[1.0, bad]).is_none(), "now = {bad}");
            t.push(vec![bad, 4.0], it(&[12.0, 1.0], &[2.0]));
            assert!(t.predict(&[1.0, 5.0]).is_none(), "remembered {bad}");
            assert!(affine_coefficients(&[0.0, bad], &[&[1.0, 1.0]], &[0.5, 0.5]).is_none());
        }
    }

    /// The projection refuses only data the decomposition refuses too: over random changes
    /// (three directions of 40 data, some nearly dependent) and right-hand sides on their
    /// span, off it by 1e-12 to 1e-3 of their size, or near the [`ON_LINE`] threshold, no
    /// case is refused by the projection that the decomposition accepts. Checked against the
    /// decomposition itself (the independent computation), not a recorded answer.
    #[test]
    fn the_projection_refuses_only_what_the_decomposition_refuses() {
        let mut draw = uniform_draws(0x2545_f491_4f6c_dd1d_u64);
        let (mut accepted, mut refused_first) = (0, 0);
        for case in 0..600 {
            let cols = 1 + case % 3;
            let mut g = DMatrix::from_fn(40, cols, |_, _| draw());
            if case % 5 == 0 && cols > 1 {
                let near = g.column(0) * 2.0 + g.column(1).map(|v| v * 1e-9);
                g.set_column(cols - 1, &near);
            }
            let c = DVector::from_fn(cols, |_, _| 4.0 * draw());
            let off = [0.0, 1e-12, 5e-10, 1e-9, 2e-9, 1e-6, 1e-3][case % 7];
            let noise = DVector::from_fn(40, |_, _| draw());
            let on = &g * &c;
            let rhs = &on + noise * (off * on.norm());
            let norm = rhs.norm();
            let by_projection = projection_residual(columns_of(&g), rhs.as_slice())
                > OFF_HULL_MARGIN * ON_LINE * norm;
            let decomposed = decomposition_coefficients(g, &rhs);
            assert!(
                !(by_projection && decomposed.is_some()),
                "case {case}: refused by the projection, accepted by the decomposition"
            );
            accepted += usize::from(decomposed.is_some());
            refused_first += usize::from(by_projection);
        }
        // Both outcomes occur, so the check is not vacuous.
        assert!(
            accepted > 100 && refused_first > 100,
            "{accepted} {refused_first}"
        );
    }

    /// The sampled rows refuse only what all the rows refuse: over random trails (four
    /// points of 40 data) and data on their hull, off it by 1e-12 to 1e-3 of the change, or
    /// near the [`ON_LINE`] threshold, [`Trail::off_every_hull`] decides as the projection of
    /// all the rows alone does (computed here directly), and the sample alone decides most
    /// of the refusals (so the check is not vacuous).
    #[test]
    fn the_sampled_rows_refuse_only_what_all_the_rows_refuse() {
        let mut draw = uniform_draws(0x9e37_79b9_7f4a_7c15_u64);
        let (mut refused, mut by_sample) = (0, 0);
        for case in 0..600 {
            let mut t = Trail::default();
            let points: Vec<Vec<f64>> = (0..KEPT)
                .map(|_| (0..40).map(|_| draw()).collect())
                .collect();
            for p in &points {
                t.push(p.clone(), it(&[0.0], &[]));
            }
            let base = &points[KEPT - 1];
            let c: Vec<f64> = (0..KEPT - 1).map(|_| 4.0 * draw()).collect();
            let others: Vec<&[f64]> = points[..KEPT - 1].iter().map(Vec::as_slice).collect();
            let on = combine(base, &others, &c);
            let change: f64 = on
                .iter()
                .zip(base)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>();
            let off = [0.0, 1e-12, 5e-10, 1e-9, 2e-9, 1e-6, 1e-3][case % 7] * change.sqrt();
            let now: Vec<f64> = on.iter().map(|v| v + off * draw()).collect();
            let columns = others
                .iter()
                .map(|d| d.iter().zip(base).map(|(a, b)| a - b).collect())
                .collect();
            let rhs: Vec<f64> = now.iter().zip(base).map(|(a, b)| a - b).collect();
            let norm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
            let limit = OFF_HULL_MARGIN * ON_LINE * norm;
            let whole = projection_residual(columns, &rhs) > limit;
            assert_eq!(t.off_every_hull(&now), whole, "case {case}");
            let sampled: Vec<Vec<f64>> = others
                .iter()
                .map(|d| {
                    d.iter()
                        .zip(base)
                        .step_by(SAMPLED_ROW)
                        .map(|(a, b)| a - b)
                        .collect()
                })
                .collect();
            let rhs_sampled: Vec<f64> = rhs.iter().step_by(SAMPLED_ROW).copied().collect();
            refused += usize::from(whole);
            by_sample += usize::from(projection_residual(sampled, &rhs_sampled) > limit);
        }
        assert!(refused > 200 && by_sample > 150, "{refused} {by_sample}");
    }

    #[test]
    fn no_prediction_off_the_hull_without_a_change_or_without_history() {
        let mut t = Trail::default();
        assert!(t.predict(&[1.0]).is_none());
        t.push(vec![1.0, 2.0, 0.0], it(&[1.0], &[]));
        assert!(
            t.predict(&[1.0, 3.0, 0.0]).is_none(),
            "one point spans nothing"
        );
        t.push(vec![1.0, 3.0, 0.0], it(&[2.0], &[]));
        assert!(t.predict(&[1.5, 4.0, 0.0]).is_none(), "off the line");
        assert!(
            t.predict(&[1.0, 3.0, 0.0]).is_none(),
            "no change: the last solution is the start"
        );
        assert!(t.predict(&[1.0]).is_none(), "another layout");
        assert!(
            Trail::default().predict(&[1.0, 4.0, 0.0]).is_none(),
            "no history"
        );
    }
}
