//! The robust path of the native solver: a primal-dual interior-point method (Mehrotra's
//! predictor-corrector with Nesterov-Todd scaling; Vandenberghe 2010, the method of CVXOPT's
//! `coneqp`) on the program written with conic rows ([`super::conic_rows`]):
//!
//! ```text
//!   minimise 1/2 x'Px + q'x   subject to   E x = e,   s = G x + h in K
//! ```
//!
//! KKT: `P x + q + E' lambda - G'z = 0`, `E x = e`, `s = G x + h`, `s o z = 0`, `s, z in K`.
//! With the scaling `W` (`W z = W^-1 s = l`) each Newton system reduces to
//!
//! ```text
//!   (P + G'W^-2 G) dx + E' dlambda = r_x + G'(W^-2 r_s + W^-1 (l \ r_c)),   E dx = r_l
//!   ds = G dx - r_s,   dz = -W^-2 ds + W^-1 (l \ r_c)
//! ```
//!
//! where `G'W^-2 G` adds a `dim x dim` block per element to the finger's compliance block, so
//! each iteration factorises one dense matrix per finger (faer) and an `m x m` Schur complement
//! on the equality rows, as the Newton method does. It needs no active set, so it converges on
//! the grasps where the semismooth Newton iteration wanders (contacts much smaller than their
//! patch, friction exactly used up), at the price of some 10-30 factorisations; its answer is
//! then polished by the semismooth Newton method.

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par};
use nalgebra::{DMatrix, DVector};

use crate::program::cone_program::ConeProgram;
use crate::solver::native::dense_cholesky::cholesky;
use crate::solver::native::finger_block::FingerBlockData;
use crate::solver::native::native_result::{Counts, NativeResult, NativeStatus};

use crate::program::cones::conic_rows::ConicRows;
use crate::program::cones::element_set::ElementSet;
use crate::program::cones::symmetric_cones::{Scaling, SymmetricCone};

/// Interior-point iterations before giving up.
const MAX_ITERATIONS: u32 = 100;
/// Fraction of the step to the boundary taken.
const STEP_FRACTION: f64 = 0.99;

/// The conic rows of the program: per finger, per element, and the list of cones.
struct Layout {
    rows: Vec<Vec<ConicRows>>,
    /// Global row of each element's first conic row.
    offsets: Vec<Vec<usize>>,
    /// Every cone with its global first row.
    cones: Vec<(SymmetricCone, usize)>,
    total: usize,
}

impl Layout {
    fn new(blocks: &[FingerBlockData], program: &ConeProgram) -> Self {
        let (mut rows, mut offsets, mut cones, mut total) = (Vec::new(), Vec::new(), Vec::new(), 0);
        for (b, pb) in blocks.iter().zip(&program.blocks) {
            let (mut r, mut o) = (Vec::new(), Vec::new());
            for k in 0..b.elements {
                let er = pb.cone.element(k).conic_rows(b.dim);
                o.push(total);
                cones.extend(er.cone_rows().map(|(c, row)| (c, total + row)));
                total += er.rows;
                r.push(er);
            }
            rows.push(r);
            offsets.push(o);
        }
        Layout {
            rows,
            offsets,
            cones,
            total,
        }
    }
}

/// The iterate of the interior-point method.
struct Point {
    x: Vec<f64>,
    lambda: Vec<f64>,
    s: Vec<f64>,
    z: Vec<f64>,
}

/// One direction.
struct Direction {
    dx: Vec<f64>,
    dlambda: Vec<f64>,
    ds: Vec<f64>,
    dz: Vec<f64>,
}

impl Direction {
    /// Whether every number of the direction is finite.
    fn is_finite(&self) -> bool {
        let all = [&self.dx, &self.dlambda, &self.ds, &self.dz];
        all.iter().all(|v| v.iter().all(|x| x.is_finite()))
    }
}

/// The factorised Newton matrix of one iteration.
struct Factors {
    l: Vec<Mat<f64>>,
    w: Vec<Mat<f64>>,
    schur: nalgebra::Cholesky<f64, nalgebra::Dyn>,
}

/// The residuals of the interior-point conditions at a point.
struct Residuals {
    /// Of stationarity, `r_x = -(P x + q + E' lambda - G' z)`.
    rx: Vec<f64>,
    /// Of the equality rows, `r_l = e - E x`.
    rl: Vec<f64>,
    /// Of the conic rows, `r_s = s - (G x + h)`.
    rs: Vec<f64>,
}

/// The residuals at a point.
fn residuals(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    lay: &Layout,
    p: &Point,
) -> Residuals {
    let mut rx: Vec<f64> = program.q.iter().map(|v| -v).collect();
    let mut rl = program.equality_rhs.clone();
    let mut rs = p.s.clone();
    for (i, b) in blocks.iter().enumerate() {
        let r = b.offset..b.offset + b.len();
        let mut px = vec![0.0; b.len()];
        b.apply(&p.x[r.clone()], &mut px);
        b.add_equality_transpose(&p.lambda, &mut px);
        let mut ex = vec![0.0; rl.len()];
        b.add_equality(&p.x[r.clone()], &mut ex);
        for (a, v) in rl.iter_mut().zip(ex) {
            *a -= v;
        }
        for k in 0..b.elements {
            let er = &lay.rows[i][k];
            let o = lay.offsets[i][k];
            let gtz = er.transpose(&p.z[o..o + er.rows], b.dim);
            let mut gx = [0.0; 4];
            er.value(b.gather(&p.x[r.clone()], k), b.dim, &mut gx);
            for c in 0..b.dim {
                px[b.index(k, c)] -= gtz[c];
            }
            for j in 0..er.rows {
                rs[o + j] -= gx[j];
            }
        }
        for (a, v) in rx[r].iter_mut().zip(px) {
            *a -= v;
        }
    }
    Residuals { rx, rl, rs }
}

/// `W^-2 u` over one cone's rows.
fn w_inv_sq(sc: &Scaling, u: &[f64], out: &mut [f64]) {
    let mut t = [0.0; 3];
    Scaling::apply(&sc.w_inv, u, &mut t[..u.len()]);
    Scaling::apply(&sc.w_inv, &t[..u.len()], out);
}

/// Factorises `P_i + G'W^-2 G` per finger and the Schur complement.
fn factorise(
    blocks: &[FingerBlockData],
    lay: &Layout,
    scalings: &[Scaling],
    m: usize,
) -> Option<Factors> {
    let mut cone_index = 0;
    let (mut ls, mut ws) = (Vec::new(), Vec::new());
    let mut s = DMatrix::<f64>::zeros(m, m);
    for (i, b) in blocks.iter().enumerate() {
        let mut h = b.matrix()?;
        for k in 0..b.elements {
            let er = &lay.rows[i][k];
            // Columns of W^-2 G over the element's rows.
            let mut wg = [[0.0; 3]; 4];
            for (c, row0) in er.cone_rows() {
                let sc = &scalings[cone_index];
                cone_index += 1;
                for col in 0..b.dim {
                    let u: Vec<f64> = (0..c.dim()).map(|r| er.g[row0 + r][col]).collect();
                    let mut out = [0.0; 3];
                    w_inv_sq(sc, &u, &mut out[..c.dim()]);
                    for (row, &o) in wg[row0..].iter_mut().zip(&out[..c.dim()]) {
                        row[col] = o;
                    }
                }
            }
            for a in 0..b.dim {
                for c in 0..b.dim {
                    let v: f64 = (0..er.rows).map(|r| er.g[r][a] * wg[r][c]).sum();
                    h[(b.index(k, a), b.index(k, c))] += v;
                }
            }
        }
        if !cholesky(h.as_mut()) {
            return None;
        }
        let mut w = b.equality_matrix().transpose().to_owned();
        solve_lower_triangular_in_place(h.as_ref(), w.as_mut(), Par::Seq);
        for r in 0..m {
            for c in 0..=r {
                let v: f64 = w
                    .col(r)
                    .iter()
                    .zip(w.col(c).iter())
                    .map(|(a, b)| a * b)
                    .sum();
                s[(r, c)] += v;
                if c != r {
                    s[(c, r)] += v;
                }
            }
        }
        ls.push(h);
        ws.push(w);
    }
    let schur = s.cholesky()?;
    Some(Factors {
        l: ls,
        w: ws,
        schur,
    })
}

/// Solves the Newton system for the complementarity right-hand side `rc` (per cone rows).
fn solve(
    blocks: &[FingerBlockData],
    lay: &Layout,
    f: &Factors,
    scalings: &[Scaling],
    lam: &[f64],
    res: &Residuals,
    rc: &[f64],
) -> Direction {
    let Residuals { rx, rl, rs } = res;
    let (t, u) = complementarity_terms(lay, scalings, lam, rs, rc);
    let (dx, dlambda) = solve_reduced(blocks, lay, f, &t, rx, rl);
    let ds = slack_direction(blocks, lay, &dx, rs);
    let mut dz = vec![0.0; lay.total];
    for ((c, row), sc) in lay.cones.iter().zip(scalings) {
        let d = c.dim();
        let mut a = [0.0; 3];
        w_inv_sq(sc, &ds[*row..row + d], &mut a[..d]);
        for j in 0..d {
            dz[row + j] = -a[j] + u[row + j];
        }
    }
    Direction {
        dx,
        dlambda,
        ds,
        dz,
    }
}

/// Per cone, `u = W^-1 (l \ rc)` (kept for `dz`) and `t = W^-2 r_s + u`, the conic rows'
/// share of the reduced right-hand side.
fn complementarity_terms(
    lay: &Layout,
    scalings: &[Scaling],
    lam: &[f64],
    rs: &[f64],
    rc: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let mut t = vec![0.0; lay.total];
    let mut u = vec![0.0; lay.total];
    for ((c, row), sc) in lay.cones.iter().zip(scalings) {
        let d = c.dim();
        let mut q = [0.0; 3];
        c.inverse_product(&lam[*row..row + d], &rc[*row..row + d], &mut q[..d]);
        Scaling::apply(&sc.w_inv, &q[..d], &mut u[*row..row + d]);
        let mut a = [0.0; 3];
        w_inv_sq(sc, &rs[*row..row + d], &mut a[..d]);
        for j in 0..d {
            t[row + j] = a[j] + u[row + j];
        }
    }
    (t, u)
}

/// Solves `(P + G'W^-2 G) dx + E' dlambda = r_x + G't`, `E dx = r_l` with the factors: per
/// finger `g_i = L_i^-1 (r_x + G't)_i`, the Schur complement for `dlambda`, then
/// `dx_i = L_i^-T (g_i - W_i dlambda)`. Returns `(dx, dlambda)`.
fn solve_reduced(
    blocks: &[FingerBlockData],
    lay: &Layout,
    f: &Factors,
    t: &[f64],
    rx: &[f64],
    rl: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let m = rl.len();
    let mut dx = rx.to_vec();
    let mut g = Vec::with_capacity(blocks.len());
    let mut rhs = DVector::from_iterator(m, rl.iter().map(|v| -v));
    for (i, b) in blocks.iter().enumerate() {
        for k in 0..b.elements {
            let er = &lay.rows[i][k];
            let o = lay.offsets[i][k];
            let gt = er.transpose(&t[o..o + er.rows], b.dim);
            for c in 0..b.dim {
                dx[b.offset + b.index(k, c)] += gt[c];
            }
        }
        let mut gi = Mat::from_fn(b.len(), 1, |r, _| dx[b.offset + r]);
        solve_lower_triangular_in_place(f.l[i].as_ref(), gi.as_mut(), Par::Seq);
        for r in 0..m {
            rhs[r] += f.w[i]
                .col(r)
                .iter()
                .zip(gi.col(0).iter())
                .map(|(a, b)| a * b)
                .sum::<f64>();
        }
        g.push(gi);
    }
    let dlambda = f.schur.solve(&rhs);
    for (i, b) in blocks.iter().enumerate() {
        let mut xi = g[i].clone();
        for r in 0..b.len() {
            xi[(r, 0)] -= (0..m).map(|c| f.w[i][(r, c)] * dlambda[c]).sum::<f64>();
        }
        solve_upper_triangular_in_place(f.l[i].as_ref().transpose(), xi.as_mut(), Par::Seq);
        for r in 0..b.len() {
            dx[b.offset + r] = xi[(r, 0)];
        }
    }
    (dx, dlambda.iter().copied().collect())
}

/// `ds = G dx - r_s`.
fn slack_direction(blocks: &[FingerBlockData], lay: &Layout, dx: &[f64], rs: &[f64]) -> Vec<f64> {
    let mut ds = vec![0.0; lay.total];
    for (i, b) in blocks.iter().enumerate() {
        for k in 0..b.elements {
            let er = &lay.rows[i][k];
            let o = lay.offsets[i][k];
            let xk = b.gather(&dx[b.offset..b.offset + b.len()], k);
            let mut gx = [0.0; 4];
            er.linear(xk, b.dim, &mut gx);
            for j in 0..er.rows {
                ds[o + j] = gx[j] - rs[o + j];
            }
        }
    }
    ds
}

/// The largest step in `[0, limit]` keeping `s + a ds` and `z + a dz` in the cones.
fn max_step(lay: &Layout, p: &Point, d: &Direction, limit: f64) -> f64 {
    lay.cones.iter().fold(limit, |a, (c, row)| {
        let r = *row..row + c.dim();
        let a = c.step_to_boundary(&p.s[r.clone()], &d.ds[r.clone()], a);
        c.step_to_boundary(&p.z[r.clone()], &d.dz[r], a)
    })
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |a, b| a.max(b.abs()))
}

/// A starting point: `x` from `(P + G'G) x + E' lambda = -q - G'h`, `E x = e`; `s = G x + h`
/// shifted into the cones' interior; `z = e`.
fn start(blocks: &[FingerBlockData], program: &ConeProgram, lay: &Layout) -> Option<Point> {
    let unit: Vec<Scaling> = lay
        .cones
        .iter()
        .map(|(c, _)| {
            let mut e = [0.0; 3];
            c.identity(&mut e[..c.dim()]);
            c.nt_scaling(&e[..c.dim()], &e[..c.dim()])
        })
        .collect();
    let f = factorise(blocks, lay, &unit, program.equality_rows())?;
    let p0 = Point {
        x: vec![0.0; program.n_unknowns],
        lambda: vec![0.0; program.equality_rows()],
        s: vec![0.0; lay.total],
        z: vec![0.0; lay.total],
    };
    // At x = 0, s = 0: r_x = -q, r_l = e, r_s = -h; with W = I, rc = 0 the step solves the
    // least-squares start.
    let res = residuals(blocks, program, lay, &p0);
    let ones: Vec<f64> = lay
        .cones
        .iter()
        .flat_map(|(c, _)| {
            let mut e = [0.0; 3];
            c.identity(&mut e[..c.dim()]);
            e[..c.dim()].to_vec()
        })
        .collect();
    let d = solve(blocks, lay, &f, &unit, &ones, &res, &vec![0.0; lay.total]);
    // s = G x + h: ds = G dx - r_s = G x + h with r_s = -h, so s = ds.
    let mut s = d.ds.clone();
    let shift = lay
        .cones
        .iter()
        .map(|(c, row)| c.margin(&s[*row..row + c.dim()]))
        .fold(f64::INFINITY, f64::min);
    let scale = max_abs(&s).max(1.0);
    for (c, row) in &lay.cones {
        let mut e = [0.0; 3];
        c.identity(&mut e[..c.dim()]);
        let add = if shift < 1e-3 * scale {
            1e-3 * scale - shift
        } else {
            0.0
        };
        for j in 0..c.dim() {
            s[row + j] += add * e[j];
        }
    }
    Some(Point {
        x: d.dx,
        lambda: d.dlambda,
        s,
        z: ones,
    })
}

/// Runs the interior-point method after the work `counts` done so far.
pub(crate) fn run(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    tolerance: f64,
    mut counts: Counts,
) -> NativeResult {
    let lay = Layout::new(blocks, program);
    let nu = lay.cones.len().max(1) as f64;
    let Some(mut p) = start(blocks, program, &lay) else {
        let zero = Point {
            x: vec![0.0; program.n_unknowns],
            lambda: vec![0.0; program.equality_rows()],
            s: vec![],
            z: vec![],
        };
        return stalled(zero, "the interior-point start is singular", counts);
    };
    counts.factorisations += blocks.len() as u32;
    let scale_x = max_abs(&program.q).max(1.0);
    let scale_l = max_abs(&program.equality_rhs).max(1.0);
    for _ in 0..MAX_ITERATIONS {
        let res = residuals(blocks, program, &lay, &p);
        let gap: f64 = p.s.iter().zip(&p.z).map(|(a, b)| a * b).sum();
        let scale_s = max_abs(&p.s).max(1.0);
        if max_abs(&res.rx) <= tolerance * scale_x
            && max_abs(&res.rl) <= tolerance * scale_l
            && max_abs(&res.rs) <= tolerance * scale_s
            && gap <= tolerance * nu * scale_s
        {
            return NativeResult::after(NativeStatus::Converged, p.x, p.lambda, counts);
        }
        if let Err(why) = predictor_corrector(blocks, program, &lay, &mut p, &res, gap, &mut counts)
        {
            return stalled(p, why, counts);
        }
    }
    stalled(p, "the interior-point iteration limit was reached", counts)
}

/// A stall at `p` after the work `counts`, for the reason `why`.
fn stalled(p: Point, why: &str, counts: Counts) -> NativeResult {
    NativeResult::after(
        NativeStatus::Stalled(why.to_string()),
        p.x,
        p.lambda,
        counts,
    )
}

/// One iteration from `p` (residuals `res`, gap `s'z`), counted in `counts`: the NT scalings,
/// the factorisation, the affine (predictor) direction, Mehrotra's centring and the corrector
/// direction, along which `p` moves [`STEP_FRACTION`] of the way to the boundary (at most a
/// full step). `Err` with the reason when the Newton matrix cannot be factorised, the
/// direction has numbers that are not finite (`p` is then left as it was: the last finite
/// point is handed on) or the step vanishes.
fn predictor_corrector(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    lay: &Layout,
    p: &mut Point,
    res: &Residuals,
    gap: f64,
    counts: &mut Counts,
) -> Result<(), &'static str> {
    let mu = gap / lay.cones.len().max(1) as f64;
    let (scalings, lam) = scaled_point(lay, p);
    let Some(f) = factorise(blocks, lay, &scalings, program.equality_rows()) else {
        // Near the end the scaling can swamp P (z/s of 1e20 when the gaps are large): the
        // point reached is handed on to be polished.
        return Err("the interior-point Newton matrix lost positive definiteness");
    };
    counts.newton_steps += 1;
    counts.factorisations += blocks.len() as u32;
    let mut rc = predictor_rhs(lay, &lam);
    let aff = solve(blocks, lay, &f, &scalings, &lam, res, &rc);
    let a_aff = max_step(lay, p, &aff, 1.0);
    let gap_aff: f64 =
        p.s.iter()
            .zip(&aff.ds)
            .zip(p.z.iter().zip(&aff.dz))
            .map(|((s, ds), (z, dz))| (s + a_aff * ds) * (z + a_aff * dz))
            .sum();
    let sigma = (gap_aff / gap).clamp(0.0, 1.0).powi(3);
    add_corrector(lay, &scalings, &aff, sigma, mu, &mut rc);
    let d = solve(blocks, lay, &f, &scalings, &lam, res, &rc);
    let alpha = (STEP_FRACTION * max_step(lay, p, &d, 1.0 / STEP_FRACTION)).min(1.0);
    if !d.is_finite() || alpha.is_nan() {
        return Err("the interior-point direction has numbers that are not finite");
    }
    if alpha < 1e-12 {
        return Err("the interior-point step vanished");
    }
    for (a, b) in p.x.iter_mut().zip(&d.dx) {
        *a += alpha * b;
    }
    for (a, b) in p.lambda.iter_mut().zip(&d.dlambda) {
        *a += alpha * b;
    }
    for (a, b) in p.s.iter_mut().zip(&d.ds) {
        *a += alpha * b;
    }
    for (a, b) in p.z.iter_mut().zip(&d.dz) {
        *a += alpha * b;
    }
    Ok(())
}

/// The NT scalings at `p`, one per cone, and the scaled point `l = W z`.
fn scaled_point(lay: &Layout, p: &Point) -> (Vec<Scaling>, Vec<f64>) {
    let scalings: Vec<Scaling> = lay
        .cones
        .iter()
        .map(|(c, row)| {
            let r = *row..row + c.dim();
            c.nt_scaling(&p.s[r.clone()], &p.z[r])
        })
        .collect();
    let mut lam = vec![0.0; lay.total];
    for ((c, row), sc) in lay.cones.iter().zip(&scalings) {
        Scaling::apply(
            &sc.w,
            &p.z[*row..row + c.dim()],
            &mut lam[*row..row + c.dim()],
        );
    }
    (scalings, lam)
}

/// The predictor's complementarity right-hand side `rc = -l o l`.
fn predictor_rhs(lay: &Layout, lam: &[f64]) -> Vec<f64> {
    let mut rc = vec![0.0; lay.total];
    for (c, row) in &lay.cones {
        let r = *row..row + c.dim();
        let mut o = [0.0; 3];
        c.product(&lam[r.clone()], &lam[r.clone()], &mut o[..c.dim()]);
        for j in 0..c.dim() {
            rc[row + j] = -o[j];
        }
    }
    rc
}

/// Turns the predictor's `rc` into the corrector's:
/// `rc = -l o l - (W^-1 ds_a) o (W dz_a) + sigma mu e`, with `aff` the affine direction.
fn add_corrector(
    lay: &Layout,
    scalings: &[Scaling],
    aff: &Direction,
    sigma: f64,
    mu: f64,
    rc: &mut [f64],
) {
    for ((c, row), sc) in lay.cones.iter().zip(scalings) {
        let d = c.dim();
        let r = *row..row + d;
        let (mut a, mut b, mut o, mut e) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        Scaling::apply(&sc.w_inv, &aff.ds[r.clone()], &mut a[..d]);
        Scaling::apply(&sc.w, &aff.dz[r.clone()], &mut b[..d]);
        c.product(&a[..d], &b[..d], &mut o[..d]);
        c.identity(&mut e[..d]);
        for j in 0..d {
            rc[row + j] += -o[j] + sigma * mu * e[j];
        }
    }
}
