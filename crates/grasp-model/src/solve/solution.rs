//! The solution of a grasp, in SI units: element forces, finger resultants, the object's
//! rigid displacement, residuals and solver statistics.

use serde::{Deserialize, Serialize};

use crate::model::patch_compliance::CompliancePath;
use crate::solver::outcome::SolverKind;

/// A finger or element counts as loaded when its normal force exceeds this fraction of the
/// load scale (below it, a force is solver round-off: friction utilisation, stick counts and
/// warm starts ignore it).
pub const LOADED_FRACTION: f64 = 1e-9;

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
    /// The status as the JSON output writes it (`"solved"`, `"reduced_accuracy"`,
    /// `"no_equilibrium"`, `"no_convergence"`).
    pub fn as_str(&self) -> &'static str {
        match self {
            SolveStatus::Solved => "solved",
            SolveStatus::ReducedAccuracy => "reduced_accuracy",
            SolveStatus::NoEquilibrium => "no_equilibrium",
            SolveStatus::NoConvergence => "no_convergence",
        }
    }

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
    /// In contact, friction force on the cone, sliding opposite to it.
    Slip,
    /// Not carrying load.
    Separated,
    /// Facing no surface (exact gaps: beyond an edge of the object, past a thin part's
    /// silhouette, beyond the fingertip's rim): it can carry nothing.
    OffSurface,
    /// In contact on a frictionless finger (`mu = 0`, no tangential unknowns): it carries a
    /// normal force and no friction, so it neither sticks nor slips.
    Frictionless,
}

impl ElementState {
    /// The state as the JSON output writes it (`"stick"`, `"slip"`, `"separated"`,
    /// `"off_surface"`, `"frictionless"`).
    pub fn as_str(&self) -> &'static str {
        match self {
            ElementState::Stick => "stick",
            ElementState::Slip => "slip",
            ElementState::Separated => "separated",
            ElementState::OffSurface => "off_surface",
            ElementState::Frictionless => "frictionless",
        }
    }
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
    /// On a viscoelastic contact, the displacement its history added this step (m, `[normal,
    /// t1, t2]`: the normal part closes the gap; `crate::solve::viscous_history`); absent on an
    /// elastic one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_displacement_m: Option<[f64; 3]>,
}

impl ElementSolution {
    /// The element's force `[F, G1, G2]`, N (a planar or frictionless finger's missing
    /// components are 0).
    pub fn force_n(&self) -> [f64; 3] {
        [
            self.normal_force_n,
            self.tangential_force_n[0],
            self.tangential_force_n[1],
        ]
    }

    /// True when the element carries a force.
    pub fn is_loaded(&self) -> bool {
        self.force_n().iter().any(|f| *f != 0.0)
    }
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
    /// Centre of pressure, world frame, m (the contact point if the finger carries no load:
    /// at most `LOADED_FRACTION` of the load scale, solver noise).
    pub center_of_pressure_m: [f64; 3],
    /// Area of the elements in contact, m^2.
    pub contact_area_m2: f64,
    /// Largest element pressure, Pa.
    pub peak_pressure_pa: f64,
    /// True when the peak pressure lies at a sharp edge of the contact (beside the elements
    /// past the object's edge or the tip's rim, or on a flat pad's rim), where the elastic
    /// pressure is singular: `peak_pressure_pa` then grows as the grid is refined (about as
    /// `n^0.5`, `n` elements a side) and is not a converged value (`grasp study` shows its
    /// trend). Absent when false.
    #[serde(default, skip_serializing_if = "is_false")]
    pub peak_pressure_grid_dependent: bool,
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
    /// The finger's rigid core moved from its commanded pose by the spring behind it
    /// (`fingers[i].mount`); absent for a finger without a mount.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mount_displacement: Option<MountDisplacement>,
    /// Elements in stick.
    pub stick_count: usize,
    /// Elements in slip.
    pub slip_count: usize,
    /// Elements in contact on a frictionless finger, which neither stick nor slip (absent
    /// when none: a finger with friction has none).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub frictionless_count: usize,
    /// Elements separated.
    pub separated_count: usize,
    /// Elements facing no surface (exact gaps past an edge or a rim; absent when none).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub off_surface_count: usize,
    /// Element fields, row-major. In JSON: `"elements"`, one record per element, up to
    /// 64 x 64 elements ([`crate::COLUMNS_ABOVE_ELEMENTS`]); `"element_fields"`, one array per
    /// field under the same names, above.
    #[serde(
        flatten,
        serialize_with = "crate::solve::element_columns::serialize",
        deserialize_with = "crate::solve::element_columns::deserialize"
    )]
    pub elements: Vec<ElementSolution>,
}

/// How far a finger's rigid core moved from its commanded pose on its mount's spring:
/// `-S (w - w0)` (`model/finger_mount.rs`) for the wrench `w` its contact carries.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MountDisplacement {
    /// Along the finger's inward normal, m: positive toward the object, negative pushed back
    /// (the pad's effective approach is the commanded `approach_m` plus this).
    pub normal_m: f64,
    /// Translation of the core, m (world frame).
    pub translation_m: [f64; 3],
    /// Small rotation of the core about the contact point, rad (world frame).
    pub rotation_rad: [f64; 3],
}

impl MountDisplacement {
    /// How far the core moved, the length of its translation, m.
    pub fn moved_m(&self) -> f64 {
        self.translation_m.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    /// How far the core turned, the length of its rotation vector, rad.
    pub fn turned_rad(&self) -> f64 {
        self.rotation_rad.iter().map(|x| x * x).sum::<f64>().sqrt()
    }
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolverStats {
    /// The solver whose answer this is (of the last convex solve).
    pub solver: SolverKind,
    /// Why the native solver's answer was not used, when it was not (the fallback to
    /// Clarabel); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fallback: Option<String>,
    /// Iterations over all convex solves: Newton steps of the native solver plus
    /// interior-point iterations of Clarabel.
    pub iterations: u32,
    /// Reduced matrices factorised by the native solver (all convex solves); with the FFT
    /// compliance, reduced systems prepared for conjugate gradients.
    pub factorizations: u32,
    /// The form of the patch compliances: dense matrices or the FFT operator.
    #[serde(default)]
    pub compliance: CompliancePath,
    /// Conjugate-gradient iterations of the FFT path's reduced systems (0 on the dense path).
    #[serde(default)]
    pub inner_iterations: u32,
    /// Time inside the convex solvers, s.
    pub solver_time_s: f64,
    /// Unknowns of the program.
    pub unknowns: usize,
    /// Equality rows (equilibrium after reduction, plus load rows).
    pub equality_rows: usize,
    /// Conic rows (nonnegative and second-order).
    pub cone_rows: usize,
}

/// Residuals of a solution; all relative ones are dimensionless.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Residuals {
    /// `|sum of forces on the object|`, N.
    pub force_n: f64,
    /// `|sum of moments on the object|`, N m.
    pub moment_nm: f64,
    /// `max(force / load, moment / (load L))`: equilibrium error over the load scale.
    pub equilibrium_relative: f64,
    /// Largest cone violation `max(0, |G_k| - mu F_k, -F_k)` over the element force unit.
    pub cone_violation_relative: f64,
    /// Largest penetration `max(0, -gap)` (frictional elements of the energy model:
    /// `max(0, mu |w| - gap)`, the dual cone) over the displacement unit `Fu Cu`.
    pub penetration_relative: f64,
    /// Largest `|gap - mu |w||` over loaded elements, over the displacement unit.
    pub compatibility_relative: f64,
    /// Largest of `F_k (gap_k - mu |w_k|)` (normal; `F_k gap_k` for Coulomb) and
    /// `(mu F_k - |G_k|) |w_k|` (tangential; `w_k` this step's slip) over `Fu * (Fu Cu)`: both
    /// vanish at an exact solution (model.md: under the associated law a slipping element
    /// opens by `mu |slip|`).
    pub complementarity_relative: f64,
    /// Largest `|w_k|` (this step's slip) over stick elements, over the displacement unit.
    pub stick_motion_relative: f64,
    /// Largest `1 + cos(angle(w_k, G_k))` over slip elements (0: slip exactly opposes the
    /// friction force; 2: along it).
    pub slip_direction_error: f64,
}

impl Residuals {
    /// The largest of the relative residuals.
    pub fn worst(&self) -> f64 {
        [
            self.equilibrium_relative,
            self.cone_violation_relative,
            self.penetration_relative,
            self.compatibility_relative,
            self.complementarity_relative,
            self.stick_motion_relative,
            self.slip_direction_error,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }

    /// Why these residuals are too large for an answer to be trusted, if they are: equilibrium
    /// and cone residuals above `force`, or penetration, compatibility, complementarity and
    /// stick-motion residuals above `kinematic` (all relative, see the fields).
    pub fn unacceptable(&self, force: f64, kinematic: f64) -> Option<String> {
        let checks = [
            ("equilibrium", self.equilibrium_relative, force),
            ("cone violation", self.cone_violation_relative, force),
            ("penetration", self.penetration_relative, kinematic),
            ("compatibility", self.compatibility_relative, kinematic),
            ("complementarity", self.complementarity_relative, kinematic),
            ("stick motion", self.stick_motion_relative, kinematic),
        ];
        // Negated on purpose: a NaN residual fails the check.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        checks
            .iter()
            .find(|(_, v, limit)| !(*v <= *limit))
            .map(|(name, v, limit)| format!("{name} residual {v:.1e} above {limit:.0e}"))
    }
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
    /// Iterates taken with a relaxation below 1: after an iterate's program had no solution,
    /// the input was moved back towards the last feasible one instead of giving up.
    #[serde(default)]
    pub damped_iterations: u32,
}

/// The full answer of one solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// Outcome.
    pub status: SolveStatus,
    /// Why, when the status is not `solved`.
    pub reason: Option<String>,
    /// Things the user should know about the answer: first the scene's (its shape checks: a
    /// patch over an edge, overlapping patches, an open mesh; kept whatever the status), then
    /// the solve's own (undersized patches).
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
    /// Wall time of the solve: program assembly (when this solve built it), solver,
    /// post-processing, s.
    pub solve_time_s: f64,
    /// Solver statistics (summed over the convex solves of a sequential solve).
    pub solver: SolverStats,
    /// The sequential solve, when the model needs one (`None`: a single convex program).
    pub sequential: Option<SequentialReport>,
    /// Per hand (`hands`, scene order), the load its fingers carry and how its base moved
    /// (absent without hands or forces).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hands: Vec<HandSolution>,
    /// Per servo (`servos`, scene order), its load and its jaws' travel (absent without
    /// servos or forces).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub servos: Vec<ServoSolution>,
}

/// A hand's base on the stiffness behind it (`hands[j]`): what its fingers carry and how far
/// it moved from its commanded pose (`-S W` over its compliant directions,
/// `model/shared_spring.rs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HandSolution {
    /// Its name in the scene.
    pub name: String,
    /// The force its fingers' contacts put on the object, N (world frame); the hand carries
    /// its opposite.
    pub force_n: [f64; 3],
    /// The moment of those forces about the hand's `origin_m`, N m (world frame).
    pub moment_nm: [f64; 3],
    /// Translation of the base (and every finger core on it), m (world frame).
    pub translation_m: [f64; 3],
    /// Small rotation of the base about its origin, rad (world frame).
    pub rotation_rad: [f64; 3],
}

/// A servo on its stiffness (`servos[j]`): its load and its jaws' travel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ServoSolution {
    /// Its name in the scene.
    pub name: String,
    /// The sum of its jaws' normal forces, N.
    pub force_n: f64,
    /// Each jaw's travel from its commanded position along its inward normal, m: `-F / k`,
    /// negative (the jaws pushed back, short of the command).
    pub travel_m: f64,
}

impl SolverStats {
    /// The statistics of no solve at all (nothing to solve: no finger holds the object).
    pub fn no_solve() -> Self {
        SolverStats {
            solver: SolverKind::Native,
            fallback: None,
            iterations: 0,
            factorizations: 0,
            compliance: CompliancePath::default(),
            inner_iterations: 0,
            solver_time_s: 0.0,
            unknowns: 0,
            equality_rows: 0,
            cone_rows: 0,
        }
    }
}

impl Solution {
    /// An outcome without forces (no equilibrium, no convergence, nothing that holds the
    /// object): its status and reason, the load scale (N), what the solver did and the time
    /// it took (s).
    pub fn without_forces(
        status: SolveStatus,
        reason: String,
        load_scale_n: f64,
        solver: SolverStats,
        solve_time_s: f64,
    ) -> Self {
        Solution {
            status,
            reason: Some(reason),
            warnings: Vec::new(),
            fingers: Vec::new(),
            rigid_displacement: None,
            residuals: None,
            load_scale_n,
            solve_time_s,
            solver,
            sequential: None,
            hands: Vec::new(),
            servos: Vec::new(),
        }
    }

    /// Marks a solution whose solver answered "almost solved" (Clarabel's): forces read, their
    /// accuracy reduced.
    pub(crate) fn mark_reduced_accuracy(&mut self) {
        self.status = SolveStatus::ReducedAccuracy;
        self.reason = Some("solved to reduced accuracy; check the residuals".into());
    }

    /// Respells the option names in the solution's texts (its reason, warnings and solver
    /// fallback) with a front end's `spelling` (pairs of library name and the front end's;
    /// see [`crate::option_names::respell`]), so its messages name the front end's flags or
    /// keywords.
    pub fn respell_options(&mut self, spelling: &[(&str, &str)]) {
        let respell = |t: &mut String| *t = crate::option_names::respell(t, spelling);
        self.reason.iter_mut().for_each(respell);
        self.warnings.iter_mut().for_each(respell);
        self.solver.fallback.iter_mut().for_each(respell);
    }

    /// The finger named `name`.
    pub fn finger(&self, name: &str) -> Option<&FingerSolution> {
        self.fingers.iter().find(|f| f.name == name)
    }

    /// The loaded frictional fingers that slide as a whole (no element sticks): loaded means a
    /// normal force above [`LOADED_FRACTION`] of the load scale; frictional, a friction
    /// coefficient above 0 at the finger's load.
    pub fn fingers_sliding_as_a_whole(&self) -> impl Iterator<Item = &FingerSolution> {
        let loaded = LOADED_FRACTION * self.load_scale_n;
        self.fingers.iter().filter(move |f| {
            f.normal_force_n > loaded && f.friction_coefficient > 0.0 && f.stick_count == 0
        })
    }

    /// True when every number of the answer (forces, fields, displacement, residuals) is
    /// finite.
    pub fn all_finite(&self) -> bool {
        let fin = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let fingers = self.fingers.iter().all(|f| {
            fin(&[
                f.normal_force_n,
                f.tangential_magnitude_n,
                f.torsional_moment_nm,
                f.contact_area_m2,
                f.peak_pressure_pa,
                f.friction_coefficient,
                f.friction_utilization,
                f.boundary_load_fraction,
                f.approach_m,
            ]) && fin(&f.tangential_force_n)
                && fin(&f.center_of_pressure_m)
                && all_elements(&f.elements, |e| {
                    fin(&[e.normal_force_n, e.pressure_pa, e.gap_m])
                        && fin(&e.tangential_force_n)
                        && fin(&e.traction_pa)
                        && fin(&e.slip_m)
                        && fin(&e.step_slip_m)
                        && fin(&e.position_m)
                })
        });
        let rigid = self
            .rigid_displacement
            .is_none_or(|r| fin(&r.translation_m) && fin(&r.rotation_rad));
        let residuals = self.residuals.is_none_or(|r| {
            fin(&[
                r.force_n,
                r.moment_nm,
                r.equilibrium_relative,
                r.cone_violation_relative,
                r.penetration_relative,
                r.compatibility_relative,
                r.complementarity_relative,
                r.stick_motion_relative,
                r.slip_direction_error,
            ])
        });
        fingers && rigid && residuals
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// True when `test` holds for every element, the elements of a fine patch tested on all cores.
fn all_elements(
    elements: &[ElementSolution],
    test: impl Fn(&ElementSolution) -> bool + Sync + Send,
) -> bool {
    use rayon::prelude::*;
    match elements.len() >= PARALLEL_ELEMENTS {
        true => elements.par_iter().all(test),
        false => elements.iter().all(test),
    }
}

/// `[value(e) for e in elements]`, the elements of a fine patch read on all cores.
pub(crate) fn element_values(
    elements: &[ElementSolution],
    value: impl Fn(&ElementSolution) -> f64 + Sync + Send,
) -> Vec<f64> {
    use rayon::prelude::*;
    match elements.len() >= PARALLEL_ELEMENTS {
        true => elements.par_iter().map(value).collect(),
        false => elements.iter().map(value).collect(),
    }
}

/// Elements from which [`all_elements`] and [`element_values`] work on all cores.
const PARALLEL_ELEMENTS: usize = 1 << 15;

#[cfg(test)]
mod tests {
    use super::*;

    /// The model counts each element's record at `ELEMENT_RECORD_BYTES` when it checks that a
    /// solve fits in memory: no fewer than the record takes.
    #[test]
    fn element_records_are_counted_whole() {
        let counted = crate::scene::memory_budget::ELEMENT_RECORD_BYTES as usize;
        assert!(std::mem::size_of::<ElementSolution>() <= counted);
    }

    /// `as_str` is the serde name of each status (the JSON output and the Python package
    /// must say the same).
    #[test]
    fn status_names_are_the_serde_names() {
        use SolveStatus::*;
        for s in [Solved, ReducedAccuracy, NoEquilibrium, NoConvergence] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.as_str());
        }
    }

    /// `ElementState::as_str` is the serde name of each state.
    #[test]
    fn element_state_names_are_the_serde_names() {
        use ElementState::*;
        for s in [Stick, Slip, Separated, OffSurface, Frictionless] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.as_str());
        }
    }
}
