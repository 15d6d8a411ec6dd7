//! The solution of a grasp, in SI units: element forces, finger resultants, the object's
//! rigid displacement, residuals and solver statistics.

use serde::{Deserialize, Serialize};

use crate::residuals::Residuals;

/// What the solve concluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolveStatus {
    /// Solved to the requested tolerance.
    Solved,
    /// Solved to reduced accuracy (Clarabel's "almost solved"); check the residuals.
    ReducedAccuracy,
    /// The fingers cannot hold the object in equilibrium (friction too low, or a direction no
    /// contact resists).
    NoEquilibrium,
    /// The solver stopped without an answer (iteration or time limit, numerical trouble).
    NoConvergence,
}

impl SolveStatus {
    /// True when the solution carries forces.
    pub fn has_forces(&self) -> bool {
        matches!(self, SolveStatus::Solved | SolveStatus::ReducedAccuracy)
    }
}

/// Contact state of one element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ElementState {
    /// In contact, friction force inside the cone, no relative tangential motion.
    Stick,
    /// In contact, friction force on the cone, sliding opposite to it. Contact elements of a
    /// frictionless finger are counted here (nothing resists their sliding).
    Slip,
    /// Not carrying load.
    Separated,
}

/// One patch element.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ElementSolution {
    /// Grid index `[i, j]` (`i` along `t1`), row-major `k = i ny + j`.
    pub index: [usize; 2],
    /// Centre in patch coordinates `[x, y]` along `t1`, `t2`, m.
    pub local_m: [f64; 2],
    /// Centre in the world frame, m.
    pub position_m: [f64; 3],
    /// Normal force `F_k` along the finger's inward normal, N.
    pub normal_force_n: f64,
    /// Tangential force `G_k` along `[t1, t2]`, N.
    pub tangential_force_n: [f64; 2],
    /// Mean pressure `F_k / A`, Pa.
    pub pressure_pa: f64,
    /// Mean traction `G_k / A` along `[t1, t2]`, Pa.
    pub traction_pa: [f64; 2],
    /// Gap after loading, m (`c_k + u_k - approach`; 0 in stick, `mu |slip|` in slip).
    pub gap_m: f64,
    /// Relative tangential displacement of the object with respect to the finger, along
    /// `[t1, t2]`, m. Energy model: 0 in stick, the slip (opposite the friction force) in slip.
    /// Coulomb model: the accumulated slip, which is the slip memory carried to the next step.
    pub slip_m: [f64; 2],
    /// Slip of this step along `[t1, t2]`, m: `slip_m` minus the memory at the start of the
    /// step (equal to `slip_m` in the energy model). Zero in stick, opposite the friction force
    /// in slip.
    pub step_slip_m: [f64; 2],
    /// Contact state.
    pub state: ElementState,
}

/// Resultants of one finger.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FingerSolution {
    /// Finger name.
    pub name: String,
    /// Total normal force `P_i = sum_k F_k` along the inward normal, N.
    pub normal_force_n: f64,
    /// Total tangential (friction) force `Q_i` in the world frame, N.
    pub tangential_force_n: [f64; 3],
    /// `|Q_i|`, N.
    pub tangential_magnitude_n: f64,
    /// Torsional moment about the normal through the contact point, N m (right-handed about
    /// the inward normal).
    pub torsional_moment_nm: f64,
    /// Centre of pressure, world frame, m (the contact point if the finger carries no load).
    pub center_of_pressure_m: [f64; 3],
    /// Area of the elements in contact, m^2.
    pub contact_area_m2: f64,
    /// Largest element pressure, Pa.
    pub peak_pressure_pa: f64,
    /// Friction coefficient `mu(P_i)` of the finger's law at its load (dimensionless).
    pub friction_coefficient: f64,
    /// `|Q_i| / (mu P_i)`: 1 when the whole finger slides (0 if frictionless or unloaded).
    pub friction_utilization: f64,
    /// Fraction of `P` carried by the patch's boundary ring of elements (thesis 2.2.1: above
    /// zero for a curved contact means the patch is too small).
    pub boundary_load_fraction: f64,
    /// Approach of the finger along its inward normal, m: the prescribed-load multiplier for
    /// a force-controlled finger, 0 for a held finger (the reference).
    pub approach_m: f64,
    /// Elements in stick.
    pub stick_count: usize,
    /// Elements in slip.
    pub slip_count: usize,
    /// Elements separated.
    pub separated_count: usize,
    /// Element fields, row-major.
    pub elements: Vec<ElementSolution>,
}

/// Small rigid displacement of the object (from the equilibrium multipliers).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidDisplacement {
    /// Translation of the centre of mass, m (world frame).
    pub translation_m: [f64; 3],
    /// Small rotation vector, rad (world frame).
    pub rotation_rad: [f64; 3],
}

/// Solver statistics.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SolverStats {
    /// Interior-point iterations (all convex solves).
    pub iterations: u32,
    /// Time inside Clarabel, s.
    pub solver_time_s: f64,
    /// Unknowns of the program.
    pub unknowns: usize,
    /// Equality rows (equilibrium after reduction, plus load rows).
    pub equality_rows: usize,
    /// Conic rows (nonnegative and second-order).
    pub cone_rows: usize,
}

/// How the sequential (fixed-point) solve went: the coulomb model, and the energy model with a
/// load-dependent `mu`, solve a sequence of convex programs with the Tresca radii or `mu`
/// frozen at the previous iterate (model.md, "coulomb", "Load-dependent friction").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SequentialReport {
    /// Convex solves of the last (successful or failed) sequence.
    pub iterations: u32,
    /// Largest change of an element normal force between the last two iterates, N.
    pub last_change_n: f64,
    /// Convergence tolerance on that change, N.
    pub tolerance_n: f64,
    /// True when the change fell below the tolerance.
    pub converged: bool,
    /// True when the first iterate started from the previous step's forces (warm start);
    /// false when it started from an energy-model solve (cold start).
    pub warm_started: bool,
    /// Times a warm start proved infeasible and the sequence restarted cold.
    pub cold_restarts: u32,
}

/// The full answer of one solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// Outcome.
    pub status: SolveStatus,
    /// Why, when the status is not `solved`.
    pub reason: Option<String>,
    /// Things the user should know about an otherwise valid answer (undersized patches).
    pub warnings: Vec<String>,
    /// Per finger, scene order (empty without forces).
    pub fingers: Vec<FingerSolution>,
    /// Rigid displacement of the object (absent without forces, or when no contact carries
    /// load and the grasp does not determine it).
    pub rigid_displacement: Option<RigidDisplacement>,
    /// Residuals computed from the solution (absent without forces).
    pub residuals: Option<Residuals>,
    /// Load scale used to normalise residuals, N.
    pub load_scale_n: f64,
    /// Wall time of the solve (assembly, solver, post-processing), s.
    pub solve_time_s: f64,
    /// Solver statistics (summed over the convex solves of a sequential solve).
    pub solver: SolverStats,
    /// The sequential solve, when the model needs one (`None`: a single convex program).
    pub sequential: Option<SequentialReport>,
}

impl Solution {
    /// The finger named `name`.
    pub fn finger(&self, name: &str) -> Option<&FingerSolution> {
        self.fingers.iter().find(|f| f.name == name)
    }
}
