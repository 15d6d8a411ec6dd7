//! Sensitivities of a solved grasp: the derivatives of every finger's normal and
//! friction force, and of every element's force, with respect to an extra wrench on the
//! object and to each force-controlled finger's commanded load, from the KKT system at the
//! solution's active set (`solver::native::newton::kkt_derivative`), not from finite differences.
//!
//! Parameters (the columns), all in SI:
//! - a force at the centre of mass along a world axis (3-D: `x`, `y`, `z`; planar: the plane's
//!   in-plane axes `e1`, `e2`), derivatives in N per N;
//! - a couple about a world axis (3-D: `x`, `y`, `z`; planar: the plane normal), in N per N m;
//! - the commanded normal load of each force-controlled finger, in N per N;
//! - `squeeze`: every commanded load scaled by a common factor `lambda` (a gripper squeezing
//!   harder), derivative at `lambda = 1` in N per unit of `lambda`. It often exists where the
//!   single loads' do not (raising one pad of a pinch alone leaves no equilibrium);
//! - on request ([`LoadDirection`]), `loads:<name>`: the commanded loads of some fingers
//!   moved together, each by its own rate (N per unit; a gripper's two jaws), derivative per
//!   unit of the common parameter;
//! - `approach:<finger>`: the commanded approach of each position-controlled finger (`control
//!   {"approach_m": d}`, or held: at 0), in N per m: it shifts the finger's gaps (`q`);
//! - `k_n:<finger>`, `k_t:<finger>`, `k_r:<finger>`: each stiffness a finger's mount gives
//!   (N per N/m; N per N m/rad), or `k_scale:<finger>`, a common factor on a mount's full
//!   matrix (N per unit factor): it changes the compliance `B'SB`, which at the solution acts
//!   as the linear cost change `B' dS (w - w0)` (`crate::model::finger_mount`).
//!
//! The derivative holds while no element changes state. Elements whose projection input lies
//! within [`NEAR_CHANGE`] of a boundary between stick, slip and separation are listed: there
//! the one-sided derivatives differ and these numbers are one of them. The friction
//! coefficient of a load-dependent law is held at its value at the solution (its change with
//! the load is not differentiated; a note says so).

use nalgebra::{DMatrix, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::model::equilibrium::MotionPlane;
use crate::model::finger_mount::StiffnessParameter;
use crate::model::grasp_model::{Control, GraspModel};
use crate::model::shared_spring::SpringParameter;
use crate::model::spring_loads::spring_loads;
use crate::program::cone_program::LoadRow;
use crate::solve::solution::Solution;
use crate::solver::native::newton::kkt_derivative::kkt_derivative;
use crate::solver::program_solver::ProgramSolver;

/// A parameter's wrench direction is unresisted when its part outside the span of the contact
/// wrenches exceeds this fraction of it (smaller parts are round-off of the row reduction).
const UNRESISTED_FRACTION: f64 = 1e-9;

/// Largest dense system (GiB) a message still offers as the way out: beyond it the grid is
/// too fine for the dense path as well.
const DENSE_WITHIN_REACH_GIB: f64 = 4.0;

/// Distance (relative to the largest scaled force) of an element's projection input from a
/// state boundary below which the element is reported as about to change state.
pub const NEAR_CHANGE: f64 = 1e-6;

/// Fraction of a parameter's right-hand side the active set cannot produce above which its
/// derivative is reported as undefined.
const UNDEFINED: f64 = 1e-6;

/// What a column differentiates with respect to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// Short name: `force_x`, `torque_z`, `force_e1`, `load:<finger>`, `squeeze`,
    /// `approach:<finger>`, `k_n:<finger>`.
    pub name: String,
    /// `force` (N at the centre of mass), `torque` (N m), `load` (N), `squeeze` (the factor
    /// of all commanded loads, dimensionless), `loads` (a [`LoadDirection`]'s parameter),
    /// `approach` (m) or `stiffness` (N/m, N m/rad, or a matrix's factor).
    pub kind: String,
    /// World direction of the force or torque axis (absent for loads).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
    /// False when no derivative exists (the grasp is at a limit along it, or no contact resists
    /// it); the finger and element derivatives of this column are then 0.
    pub defined: bool,
    /// Why the derivative does not exist.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// Derivatives of one finger's forces, one entry per parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FingerSensitivity {
    /// Finger name.
    pub name: String,
    /// `dP_i / dp`: total normal force (N per parameter unit).
    pub normal_force: Vec<f64>,
    /// `dQ_i / dp`: total friction force, world frame (N per parameter unit).
    pub tangential_force: Vec<[f64; 3]>,
    /// `dF_k / dp` per element (row-major, as in the solution), per parameter.
    pub element_normal_force: Vec<Vec<f64>>,
    /// `dG_k / dp` along `[t1, t2]` per element, per parameter.
    pub element_tangential_force: Vec<Vec<[f64; 2]>>,
}

/// An element close to a change of state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NearChange {
    /// Finger name.
    pub finger: String,
    /// Element grid index `[i, j]`.
    pub index: [usize; 2],
    /// `stick/slip` or `contact/separation`.
    pub transition: String,
    /// Distance from the boundary relative to the largest scaled force.
    pub distance_relative: f64,
}

/// A combination of commanded loads moved by one parameter: `dL_i = rate` for each named
/// finger (N per unit of the parameter); fingers absent from the model are left out.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadDirection {
    /// Its parameter's name, after `loads:`.
    pub name: String,
    /// `(finger, dL/dparameter)` pairs, N per unit.
    pub rates: Vec<(String, f64)>,
}

/// The sensitivities of one solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sensitivities {
    /// The columns.
    pub parameters: Vec<Parameter>,
    /// Per finger, scene order.
    pub fingers: Vec<FingerSensitivity>,
    /// Elements at a state boundary: the derivatives are one-sided there.
    pub near_changes: Vec<NearChange>,
    /// Assumptions the user should know.
    pub notes: Vec<String>,
}

/// The parameters of `model` with their world wrenches about `O` (unit force or couple).
fn wrench_parameters(model: &GraspModel) -> Vec<(Parameter, Option<nalgebra::Vector6<f64>>)> {
    let axes: Vec<(String, &str, Vector3<f64>)> = match model.plane() {
        None => ["x", "y", "z"]
            .iter()
            .enumerate()
            .flat_map(|(c, a)| {
                let mut v = Vector3::zeros();
                v[c] = 1.0;
                [
                    (format!("force_{a}"), "force", v),
                    (format!("torque_{a}"), "torque", v),
                ]
            })
            .collect(),
        Some(MotionPlane { e1, e2, normal: p }) => vec![
            ("force_e1".into(), "force", e1),
            ("force_e2".into(), "force", e2),
            ("torque_normal".into(), "torque", p),
        ],
    };
    let mut out: Vec<_> = axes
        .into_iter()
        .map(|(name, kind, v)| {
            let zero = Vector3::zeros();
            let w = if kind == "force" {
                model.wrench_at_center_of_mass(&v, &zero)
            } else {
                model.wrench_at_center_of_mass(&zero, &v)
            };
            let p = Parameter {
                name,
                kind: kind.into(),
                direction: Some([v.x, v.y, v.z]),
                defined: true,
                reason: None,
            };
            (p, Some(w))
        })
        .collect();
    out.sort_by_key(|(p, _)| p.kind != "force");
    let commanded = model.force_controlled();
    for &i in &commanded {
        let p = Parameter {
            name: format!("load:{}", model.fingers[i].name),
            kind: "load".into(),
            direction: None,
            defined: true,
            reason: None,
        };
        out.push((p, None));
    }
    if !commanded.is_empty() {
        out.push((
            Parameter {
                name: "squeeze".into(),
                kind: "squeeze".into(),
                direction: None,
                defined: true,
                reason: None,
            },
            None,
        ));
    }
    out
}

/// The right-hand side columns (`m x p`, scaled like `e`) of the parameters; marks those with a
/// component no contact resists.
fn rhs_columns(
    model: &GraspModel,
    ps: &ProgramSolver,
    params: &mut [(Parameter, Option<nalgebra::Vector6<f64>>)],
    directions: &[LoadDirection],
) -> DMatrix<f64> {
    let program = &ps.program;
    let fu = model.scales.element_force_n;
    let red = &program.reduction;
    let mut rhs = DMatrix::zeros(program.equality_rows(), params.len());
    let mut load = 0;
    for (c, (p, w)) in params.iter_mut().enumerate() {
        match w {
            Some(w) => {
                let s: Vec<f64> = model.equilibrium.apply(w).iter().map(|v| v / fu).collect();
                let norm = s.iter().map(|v| v * v).sum::<f64>().sqrt();
                for r in 0..red.basis.ncols() {
                    rhs[(r, c)] = -(0..s.len()).map(|k| red.basis[(k, r)] * s[k]).sum::<f64>();
                }
                let off: f64 = (0..red.null.ncols())
                    .map(|j| {
                        (0..s.len())
                            .map(|k| red.null[(k, j)] * s[k])
                            .sum::<f64>()
                            .powi(2)
                    })
                    .sum::<f64>()
                    .sqrt();
                if off > UNRESISTED_FRACTION * norm {
                    p.defined = false;
                    p.reason = Some("no contact force can resist this direction".into());
                }
            }
            None if p.kind == "approach" || p.kind == "stiffness" => {}
            None if p.kind == "squeeze" => {
                for &LoadRow { row, .. } in &program.load_rows {
                    rhs[(row, c)] = program.equality_rhs[row];
                }
            }
            None if p.kind == "loads" => {
                let d = directions
                    .iter()
                    .find(|d| p.name == format!("loads:{}", d.name));
                for (name, rate) in d.map_or(&[][..], |d| &d.rates[..]) {
                    let at = program
                        .load_rows
                        .iter()
                        .find(|l| model.fingers[l.finger].name == *name);
                    if let Some(l) = at {
                        rhs[(l.row, c)] = rate / fu;
                    }
                }
            }
            None => {
                rhs[(program.load_rows[load].row, c)] = 1.0 / fu;
                load += 1;
            }
        }
    }
    rhs
}

/// Per finger the coefficient of the Tresca radii at the solution's loads.
fn radius_coefficients(model: &GraspModel, ps: &ProgramSolver, solution: &Solution) -> Vec<f64> {
    let loads: Vec<f64> = solution.fingers.iter().map(|f| f.normal_force_n).collect();
    let mu = model.mu_at(&loads);
    ps.program
        .blocks
        .iter()
        .zip(mu)
        .map(|(b, m)| if b.cone.is_tresca() { m } else { 0.0 })
        .collect()
}

/// The sensitivities of `solution`, the last answer of `ps` for `model`.
pub(crate) fn sensitivities(
    ps: &mut ProgramSolver,
    model: &GraspModel,
    solution: &Solution,
    directions: &[LoadDirection],
) -> Result<Sensitivities, ModelError> {
    let iterate = match (solution.status.has_forces(), ps.last()) {
        (true, Some(it)) => it.clone(),
        _ => return Err(ModelError::NoSolution),
    };
    refuse_fine_fft(model)?;
    let mut params = wrench_parameters(model);
    params.extend(directions.iter().map(load_direction_parameter));
    let costs = cost_parameters(model);
    params.extend(costs.iter().map(|(p, _)| (p.clone(), None)));
    let rhs = rhs_columns(model, ps, &mut params, directions);
    let dq = cost_columns(model, &iterate.x, &costs);
    let mu = radius_coefficients(model, ps, solution);
    // The element forces' size (a shared spring's coordinates, whole loads, left out).
    let forces = &iterate.x[..ps.program.finger_unknowns()];
    let scale = forces.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let near = NEAR_CHANGE * scale.max(f64::MIN_POSITIVE);
    let (native, program) = ps.native_workspace(model);
    let deriv = kkt_derivative(native.blocks(), program, &iterate, &mu, &rhs, &dq, near)
        .map_err(ModelError::Derivative)?;
    for ((p, _), &u) in params.iter_mut().zip(&deriv.unreachable) {
        if p.defined && deriv.ambiguous {
            p.defined = false;
            p.reason = Some(
                "the grasp is at a limit: the object can move (slide as a whole) without a \
                 change of the forces' equilibrium, and the forces' derivative is not \
                 determined there"
                    .into(),
            );
        } else if p.defined && u > UNDEFINED {
            p.defined = false;
            p.reason = Some(format!(
                "the grasp is at a limit: {:.0}% of this direction cannot be taken by the \
                 current stick, slip and separation sets",
                100.0 * u
            ));
        }
    }
    let fu = model.scales.element_force_n;
    let defined: Vec<bool> = params.iter().map(|(p, _)| p.defined).collect();
    let dx = |row: usize, c: usize| {
        if defined[c] {
            fu * deriv.dx[(row, c)]
        } else {
            0.0
        }
    };
    let fingers = model
        .fingers
        .iter()
        .map(|f| finger_sensitivity(f, params.len(), &dx))
        .collect();
    let near_changes = near_changes(model, &deriv.margins, scale);
    Ok(Sensitivities {
        parameters: params.into_iter().map(|(p, _)| p).collect(),
        fingers,
        near_changes,
        notes: notes(model),
    })
}

/// What changes the linear cost `q`: a finger's commanded approach, or a stiffness of its mount.
#[derive(Debug, Clone, Copy, PartialEq)]
enum CostChange {
    /// The approach of finger `i`.
    Approach(usize),
    /// A stiffness of finger `i`'s mount.
    Stiffness(usize, StiffnessParameter),
    /// A stiffness of shared spring `s` (a hand, a servo).
    Spring(usize, SpringParameter),
}

/// The parameters that change `q`: per finger in scene order, its approach when it is
/// position-controlled (held included), then its mount's stiffnesses; then each hand's and
/// servo's stiffnesses.
fn cost_parameters(model: &GraspModel) -> Vec<(Parameter, CostChange)> {
    let parameter = |name: String, kind: &str| Parameter {
        name,
        kind: kind.into(),
        direction: None,
        defined: true,
        reason: None,
    };
    let mut out = Vec::new();
    for (i, f) in model.fingers.iter().enumerate() {
        // Held is position-controlled at approach 0: its approach is a parameter as any.
        if !matches!(f.control(), Control::NormalLoad { .. }) {
            let p = parameter(format!("approach:{}", f.name), "approach");
            out.push((p, CostChange::Approach(i)));
        }
        for &k in f.mount().map_or(&[][..], |m| m.stiffness_parameters()) {
            let p = parameter(format!("{}:{}", k.name(), f.name), "stiffness");
            out.push((p, CostChange::Stiffness(i, k)));
        }
    }
    for (j, spring) in model.springs.iter().enumerate() {
        for &k in spring.stiffness_parameters() {
            let p = parameter(format!("{}:{}", k.name(), spring.name()), "stiffness");
            out.push((p, CostChange::Spring(j, k)));
        }
    }
    out
}

/// The linear cost changes `dq` (`n x costs`, scaled like `q`: m over `Fu Cu`) of the
/// `costs` (the last parameters) at the scaled forces `x`.
fn cost_columns(model: &GraspModel, x: &[f64], costs: &[(Parameter, CostChange)]) -> DMatrix<f64> {
    // The shared springs' coordinates follow the fingers' unknowns (`program/cone_program.rs`).
    let n = model.n_unknowns + model.springs.iter().map(|s| s.coordinates()).sum::<usize>();
    let mut dq = DMatrix::zeros(n, costs.len());
    let (fu, unit) = (model.scales.element_force_n, model.scales.displacement_m());
    for (c, (_, change)) in costs.iter().enumerate() {
        let mut column = vec![0.0; n];
        match *change {
            // The offset `-d` on every normal unknown.
            CostChange::Approach(i) => {
                let f = &model.fingers[i];
                for v in &mut column[f.offset..f.offset + f.patch.len()] {
                    *v = -1.0 / unit;
                }
            }
            // `B' dS (w - w0)`, the forces in newtons.
            CostChange::Stiffness(i, k) => {
                let f = &model.fingers[i];
                let range = f.offset..f.offset + f.n_unknowns();
                let v: Vec<f64> = x[range.clone()].iter().map(|x| x * fu).collect();
                if let Some(m) = f.mount() {
                    let motion = m.retreat_per_stiffness(&v, k);
                    m.add_motion(&motion, 1.0 / unit, &mut column[range]);
                }
            }
            CostChange::Spring(j, k) => spring_cost_change(model, x, j, k, &mut column),
        }
        dq.set_column(c, &nalgebra::DVector::from_vec(column));
    }
    dq
}

/// Writes into `column` (scaled like `q`) the change of shared spring `j`'s cost per unit of
/// its stiffness `k` at the scaled forces `x`: on its coordinates `D dS W / (Fu Cu)` with `W`
/// its load (N, N m) and `D` the length unit on a moment (its block `D S D / Cu` of `P` times
/// its coordinates `z = D^-1 W / Fu`).
fn spring_cost_change(
    model: &GraspModel,
    x: &[f64],
    j: usize,
    k: SpringParameter,
    column: &mut [f64],
) {
    let (fu, unit) = (model.scales.element_force_n, model.scales.displacement_m());
    let x_n: Vec<f64> = x[..model.n_unknowns].iter().map(|v| v * fu).collect();
    let offset = model.n_unknowns
        + model.springs[..j]
            .iter()
            .map(|s| s.coordinates())
            .sum::<usize>();
    let spring = &model.springs[j];
    let w = &spring_loads(model, &x_n)[j];
    for (c, d) in spring.retreat_per_stiffness(w, k).iter().enumerate() {
        let length = if spring.is_moment(c) {
            model.scales.length_m
        } else {
            1.0
        };
        column[offset + c] = length * d / unit;
    }
}

/// Refuses a finger on the FFT compliance too large for the derivative's dense system, with
/// the way out: a dense compliance where it fits, a coarser grid where it does not.
fn refuse_fine_fft(model: &GraspModel) -> Result<(), ModelError> {
    let Some(f) = model.fingers.iter().find(|f| f.is_matrix_free()) else {
        return Ok(());
    };
    // The derivative's system is dense in the free directions (n_free^2 entries).
    let n = f.n_unknowns();
    let gib = (n as f64).powi(2) * 8.0 / (1u64 << 30) as f64;
    let fix = if gib <= DENSE_WITHIN_REACH_GIB {
        format!(
            "set `{}` to dense for them",
            crate::option_names::COMPLIANCE
        )
    } else {
        "the grid is too fine for them (a dense compliance would hold as much): coarsen \
             its `patch.grid`"
            .to_string()
    };
    Err(ModelError::Derivative(format!(
        "finger `{}` has {n} unknowns on the FFT compliance, too many for the dense system \
             of the derivative ({gib:.1} GiB); sensitivities need a matrix: {fix}",
        f.name
    )))
}

/// The parameter column of a [`LoadDirection`] (`loads:<name>`).
fn load_direction_parameter(d: &LoadDirection) -> (Parameter, Option<nalgebra::Vector6<f64>>) {
    let p = Parameter {
        name: format!("loads:{}", d.name),
        kind: "loads".into(),
        direction: None,
        defined: true,
        reason: None,
    };
    (p, None)
}

/// One finger's derivatives from `dx(row, column)` (N per parameter unit).
fn finger_sensitivity(
    f: &crate::model::grasp_model::FingerModel,
    columns: usize,
    dx: &dyn Fn(usize, usize) -> f64,
) -> FingerSensitivity {
    let ne = f.patch.len();
    let comp = |k: usize, c: usize, p: usize| {
        if c <= f.n_tangential {
            dx(f.offset + c * ne + k, p)
        } else {
            0.0
        }
    };
    let element_normal_force: Vec<Vec<f64>> = (0..ne)
        .map(|k| (0..columns).map(|p| comp(k, 0, p)).collect())
        .collect();
    let element_tangential_force: Vec<Vec<[f64; 2]>> = (0..ne)
        .map(|k| {
            (0..columns)
                .map(|p| [comp(k, 1, p), comp(k, 2, p)])
                .collect()
        })
        .collect();
    let normal_force = (0..columns)
        .map(|p| (0..ne).map(|k| element_normal_force[k][p]).sum())
        .collect();
    let tangential_force = (0..columns)
        .map(|p| {
            let (g1, g2): (f64, f64) = (0..ne).fold((0.0, 0.0), |(a, b), k| {
                let g = element_tangential_force[k][p];
                (a + g[0], b + g[1])
            });
            let q = f.frame.t1 * g1 + f.frame.t2 * g2;
            [q.x, q.y, q.z]
        })
        .collect();
    FingerSensitivity {
        name: f.name.clone(),
        normal_force,
        tangential_force,
        element_normal_force,
        element_tangential_force,
    }
}

fn near_changes(
    model: &GraspModel,
    margins: &[Vec<crate::program::cones::element_set::StateMargin>],
    scale: f64,
) -> Vec<NearChange> {
    let mut out = Vec::new();
    for (f, m) in model.fingers.iter().zip(margins) {
        for (k, s) in m.iter().enumerate() {
            if s.distance <= NEAR_CHANGE * scale.max(f64::MIN_POSITIVE) {
                let ny = f.patch.grid.ny;
                out.push(NearChange {
                    finger: f.name.clone(),
                    index: [k / ny, k % ny],
                    transition: if s.stick_slip {
                        "stick/slip"
                    } else {
                        "contact/separation"
                    }
                    .into(),
                    distance_relative: s.distance / scale.max(f64::MIN_POSITIVE),
                });
            }
        }
    }
    out
}

fn notes(model: &GraspModel) -> Vec<String> {
    let mut notes = Vec::new();
    if model
        .fingers
        .iter()
        .any(|f| f.n_tangential > 0 && !f.friction.is_constant())
    {
        notes.push(
            "load-dependent friction: mu is held at its value at the solution's loads (its \
             change with the load is not differentiated)"
                .into(),
        );
    }
    if model.kind() == crate::scene::scene_format::ModelKind::Coulomb {
        notes.push(
            "coulomb model: derivatives of this step's result with the slip memory at the start \
             of the step held fixed (the Tresca radii follow mu F_k)"
                .into(),
        );
    }
    notes
}
