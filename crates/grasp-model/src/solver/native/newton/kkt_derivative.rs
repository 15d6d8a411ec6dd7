//! The derivative of the program's solution with respect to its equality right-hand side `e`
//! (loads and external wrench) and its linear cost `q` (approaches, a mount's compliance), by
//! the implicit function theorem on the KKT conditions at the solution's active set (Dontchev &
//! Rockafellar, *Implicit Functions and Solution Mappings*, 2.E, for the semismooth case).
//!
//! At a KKT point the natural residual `Phi_k = x_k - Proj_{K_k}(x_k - gamma y_k)` vanishes
//! ([`super::linearisation`]). Differentiating it with the projection's Jacobian
//! `sum_j theta_j d_j d_j'` ([`crate::program::cones::element_cone`]) gives, per
//! direction `d_j` of element `k` and with `dy = P dx + dq + E' dlambda`:
//!
//! - `theta_j = 0` (separated, or the cone normal of a sliding element): `d_j . dx_k = dr_j`,
//!   where `dr_j` is the change of the set itself: 0, except the radial direction of a sliding
//!   Tresca element, whose radius `r_k = mu F_k` (the coulomb fixed point) follows the normal
//!   force: `dr = mu dF_k`;
//! - `theta_j > 0`: `d_j . dy_k + beta_j xi_j = 0`, `beta_j = (1 - theta_j) / (gamma theta_j)`,
//!   `xi_j = d_j . dx_k` (stick: the element moves with the object; slip: along the cone);
//!
//! and `E dx = de`. Writing `dx_i = C_i xi_i` over the free directions (`C_i` is `D_F` plus the
//! radial coupling) the system is, per finger, `A_i xi_i + B_i dlambda + D_F' dq_i = 0` with
//! `A_i = D_F' P_i C_i + diag(beta)`, `B_i = D_F' E_i'`, and it couples the fingers only through
//! `sum_i E_i C_i xi_i = de`: each `A_i` is factorised (LU, faer; it is not symmetric where the
//! radial coupling enters) and the `m x m` Schur complement `S = sum_i E_i C_i A_i^-1 B_i` gives
//! `S dlambda = -(de + sum_i E_i C_i h_i)`, `h_i = A_i^-1 D_F' dq_i`, then `xi_i = -A_i^-1 B_i
//! dlambda - h_i`. Directions that `S` cannot produce (the active set has no free direction
//! along them: the grasp is at a limit) are reported, not inverted.

use faer::linalg::solvers::Solve;
use faer::Mat;
use nalgebra::DMatrix;

use crate::program::cone_program::ConeProgram;
use crate::program::cones::element_set::{ElementSet, StateMargin};
use crate::program::cones::finger_cones::FingerCones;
use crate::solver::iterate::Iterate;
use crate::solver::native::finger_block::FingerBlockData;

use super::linearisation::{linearise, projection_input, Direction, FingerLinearisation};
use super::semismooth_newton::dual_of;

/// Relative singular value below which a direction of the Schur complement counts as not
/// producible by the active set.
const SCHUR_CUTOFF: f64 = 1e-10;

/// The derivative of the solution at a KKT point.
#[derive(Debug, Clone)]
pub(crate) struct KktDerivative {
    /// `dx` for each column (`n x p`, scaled forces): the change of the solution under that
    /// column's `de` and `dq` together.
    pub dx: DMatrix<f64>,
    /// Per column: the fraction (0 to 1) of `de` that the active set cannot produce (0 when the
    /// derivative exists).
    pub unreachable: Vec<f64>,
    /// True when the multipliers are not determined (the Schur complement is singular) and
    /// the forces move along that freedom: the grasp is at a limit where the object can move
    /// (slide as a whole) with no change of equilibrium, and the linearisation cannot tell the
    /// forces' derivative.
    pub ambiguous: bool,
    /// Per finger, per element: how close the element is to a change of state.
    pub margins: Vec<Vec<StateMargin>>,
}

/// Relative size of the force change along an undetermined multiplier direction above which
/// the derivative is ambiguous.
const AMBIGUOUS: f64 = 1e-6;

/// One free direction of the derivative: its row direction `d_j`, weight, and column `c_j`
/// (local index, value) in `dx`.
struct FreeColumn {
    row: Direction,
    column: Vec<(usize, f64)>,
}

/// The cones at which to differentiate: the program's, with Tresca radii set to
/// `mu_i max(F_k, 0)` of the solution itself (the fixed point).
fn differentiation_cone(
    block: &FingerBlockData,
    cone: &FingerCones,
    x: &[f64],
    mu: f64,
) -> FingerCones {
    cone.with_radii(|k| mu * block.gather(x, k)[0].max(0.0))
}

/// The free directions of one finger with their columns (radial coupling of sliding Tresca
/// elements included; a Tresca element without radius has no free tangential direction).
fn free_columns(
    block: &FingerBlockData,
    cone: &FingerCones,
    lin: &FingerLinearisation,
    mu: f64,
    pinned: &[bool],
) -> Vec<FreeColumn> {
    let radius = |k: usize| cone.radii().map(|radii| radii[k]);
    let radial = |k: usize| {
        lin.fixed
            .iter()
            .find(|d| d.element == k && d.dir[0] == 0.0)
            .map(|d| d.dir)
    };
    let mut out = Vec::new();
    for d in &lin.free {
        let k = d.element;
        let normal_dir = d.dir[0] == 1.0;
        if pinned[k] || (radius(k) == Some(0.0) && !normal_dir) {
            continue;
        }
        let mut column: Vec<(usize, f64)> = (0..block.dim)
            .filter(|&c| d.dir[c] != 0.0)
            .map(|c| (block.index(k, c), d.dir[c]))
            .collect();
        if let (Some(r), true, Some(rad)) = (radius(k), normal_dir, radial(k)) {
            if r > 0.0 {
                for (c, &rc) in rad.iter().enumerate().take(block.dim).skip(1) {
                    if rc != 0.0 {
                        column.push((block.index(k, c), mu * rc));
                    }
                }
            }
        }
        out.push(FreeColumn { row: *d, column });
    }
    out
}

/// One finger's part of the system: `X_i = A_i^-1 B_i`, `H_i = A_i^-1 D_F' dq_i` and `G_i = E_i
/// C_i`.
struct FingerSystem {
    columns: Vec<FreeColumn>,
    /// `A_i^-1 B_i` (`n_free x m`).
    x: Mat<f64>,
    /// `A_i^-1 D_F' dq_i` (`n_free x c`, one column per column of `dq`).
    h: Mat<f64>,
    /// False when no column of `dq` moves this finger's free directions (`h` is 0).
    moved: bool,
    /// `E_i C_i` (`m x n_free`).
    g: Mat<f64>,
}

/// The finger's system for the free `columns`, with the change of its linear cost `dq` (rows
/// `block.offset..` of an `n x p` matrix, scaled like `q`).
fn finger_system(
    block: &FingerBlockData,
    columns: Vec<FreeColumn>,
    dq: &DMatrix<f64>,
) -> FingerSystem {
    let (n, nf, m) = (block.len(), columns.len(), block.equality_rows());
    let mut pc = Mat::<f64>::zeros(n, nf);
    let mut g = Mat::<f64>::zeros(m, nf);
    for (b, col) in columns.iter().enumerate() {
        for &(idx, val) in &col.column {
            let val_p = val * block.scale;
            for (r, c) in block.compliance_column(idx).iter().enumerate() {
                pc[(r, b)] += val_p * c;
            }
            for r in 0..m {
                g[(r, b)] += val * block.equality(r, idx);
            }
        }
    }
    let row_dot = |d: &Direction, f: &dyn Fn(usize) -> f64| -> f64 {
        (0..block.dim)
            .map(|c| d.dir[c] * f(block.index(d.element, c)))
            .sum()
    };
    let a = Mat::<f64>::from_fn(nf, nf, |i, j| {
        let d = &columns[i].row;
        let beta = if i == j {
            (1.0 - d.theta) / (block.gamma * d.theta)
        } else {
            0.0
        };
        row_dot(d, &|idx| pc[(idx, j)]) + beta
    });
    let b = Mat::<f64>::from_fn(nf, m, |i, r| {
        row_dot(&columns[i].row, &|idx| block.equality(r, idx))
    });
    let p = dq.ncols();
    let dq_rows = Mat::<f64>::from_fn(nf, p, |i, c| {
        // Rows past `dq`'s (one written over the fingers' unknowns alone) change no cost.
        row_dot(
            &columns[i].row,
            &|idx| match block.offset + idx < dq.nrows() {
                true => dq[(block.offset + idx, c)],
                false => 0.0,
            },
        )
    });
    // Most fingers' costs do not move (no approach, no mount): their `h` is 0 unsolved.
    let moved = (0..nf).any(|i| (0..p).any(|c| dq_rows[(i, c)] != 0.0));
    let (x, h) = if nf == 0 {
        (Mat::zeros(0, m), Mat::zeros(0, p))
    } else {
        let lu = a.partial_piv_lu();
        let h = match moved {
            true => lu.solve(&dq_rows),
            false => Mat::zeros(nf, p),
        };
        (lu.solve(&b), h)
    };
    FingerSystem {
        columns,
        x,
        h,
        moved,
        g,
    }
}

/// `dx` at the KKT point `iterate` of `program` for each column of `rhs` (`de`, `m x p`, scaled
/// like `e`), the last `c` of them with the column of `dq` (`n x c`, scaled like `q`) beside
/// them (none for the others: `c` may be 0); `mu` per finger is
/// the coefficient of the Tresca radii `r_k = mu F_k` (unused for other cones). An element
/// that carries no load and whose projection input is within `near` (scaled force) of the
/// boundary of the separated piece is held separated: it is just touching (or, energy model,
/// sliding along at zero load), and a free direction there would let the linearisation pull
/// on it (an unloaded force-controlled finger's elements are such). `Err` when a block cannot
/// be factorised.
pub(crate) fn kkt_derivative(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    iterate: &Iterate,
    mu: &[f64],
    rhs: &DMatrix<f64>,
    dq: &DMatrix<f64>,
    near: f64,
) -> Result<KktDerivative, String> {
    let y = dual_of(blocks, program, &iterate.x, &iterate.lambda);
    let m = rhs.nrows();
    let mut systems = Vec::with_capacity(blocks.len());
    let mut margins = Vec::with_capacity(blocks.len());
    let mut s = DMatrix::<f64>::zeros(m, m);
    // A shared spring's block has no Tresca radii: coefficient 0.
    let mu = mu.iter().chain(std::iter::repeat(&0.0));
    for ((block, pb), &mu_i) in blocks.iter().zip(&program.blocks).zip(mu) {
        let range = block.offset..block.offset + block.len();
        let (x, yl) = (&iterate.x[range.clone()], &y[range]);
        let (sys, finger_margins) = finger_at(block, &pb.cone, x, yl, mu_i, near, dq);
        margins.push(finger_margins);
        for r in 0..m {
            for c in 0..m {
                s[(r, c)] += (0..sys.columns.len())
                    .map(|a| sys.g[(r, a)] * sys.x[(a, c)])
                    .sum::<f64>();
            }
        }
        systems.push(sys);
    }
    if !s.iter().all(|v| v.is_finite()) {
        return Err("a block of the active set could not be factorised".into());
    }
    let first = rhs.ncols() - dq.ncols();
    let (dlambda, unreachable, null) = solve_schur(s, &with_cost_changes(rhs, &systems, first));
    let ambiguous = is_ambiguous(&systems, &null, m);
    let mut dx = DMatrix::<f64>::zeros(program.n_unknowns, rhs.ncols());
    for (block, sys) in blocks.iter().zip(&systems) {
        for (a, col) in sys.columns.iter().enumerate() {
            for p in 0..rhs.ncols() {
                let h = match sys.moved && p >= first {
                    true => sys.h[(a, p - first)],
                    false => 0.0,
                };
                let xi: f64 = -(0..m).map(|r| sys.x[(a, r)] * dlambda[(r, p)]).sum::<f64>() - h;
                for &(idx, val) in &col.column {
                    dx[(block.offset + idx, p)] += val * xi;
                }
            }
        }
    }
    Ok(KktDerivative {
        dx,
        unreachable,
        ambiguous,
        margins,
    })
}

/// `de + sum_i E_i C_i h_i`: the right-hand side `rhs` with the linear cost's changes carried
/// to the equality rows (its columns from `first` on).
fn with_cost_changes(rhs: &DMatrix<f64>, systems: &[FingerSystem], first: usize) -> DMatrix<f64> {
    let mut out = rhs.clone();
    for sys in systems.iter().filter(|s| s.moved) {
        for p in first..rhs.ncols() {
            for r in 0..rhs.nrows() {
                out[(r, p)] += (0..sys.columns.len())
                    .map(|a| sys.g[(r, a)] * sys.h[(a, p - first)])
                    .sum::<f64>();
            }
        }
    }
    out
}

/// One finger's system at its KKT point `x`, `yl` (cone `cone`, Tresca coefficient `mu`, linear
/// cost changes `dq`) and its elements' state margins; elements that carry no load and are
/// within `near` of the boundary of the separated piece are held separated (see
/// [`kkt_derivative`]).
fn finger_at(
    block: &FingerBlockData,
    cone: &FingerCones,
    x: &[f64],
    yl: &[f64],
    mu: f64,
    near: f64,
    dq: &DMatrix<f64>,
) -> (FingerSystem, Vec<StateMargin>) {
    let cone = differentiation_cone(block, cone, x, mu);
    let lin = linearise(block, &cone, x, yl);
    let margins: Vec<StateMargin> = (0..block.elements)
        .map(|k| {
            cone.element(k)
                .state_margin(projection_input(block, x, yl, k), block.dim)
        })
        .collect();
    let pinned: Vec<bool> = margins
        .iter()
        .enumerate()
        .map(|(k, margin)| {
            block.gather(x, k)[0] <= near && margin.distance <= near && !margin.stick_slip
        })
        .collect();
    let sys = finger_system(block, free_columns(block, &cone, &lin, mu, &pinned), dq);
    (sys, margins)
}

/// True when the forces move along an undetermined multiplier direction (a null vector of
/// `S` in `null`) by more than [`AMBIGUOUS`] of their typical response to a unit `de`.
fn is_ambiguous(systems: &[FingerSystem], null: &[Vec<f64>], m: usize) -> bool {
    let response = |z: &[f64]| -> f64 {
        let mut worst = 0.0_f64;
        for sys in systems {
            for (a, col) in sys.columns.iter().enumerate() {
                let xi: f64 = (0..m).map(|r| sys.x[(a, r)] * z[r]).sum();
                for &(_, val) in &col.column {
                    worst = worst.max((val * xi).abs());
                }
            }
        }
        worst
    };
    let typical = (0..m)
        .map(|r| {
            let mut e = vec![0.0; m];
            e[r] = 1.0;
            response(&e)
        })
        .fold(0.0_f64, f64::max);
    null.iter().any(|z| response(z) > AMBIGUOUS * typical)
}

/// `dlambda`, the fraction of each column outside the range of `S`, and the null vectors of
/// `S`.
type SchurSolution = (DMatrix<f64>, Vec<f64>, Vec<Vec<f64>>);

/// Solves `S dlambda = -rhs` over the singular directions of `S` above the cutoff.
fn solve_schur(s: DMatrix<f64>, rhs: &DMatrix<f64>) -> SchurSolution {
    let (m, p) = (rhs.nrows(), rhs.ncols());
    if m == 0 {
        return (DMatrix::zeros(0, p), vec![0.0; p], Vec::new());
    }
    let svd = nalgebra::SVD::new(s, true, true);
    let (u, vt) = (svd.u.expect("u requested"), svd.v_t.expect("v_t requested"));
    let smax = svd.singular_values.max();
    let mut out = DMatrix::<f64>::zeros(m, p);
    let mut unreachable = vec![0.0; p];
    for c in 0..p {
        let b = rhs.column(c);
        let norm = b.norm();
        let mut reached_sq = 0.0;
        for j in 0..m {
            let sigma = svd.singular_values[j];
            let uj = u.column(j).dot(&b);
            if smax > 0.0 && sigma > SCHUR_CUTOFF * smax {
                reached_sq += uj * uj;
                for r in 0..m {
                    out[(r, c)] -= vt[(j, r)] * uj / sigma;
                }
            }
        }
        if norm > 0.0 {
            unreachable[c] = ((norm * norm - reached_sq).max(0.0)).sqrt() / norm;
        }
    }
    let null = (0..m)
        .filter(|&j| !(smax > 0.0 && svd.singular_values[j] > SCHUR_CUTOFF * smax))
        .map(|j| (0..m).map(|r| vt[(j, r)]).collect())
        .collect();
    (out, unreachable, null)
}
