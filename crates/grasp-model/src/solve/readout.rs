//! Reading a solved program: the SI [`Solution`] from scaled forces and equality multipliers,
//! the explanations of programs without solution, and the checks every answer must pass before
//! it is reported as solved. Written once for every backend.
//!
//! Multipliers (KKT of `min 1/2 x'Px + q'x, E x = e, x in K`: `P x + q + E' lambda = y`):
//! - equilibrium rows: the object's rigid displacement, `delta = Fu Cu S' U lambda_eq`
//!   (translation of `O` in m, rotation in rad);
//! - load rows: minus the approach of the force-controlled finger, `a_i = -Fu Cu lambda_i` (a
//!   position-controlled finger reports its commanded approach).

use std::borrow::Cow;
use std::time::Instant;

use nalgebra::{DVector, Vector3};
use rayon::prelude::*;

use crate::model::equilibrium::Wrench;
use crate::model::grasp_model::{Control, FingerModel, GraspModel};
use crate::model::shared_spring::SpringKind;
use crate::model::spring_loads::{add_hand_poses, add_spring_retreat, hand_wrench, spring_loads};
use crate::option_names;
use crate::program::cone_program::{ConeProgram, LoadRow};
use crate::solve::patch_check::patch_warnings;
use crate::solve::residuals::{
    check_contacts, tangential, ElementCheck, RigidMotion, SolvedWith, StepMotion,
};
use crate::solve::singular_edge::peak_at_sharp_edge;
use crate::solve::solution::{
    ElementSolution, ElementState, FingerSolution, HandSolution, MountDisplacement,
    RigidDisplacement, ServoSolution, Solution, SolveStatus, SolverStats, LOADED_FRACTION,
};
use crate::solver::native::parallel_vectors::PARALLEL_LEN;
use crate::solver::outcome::Certificate;

/// Largest equilibrium and cone residual (relative to the load and the element force unit) of
/// an answer reported as solved; a larger one means the solver's answer is not trusted.
pub const ACCEPTED_FORCE_RESIDUAL: f64 = 1e-6;

/// Largest compatibility, penetration, complementarity and stick-motion residual (relative to
/// the displacement and work units) of an answer reported as solved.
pub const ACCEPTED_KINEMATIC_RESIDUAL: f64 = 1e-3;

/// Largest relative residual of any kind of an answer reported as `solved`; an accepted
/// answer above it (kinematic residuals up to [`ACCEPTED_KINEMATIC_RESIDUAL`]) is reported as
/// `reduced_accuracy` with the residual named.
pub const SOLVED_RESIDUAL: f64 = 1e-6;

/// A solution without forces: `status` with its `reason`.
pub(crate) fn failed(
    model: &GraspModel,
    status: SolveStatus,
    reason: String,
    start: Instant,
    solver: SolverStats,
) -> Solution {
    let solve_time_s = start.elapsed().as_secs_f64();
    Solution::without_forces(status, reason, model.scales.load_n, solver, solve_time_s)
}

/// Rigid displacement `(translation of O, rotation)` from the scaled equality multipliers.
pub(crate) fn rigid_from_multipliers(
    model: &GraspModel,
    program: &ConeProgram,
    multipliers: &[f64],
) -> (Vector3<f64>, Vector3<f64>) {
    let r = program.equilibrium_rows();
    let zr = DVector::from_column_slice(&multipliers[..r]);
    // Scaled equilibrium coordinates, then delta = Fu Cu S' (U z); S has 1/L on moment rows.
    let full = &program.reduction.basis * zr;
    let d = model.equilibrium.select.transpose() * full * model.scales.displacement_m();
    (
        Vector3::new(d[0], d[1], d[2]),
        Vector3::new(d[3], d[4], d[5]),
    )
}

fn fmt3(v: &Vector3<f64>) -> String {
    format!("[{:.3}, {:.3}, {:.3}]", v.x, v.y, v.z)
}

/// The object's rigid displacement is reported only when some element force exceeds this many
/// `Fu`: with no contact force at all the equality multipliers are any interior point, and
/// the displacement is not determined by the grasp.
pub const RIGID_DISPLACEMENT_FORCE_FU: f64 = 1e-12;

/// A part of the escape motion (translation or rotation) is named when it is at least this
/// fraction of the larger part (the rotation measured as its displacement over the length
/// unit): smaller parts are round-off of the certificate.
const MOTION_PART_FRACTION: f64 = 1e-6;

/// The escape motion of a certificate: the centre of mass's translation direction and the
/// rotation axis, each only when it is a visible part of the motion.
struct EscapeMotion {
    along: Option<Vector3<f64>>,
    about: Option<Vector3<f64>>,
}

fn escape_motion(model: &GraspModel, program: &ConeProgram, cert: &Certificate) -> EscapeMotion {
    let (t_o, theta) = rigid_from_multipliers(model, program, &cert.equality);
    let t = t_o + theta.cross(&(model.center_of_mass_m() - model.reference_point_m));
    let turn = theta.norm() * model.scales.length_m;
    let scale = t.norm().max(turn);
    if !(scale > 0.0 && scale.is_finite()) {
        return EscapeMotion {
            along: None,
            about: None,
        };
    }
    EscapeMotion {
        along: (t.norm() > MOTION_PART_FRACTION * scale).then(|| t.normalize()),
        about: (turn > MOTION_PART_FRACTION * scale).then(|| theta.normalize()),
    }
}

/// The motion of the centre of mass in a certificate, as words (`None` if negligible).
fn motion_words(model: &GraspModel, program: &ConeProgram, cert: &Certificate) -> Option<String> {
    let m = escape_motion(model, program, cert);
    if m.along.is_none() && m.about.is_none() {
        return None;
    }
    let mut s = String::new();
    if let Some(d) = m.along {
        s.push_str(&format!(" moving along {}", fmt3(&d)));
    }
    if let Some(d) = m.about {
        s.push_str(&format!(" turning about {}", fmt3(&d)));
    }
    Some(s)
}

/// Reads an infeasibility certificate of the energy model as the rigid motion by which the
/// object escapes.
pub(crate) fn escape_reason(
    model: &GraspModel,
    program: &ConeProgram,
    cert: &Certificate,
) -> String {
    let mut s = String::from(
        "no equilibrium: the friction cones cannot balance the load (friction too low, or the \
         contacts cannot resist it)",
    );
    if let Some(m) = motion_words(model, program, cert) {
        s.push_str("; the object would escape");
        s.push_str(&m);
    }
    s.push_str("; raise mu or move the fingers");
    s
}

/// Which fingers slide in a certificate of a Tresca program, with their share of the slip.
fn sliding_fingers(model: &GraspModel, cert: &Certificate) -> Vec<(String, f64)> {
    let total: f64 = cert.finger_slip.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Vec::new();
    }
    let mut v: Vec<(String, f64)> = model
        .fingers
        .iter()
        .zip(&cert.finger_slip)
        .filter(|(_, &s)| s > 0.02 * total)
        .map(|(f, &s)| (f.name.clone(), s / total))
        .collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1));
    v
}

/// The reason of an infeasible Tresca program: too little normal force, which fingers slide,
/// and where the object would move.
pub(crate) fn cannot_hold_reason(
    model: &GraspModel,
    program: &ConeProgram,
    cert: &Certificate,
) -> String {
    let mut s = String::from(
        "cannot hold: the commanded loads give too little normal force for Coulomb friction",
    );
    let sliding = sliding_fingers(model, cert);
    if !sliding.is_empty() {
        let list: Vec<String> = sliding
            .iter()
            .map(|(n, share)| format!("{n} ({:.0} % of the slip)", share * 100.0))
            .collect();
        s.push_str(&format!("; lacking grip: {}", list.join(", ")));
    }
    if let Some(d) = escape_motion(model, program, cert).along {
        s.push_str(&format!("; the object would slide along {}", fmt3(&d)));
    }
    s.push_str(grip_fix(model, &sliding));
    s
}

/// How to give the fingers lacking grip more of it: a force-controlled finger's load, a
/// position-controlled one's approach (its load is the model's answer to it); only the advice
/// that fits the fingers named.
fn grip_fix(model: &GraspModel, sliding: &[(String, f64)]) -> &'static str {
    let positioned = |name: &String| {
        model.fingers.iter().any(|f| {
            f.name == *name && matches!(f.control, Control::Approach { .. } | Control::Held)
        })
    };
    let some = sliding.iter().filter(|(name, _)| positioned(name)).count();
    match (some, sliding.len() - some) {
        (0, _) => "; raise the normal load of the fingers lacking grip (or mu)",
        (_, 0) => {
            "; press the position-controlled fingers lacking grip in further (a larger \
             approach), or raise mu"
        }
        _ => {
            "; press the position-controlled fingers lacking grip in further (a larger \
             approach), or raise the normal load of the force-controlled ones (or mu)"
        }
    }
}

/// What the readout found of one finger beyond its forces: its friction coefficient at its
/// load and its approach.
#[derive(Debug, Clone, Copy)]
struct FingerFound {
    /// The friction coefficient of its law at the load it carries.
    mu_at_load: f64,
    /// Its approach, m.
    approach_m: f64,
}

/// Resultants and element fields of finger `i` from its elements' checks.
fn finger_solution(
    model: &GraspModel,
    i: usize,
    x_n: &[f64],
    checks: &[ElementCheck],
    found: FingerFound,
) -> FingerSolution {
    let f = &model.fingers[i];
    let ne = f.patch.len();
    let area = f.patch.element_area_m2();
    let mu = found.mu_at_load * (f.n_tangential > 0) as u8 as f64;
    let (mut p, mut q, mut torsion, mut cx, mut cy) = (0.0, Vector3::zeros(), 0.0, 0.0, 0.0);
    let (mut counts, mut peak, mut boundary) = ([0usize; 5], 0.0_f64, 0.0);
    for (k, c) in checks.iter().enumerate() {
        let fk = x_n[f.offset + k];
        let g = tangential(x_n, f.offset, ne, f.n_tangential, k);
        let [x, y] = f.patch.centres_m[k];
        p += fk;
        if f.patch.on_boundary(k) {
            boundary += fk;
        }
        q += f.frame.t1 * g[0] + f.frame.t2 * g[1];
        torsion += x * g[1] - y * g[0];
        cx += fk * x;
        cy += fk * y;
        peak = peak.max(fk / area);
        counts[c.state as usize] += 1;
    }
    let element = |(k, c): (usize, &ElementCheck)| {
        let g = tangential(x_n, f.offset, ne, f.n_tangential, k);
        element_solution(f, k, x_n[f.offset + k], g, c)
    };
    // Each element's fields are its own: built on all cores for a fine patch.
    let elements: Vec<ElementSolution> = match ne >= PARALLEL_LEN {
        true => checks.par_iter().enumerate().map(element).collect(),
        false => checks.iter().enumerate().map(element).collect(),
    };
    // An unloaded finger (solver noise only) has no centre of pressure: its contact point.
    let loaded = p > LOADED_FRACTION * model.scales.load_n;
    let cop = if loaded {
        f.frame.point(cx / p, cy / p)
    } else {
        f.frame.origin_m
    };
    let qn = q.norm();
    FingerSolution {
        name: f.name.clone(),
        normal_force_n: p,
        tangential_force_n: [q.x, q.y, q.z],
        tangential_magnitude_n: qn,
        torsional_moment_nm: torsion,
        center_of_pressure_m: [cop.x, cop.y, cop.z],
        contact_area_m2: (ne
            - counts[ElementState::Separated as usize]
            - counts[ElementState::OffSurface as usize]) as f64
            * area,
        peak_pressure_pa: peak,
        peak_pressure_grid_dependent: loaded
            && peak_at_sharp_edge(&f.patch, &x_n[f.offset..f.offset + ne]),
        friction_coefficient: mu,
        // An unloaded finger (solver noise only) has no meaningful ratio.
        friction_utilization: if mu > 0.0 && loaded {
            qn / (mu * p)
        } else {
            0.0
        },
        boundary_load_fraction: if loaded { boundary / p } else { 0.0 },
        approach_m: found.approach_m,
        mount_displacement: mount_displacement(f, &x_n[f.offset..f.offset + f.n_unknowns()]),
        stick_count: counts[ElementState::Stick as usize],
        slip_count: counts[ElementState::Slip as usize],
        frictionless_count: counts[ElementState::Frictionless as usize],
        separated_count: counts[ElementState::Separated as usize],
        off_surface_count: counts[ElementState::OffSurface as usize],
        elements,
    }
}

/// Element `k` of finger `f`: its normal force `fk` (N) and friction `g` (N, `[t1, t2]`),
/// their tractions (Pa) and its check's gap, slip and state.
fn element_solution(
    f: &FingerModel,
    k: usize,
    fk: f64,
    g: [f64; 2],
    c: &ElementCheck,
) -> ElementSolution {
    let area = f.patch.element_area_m2();
    let pos = f.element_point(k);
    ElementSolution {
        index: [k / f.patch.grid.ny, k % f.patch.grid.ny],
        local_m: f.patch.centres_m[k],
        position_m: [pos.x, pos.y, pos.z],
        normal_force_n: fk,
        tangential_force_n: g,
        pressure_pa: fk / area,
        traction_pa: [g[0] / area, g[1] / area],
        gap_m: c.gap_m,
        slip_m: c.slip_m,
        step_slip_m: c.step_slip_m,
        state: c.state,
        viscous_displacement_m: None,
    }
}

/// Each element's viscoelastic history displacement this step (m, `[normal, t1, t2]`): the
/// program's offset less the finger's commanded approach `d` (m) and its mount's preload
/// offset (`FingerMount::add_preload_offset`).
fn set_viscous_displacement(f: &FingerModel, offset_m: &[f64], d: f64, fs: &mut FingerSolution) {
    let ne = f.patch.len();
    let mut o = offset_m[f.offset..f.offset + f.n_unknowns()].to_vec();
    if let Some(m) = &f.mount {
        let mut preload = vec![0.0; o.len()];
        m.add_preload_offset(&mut preload);
        o.iter_mut().zip(preload).for_each(|(x, p)| *x -= p);
    }
    for (k, e) in fs.elements.iter_mut().enumerate() {
        let mut v = [o[k] + d, 0.0, 0.0];
        for c in 0..f.n_tangential {
            v[c + 1] = o[(c + 1) * ne + k];
        }
        e.viscous_displacement_m = Some(v);
    }
}

/// The approach (m) of each force-controlled finger found by the program (0 for the others),
/// and every finger's approach as reported: the found one, else the commanded one (in the
/// offsets).
fn approaches_m(
    model: &GraspModel,
    program: &ConeProgram,
    multipliers: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let mut found = vec![0.0; model.fingers.len()];
    let mut approach = program.approach_m.clone();
    for &LoadRow { finger: i, row } in &program.load_rows {
        found[i] = -multipliers[row] * model.scales.displacement_m();
        approach[i] = found[i];
    }
    (found, approach)
}

/// The friction law's coefficient at each finger's load `P_i` (N) from the element normal
/// forces `x_n` (N): equal to the frozen one at a fixed point.
fn mu_at_loads(model: &GraspModel, x_n: &[f64]) -> Vec<f64> {
    let load = |f: &crate::model::grasp_model::FingerModel| -> f64 {
        x_n[f.offset..f.offset + f.patch.len()].iter().sum()
    };
    model
        .fingers
        .iter()
        .map(|f| f.friction.mu_at(load(f)))
        .collect()
}

/// Builds the SI solution from the scaled forces `x` and equality multipliers.
pub(crate) fn build_solution(
    model: &GraspModel,
    program: &ConeProgram,
    x_scaled: &[f64],
    multipliers: &[f64],
    stats: SolverStats,
    solved_with: &SolvedWith<'_>,
) -> Solution {
    let s = model.scales;
    let x_n: Vec<f64> = match x_scaled.len() >= PARALLEL_LEN {
        true => x_scaled.par_iter().map(|v| v * s.element_force_n).collect(),
        false => x_scaled.iter().map(|v| v * s.element_force_n).collect(),
    };
    let (t_o, theta) = rigid_from_multipliers(model, program, multipliers);
    let (found, approach) = approaches_m(model, program, multipliers);
    let mu_at_load = mu_at_loads(model, &x_n);
    let offset_m = offsets_with_springs(model, &program.offset_m, &x_n);
    let motion = StepMotion {
        rigid: RigidMotion {
            translation_o_m: t_o,
            rotation_rad: theta,
        },
        approach_m: &found,
        offset_m: &offset_m,
        external: &program.external_wrench,
    };
    let check = check_contacts(model, &x_n, &motion, solved_with, &mu_at_load);
    let mut fingers: Vec<FingerSolution> = (0..model.fingers.len())
        .map(|i| {
            let found = FingerFound {
                mu_at_load: mu_at_load[i],
                approach_m: approach[i],
            };
            finger_solution(model, i, &x_n, &check.elements[i], found)
        })
        .collect();
    let history_m = offsets_without_hand_poses(model, program);
    for (i, (f, fs)) in model.fingers.iter().zip(fingers.iter_mut()).enumerate() {
        if f.viscous.is_some() {
            set_viscous_displacement(f, &history_m, program.approach_m[i], fs);
        }
    }
    let t_com = t_o + theta.cross(&(model.center_of_mass_m() - model.reference_point_m));
    let mut sol = Solution {
        status: SolveStatus::Solved,
        reason: None,
        warnings: Vec::new(),
        fingers,
        // With no contact force at all the multipliers are any interior point: the object's
        // position is not determined by the grasp, so none is reported.
        rigid_displacement: x_n
            .iter()
            .any(|&v| v.abs() > RIGID_DISPLACEMENT_FORCE_FU * s.element_force_n)
            .then_some(RigidDisplacement {
                translation_m: [t_com.x, t_com.y, t_com.z],
                rotation_rad: [theta.x, theta.y, theta.z],
            }),
        residuals: Some(check.residuals),
        load_scale_n: s.load_n,
        solve_time_s: 0.0,
        solver: stats,
        sequential: None,
        hands: Vec::new(),
        servos: Vec::new(),
    };
    (sol.hands, sol.servos) = shared_spring_solutions(model, &x_n);
    sol.warnings = patch_warnings(model, &sol);
    sol.warnings
        .extend(crate::solve::contact_validity::validity_warnings(
            model,
            &sol,
            &check.compression_m,
        ));
    sol
}

/// The end-of-solve invariant: a solution with forces is reported as solved only if every
/// number in it is finite and its residuals are within [`ACCEPTED_FORCE_RESIDUAL`] and
/// [`ACCEPTED_KINEMATIC_RESIDUAL`]; otherwise it becomes `no_convergence` with the reason and
/// loses its forces. An accepted answer with a residual above [`SOLVED_RESIDUAL`] is
/// `reduced_accuracy`, the residual named.
pub(crate) fn enforce_invariant(sol: &mut Solution) {
    if !sol.status.has_forces() {
        return;
    }
    let problem = match &sol.residuals {
        None => Some("it has no residuals".to_string()),
        Some(r) if !sol.all_finite() => Some(format!(
            "it contains numbers that are not finite (worst residual {:.1e})",
            r.worst()
        )),
        Some(r) => r.unacceptable(ACCEPTED_FORCE_RESIDUAL, ACCEPTED_KINEMATIC_RESIDUAL),
    };
    if let Some(p) = problem {
        sol.status = SolveStatus::NoConvergence;
        sol.reason = Some(format!(
            "no convergence: the solver's answer fails its own checks: {p}; try `{}` = \
             clarabel, a coarser grid, or report the scene",
            option_names::SOLVER
        ));
        sol.fingers.clear();
        sol.rigid_displacement = None;
        sol.warnings.clear();
        return;
    }
    let loose = sol
        .residuals
        .and_then(|r| r.unacceptable(SOLVED_RESIDUAL, SOLVED_RESIDUAL));
    if let (SolveStatus::Solved, Some(p)) = (sol.status, loose) {
        sol.status = SolveStatus::ReducedAccuracy;
        sol.reason = Some(format!(
            "solved to reduced accuracy: {p} (a solved answer's are within {SOLVED_RESIDUAL:.0e}); \
             the forces are approximate: try the other solver (`{}`), a tighter `{}`, or check \
             the scene's extremes (an approach beyond small strain, say)",
            option_names::SOLVER,
            option_names::TOLERANCE
        ));
    }
}

/// The displacement of finger `f`'s core on its mount under its element forces `x` (N, local
/// layout): `-S (B x - w0)` in the contact frame (`FingerMount::core_displacement`), turned
/// into the world frame.
fn mount_displacement(f: &FingerModel, x: &[f64]) -> Option<MountDisplacement> {
    let m = f.mount.as_ref()?;
    let d = m.core_displacement(x);
    let frame = &f.frame;
    let world = |a: f64, b: f64, c: f64| frame.t1 * a + frame.t2 * b + frame.normal * c;
    let t = world(d[0], d[1], d[2]);
    let r = world(d[3], d[4], d[5]);
    Some(MountDisplacement {
        normal_m: d[2],
        translation_m: [t.x, t.y, t.z],
        rotation_rad: [r.x, r.y, r.z],
    })
}

/// The displacement offsets (m, the fingers' unknowns) with the shared springs' retreat under
/// the forces `x_n` (N) added: the check of the contacts sees the fingers' cores where the
/// springs put them.
fn offsets_with_springs<'a>(
    model: &GraspModel,
    offset_m: &'a [f64],
    x_n: &[f64],
) -> Cow<'a, [f64]> {
    if model.springs.is_empty() {
        return Cow::Borrowed(offset_m);
    }
    let mut o = offset_m[..model.n_unknowns].to_vec();
    add_spring_retreat(model, x_n, &mut o);
    Cow::Owned(o)
}

/// The program's displacement offsets (m) less the commanded hand poses' motion: what a
/// viscoelastic history and the fingers' own commands put there.
fn offsets_without_hand_poses<'a>(model: &GraspModel, program: &'a ConeProgram) -> Cow<'a, [f64]> {
    if program.hand_poses.is_empty() {
        return Cow::Borrowed(&program.offset_m);
    }
    let mut poses = vec![0.0; model.n_unknowns];
    add_hand_poses(model, &program.hand_poses, &mut poses);
    let o = program
        .offset_m
        .iter()
        .zip(&poses)
        .map(|(o, p)| o - p)
        .collect();
    Cow::Owned(o)
}

/// Each hand's and servo's load and displacement under the forces `x_n` (N).
fn shared_spring_solutions(
    model: &GraspModel,
    x_n: &[f64],
) -> (Vec<HandSolution>, Vec<ServoSolution>) {
    let (mut hands, mut servos) = (Vec::new(), Vec::new());
    for (s, w) in model.springs.iter().zip(spring_loads(model, x_n)) {
        let d = s.displacement(&w);
        match s.kind() {
            SpringKind::Hand { directions, .. } => {
                let whole = hand_wrench(model, s, x_n).unwrap_or_default();
                let motion = directions
                    .iter()
                    .zip(&d)
                    .fold(Wrench::zeros(), |m, (u, x)| m + u * *x);
                let v = |w: &Wrench, a: usize| [w[a], w[a + 1], w[a + 2]];
                hands.push(HandSolution {
                    name: s.name().to_string(),
                    force_n: v(&whole, 0),
                    moment_nm: v(&whole, 3),
                    translation_m: v(&motion, 0),
                    rotation_rad: v(&motion, 3),
                });
            }
            SpringKind::Servo => servos.push(ServoSolution {
                name: s.name().to_string(),
                force_n: w[0],
                travel_m: d[0],
            }),
        }
    }
    (hands, servos)
}
