//! The grasp program (model.md, "The grasp program" and "coulomb"), scaled and stated once for
//! every solver backend:
//!
//! ```text
//!   minimise   1/2 x'Px + q'x     subject to   E x = e,   x_k in K_k for every element k
//! ```
//!
//! - `x = forces / Fu` (N over the element force unit), program layout: fingers in scene order,
//!   within finger `i` the blocks `[F_1..F_N, G1_1..G1_N, G2_1..G2_N]` truncated to
//!   `1 + n_tangential` (see [`crate::model::grasp_model`]); `x_k = (F_k, G1_k[, G2_k])` gathers element
//!   `k`'s components.
//! - `P = C / Cu`: block-diagonal over fingers; block `i` is the finger's patch compliance
//!   (m/N) over the compliance unit. It is not copied here: backends read
//!   [`crate::FingerModel::compliance_m_per_n`] and multiply by [`ConeProgram::compliance_scale`].
//! - `q = (c + o_n) / (Fu Cu)` on normal unknowns (initial gaps `c`, m) and `q = (o_t - m) /
//!   (Fu Cu)` on tangential ones (slip memory `m`, m, coulomb model), with `o` a displacement
//!   added to the elastic one `C x` (m): `-d` on the normal unknowns of a finger pressed in by
//!   a prescribed approach `d`, and a viscoelastic body's history displacement
//!   ([`crate::model::viscoelasticity`]).
//! - `E x = e`: the equilibrium rows reduced to their range (thesis eqs. 48-49; 6 in 3-D, 3
//!   planar, fewer when contacts cannot resist some direction), then one row
//!   `sum_k F_k = P_i / Fu` per force-controlled finger, then one row `U_c' x - z_c = 0` per
//!   coordinate of each shared spring. Dense, `m x n` with `m <= 6 + fingers + springs'
//!   coordinates`. The first rows' multipliers are the object's rigid displacement and the
//!   approaches (see [`crate::solve::readout`]).
//! - Shared springs (`hands`, `servos`; [`crate::model::shared_spring`]): after the fingers'
//!   unknowns, each spring's load coordinates `z = D^-1 W / Fu` (`D` the length unit `Lu` on a
//!   moment, 1 on a force), free of any cone, with the block `D S D / Cu` of `P`: its
//!   complementary energy `1/2 W' S W` over `Fu^2 Cu`, as the fingers' is. Each is one more
//!   block of [`ConeProgram::blocks`] (cones [`FingerCones::Free`]).
//! - `K_k`, per finger ([`FingerCones`], one file per set in [`crate::program::cones`]): `F_k >= 0` (frictionless); the associated Coulomb cone
//!   `||G_k|| <= mu F_k` (energy model; planar: `|G_k| <= mu F_k`, thesis eqs. 21-24); or
//!   `F_k >= 0` with the Tresca disc `||G_k|| <= r_k`, radius fixed at the previous iterate
//!   (coulomb model).
//!
//! Loads live in `e`, Tresca radii and frozen friction coefficients in the cones, slip memory in
//! `q`: the sequential solve changes them in place through the `set_*` methods, and each backend
//! notices by itself what changed since its last solve.

use std::sync::Arc;

use nalgebra::DMatrix;
use rayon::prelude::*;

use crate::model::equilibrium::{MotionPlane, RowReduction, Wrench};
use crate::model::grasp_model::GraspModel;
use crate::model::spring_loads::for_each_unit_load;
use crate::program::cones::finger_cones::{ConeLaw, FingerCones};
use crate::scene::scene_format::ModelKind;

/// Largest floor on the Tresca radii Clarabel is given, in element force units `Fu` (the
/// floor is this or Clarabel's tolerance, whichever is smaller). A disc of radius 0
/// has no interior (it stalled Clarabel's interior-point method on the Cattaneo case of
/// `tests/cattaneo_mindlin.rs` at `Q = 0.5 mu P`); with the floor an unloaded element can
/// carry at most the floor of friction in Clarabel's answers, which shows as a cone violation
/// of that size. The program itself keeps the exact radii, which the native solver uses
/// (its projection onto a disc of radius 0 is exact).
pub const RADIUS_FLOOR: f64 = 1e-8;

/// One finger's part of the program.
#[derive(Debug, Clone, PartialEq)]
pub struct FingerBlock {
    /// Index of the finger's first unknown in `x`.
    pub offset: usize,
    /// Elements of the patch.
    pub elements: usize,
    /// Tangential unknowns per element: 0, 1 (planar) or 2.
    pub n_tangential: usize,
    /// The element constraint sets.
    pub cone: FingerCones,
}

impl FingerBlock {
    /// Unknowns of the block, `elements * (1 + n_tangential)`.
    pub fn len(&self) -> usize {
        self.elements * (1 + self.n_tangential)
    }
}

/// A shared spring's block of the program: its load coordinates' compliance.
#[derive(Debug, Clone)]
pub struct SpringBlock {
    /// `D S D` (m/N; `P`'s block is this times [`ConeProgram::compliance_scale`]).
    pub compliance_m_per_n: Arc<DMatrix<f64>>,
}

/// The equality row that fixes a force-controlled finger's total normal load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadRow {
    /// The finger's index in the model.
    pub finger: usize,
    /// Its row in the equality matrix (after the equilibrium rows).
    pub row: usize,
}

/// The assembled, scaled program.
#[derive(Debug, Clone)]
pub struct ConeProgram {
    /// Which cones bound the friction forces.
    pub(crate) law: ConeLaw,
    /// Per finger, scene order; then one per shared spring (its load coordinates).
    pub(crate) blocks: Vec<FingerBlock>,
    /// Per shared spring (model order), the compliance of its block: `blocks[fingers + s]`.
    pub(crate) springs: Vec<SpringBlock>,
    /// Total number of unknowns.
    pub(crate) n_unknowns: usize,
    /// `P = compliance_scale * C` (C in m/N): `1 / Cu`.
    pub(crate) compliance_scale: f64,
    /// Linear cost `q`.
    pub(crate) q: Vec<f64>,
    /// Per unknown, the displacement `o` added to the elastic one (m): prescribed approaches
    /// and viscoelastic history (module docs). Zero by default.
    pub(crate) offset_m: Vec<f64>,
    /// Per unknown, the slip memory `m` (m; zero on the normal unknowns).
    memory_m: Vec<f64>,
    /// Equality matrix `E` (`m x n`): reduced equilibrium rows, then load rows; shared with
    /// the native solver's finger blocks (it holds a column per unknown).
    pub(crate) equality: Arc<DMatrix<f64>>,
    /// Right-hand side `e` (for the loads last set).
    pub(crate) equality_rhs: Vec<f64>,
    /// Reduction of the equilibrium rows.
    pub(crate) reduction: RowReduction,
    /// The load equation of each force-controlled finger, in finger order.
    pub(crate) load_rows: Vec<LoadRow>,
    /// The external wrench of the last solve (N, N m about `O`): the model's and the step's
    /// extra one ([`crate::StepInputs`]).
    pub(crate) external_wrench: Wrench,
    /// Each finger's commanded approach of the last solve, m (0 where none).
    pub(crate) approach_m: Vec<f64>,
    /// The commanded hand poses of the last solve (also in the offsets): `(hand's index among
    /// the model's springs, [m; rad])`.
    pub(crate) hand_poses: Vec<(usize, [f64; 6])>,
    /// Scaled external wrench in equilibrium coordinates (`S w_ext / Fu`).
    pub(crate) external_scaled: Vec<f64>,
    /// Set when the external load has a component no contact force can resist: the reason.
    pub(crate) unbalanced: Option<String>,
}

impl ConeProgram {
    /// The program of `model` with the scene's prescribed loads and the cones of its contact
    /// law (the associated friction cone for the energy model, Tresca sets for coulomb), the
    /// friction coefficients at the loads' first guess ([`GraspModel::guess_loads`]).
    pub(crate) fn with_scene_loads(model: &GraspModel) -> ConeProgram {
        let loads = model.scene_loads_n();
        let law = match model.kind() {
            ModelKind::Energy => ConeLaw::Associated,
            ModelKind::Coulomb => ConeLaw::Tresca,
        };
        let mu = model.mu_at(&model.guess_loads(&loads));
        ConeProgram::assemble(model, &loads, law, &mu)
    }

    /// Assembles the program for `model` with prescribed loads `loads_n` (one per
    /// force-controlled finger, N; checked by the caller), cones of kind `law` and, for the
    /// associated law, friction coefficients `mu` (one per finger). Tresca radii start at 0.
    pub fn assemble(model: &GraspModel, loads_n: &[f64], law: ConeLaw, mu: &[f64]) -> ConeProgram {
        let s = model.scales;
        let mut blocks: Vec<FingerBlock> = model
            .fingers
            .iter()
            .zip(mu)
            .map(|(f, &m)| FingerBlock {
                offset: f.offset,
                elements: f.patch.len(),
                n_tangential: f.n_tangential,
                cone: FingerCones::of_law(law, f.n_tangential, f.patch.len(), m),
            })
            .collect();
        let e_hat = equilibrium_matrix(model);
        let reduction = RowReduction::new(&e_hat);
        let (mut equality, load_rows) = equality_matrix(model, &reduction, &e_hat);
        let springs = spring_blocks(model, &mut blocks, &mut equality);
        let n = equality.ncols();
        let mut program = ConeProgram {
            law,
            blocks,
            springs,
            n_unknowns: n,
            compliance_scale: 1.0 / s.compliance_m_per_n,
            q: vec![0.0; n],
            offset_m: vec![0.0; n],
            memory_m: vec![0.0; n],
            equality_rhs: vec![0.0; equality.nrows()],
            equality: Arc::new(equality),
            reduction,
            load_rows,
            external_wrench: model.external_wrench,
            approach_m: vec![0.0; model.fingers.len()],
            hand_poses: Vec::new(),
            external_scaled: Vec::new(),
            unbalanced: None,
        };
        program.set_external_wrench(model, &model.external_wrench);
        program.set_loads(model, loads_n);
        program.refresh_q(model);
        program
    }

    /// This program's data (rows, loads, wrench, law) over other blocks: `blocks` with the
    /// equality columns `equality`, `q` and the offsets zero (a coarse twin,
    /// [`crate::program::coarse_program`], writes its own).
    pub(crate) fn with_layout(
        &self,
        blocks: Vec<FingerBlock>,
        equality: Arc<DMatrix<f64>>,
    ) -> Self {
        let n = equality.ncols();
        ConeProgram {
            law: self.law,
            blocks,
            springs: self.springs.clone(),
            n_unknowns: n,
            compliance_scale: self.compliance_scale,
            q: vec![0.0; n],
            offset_m: vec![0.0; n],
            memory_m: vec![0.0; n],
            equality,
            equality_rhs: self.equality_rhs.clone(),
            reduction: self.reduction.clone(),
            load_rows: self.load_rows.clone(),
            external_wrench: self.external_wrench,
            approach_m: self.approach_m.clone(),
            hand_poses: self.hand_poses.clone(),
            external_scaled: self.external_scaled.clone(),
            unbalanced: self.unbalanced.clone(),
        }
    }

    /// `q` from the gaps, the offsets and the slip memory (module docs).
    fn refresh_q(&mut self, model: &GraspModel) {
        let du = model.scales.displacement_m();
        for f in &model.fingers {
            let ne = f.patch.len();
            for (k, gap) in f.patch.gap_m.iter().enumerate() {
                let j = f.offset + k;
                self.q[j] = (gap + self.offset_m[j]) / du;
            }
            for j in f.offset + ne..f.offset + f.n_unknowns() {
                self.q[j] = (self.offset_m[j] - self.memory_m[j]) / du;
            }
        }
    }

    /// The external wrench of the last solve (N, N m about `O`).
    pub fn external_wrench(&self) -> Wrench {
        self.external_wrench
    }

    /// Sets each finger's commanded approach (m; it is also in the offsets, see
    /// [`ConeProgram::set_offsets`]): the readout reports it as the finger's approach.
    pub fn set_approaches(&mut self, approach_m: &[f64]) {
        self.approach_m.copy_from_slice(approach_m);
    }

    /// Sets the commanded hand poses (their motion is also in the offsets, see
    /// [`ConeProgram::set_offsets`]): the readout tells it from a viscoelastic history.
    pub fn set_hand_poses(&mut self, poses: &[(usize, [f64; 6])]) {
        self.hand_poses = poses.to_vec();
    }

    /// Sets the offsets `o` (m, per unknown of the fingers; module docs) and rewrites `q`.
    pub fn set_offsets(&mut self, model: &GraspModel, offset_m: &[f64]) {
        let own = &mut self.offset_m[..offset_m.len()];
        if own != offset_m {
            own.copy_from_slice(offset_m);
            self.refresh_q(model);
        }
    }

    /// Overwrites the equilibrium rows of `e` with the external wrench `w_ext` (N, N m about
    /// `O`; thesis eqs. 48-49: `U' E_hat x = -U' S w_ext / Fu`) and re-checks that no
    /// component of it lies in a direction no contact resists.
    pub fn set_external_wrench(&mut self, model: &GraspModel, wrench: &Wrench) {
        let fu = model.scales.element_force_n;
        self.external_wrench = *wrench;
        self.external_scaled = model
            .equilibrium
            .apply(wrench)
            .iter()
            .map(|v| v / fu)
            .collect();
        self.unbalanced = unbalanced_reason(model, &self.reduction, &self.external_scaled);
        let basis = &self.reduction.basis;
        for r in 0..basis.ncols() {
            self.equality_rhs[r] = -(0..self.external_scaled.len())
                .map(|k| basis[(k, r)] * self.external_scaled[k])
                .sum::<f64>();
        }
    }

    /// Number of equilibrium rows kept after the reduction.
    pub fn equilibrium_rows(&self) -> usize {
        self.reduction.basis.ncols()
    }

    /// Number of equality rows (equilibrium, then loads, then shared springs).
    pub fn equality_rows(&self) -> usize {
        self.equality.nrows()
    }

    /// Energy model: the friction coefficients `mu` (one per finger) of the cones.
    pub fn set_mu(&mut self, mu: &[f64]) {
        for (b, &m) in self.blocks.iter_mut().zip(mu) {
            b.cone.set_mu(m);
        }
    }

    /// The friction coefficient of each finger's cones (0 for other cones).
    pub fn mu(&self) -> Vec<f64> {
        self.finger_blocks().iter().map(|b| b.cone.mu()).collect()
    }

    /// The fingers' unknowns, those before the shared springs' coordinates: the element
    /// forces, to whose size the solvers' tolerances are relative (a spring's coordinates are
    /// whole loads in element force units, larger by the elements that share them).
    pub fn finger_unknowns(&self) -> usize {
        let springs = &self.blocks[self.blocks.len() - self.springs.len()..];
        springs.first().map_or(self.n_unknowns, |b| b.offset)
    }

    /// The fingers' blocks (those before the shared springs').
    pub fn finger_blocks(&self) -> &[FingerBlock] {
        &self.blocks[..self.blocks.len() - self.springs.len()]
    }

    /// Coulomb model: the Tresca radii `r_k` (N; per finger, per element).
    pub fn set_radii(&mut self, model: &GraspModel, radii_n: &[Vec<f64>]) {
        let fu = model.scales.element_force_n;
        for (b, r) in self.blocks.iter_mut().zip(radii_n) {
            b.cone.set_radii(r, fu);
        }
    }

    /// Writes the slip memory `m` (m; per finger, per element `[t1, t2]`) into `q`:
    /// `q_G = (o_t - m) / (Fu Cu)`, so that a sticking element keeps its relative tangential
    /// displacement `w_k = m_k` (model.md, "coulomb").
    pub fn set_slip_memory(&mut self, model: &GraspModel, memory_m: &[Vec<[f64; 2]>]) {
        for (i, f) in model.fingers.iter().enumerate() {
            let ne = f.patch.len();
            for c in 0..f.n_tangential {
                for (k, m) in memory_m[i].iter().enumerate().take(ne) {
                    self.memory_m[f.offset + (c + 1) * ne + k] = m[c];
                }
            }
        }
        self.refresh_q(model);
    }

    /// Overwrites the load rows of `e` (N, one per force-controlled finger).
    pub fn set_loads(&mut self, model: &GraspModel, loads_n: &[f64]) {
        for (j, &LoadRow { row, .. }) in self.load_rows.iter().enumerate() {
            self.equality_rhs[row] = loads_n[j] / model.scales.element_force_n;
        }
    }
}

/// The scaled equilibrium matrix `E_hat = S W` (rows x n): column `j` is the scaled wrench of a
/// unit force in unknown `j` (thesis eqs. 48-49).
fn equilibrium_matrix(model: &GraspModel) -> DMatrix<f64> {
    let rows = model.equilibrium.rows();
    let mut e_hat = zeros(rows, model.n_unknowns);
    if rows == 0 {
        return e_hat;
    }
    let columns = e_hat.as_mut_slice();
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        let block = &mut columns[f.offset * rows..(f.offset + (f.n_tangential + 1) * ne) * rows];
        // Column `c ne + k` is unknown `(k, c)`'s wrench: each column on its own (a fine
        // patch's million on all cores).
        block
            .par_chunks_mut(rows)
            .with_min_len(COLUMNS_PER_TASK)
            .enumerate()
            .for_each(|(j, col)| {
                let w = model
                    .equilibrium
                    .apply(&model.unit_wrench(i, j % ne, j / ne));
                col.copy_from_slice(&w);
            });
    }
    e_hat
}

/// A `rows x cols` zero matrix, its zeros written on all cores for a wide one (the first write
/// of a fine patch's equality rows, tens of megabytes, is where their pages are mapped).
fn zeros(rows: usize, cols: usize) -> DMatrix<f64> {
    let mut v = Vec::new();
    crate::allocation::resize_on_all_cores(&mut v, rows * cols, 0.0);
    DMatrix::from_vec(rows, cols, v)
}

/// Columns of the equality rows one task forms.
const COLUMNS_PER_TASK: usize = 4096;

/// `a b` for a `b` with many columns: per [`COLUMNS_PER_TASK`] of them on all cores (each
/// column's product is the same arithmetic as in the whole product).
fn times_columns(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let (rows, n) = (a.nrows(), b.ncols());
    if rows == 0 || n < 2 * COLUMNS_PER_TASK {
        return a * b;
    }
    let mut out = zeros(rows, n);
    let chunk = rows * COLUMNS_PER_TASK;
    out.as_mut_slice()
        .par_chunks_mut(chunk)
        .enumerate()
        .for_each(|(c, part)| {
            let product = a * b.columns(c * COLUMNS_PER_TASK, part.len() / rows);
            part.copy_from_slice(product.as_slice());
        });
    out
}

/// `E`: the reduced equilibrium rows `U' E_hat`, then one load row per force-controlled
/// finger; returns it with the `(finger, row)` of each load row.
fn equality_matrix(
    model: &GraspModel,
    reduction: &RowReduction,
    e_hat: &DMatrix<f64>,
) -> (DMatrix<f64>, Vec<LoadRow>) {
    let e_red = times_columns(&reduction.basis.transpose(), e_hat);
    let r_eq = e_red.nrows();
    let fc = model.force_controlled();
    let rows = r_eq + fc.len();
    let load_rows: Vec<LoadRow> = fc
        .iter()
        .enumerate()
        .map(|(j, &i)| LoadRow {
            finger: i,
            row: r_eq + j,
        })
        .collect();
    // Per load row, the columns of its finger's normal unknowns.
    let loads: Vec<(usize, std::ops::Range<usize>)> = load_rows
        .iter()
        .map(|l| {
            let f = &model.fingers[l.finger];
            (l.row, f.offset..f.offset + f.patch.len())
        })
        .collect();
    let mut e = zeros(rows, model.n_unknowns);
    if rows > 0 {
        // Column by column (a fine patch's million on all cores): the reduced equilibrium
        // rows' entries, then a 1 in the load row of a force-controlled normal unknown.
        e.as_mut_slice()
            .par_chunks_mut(rows)
            .with_min_len(COLUMNS_PER_TASK)
            .enumerate()
            .for_each(|(j, col)| {
                col[..r_eq].copy_from_slice(&e_red.as_slice()[j * r_eq..(j + 1) * r_eq]);
                for (row, columns) in &loads {
                    if columns.contains(&j) {
                        col[*row] = 1.0;
                    }
                }
            });
    }
    (e, load_rows)
}

/// The shared springs' blocks: one block of free coordinates per spring appended to `blocks`
/// and its rows `U_c' x / d_c - z_c = 0` appended to `equality` (module docs), which gains the
/// coordinates' columns.
fn spring_blocks(
    model: &GraspModel,
    blocks: &mut Vec<FingerBlock>,
    equality: &mut DMatrix<f64>,
) -> Vec<SpringBlock> {
    if model.springs.is_empty() {
        return Vec::new();
    }
    let coordinates: usize = model.springs.iter().map(|s| s.coordinates()).sum();
    let (rows0, n0) = (equality.nrows(), equality.ncols());
    let mut e = zeros(rows0 + coordinates, n0 + coordinates);
    e.view_mut((0, 0), (rows0, n0)).copy_from(&*equality);
    let mut out = Vec::with_capacity(model.springs.len());
    let (mut row, mut col) = (rows0, n0);
    for spring in &model.springs {
        let h = spring.coordinates();
        let lu = model.scales.length_m;
        let length_m: Vec<f64> = (0..h)
            .map(|c| if spring.is_moment(c) { lu } else { 1.0 })
            .collect();
        for_each_unit_load(model, spring, |j, load| {
            for c in 0..h {
                e[(row + c, j)] = load[c] / length_m[c];
            }
        });
        let d = DMatrix::from_fn(h, h, |r, c| {
            length_m[r] * spring.compliance()[(r, c)] * length_m[c]
        });
        for c in 0..h {
            e[(row + c, col + c)] = -1.0;
        }
        blocks.push(FingerBlock {
            offset: col,
            elements: h,
            n_tangential: 0,
            cone: FingerCones::Free,
        });
        out.push(SpringBlock {
            compliance_m_per_n: Arc::new(d),
        });
        row += h;
        col += h;
    }
    *equality = e;
    out
}

/// A component of the scaled external wrench that no contact force can produce is reported
/// when it exceeds this fraction of the wrench (smaller ones are round-off of the row reduction).
const UNBALANCED_FRACTION: f64 = 1e-9;

/// If the scaled external wrench has a component no contact force can produce, says which.
fn unbalanced_reason(model: &GraspModel, red: &RowReduction, w: &[f64]) -> Option<String> {
    let norm_w = w.iter().map(|v| v * v).sum::<f64>().sqrt();
    let rows = w.len();
    for c in 0..red.null.ncols() {
        let u: Vec<f64> = (0..rows).map(|r| red.null[(r, c)]).collect();
        let comp: f64 = u.iter().zip(w).map(|(a, b)| a * b).sum();
        if comp.abs() > UNBALANCED_FRACTION * norm_w.max(f64::MIN_POSITIVE) {
            // Express the unresisted direction in the world frame.
            let (force, moment) = match model.plane() {
                None => ([u[0], u[1], u[2]], [u[3], u[4], u[5]]),
                Some(MotionPlane { e1, e2, normal: p }) => {
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
