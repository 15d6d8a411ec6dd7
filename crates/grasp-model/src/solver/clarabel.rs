//! The Clarabel backend: the program in Clarabel's conic form (assembly, kept apart from the
//! solve) and Clarabel's workspace, which notices by itself what changed since its last solve.
//!
//! Clarabel's form is `minimise 1/2 x'Px + q'x subject to A x + s = b, s in K` with rows, in
//! this order:
//!
//! 1. zero cone: the equality rows `E x = e` of [`ConeProgram`];
//! 2. nonnegative cone: for the Tresca law, `F_k >= 0` for every element of every finger; then
//!    per finger `F_k >= 0` (frictionless finger, associated law), or the planar pairs
//!    `mu F_k + G_k >= 0`, `mu F_k - G_k >= 0` (associated) / `r_k + G_k >= 0`, `r_k - G_k >= 0`
//!    (Tresca, `r_k` in `b`, at least the radius floor, see [`radius_floor`]);
//! 3. second-order cones of dimension 3, scalar first: `(mu F_k, G1_k, G2_k)` (associated) or
//!    `(r_k, G1_k, G2_k)` with `r_k` in `b` (Tresca).
//!
//! The sparsity pattern is fixed for a program (friction coefficients are structural entries
//! even when zero), so later solves update `q`, `A` and `b` in place.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::DMatrix;

use crate::program::cone_program::{ConeProgram, FingerBlock, RADIUS_FLOOR};
use crate::program::cones::element_set::{ClarabelRow, ElementSet};
use crate::program::cones::finger_cones::ConeLaw;
use crate::solver::outcome::{Certificate, ConvexOutcome};

use crate::error::ModelError;
use crate::model::grasp_model::{FingerModel, GraspModel};
use crate::option_names;

/// Where a finger's conic rows are in Clarabel's form.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ConeRows {
    /// No friction rows (frictionless finger).
    None,
    /// Planar pairs start here, two rows per element.
    PlanarPairs(usize),
    /// 3-D second-order cones start here, three rows per element.
    SecondOrder(usize),
}

/// The program in Clarabel's form.
#[derive(Debug, Clone)]
pub struct ClarabelForm {
    /// Upper triangle of `P` (CSC).
    pub p: CscMatrix<f64>,
    /// Linear cost `q`.
    pub q: Vec<f64>,
    /// Constraint matrix `A` (CSC).
    pub a: CscMatrix<f64>,
    /// Right-hand side `b`.
    pub b: Vec<f64>,
    /// Cone list in row order.
    pub cones: Vec<SupportedConeT<f64>>,
    friction_rows: Vec<ConeRows>,
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
            for &(r, v) in col.iter() {
                // Rows are distinct within a column by construction.
                rowval.push(r);
                nzval.push(v);
            }
            colptr.push(rowval.len());
        }
        CscMatrix::new(m, n, colptr, rowval, nzval)
    }
}

/// The constraint rows as they are assembled, in the order of the module docs.
struct Rows {
    /// Columns of `A`.
    acols: Columns,
    /// Right-hand side `b` (resized as rows with entries in it are added).
    b: Vec<f64>,
    /// The next row.
    row: usize,
    /// Where each finger's conic rows are.
    friction_rows: Vec<ConeRows>,
}

impl Rows {
    /// The zero-cone rows: the equality rows `E x = e`.
    fn equality(program: &ConeProgram) -> Rows {
        let n = program.n_unknowns;
        let mut acols = Columns::new(n);
        let e = &program.equality;
        for r in 0..e.nrows() {
            for col in 0..n {
                acols.push(r, col, e[(r, col)]);
            }
        }
        Rows {
            acols,
            b: program.equality_rhs.clone(),
            row: e.nrows(),
            friction_rows: vec![ConeRows::None; program.blocks.len()],
        }
    }

    /// The nonnegative-cone rows: for the Tresca law the own `F_k >= 0` rows of every finger
    /// first; then per finger its own `F_k >= 0` rows (associated law) and its planar pairs.
    fn nonnegative(&mut self, program: &ConeProgram, floor: f64) {
        let tresca = program.law == ConeLaw::Tresca;
        if tresca {
            for blk in &program.blocks {
                self.normal_forces(blk, floor);
            }
        }
        for (i, blk) in program.blocks.iter().enumerate() {
            if !tresca {
                self.normal_forces(blk, floor);
            }
            self.pairs(i, blk, floor);
        }
    }

    /// `F_k >= 0` for every element of `blk` whose set has a row of its own.
    fn normal_forces(&mut self, blk: &FingerBlock, floor: f64) {
        let mut rows = 0;
        for k in 0..blk.elements {
            if blk
                .cone
                .element(k)
                .clarabel_rows(1 + blk.n_tangential, floor)
                .normal
            {
                self.acols.push(self.row + rows, blk.offset + k, -1.0);
                rows += 1;
            }
        }
        self.row += rows;
    }

    /// The rows of one element's unknowns `(F, G1, G2)` at `row`, with their right-hand sides.
    fn element_rows(&mut self, blk: &FingerBlock, k: usize, row: usize, rows: &[ClarabelRow]) {
        let ne = blk.elements;
        for (j, r) in rows.iter().enumerate() {
            if r.structural_f {
                self.acols.push_structural(row + j, blk.offset + k, r.a[0]);
            } else {
                self.acols.push(row + j, blk.offset + k, r.a[0]);
            }
            for c in 1..=blk.n_tangential {
                self.acols.push(row + j, blk.offset + c * ne + k, r.a[c]);
            }
            self.b[row + j] = r.b;
        }
    }

    /// The planar pairs of finger `i` (two nonnegative rows per element), when its sets have
    /// them.
    fn pairs(&mut self, i: usize, blk: &FingerBlock, floor: f64) {
        let (row, ne, d) = (self.row, blk.elements, 1 + blk.n_tangential);
        if blk.n_tangential != 1 {
            return;
        }
        self.friction_rows[i] = ConeRows::PlanarPairs(row);
        self.b.resize(row + 2 * ne, 0.0);
        for k in 0..ne {
            if let Some(pair) = blk.cone.element(k).clarabel_rows(d, floor).pair {
                self.element_rows(blk, k, row + 2 * k, &pair);
            }
        }
        self.row += 2 * ne;
    }

    /// The second-order cones of the fingers with two tangential directions, radii at least
    /// `floor`; returns how many.
    fn second_order(&mut self, program: &ConeProgram, floor: f64) -> usize {
        let mut n_soc = 0;
        for (i, blk) in program.blocks.iter().enumerate() {
            if blk.n_tangential != 2 {
                continue;
            }
            let (row, ne) = (self.row, blk.elements);
            self.friction_rows[i] = ConeRows::SecondOrder(row);
            self.b.resize(row + 3 * ne, 0.0);
            for k in 0..ne {
                if let Some(cone) = blk.cone.element(k).clarabel_rows(3, floor).second_order {
                    self.element_rows(blk, k, row + 3 * k, &cone);
                }
            }
            self.row += 3 * ne;
            n_soc += ne;
        }
        n_soc
    }
}

impl ClarabelForm {
    /// Assembles Clarabel's form of `program` (see the module docs for the row order), Tresca
    /// radii raised to at least `floor` (element force units `Fu`, see [`radius_floor`]).
    pub fn assemble(model: &GraspModel, program: &ConeProgram, floor: f64) -> ClarabelForm {
        let mut form = ClarabelForm::constraints(program, floor);
        form.p = objective_matrix(model, program);
        form
    }

    /// Everything but `P` (left empty), from the program alone, Tresca radii at least `floor`.
    pub(crate) fn constraints(program: &ConeProgram, floor: f64) -> ClarabelForm {
        let n = program.n_unknowns;
        let mut rows = Rows::equality(program);
        let n_zero = rows.row;
        rows.nonnegative(program, floor);
        let n_nonneg = rows.row - n_zero;
        let n_soc = rows.second_order(program, floor);
        let Rows {
            acols,
            mut b,
            row,
            friction_rows,
        } = rows;
        b.resize(row, 0.0);
        let mut cones = vec![SupportedConeT::ZeroConeT(n_zero)];
        if n_nonneg > 0 {
            cones.push(SupportedConeT::NonnegativeConeT(n_nonneg));
        }
        cones.extend(std::iter::repeat_n(
            SupportedConeT::SecondOrderConeT(3),
            n_soc,
        ));
        ClarabelForm {
            p: CscMatrix::zeros((n, n)),
            q: program.q.clone(),
            a: acols.build(row),
            b,
            cones,
            friction_rows,
        }
    }

    /// Reads Clarabel's infeasibility certificate `z` (all rows) as a solver-neutral one.
    fn certificate(&self, program: &ConeProgram, z: &[f64]) -> Certificate {
        let finger_slip = program
            .finger_blocks()
            .iter()
            .zip(&self.friction_rows)
            .map(|(blk, rows)| match *rows {
                ConeRows::PlanarPairs(r) => (0..blk.elements)
                    .map(|k| (z[r + 2 * k] - z[r + 2 * k + 1]).abs())
                    .sum(),
                ConeRows::SecondOrder(r) => (0..blk.elements)
                    .map(|k| z[r + 3 * k + 1].hypot(z[r + 3 * k + 2]))
                    .sum(),
                ConeRows::None => 0.0,
            })
            .collect();
        Certificate {
            equality: z[..program.equality_rows()].to_vec(),
            finger_slip,
        }
    }
}

/// The smallest Tresca radius Clarabel is given at solve tolerance `tolerance`, in element
/// force units `Fu`: [`RADIUS_FLOOR`], or the tolerance when that is smaller, so that the
/// friction an unloaded element may carry in Clarabel's answer stays within the accuracy
/// Clarabel was asked for (a disc of radius 0 has no interior for its interior-point method).
pub fn radius_floor(tolerance: f64) -> f64 {
    RADIUS_FLOOR.min(tolerance)
}

/// Clarabel's settings for a tolerance and limits.
pub(crate) fn settings(
    tolerance: f64,
    max_iterations: u32,
    time_limit_s: f64,
) -> Result<DefaultSettings<f64>, ModelError> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_feas(tolerance)
        .tol_gap_abs(tolerance)
        .tol_gap_rel(tolerance)
        .max_iter(max_iterations)
        .time_limit(time_limit_s)
        .presolve_enable(false)
        .input_sparse_dropzeros(false)
        .direct_solve_method("faer".to_string())
        .build()
        .map_err(|e| ModelError::Solver(format!("Clarabel settings: {e}")))
}

/// Clarabel's workspace for one program: created at the first solve; later solves update `q`,
/// `A` and `b` in place when they changed, and the settings (tolerances) to their own.
pub(crate) struct ClarabelWorkspace {
    form: ClarabelForm,
    solver: Option<DefaultSolver<f64>>,
    /// Some finger's compliance is the FFT operator: `P` cannot be handed to Clarabel.
    matrix_free: bool,
}

/// What one Clarabel solve gave: the outcome, interior-point iterations and solver time (s).
pub(crate) struct ClarabelRun {
    pub outcome: ConvexOutcome,
    pub iterations: u32,
    pub solve_time_s: f64,
}

impl ClarabelWorkspace {
    /// A workspace for `program` (assembles `P` from the model's compliance blocks).
    pub(crate) fn new(model: &GraspModel, program: &ConeProgram) -> Self {
        ClarabelWorkspace {
            form: ClarabelForm::assemble(model, program, RADIUS_FLOOR),
            solver: None,
            matrix_free: model.fingers.iter().any(FingerModel::is_matrix_free),
        }
    }

    /// Brings the workspace up to date with `program` and solves at `tolerance` (the
    /// tolerance sets the radius floor, [`radius_floor`]).
    pub(crate) fn solve(
        &mut self,
        program: &ConeProgram,
        tolerance: f64,
        settings: &DefaultSettings<f64>,
    ) -> Result<ClarabelRun, ModelError> {
        if self.matrix_free {
            return Err(ModelError::Solver(format!(
                "Clarabel needs every patch compliance as a matrix, and this model holds an FFT \
                 operator too large to write out: solve with the native solver (the default), \
                 or, for a patch of up to about 20,000 unknowns (3 GiB), set `{}` to dense; a \
                 finer grid is too fine for Clarabel",
                option_names::COMPLIANCE
            )));
        }
        let mut fresh = ClarabelForm::constraints(program, radius_floor(tolerance));
        fresh.p = std::mem::replace(&mut self.form.p, CscMatrix::zeros((0, 0)));
        let err = |e: clarabel::solver::DataUpdateError| ModelError::Solver(e.to_string());
        let solver = match self.solver.as_mut() {
            Some(s) => {
                // The tolerances may differ from solve to solve (a sequence's inexact iterates):
                // the settings the solver was made with are not kept.
                s.update_settings(settings.clone())
                    .map_err(|e| ModelError::Solver(format!("Clarabel settings: {e}")))?;
                if fresh.a.nzval != self.form.a.nzval {
                    s.update_A(&fresh.a.nzval).map_err(err)?;
                }
                if fresh.q != self.form.q {
                    s.update_q(&fresh.q).map_err(err)?;
                }
                if fresh.b != self.form.b {
                    s.update_b(&fresh.b).map_err(err)?;
                }
                self.form = fresh;
                s
            }
            None => {
                self.form = fresh;
                let f = &self.form;
                let s = DefaultSolver::new(&f.p, &f.q, &f.a, &f.b, &f.cones, settings.clone())
                    .map_err(|e| ModelError::Solver(e.to_string()))?;
                self.solver.insert(s)
            }
        };
        solver.solve();
        let sol = &solver.solution;
        let m = program.equality_rows();
        let outcome = match sol.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => ConvexOutcome::Solved {
                reduced_accuracy: sol.status == SolverStatus::AlmostSolved,
                x: sol.x.clone(),
                multipliers: sol.z[..m].to_vec(),
            },
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                ConvexOutcome::Infeasible(self.form.certificate(program, &sol.z))
            }
            other => ConvexOutcome::Failed {
                reason: format!(
                    "no convergence: the cone solver (Clarabel) stopped with status {other:?} \
                     after {} iterations",
                    sol.iterations
                ),
            },
        };
        Ok(ClarabelRun {
            outcome,
            iterations: sol.iterations,
            solve_time_s: sol.solve_time,
        })
    }
}

/// The upper triangle of `P = C / Cu`, block-diagonal over fingers and then shared springs
/// (a finger whose FFT operator is too large to write out is left out:
/// [`ClarabelWorkspace::solve`] refuses such a model).
fn objective_matrix(model: &GraspModel, program: &ConeProgram) -> CscMatrix<f64> {
    let mut pcols = Columns::new(program.n_unknowns);
    let mut add_block = |offset: usize, c: &DMatrix<f64>| {
        for col in 0..c.ncols() {
            for row in 0..=col {
                let v = c[(row, col)] * program.compliance_scale;
                pcols.push(offset + row, offset + col, v);
            }
        }
    };
    for f in &model.fingers {
        if let Some(c) = f.compliance_m_per_n.matrix() {
            add_block(f.offset, &c);
        }
    }
    let springs = &program.blocks[model.fingers.len()..];
    for (b, s) in springs.iter().zip(&program.springs) {
        add_block(b.offset, &s.compliance_m_per_n);
    }
    pcols.build(program.n_unknowns)
}
