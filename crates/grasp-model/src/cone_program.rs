//! Assembly of the grasp program (model.md, "The grasp program" and "coulomb") as a scaled
//! conic program in Clarabel's form
//!
//! ```text
//!   minimise   1/2 x'Px + q'x     subject to   A x + s = b,   s in K
//! ```
//!
//! with `x = forces / Fu`, `P = C / Cu` (block-diagonal over fingers), `q = c / (Fu Cu)` on
//! normal unknowns and `q = -m / (Fu Cu)` on tangential ones (`m`: slip memory, coulomb model).
//! Rows, in this order:
//!
//! 1. zero cone: the equilibrium rows reduced to their range (thesis eqs. 48-49; 6 in 3-D, 3
//!    planar, fewer when contacts cannot resist some direction), then one row
//!    `sum_k F_k = P_i / Fu` per force-controlled finger;
//! 2. nonnegative cone. Energy model ([`ConeLaw::Associated`]): `F_k >= 0` for frictionless
//!    fingers; `mu F_k + G_k >= 0` and `mu F_k - G_k >= 0` for planar friction (thesis eqs.
//!    21-24). Coulomb model ([`ConeLaw::Tresca`]): `F_k >= 0` for every element, then planar
//!    `r_k - G_k >= 0`, `r_k + G_k >= 0` with the radius `r_k` in `b`;
//! 3. second-order cones, scalar first (Clarabel's layout): `(mu F_k, G_k1, G_k2)` (energy) or
//!    `(r_k, G_k1, G_k2)` with `r_k` in `b` (coulomb: Tresca cones).
//!
//! The matrices are assembled once. Loads and Tresca radii live in `b`, slip memory in `q`,
//! frozen friction coefficients of the energy model in `A` (fixed sparsity, explicit entries
//! even when `mu = 0`), so the sequential solve updates them in place.

use clarabel::algebra::CscMatrix;
use clarabel::solver::SupportedConeT;
use nalgebra::DMatrix;

use crate::equilibrium::RowReduction;
use crate::grasp_model::GraspModel;

/// Which cones bound the friction forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConeLaw {
    /// `||G_k|| <= mu F_k`: the energy model's associated cones.
    Associated,
    /// `||G_k|| <= r_k` with `r_k` fixed (Tresca): one iterate of the coulomb model.
    Tresca,
}

/// Where a finger's conic rows are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConeRows {
    /// `F_k >= 0` rows start here (frictionless finger, energy model).
    Nonnegative(usize),
    /// Planar pairs start here, two rows per element.
    PlanarPairs(usize),
    /// 3-D second-order cones start here, three rows per element.
    SecondOrder(usize),
}

/// The assembled, scaled program.
#[derive(Debug, Clone)]
pub struct ConeProgram {
    /// Upper triangle of `P` (CSC).
    pub p: CscMatrix<f64>,
    /// Linear cost `q`.
    pub q: Vec<f64>,
    /// Constraint matrix `A` (CSC).
    pub a: CscMatrix<f64>,
    /// Right-hand side `b` (for the loads last set).
    pub b: Vec<f64>,
    /// Cone list in row order.
    pub cones: Vec<SupportedConeT<f64>>,
    /// Reduction of the equilibrium rows.
    pub reduction: RowReduction,
    /// Row of each force-controlled finger's load equation, as `(finger index, row)`.
    pub load_rows: Vec<(usize, usize)>,
    /// Conic rows of each finger.
    pub cone_rows: Vec<ConeRows>,
    /// Which cones bound the friction forces.
    pub law: ConeLaw,
    /// Tresca model only: per finger, the row of its first `F_k >= 0` row.
    pub normal_rows: Vec<Option<usize>>,
    /// Energy model only: per finger, the positions in `a.nzval` of its `-mu` entries.
    pub mu_entries: Vec<Vec<usize>>,
    /// Friction coefficient per finger currently in `A` (energy model).
    pub mu: Vec<f64>,
    /// Scaled external wrench in equilibrium coordinates (`S w_ext / Fu`).
    pub external_scaled: Vec<f64>,
    /// Set when the external load has a component no contact force can resist: the reason.
    pub unbalanced: Option<String>,
}

/// Column-wise sparse builder.
struct Columns(Vec<Vec<(usize, f64)>>);

impl Columns {
    fn new(n: usize) -> Self {
        Columns(vec![Vec::new(); n])
    }
    fn push(&mut self, row: usize, col: usize, v: f64) {
        if v != 0.0 {
            self.0[col].push((row, v));
        }
    }
    /// Pushes an entry even when it is zero (a structural entry that may change later).
    fn push_structural(&mut self, row: usize, col: usize, v: f64) {
        self.0[col].push((row, v));
    }
    fn build(mut self, m: usize) -> CscMatrix<f64> {
        let n = self.0.len();
        let mut colptr = Vec::with_capacity(n + 1);
        let mut rowval = Vec::new();
        let mut nzval = Vec::new();
        colptr.push(0);
        for col in &mut self.0 {
            col.sort_by_key(|e| e.0);
            let mut last: Option<usize> = None;
            for &(r, v) in col.iter() {
                if last == Some(r) {
                    *nzval.last_mut().expect("entry") += v;
                } else {
                    rowval.push(r);
                    nzval.push(v);
                    last = Some(r);
                }
            }
            colptr.push(rowval.len());
        }
        CscMatrix::new(m, n, colptr, rowval, nzval)
    }
}

impl ConeProgram {
    /// Assembles the program for `model` with prescribed loads `loads_n` (one per
    /// force-controlled finger, N; checked by the caller), cones of kind `law` and, for the
    /// associated law, friction coefficients `mu` (one per finger). Tresca radii start at 0.
    pub fn assemble(model: &GraspModel, loads_n: &[f64], law: ConeLaw, mu: &[f64]) -> ConeProgram {
        let s = model.scales;
        let n = model.n_unknowns;

        // Objective.
        let mut pcols = Columns::new(n);
        let mut q = vec![0.0; n];
        for f in &model.fingers {
            let c = &f.compliance_m_per_n;
            let dim = c.nrows();
            for col in 0..dim {
                for row in 0..=col {
                    pcols.push(
                        f.offset + row,
                        f.offset + col,
                        c[(row, col)] / s.compliance_m_per_n,
                    );
                }
            }
            for (k, gap) in f.patch.gap_m.iter().enumerate() {
                q[f.offset + k] = gap / s.displacement_m();
            }
        }
        let p = pcols.build(n);

        // Equilibrium rows, scaled: E_hat (rows x n), then reduced to U' E_hat.
        let rows = model.equilibrium.rows();
        let mut e_hat = DMatrix::<f64>::zeros(rows, n);
        for (i, f) in model.fingers.iter().enumerate() {
            let ne = f.patch.len();
            for c in 0..=f.n_tangential {
                for k in 0..ne {
                    let col = model.equilibrium.apply(&model.unit_wrench(i, k, c));
                    for r in 0..rows {
                        e_hat[(r, f.offset + c * ne + k)] = col[r];
                    }
                }
            }
        }
        let reduction = RowReduction::new(&e_hat);
        let external_scaled: Vec<f64> = model
            .equilibrium
            .apply(&model.external_wrench)
            .iter()
            .map(|v| v / s.element_force_n)
            .collect();
        let unbalanced = unbalanced_reason(model, &reduction, &external_scaled);
        let e_red = reduction.basis.transpose() * &e_hat;
        let r_eq = e_red.nrows();

        let fc = model.force_controlled();
        let n_zero = r_eq + fc.len();
        let mut acols = Columns::new(n);
        let mut b = Vec::new();
        for r in 0..r_eq {
            for col in 0..n {
                acols.push(r, col, e_red[(r, col)]);
            }
            let rhs: f64 = (0..rows)
                .map(|k| -reduction.basis[(k, r)] * external_scaled[k])
                .sum();
            b.push(rhs);
        }
        let mut load_rows = Vec::with_capacity(fc.len());
        for (j, &i) in fc.iter().enumerate() {
            let row = r_eq + j;
            let f = &model.fingers[i];
            for k in 0..f.patch.len() {
                acols.push(row, f.offset + k, 1.0);
            }
            b.push(loads_n[j] / s.element_force_n);
            load_rows.push((i, row));
        }

        // Conic rows: all nonnegative rows first, then all second-order cones.
        let nf = model.fingers.len();
        let mut row = n_zero;
        let mut cone_rows = vec![ConeRows::Nonnegative(0); nf];
        let mut normal_rows = vec![None; nf];
        let mut mu_rows: Vec<Vec<usize>> = vec![Vec::new(); nf];
        if law == ConeLaw::Tresca {
            for (i, f) in model.fingers.iter().enumerate() {
                normal_rows[i] = Some(row);
                cone_rows[i] = ConeRows::Nonnegative(row);
                for k in 0..f.patch.len() {
                    acols.push(row + k, f.offset + k, -1.0);
                }
                row += f.patch.len();
            }
        }
        for (i, f) in model.fingers.iter().enumerate() {
            let ne = f.patch.len();
            match (f.n_tangential, law) {
                (0, ConeLaw::Associated) => {
                    cone_rows[i] = ConeRows::Nonnegative(row);
                    for k in 0..ne {
                        acols.push(row + k, f.offset + k, -1.0);
                    }
                    row += ne;
                }
                (1, _) => {
                    cone_rows[i] = ConeRows::PlanarPairs(row);
                    for k in 0..ne {
                        let (r0, r1) = (row + 2 * k, row + 2 * k + 1);
                        if law == ConeLaw::Associated {
                            acols.push_structural(r0, f.offset + k, -mu[i]);
                            acols.push_structural(r1, f.offset + k, -mu[i]);
                            mu_rows[i].extend([r0, r1]);
                        }
                        acols.push(r0, f.offset + ne + k, -1.0);
                        acols.push(r1, f.offset + ne + k, 1.0);
                    }
                    row += 2 * ne;
                }
                _ => {}
            }
        }
        let n_nonneg = row - n_zero;
        let mut n_soc = 0;
        for (i, f) in model.fingers.iter().enumerate() {
            if f.n_tangential == 2 {
                let ne = f.patch.len();
                cone_rows[i] = ConeRows::SecondOrder(row);
                for k in 0..ne {
                    if law == ConeLaw::Associated {
                        acols.push_structural(row + 3 * k, f.offset + k, -mu[i]);
                        mu_rows[i].push(row + 3 * k);
                    }
                    acols.push(row + 3 * k + 1, f.offset + ne + k, -1.0);
                    acols.push(row + 3 * k + 2, f.offset + 2 * ne + k, -1.0);
                }
                row += 3 * ne;
                n_soc += ne;
            }
        }
        b.resize(row, 0.0);
        let a = acols.build(row);
        // Positions of the mu entries in nzval: they sit in the columns of the F_k unknowns.
        let mu_entries: Vec<Vec<usize>> = model
            .fingers
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let per = if f.n_tangential == 1 { 2 } else { 1 };
                mu_rows[i]
                    .iter()
                    .enumerate()
                    .map(|(j, &r)| {
                        let col = f.offset + j / per;
                        let (lo, hi) = (a.colptr[col], a.colptr[col + 1]);
                        lo + a.rowval[lo..hi]
                            .binary_search(&r)
                            .expect("structural mu entry")
                    })
                    .collect()
            })
            .collect();
        let mut cones = vec![SupportedConeT::ZeroConeT(n_zero)];
        if n_nonneg > 0 {
            cones.push(SupportedConeT::NonnegativeConeT(n_nonneg));
        }
        cones.extend(std::iter::repeat_n(
            SupportedConeT::SecondOrderConeT(3),
            n_soc,
        ));
        ConeProgram {
            p,
            q,
            a,
            b,
            cones,
            reduction,
            load_rows,
            cone_rows,
            law,
            normal_rows,
            mu_entries,
            mu: mu.to_vec(),
            external_scaled,
            unbalanced,
        }
    }

    /// Number of equilibrium rows kept after the reduction.
    pub fn equilibrium_rows(&self) -> usize {
        self.reduction.basis.ncols()
    }

    /// Energy model: writes the friction coefficients `mu` (one per finger) into `A`.
    /// Returns true when `A` changed.
    pub fn set_mu(&mut self, mu: &[f64]) -> bool {
        let mut changed = false;
        for (i, entries) in self.mu_entries.iter().enumerate() {
            if self.mu[i] != mu[i] {
                for &e in entries {
                    self.a.nzval[e] = -mu[i];
                }
                self.mu[i] = mu[i];
                changed |= !entries.is_empty();
            }
        }
        changed
    }

    /// Coulomb model: writes the Tresca radii `r_k` (N; per finger, per element) into `b`.
    pub fn set_radii(&mut self, model: &GraspModel, radii_n: &[Vec<f64>]) {
        let fu = model.scales.element_force_n;
        for (i, f) in model.fingers.iter().enumerate() {
            match self.cone_rows[i] {
                ConeRows::PlanarPairs(r) if f.n_tangential == 1 => {
                    for (k, rk) in radii_n[i].iter().enumerate() {
                        self.b[r + 2 * k] = rk / fu;
                        self.b[r + 2 * k + 1] = rk / fu;
                    }
                }
                ConeRows::SecondOrder(r) if f.n_tangential == 2 => {
                    for (k, rk) in radii_n[i].iter().enumerate() {
                        self.b[r + 3 * k] = rk / fu;
                    }
                }
                _ => {}
            }
        }
    }

    /// Writes the slip memory `m` (m; per finger, per element `[t1, t2]`) into `q`:
    /// `q_G = -m / (Fu Cu)`, so that a sticking element keeps its relative tangential
    /// displacement `w_k = m_k` (model.md, "coulomb").
    pub fn set_slip_memory(&mut self, model: &GraspModel, memory_m: &[Vec<[f64; 2]>]) {
        let du = model.scales.displacement_m();
        for (i, f) in model.fingers.iter().enumerate() {
            let ne = f.patch.len();
            for c in 0..f.n_tangential {
                for k in 0..ne {
                    self.q[f.offset + (c + 1) * ne + k] = -memory_m[i][k][c] / du;
                }
            }
        }
    }

    /// Overwrites the load rows of `b` (N, one per force-controlled finger).
    pub fn set_loads(&mut self, model: &GraspModel, loads_n: &[f64]) {
        for (j, &(_, row)) in self.load_rows.iter().enumerate() {
            self.b[row] = loads_n[j] / model.scales.element_force_n;
        }
    }
}

/// If the scaled external wrench has a component no contact force can produce, says which.
fn unbalanced_reason(model: &GraspModel, red: &RowReduction, w: &[f64]) -> Option<String> {
    let norm_w = w.iter().map(|v| v * v).sum::<f64>().sqrt();
    let rows = w.len();
    for c in 0..red.null.ncols() {
        let u: Vec<f64> = (0..rows).map(|r| red.null[(r, c)]).collect();
        let comp: f64 = u.iter().zip(w).map(|(a, b)| a * b).sum();
        if comp.abs() > 1e-9 * norm_w.max(1e-300) {
            // Express the unresisted direction in the world frame.
            let (force, moment) = match model.plane {
                None => ([u[0], u[1], u[2]], [u[3], u[4], u[5]]),
                Some((e1, e2, p)) => {
                    let f = e1 * u[0] + e2 * u[1];
                    let m = p * u[2];
                    ([f.x, f.y, f.z], [m.x, m.y, m.z])
                }
            };
            return Some(format!(
                "no equilibrium: the load has a component that no contact force can resist \
                 (force direction [{:.3}, {:.3}, {:.3}], moment axis [{:.3}, {:.3}, {:.3}]); \
                 add friction or a finger whose normal or moment arm covers that direction",
                force[0], force[1], force[2], moment[0], moment[1], moment[2]
            ));
        }
    }
    None
}
