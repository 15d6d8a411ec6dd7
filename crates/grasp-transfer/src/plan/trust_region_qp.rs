//! One step of the planner: the quadratic program of the linearised hand-off (Nocedal and
//! Wright, *Numerical Optimization*, 2nd ed., section 18.5, the elastic SL1QP form), solved
//! with Clarabel.
//!
//! Variables `z = [x, T, w, v]`: the keyframe values `x` (a load group's loads, N; an approach
//! group's scaled approaches, [`crate::plan::planned_group`]), the duration `T` (s) and two
//! scalars. With the objective [`Objective::Duration`], `w >= 0` is the largest violation of
//! the slip-margin threshold, and the program minimises `T / T0 + rho w + rho v`; with
//! [`Objective::Margin`], `w` is the smallest linearised slip margin, and the program
//! maximises `w - rho v` at a fixed `T`. `v >= 0` is the largest violation of the
//! disturbance-margin rows (each the margin over its threshold, kept at least 1).
//! Constraints: every slip row `m + g (x - x0) + g_T (T - T0) >= threshold - w` (or `>= w`),
//! every disturbance row `m + g (x - x0) + g_T (T - T0) >= 1 - v`,
//! the fixed end keyframes, the bounds, the trust region `|x - x0| <= radius`, the rates
//! `|x_{k+1} - x_k| <= rate (f_{k+1} - f_k) T` (each group's limit in its variable's units)
//! and the duration's bounds. A small
//! proximal term `eps |x - x0|^2 / L^2` makes the program strictly convex.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

use grasp_model::limits::MAX_FORCE_N;

use crate::plan::keyframe_path::KeyframePath;
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::plan::plan_options::{Objective, PlanOptions};

/// Weight of the violation in the duration objective (per unit of margin, against a duration
/// relative to the current one): above the multipliers of the margin rows, so that a
/// schedule meeting the threshold, when one exists nearby, is preferred to any shorter one.
pub const VIOLATION_WEIGHT: f64 = 100.0;

/// Weight of the proximal term, relative to the load scale squared.
const PROXIMAL: f64 = 1e-3;

/// The next point and the merit the linear model predicts for it.
#[derive(Debug, Clone)]
pub struct QpStep {
    /// Keyframe values, `[group][keyframe]` ([`KeyframePath::values`]).
    pub values: Vec<Vec<f64>>,
    /// Duration, s.
    pub duration_s: f64,
    /// The merit the linearisation predicts at the new point.
    pub predicted_merit: f64,
}

/// Which keyframe loads are fixed (`Some(value)`) and which free.
pub type Pinned = Vec<Vec<Option<f64>>>;

/// The columns of the program's scalars, after the keyframe loads `x`.
#[derive(Debug, Clone, Copy)]
struct Columns {
    /// The duration `T`, s.
    t: usize,
    /// `w`: the largest violation of the slip-margin threshold (duration objective), or the
    /// smallest linearised slip margin (margin objective).
    w: usize,
    /// `v`: the largest violation of the disturbance-margin rows.
    v: usize,
}

/// Rows of `A z + s = b` with `s` in a cone, built one at a time (triplets).
#[derive(Default)]
struct Rows {
    triplets: Vec<(usize, usize, f64)>,
    b: Vec<f64>,
}

impl Rows {
    fn push(&mut self, entries: &[(usize, f64)], b: f64) {
        let r = self.b.len();
        self.triplets
            .extend(entries.iter().map(|&(c, v)| (r, c, v)));
        self.b.push(b);
    }
}

/// The program's step from `path` with its `rows`, in a trust region of `radius_n` (loads
/// of the order of `scale_n`).
pub fn qp_step(
    path: &KeyframePath,
    rows: &[MarginRow],
    pinned: &Pinned,
    options: &PlanOptions,
    radius_n: f64,
    scale_n: f64,
) -> Result<QpStep, String> {
    let (nf, nk) = (path.groups.len(), path.fractions.len());
    let nx = nf * nk;
    let columns = Columns {
        t: nx,
        w: nx + 1,
        v: nx + 2,
    };
    let (t_col, w_col, v_col, n) = (columns.t, columns.w, columns.v, nx + 3);
    let x0: Vec<f64> = path.values.iter().flatten().copied().collect();
    let t0 = path.duration_s;
    let (mut zero, mut nonneg) = (Rows::default(), Rows::default());
    for (j, &x) in x0.iter().enumerate() {
        match pinned[j / nk][j % nk] {
            Some(v) => zero.push(&[(j, 1.0)], v),
            None => {
                let (hi, lo) = group_bounds(path, j / nk, options);
                nonneg.push(&[(j, 1.0)], (x + radius_n).min(hi));
                nonneg.push(&[(j, -1.0)], -(x - radius_n).max(lo));
            }
        }
    }
    duration_rows(&mut zero, &mut nonneg, path, options, t_col);
    rate_rows(&mut nonneg, path, options, radius_n, t_col);
    margin_rows(&mut nonneg, rows, &x0, t0, options, columns);
    match options.objective {
        Objective::Duration => nonneg.push(&[(w_col, -1.0)], 0.0),
        Objective::Margin => nonneg.push(&[(w_col, 1.0)], 1.0),
    }
    nonneg.push(&[(v_col, -1.0)], 0.0);
    let scale = scale_n.max(f64::MIN_POSITIVE);
    let (p, q) = objective(&x0, t0, scale, options.objective, columns);
    let z = solve(n, &p, &q, zero, nonneg)?;
    // The fixed keyframes exactly, the free ones within their bounds; a load within
    // round-off of 0 N is 0 N (released), not a load too small to command.
    let values = (0..nf)
        .map(|i| {
            (0..nk)
                .map(|k| match pinned[i][k] {
                    Some(v) => v,
                    None => {
                        let (hi, lo) = group_bounds(path, i, options);
                        let x = z[i * nk + k].clamp(lo, hi);
                        if x.abs() < 1e-9 * scale {
                            0.0
                        } else {
                            x
                        }
                    }
                })
                .collect()
        })
        .collect();
    let predicted_merit = VIOLATION_WEIGHT * z[v_col].max(0.0)
        + match options.objective {
            Objective::Duration => z[t_col] / t0 + VIOLATION_WEIGHT * z[w_col].max(0.0),
            Objective::Margin => -z[w_col],
        };
    Ok(QpStep {
        values,
        duration_s: z[t_col],
        predicted_merit,
    })
}

/// The objective `z'Pz/2 + q'z` (P as triplets): the proximal term around `(x0, t0)` (loads
/// relative to `scale`), then the duration relative to `t0` plus the weighted violations, or
/// the smallest slip margin negated plus the weighted disturbance violation.
fn objective(
    x0: &[f64],
    t0: f64,
    scale: f64,
    kind: Objective,
    columns: Columns,
) -> (Vec<(usize, usize, f64)>, Vec<f64>) {
    let Columns {
        t: t_col,
        w: w_col,
        v: v_col,
    } = columns;
    let per_load = PROXIMAL / (scale * scale);
    let mut p: Vec<_> = (0..x0.len()).map(|j| (j, j, per_load)).collect();
    p.push((t_col, t_col, PROXIMAL / (t0 * t0)));
    let mut q: Vec<f64> = x0.iter().map(|x| -per_load * x).collect();
    q.resize(v_col + 1, 0.0);
    q[t_col] = -PROXIMAL / t0;
    match kind {
        Objective::Duration => {
            q[t_col] += 1.0 / t0;
            q[w_col] = VIOLATION_WEIGHT;
        }
        Objective::Margin => q[w_col] = -1.0,
    }
    q[v_col] = VIOLATION_WEIGHT;
    (p, q)
}

/// Group `g`'s variable bounds `(largest, smallest)`: every member's load within the
/// options' (and at most the largest force a schedule takes), or its approach within its
/// group's range ([`crate::plan::planned_group::PlannedGroup::bounds`]).
pub fn group_bounds(path: &KeyframePath, g: usize, options: &PlanOptions) -> (f64, f64) {
    path.groups[g].bounds(options.min_load_n, options.max_load_n.min(MAX_FORCE_N))
}

/// The duration: fixed with the margin objective (or fixed bounds), else within its bounds
/// and within half to twice the current one (its own trust region).
fn duration_rows(
    zero: &mut Rows,
    nonneg: &mut Rows,
    path: &KeyframePath,
    options: &PlanOptions,
    t_col: usize,
) {
    let t0 = path.duration_s;
    if options.objective == Objective::Margin {
        zero.push(&[(t_col, 1.0)], t0);
        return;
    }
    nonneg.push(&[(t_col, 1.0)], options.max_duration_s.min(2.0 * t0));
    nonneg.push(&[(t_col, -1.0)], -shortest_in_region(path, options));
}

/// The shortest duration the program may take from `path`, s: half the current one, and no
/// shorter than `PlanOptions::min_duration_s` or what a planned schedule spans
/// ([`KeyframePath::shortest_planned_s`]).
fn shortest_in_region(path: &KeyframePath, options: &PlanOptions) -> f64 {
    (options.min_duration_s.max(0.5 * path.duration_s)).max(path.shortest_planned_s())
}

/// A rate row whose allowed change exceeds the most the loads can change within the trust
/// region by this factor cannot bind; it is left out, so that a rate limit far above the
/// loads' (1e300 N/s) puts no huge coefficient into the program.
const SLACK_RATE_FACTOR: f64 = 1e6;

/// `|x_{k+1} - x_k| <= rate (f_{k+1} - f_k) T` for every planned finger and keyframe span
/// (but those that cannot bind within the trust region of `radius_n`, N: see
/// [`SLACK_RATE_FACTOR`]).
fn rate_rows(
    nonneg: &mut Rows,
    path: &KeyframePath,
    options: &PlanOptions,
    radius_n: f64,
    t_col: usize,
) {
    let limits = options.rate_limits();
    let nk = path.fractions.len();
    let t_lo = match options.objective {
        Objective::Margin => path.duration_s,
        Objective::Duration => shortest_in_region(path, options),
    };
    for (i, group) in path.groups.iter().enumerate() {
        let Some(rate) = group.variable_rate(&limits) else {
            continue;
        };
        for k in 0..nk - 1 {
            let span = rate * (path.fractions[k + 1] - path.fractions[k]);
            let most_n = (path.values[i][k + 1] - path.values[i][k]).abs() + 2.0 * radius_n;
            if span * t_lo > SLACK_RATE_FACTOR * most_n {
                continue;
            }
            let (a, b) = (i * nk + k, i * nk + k + 1);
            nonneg.push(&[(b, 1.0), (a, -1.0), (t_col, -span)], 0.0);
            nonneg.push(&[(b, -1.0), (a, 1.0), (t_col, -span)], 0.0);
        }
    }
}

/// The linearised rows at the keyframe loads `x0` (N) and the duration `t0` (s):
/// `-g x - g_T T - w <= m - g x0 - g_T T0 - threshold` for a slip row (`+ w <= m - ...` with
/// the margin objective), `-g x - g_T T - v <= m - ... - 1` for a disturbance row.
fn margin_rows(
    nonneg: &mut Rows,
    rows: &[MarginRow],
    x0: &[f64],
    t0: f64,
    options: &PlanOptions,
    columns: Columns,
) {
    let Columns {
        t: t_col,
        w: w_col,
        v: v_col,
    } = columns;
    for r in rows {
        let mut entries: Vec<(usize, f64)> = r
            .gradient
            .iter()
            .enumerate()
            .filter(|(_, g)| **g != 0.0)
            .map(|(j, g)| (j, -g))
            .collect();
        entries.push((t_col, -r.per_duration));
        let lin: f64 = r.gradient.iter().zip(x0).map(|(g, x)| g * x).sum::<f64>();
        let constant = r.margin - lin - r.per_duration * t0;
        let (column, sign, threshold) = match (r.kind, options.objective) {
            (RowKind::Disturbance, _) => (v_col, -1.0, 1.0),
            (RowKind::Slip, Objective::Duration) => (w_col, -1.0, options.min_slip_margin),
            (RowKind::Slip, Objective::Margin) => (w_col, 1.0, 0.0),
        };
        entries.push((column, sign));
        nonneg.push(&entries, constant - threshold);
    }
}

/// Solves `min z'Pz/2 + q'z` with `zero` rows equal and `nonneg` rows `<=`.
fn solve(
    n: usize,
    p: &[(usize, usize, f64)],
    q: &[f64],
    zero: Rows,
    nonneg: Rows,
) -> Result<Vec<f64>, String> {
    let (n_zero, n_nonneg) = (zero.b.len(), nonneg.b.len());
    let mut triplets = zero.triplets;
    triplets.extend(nonneg.triplets.iter().map(|&(r, c, v)| (r + n_zero, c, v)));
    let b: Vec<f64> = zero.b.into_iter().chain(nonneg.b).collect();
    let a = csc(n_zero + n_nonneg, n, &triplets);
    let p = csc(n, n, p);
    let cones = [
        SupportedConeT::ZeroConeT(n_zero),
        SupportedConeT::NonnegativeConeT(n_nonneg),
    ];
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .max_iter(200)
        .build()
        .map_err(|e| e.to_string())?;
    let mut solver =
        DefaultSolver::new(&p, q, &a, &b, &cones, settings).map_err(|e| e.to_string())?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(solver.solution.x.clone()),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Err(
            "the bounds, rates and duration admit no schedule (the program is infeasible)".into(),
        ),
        other => Err(format!("the step's program stopped with status {other:?}")),
    }
}

/// A compressed-column matrix from triplets (duplicates summed).
fn csc(m: usize, n: usize, triplets: &[(usize, usize, f64)]) -> CscMatrix<f64> {
    let mut sorted = triplets.to_vec();
    sorted.sort_by_key(|&(r, c, _)| (c, r));
    let (mut colptr, mut rowval, mut nzval) = (vec![0usize; n + 1], Vec::new(), Vec::new());
    let mut last: Option<(usize, usize)> = None;
    for (r, c, v) in sorted {
        if last == Some((r, c)) {
            *nzval.last_mut().expect("a previous entry") += v;
            continue;
        }
        rowval.push(r);
        nzval.push(v);
        colptr[c + 1] += 1;
        last = Some((r, c));
    }
    for c in 0..n {
        colptr[c + 1] += colptr[c];
    }
    CscMatrix::new(m, n, colptr, rowval, nzval)
}
