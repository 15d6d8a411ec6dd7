//! Assembly of the energy program (model.md, "The grasp program") as a scaled conic program in
//! Clarabel's form
//!
//! ```text
//!   minimise   1/2 x'Px + q'x     subject to   A x + s = b,   s in K
//! ```
//!
//! with `x = forces / Fu`, `P = C / Cu` (block-diagonal over fingers), `q = c / (Fu Cu)` on
//! normal unknowns (plus slip memory on tangential ones). Rows, in this order:
//!
//! 1. zero cone: the equilibrium rows reduced to their range (thesis eqs. 48-49; 6 in 3-D, 3
//!    planar, fewer when contacts cannot resist some direction), then one row
//!    `sum_k F_k = P_i / Fu` per force-controlled finger;
//! 2. nonnegative cone: `F_k >= 0` for frictionless fingers; `mu F_k + G_k >= 0` and
//!    `mu F_k - G_k >= 0` for planar friction (thesis eqs. 21-24);
//! 3. second-order cones `(mu F_k, G_k1, G_k2)` (scalar first, Clarabel's layout) in 3-D.
//!
//! The matrices are assembled once; only `b` depends on prescribed loads, so later solves
//! update `b` in place.

use clarabel::algebra::CscMatrix;
use clarabel::solver::SupportedConeT;
use nalgebra::DMatrix;

use crate::equilibrium::RowReduction;
use crate::grasp_model::GraspModel;

/// Where a finger's conic rows are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConeRows {
    /// `F_k >= 0` rows start here (frictionless finger).
    Nonnegative(usize),
    /// Planar pairs `(mu F + G, mu F - G)` start here, two rows per element.
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
    /// force-controlled finger, N; checked by the caller).
    pub fn assemble(model: &GraspModel, loads_n: &[f64]) -> ConeProgram {
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
        let mut row = n_zero;
        let mut cone_rows = vec![ConeRows::Nonnegative(0); model.fingers.len()];
        for (i, f) in model.fingers.iter().enumerate() {
            let ne = f.patch.len();
            let mu = f.mu();
            match f.n_tangential {
                0 => {
                    cone_rows[i] = ConeRows::Nonnegative(row);
                    for k in 0..ne {
                        acols.push(row + k, f.offset + k, -1.0);
                    }
                    row += ne;
                }
                1 => {
                    cone_rows[i] = ConeRows::PlanarPairs(row);
                    for k in 0..ne {
                        let (r0, r1) = (row + 2 * k, row + 2 * k + 1);
                        acols.push(r0, f.offset + k, -mu);
                        acols.push(r0, f.offset + ne + k, -1.0);
                        acols.push(r1, f.offset + k, -mu);
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
                let mu = f.mu();
                cone_rows[i] = ConeRows::SecondOrder(row);
                for k in 0..ne {
                    acols.push(row + 3 * k, f.offset + k, -mu);
                    acols.push(row + 3 * k + 1, f.offset + ne + k, -1.0);
                    acols.push(row + 3 * k + 2, f.offset + 2 * ne + k, -1.0);
                }
                row += 3 * ne;
                n_soc += ne;
            }
        }
        b.resize(row, 0.0);
        let a = acols.build(row);
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
            external_scaled,
            unbalanced,
        }
    }

    /// Number of equilibrium rows kept after the reduction.
    pub fn equilibrium_rows(&self) -> usize {
        self.reduction.basis.ncols()
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
