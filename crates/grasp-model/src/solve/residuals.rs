//! One pass over the elements of a solved program: each element's kinematics, opening, state
//! and residuals, computed from the forces and the rigid displacement with this crate's own
//! matrices, never taken from the solver's report. The readout only assembles them.
//!
//! Compatibility (thesis eqs. 61-65): `gap_k = c_k + (C x + o)_n,k + n . delta(p_k) - a_i >= 0`,
//! with `w_k = (C x + o)_t,k + t . delta(p_k)` the relative tangential displacement (object
//! minus finger), `delta(p) = t + theta x (p - O)` the object's rigid displacement and `o` the
//! displacement added to the elastic one (prescribed approaches, viscoelastic history).
//!
//! - Energy model (associated friction, model.md): `gap_k = 0` where element `k` sticks and
//!   `= mu |w_k|` where it slips.
//! - Coulomb model (non-associated): `gap_k = 0` wherever `F_k > 0`; the slip of this step is
//!   `w_k - m_k` (`m_k`: slip memory), zero in stick and opposite `G_k` in slip.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::model::equilibrium::Wrench;
use crate::model::grasp_model::{FingerModel, GraspModel};
use crate::solve::solution::{ElementState, Residuals};
use crate::solver::native::parallel_vectors::{CHUNK, PARALLEL_LEN};

/// The slip direction of an element is checked against its friction force only when the slip
/// exceeds this many displacement units `Fu Cu` (a shorter slip has no direction worth the
/// name: it is the round-off of a sticking element's relative motion).
const SLIP_DIRECTION_FLOOR: f64 = 1e-9;

/// An element is in contact when its normal force, in element force units `Fu`, exceeds both
/// its opening (gap, in displacement units) and this floor: a smaller force is the solver's
/// round-off on a separated element (the tolerance 1e-10 of the scaled program, with margin).
/// It judges elements; a finger is loaded by [`crate::LOADED_FRACTION`] of the load scale.
pub const CONTACT_FORCE_FLOOR_FU: f64 = 1e-7;

/// The friction rule a solution is checked against.
#[derive(Debug, Clone, Copy)]
pub enum FrictionRule<'a> {
    /// Energy model: associated cones, a slipping element opens by `mu |slip|`.
    Associated,
    /// Coulomb model: no opening on slip; slip measured from the memory `m` (m, per finger,
    /// per element).
    Coulomb {
        /// Slip memory at the start of the step.
        memory_m: &'a [Vec<[f64; 2]>],
    },
}

impl FrictionRule<'_> {
    /// This step's slip `w_k - m_k` of element `k` of finger `i` (`w_k` for the energy model).
    pub fn step_slip(&self, i: usize, k: usize, w: [f64; 2]) -> [f64; 2] {
        match self {
            FrictionRule::Associated => w,
            FrictionRule::Coulomb { memory_m } => {
                [w[0] - memory_m[i][k][0], w[1] - memory_m[i][k][1]]
            }
        }
    }

    /// The opening a slip of `|w|` comes with per unit slip: `mu` for the associated law on a
    /// frictional finger (model.md: a slipping element opens by `mu |slip|`), 0 otherwise.
    fn dilatancy(&self, mu: f64, n_tangential: usize) -> f64 {
        match self {
            FrictionRule::Associated if n_tangential > 0 => mu,
            _ => 0.0,
        }
    }
}

/// What a solved program was solved with (its friction rule, coefficients and radii): how to
/// read its answer.
pub(crate) struct SolvedWith<'a> {
    /// The friction rule (energy: associated; coulomb: with the step's starting memory).
    pub rule: FrictionRule<'a>,
    /// Friction coefficient per finger the program was solved with.
    pub mu: &'a [f64],
    /// Tresca radii per finger, per element (N), coulomb model only.
    pub radii_n: Option<&'a [Vec<f64>]>,
}

/// The object's rigid displacement at the reference point `O`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RigidMotion {
    /// Translation of `O`, m.
    pub translation_o_m: Vector3<f64>,
    /// Small rotation, rad.
    pub rotation_rad: Vector3<f64>,
}

/// One element's kinematics and state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElementCheck {
    /// Gap after loading, m.
    pub gap_m: f64,
    /// Relative tangential displacement along `[t1, t2]`, m (object minus finger; for a
    /// frictionless finger only the rigid part, its elastic tangential displacement not
    /// being modelled).
    pub slip_m: [f64; 2],
    /// This step's slip (`slip_m` less the slip memory), m.
    pub step_slip_m: [f64; 2],
    /// Stick, slip, separation or frictionless contact.
    pub state: ElementState,
}

/// Every element's check and the residuals of a solution.
pub(crate) struct ContactCheck {
    /// Per finger, per element.
    pub elements: Vec<Vec<ElementCheck>>,
    /// The residuals over all elements and the object's equilibrium.
    pub residuals: Residuals,
    /// Per finger, its compression: the largest elastic normal closure of the surfaces over
    /// its loaded elements (the compliance applied to its forces, Johnson 3.2), m.
    pub compression_m: Vec<f64>,
}

/// The step's data a check reads besides the forces: the rigid motion, each finger's approach
/// (m), the displacement offsets (m, program layout: prescribed approaches and viscoelastic
/// history, [`crate::program::cone_program`]) and the external wrench (N, N m about `O`).
pub(crate) struct StepMotion<'a> {
    /// Rigid displacement of the object.
    pub rigid: RigidMotion,
    /// Per finger, its advance along the inward normal as the program found it
    /// (force-controlled fingers; 0 for the others, whose approach is in the offsets).
    pub approach_m: &'a [f64],
    /// Per unknown, the displacement added to the elastic one.
    pub offset_m: &'a [f64],
    /// External wrench on the object.
    pub external: &'a Wrench,
}

/// Checks forces `x_n` (N, program layout): every element's gap (thesis eqs. 61-65, module
/// docs), slip and state, and the residuals, in one pass. `mu_at_load` is each finger's law
/// at its load (the residuals' coefficient), `solved_with.mu` the coefficient the program was
/// solved with (the states').
pub(crate) fn check_contacts(
    model: &GraspModel,
    x_n: &[f64],
    motion: &StepMotion<'_>,
    solved_with: &SolvedWith<'_>,
    mu_at_load: &[f64],
) -> ContactCheck {
    let mut r = equilibrium_residuals(model, x_n, motion.external);
    let mut compression_m = Vec::with_capacity(model.fingers.len());
    let elements = model
        .fingers
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let (gap, w, compression) = finger_kinematics(model, f, i, x_n, motion);
            compression_m.push(compression);
            let mut checks = Vec::new();
            let parts = fill_indices_folding(&mut checks, f.patch.len(), r, |k, part| {
                Element::of(f, x_n, k, gap[k], w[k]).check(
                    i,
                    solved_with,
                    model,
                    mu_at_load[i],
                    part,
                )
            });
            parts
                .iter()
                .for_each(|part| fold_element_residuals(&mut r, part));
            checks
        })
        .collect();
    ContactCheck {
        elements,
        residuals: r,
        compression_m,
    }
}

/// `out = [f(0, r_0), .., f(len - 1, r_c)]` with `f` folding its element's residuals into its
/// chunk's copy `r_c` of `start`, chunk by chunk ([`CHUNK`] elements) on all cores for many
/// elements; the chunks' residuals in chunk order. The largest of the chunks' residuals is the
/// one pass's: a maximum does not depend on the order its terms are taken in.
fn fill_indices_folding(
    out: &mut Vec<ElementCheck>,
    len: usize,
    start: Residuals,
    f: impl Fn(usize, &mut Residuals) -> ElementCheck + Sync + Send,
) -> Vec<Residuals> {
    let blank = ElementCheck {
        gap_m: 0.0,
        slip_m: [0.0; 2],
        step_slip_m: [0.0; 2],
        state: ElementState::Separated,
    };
    out.clear();
    crate::allocation::resize_on_all_cores(out, len, blank);
    let run = |(c, chunk): (usize, &mut [ElementCheck])| {
        let mut part = start;
        for (k, o) in chunk.iter_mut().enumerate() {
            *o = f(c * CHUNK + k, &mut part);
        }
        part
    };
    if len >= PARALLEL_LEN {
        out.par_chunks_mut(CHUNK).enumerate().map(run).collect()
    } else {
        out.chunks_mut(CHUNK).enumerate().map(run).collect()
    }
}

/// Folds the element residuals of `part` into `r` (each the larger of the two).
fn fold_element_residuals(r: &mut Residuals, part: &Residuals) {
    r.cone_violation_relative = r.cone_violation_relative.max(part.cone_violation_relative);
    r.penetration_relative = r.penetration_relative.max(part.penetration_relative);
    r.compatibility_relative = r.compatibility_relative.max(part.compatibility_relative);
    r.complementarity_relative = r
        .complementarity_relative
        .max(part.complementarity_relative);
    r.stick_motion_relative = r.stick_motion_relative.max(part.stick_motion_relative);
    r.slip_direction_error = r.slip_direction_error.max(part.slip_direction_error);
}

/// Equilibrium residuals of forces `x_n` (N) under `external` (N, N m); the element residuals
/// start at zero.
fn equilibrium_residuals(model: &GraspModel, x_n: &[f64], external: &Wrench) -> Residuals {
    let s = model.scales;
    let w = model.net_wrench(x_n, external);
    let force_n = w.fixed_rows::<3>(0).norm();
    let moment_nm = w.fixed_rows::<3>(3).norm();
    let equilibrium_relative = (force_n / s.load_n).max(moment_nm / (s.load_n * s.length_m));
    Residuals {
        force_n,
        moment_nm,
        equilibrium_relative,
        cone_violation_relative: 0.0,
        penetration_relative: 0.0,
        compatibility_relative: 0.0,
        complementarity_relative: 0.0,
        stick_motion_relative: 0.0,
        slip_direction_error: 0.0,
    }
}

/// Gaps (m) and relative tangential displacements (m) of finger `i`'s elements:
/// `gap_k = c_k + (C x + o)_n,k + n . delta(p_k) - a_i`, `w_k = (C x + o)_t,k + t . delta(p_k)`.
fn finger_kinematics(
    model: &GraspModel,
    f: &FingerModel,
    i: usize,
    x_n: &[f64],
    motion: &StepMotion<'_>,
) -> (Vec<f64>, Vec<[f64; 2]>, f64) {
    let ne = f.patch.len();
    let range = f.offset..f.offset + f.n_unknowns();
    let mut u = vec![0.0; range.len()];
    f.compliance_m_per_n.apply(&x_n[range.clone()], &mut u);
    // The answer's elements are read out next: the operator's work buffers are not kept.
    f.compliance_m_per_n.release_work();
    let compression = (0..ne)
        .filter(|&k| x_n[f.offset + k] > 0.0)
        .map(|k| u[k])
        .fold(0.0, f64::max);
    for (uj, o) in u.iter_mut().zip(&motion.offset_m[range]) {
        *uj += o;
    }
    let RigidMotion {
        translation_o_m,
        rotation_rad,
    } = motion.rigid;
    let element = |k: usize| {
        let p = f.element_point(k);
        let delta = translation_o_m + rotation_rad.cross(&(p - model.reference_point_m));
        let gap = f.patch.gap_m[k] + u[k] + f.frame.normal.dot(&delta) - motion.approach_m[i];
        let mut wk = [f.frame.t1.dot(&delta), f.frame.t2.dot(&delta)];
        for (c, wc) in wk.iter_mut().enumerate().take(f.n_tangential) {
            *wc += u[(c + 1) * ne + k];
        }
        (gap, wk)
    };
    let (g, w) = match ne >= PARALLEL_LEN {
        true => (0..ne).into_par_iter().map(element).unzip(),
        false => (0..ne).map(element).unzip(),
    };
    (g, w, compression)
}

/// One element's forces and kinematics, SI.
struct Element {
    /// Normal force, N.
    fk: f64,
    /// Tangential force `[G1, G2]`, N.
    g: [f64; 2],
    /// Gap, m.
    gap: f64,
    /// Relative tangential displacement, m.
    w: [f64; 2],
    /// Element index and the finger's tangential unknowns per element.
    k: usize,
    n_tangential: usize,
    /// True when the element faces no surface.
    off_surface: bool,
}

impl Element {
    fn of(f: &FingerModel, x_n: &[f64], k: usize, gap: f64, w: [f64; 2]) -> Element {
        Element {
            fk: x_n[f.offset + k],
            g: tangential(x_n, f.offset, f.patch.len(), f.n_tangential, k),
            gap,
            w,
            k,
            n_tangential: f.n_tangential,
            off_surface: f.patch.is_off_surface(k),
        }
    }

    /// The element's state and slips, its residuals folded into `r`.
    fn check(
        &self,
        i: usize,
        with: &SolvedWith<'_>,
        model: &GraspModel,
        mu_at_load: f64,
        r: &mut Residuals,
    ) -> ElementCheck {
        let step_slip_m = with.rule.step_slip(i, self.k, self.w);
        let state = self.state(i, with, model, step_slip_m);
        self.fold_residuals(state, step_slip_m, with.rule, model, mu_at_load, r);
        ElementCheck {
            gap_m: self.gap,
            slip_m: self.w,
            step_slip_m,
            state,
        }
    }

    /// Stick, slip, separation or frictionless contact, in the program's units: primal slack
    /// against dual slack, the larger one says which side of each complementarity is active.
    fn state(
        &self,
        i: usize,
        with: &SolvedWith<'_>,
        model: &GraspModel,
        w: [f64; 2],
    ) -> ElementState {
        let (fu, du) = (model.scales.element_force_n, model.scales.displacement_m());
        let mu = with.mu[i];
        let fk = self.fk / fu;
        let gn = self.g[0].hypot(self.g[1]) / fu;
        let wn = w[0].hypot(w[1]) / du;
        let opening = self.gap / du - with.rule.dilatancy(mu, self.n_tangential) * wn;
        let radius = match with.radii_n {
            Some(r) => r[i][self.k] / fu,
            None => mu * fk,
        };
        if self.off_surface {
            ElementState::OffSurface
        } else if fk < opening.max(CONTACT_FORCE_FLOOR_FU) {
            ElementState::Separated
        } else if self.n_tangential == 0 {
            ElementState::Frictionless
        } else if wn > radius - gn {
            ElementState::Slip
        } else {
            ElementState::Stick
        }
    }

    /// Folds the element's cone, penetration, compatibility, complementarity, stick-motion and
    /// slip-direction residuals (SI, over the program's units) into `r`.
    fn fold_residuals(
        &self,
        state: ElementState,
        wk: [f64; 2],
        rule: FrictionRule<'_>,
        model: &GraspModel,
        mu: f64,
        r: &mut Residuals,
    ) {
        let (fu, du) = (model.scales.element_force_n, model.scales.displacement_m());
        let (fk, g, gap) = (self.fk, self.g, self.gap);
        let dilatancy = rule.dilatancy(mu, self.n_tangential);
        let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
        let viol = (gn - mu * fk).max(-fk).max(0.0);
        r.cone_violation_relative = r.cone_violation_relative.max(viol / fu);
        let wn = (wk[0] * wk[0] + wk[1] * wk[1]).sqrt();
        // Penetration, and for the associated law the dual cone `gap >= mu |w|` (model.md: a
        // slipping element opens by mu |slip|; a separated one at least as much).
        let opening = gap - dilatancy * wn;
        r.penetration_relative = r.penetration_relative.max((-opening).max(0.0) / du);
        let tangential_slack = match self.n_tangential {
            0 => 0.0,
            _ => (mu * fk - gn).max(0.0) * wn,
        };
        let normal = fk.max(0.0) * opening.abs();
        r.complementarity_relative = r
            .complementarity_relative
            .max(normal.max(tangential_slack) / (fu * du));
        match state {
            ElementState::Separated | ElementState::OffSurface => {}
            ElementState::Stick => {
                r.compatibility_relative = r.compatibility_relative.max(gap.abs() / du);
                r.stick_motion_relative = r.stick_motion_relative.max(wn / du);
            }
            ElementState::Frictionless => {
                r.compatibility_relative = r.compatibility_relative.max(opening.abs() / du);
            }
            ElementState::Slip => {
                r.compatibility_relative = r.compatibility_relative.max(opening.abs() / du);
                if gn > 0.0 && wn > SLIP_DIRECTION_FLOOR * du {
                    let cos = (wk[0] * g[0] + wk[1] * g[1]) / (wn * gn);
                    r.slip_direction_error = r.slip_direction_error.max(1.0 + cos);
                }
            }
        }
    }
}

/// Tangential force `[G1, G2]` of element `k` (N), zero-filled for missing components.
pub(crate) fn tangential(x: &[f64], offset: usize, ne: usize, n_tan: usize, k: usize) -> [f64; 2] {
    let mut g = [0.0; 2];
    for (c, gc) in g.iter_mut().enumerate().take(n_tan) {
        *gc = x[offset + (c + 1) * ne + k];
    }
    g
}
