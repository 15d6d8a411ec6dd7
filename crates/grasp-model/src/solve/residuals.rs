//! Residuals of a solution, computed from the forces and the rigid displacement with this
//! crate's own matrices, never taken from the solver's report.
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

use crate::model::grasp_model::GraspModel;
use crate::solve::solution::{ElementState, Residuals};

/// The slip direction of an element is checked against its friction force only when the slip
/// exceeds this many displacement units `Fu Cu` (a shorter slip has no direction worth the
/// name: it is the round-off of a sticking element's relative motion).
const SLIP_DIRECTION_FLOOR: f64 = 1e-9;

/// Kinematics of every element: gaps and relative tangential displacements (m).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactKinematics {
    /// Per finger, per element: gap after loading, m.
    pub gap_m: Vec<Vec<f64>>,
    /// Per finger, per element: relative tangential displacement along `[t1, t2]`, m. For a
    /// frictionless finger only the rigid part is known (its elastic tangential displacement
    /// is not modelled).
    pub tangential_m: Vec<Vec<[f64; 2]>>,
}

/// Evaluates gaps and tangential displacements (see the module docs).
///
/// - `x_n`: element forces, N, program layout;
/// - `translation_o_m`, `rotation_rad`: rigid displacement of the object at the reference
///   point `O`;
/// - `approach_m`: per finger, its advance along the inward normal as the program found it
///   (force-controlled fingers; 0 for the others);
/// - `offset_m`: per unknown (program layout), the displacement added to the elastic one:
///   a prescribed approach (`-d` on the normal unknowns) and viscoelastic history
///   ([`crate::program::cone_program`]).
pub fn contact_kinematics(
    model: &GraspModel,
    x_n: &[f64],
    translation_o_m: &Vector3<f64>,
    rotation_rad: &Vector3<f64>,
    approach_m: &[f64],
    offset_m: &[f64],
) -> ContactKinematics {
    let mut gap_m = Vec::with_capacity(model.fingers.len());
    let mut tangential_m = Vec::with_capacity(model.fingers.len());
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        let xi = &x_n[f.offset..f.offset + f.n_unknowns()];
        let mut u = vec![0.0; xi.len()];
        f.compliance_m_per_n.apply(xi, &mut u);
        for (uj, o) in u
            .iter_mut()
            .zip(&offset_m[f.offset..f.offset + f.n_unknowns()])
        {
            *uj += o;
        }
        let mut g = Vec::with_capacity(ne);
        let mut w = Vec::with_capacity(ne);
        for k in 0..ne {
            let p = f.element_point(k);
            let delta = translation_o_m + rotation_rad.cross(&(p - model.reference_point_m));
            g.push(f.patch.gap_m[k] + u[k] + f.frame.normal.dot(&delta) - approach_m[i]);
            let mut wk = [f.frame.t1.dot(&delta), f.frame.t2.dot(&delta)];
            for (c, wc) in wk.iter_mut().enumerate().take(f.n_tangential) {
                *wc += u[(c + 1) * ne + k];
            }
            w.push(wk);
        }
        gap_m.push(g);
        tangential_m.push(w);
    }
    ContactKinematics {
        gap_m,
        tangential_m,
    }
}

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

    /// True for the associated (energy) rule.
    pub fn is_associated(&self) -> bool {
        matches!(self, FrictionRule::Associated)
    }
}

/// Computes the residuals of forces `x_n` (N), given their kinematics, element states, the
/// friction coefficient of each finger at its load (`mu`) and the friction rule.
pub fn evaluate(
    model: &GraspModel,
    x_n: &[f64],
    kin: &ContactKinematics,
    states: &[Vec<ElementState>],
    mu: &[f64],
    rule: FrictionRule<'_>,
) -> Residuals {
    let s = model.scales;
    let w = model.net_wrench(x_n);
    let force_n = w.fixed_rows::<3>(0).norm();
    let moment_nm = w.fixed_rows::<3>(3).norm();
    let equilibrium_relative = (force_n / s.load_n).max(moment_nm / (s.load_n * s.length_m));
    let (fu, du) = (s.element_force_n, s.displacement_m());
    let mut r = Residuals {
        force_n,
        moment_nm,
        equilibrium_relative,
        cone_violation_relative: 0.0,
        penetration_relative: 0.0,
        compatibility_relative: 0.0,
        complementarity_relative: 0.0,
        stick_motion_relative: 0.0,
        slip_direction_error: 0.0,
    };
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        let mu = mu[i];
        // Opening on slip: `mu` for the associated law, none for Coulomb.
        let dilatancy = if rule.is_associated() && f.n_tangential > 0 {
            mu
        } else {
            0.0
        };
        for k in 0..ne {
            let fk = x_n[f.offset + k];
            let g = tangential(x_n, f.offset, ne, f.n_tangential, k);
            let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
            let viol = (gn - mu * fk).max(-fk).max(0.0);
            r.cone_violation_relative = r.cone_violation_relative.max(viol / fu);
            let gap = kin.gap_m[i][k];

            let wk = rule.step_slip(i, k, kin.tangential_m[i][k]);
            let wn = (wk[0] * wk[0] + wk[1] * wk[1]).sqrt();
            // Penetration, and for the associated law the dual cone `gap >= mu |w|` (model.md:
            // a slipping element opens by mu |slip|; a separated one at least as much).
            let dual_gap = gap - dilatancy * wn;
            r.penetration_relative = r.penetration_relative.max((-dual_gap).max(0.0) / du);
            let (opening, tangential_slack) = if f.n_tangential == 0 {
                (gap, 0.0)
            } else {
                (gap - dilatancy * wn, (mu * fk - gn).max(0.0) * wn)
            };
            let normal = fk.max(0.0) * opening.abs();
            r.complementarity_relative = r
                .complementarity_relative
                .max(normal.max(tangential_slack) / (fu * du));
            match states[i][k] {
                ElementState::Separated => {}
                ElementState::Stick => {
                    r.compatibility_relative = r.compatibility_relative.max(gap.abs() / du);
                    r.stick_motion_relative = r.stick_motion_relative.max(wn / du);
                }
                ElementState::Slip => {
                    let slip_gap = dilatancy * wn;
                    r.compatibility_relative =
                        r.compatibility_relative.max((gap - slip_gap).abs() / du);
                    if f.n_tangential > 0 && gn > 0.0 && wn > SLIP_DIRECTION_FLOOR * du {
                        let cos = (wk[0] * g[0] + wk[1] * g[1]) / (wn * gn);
                        r.slip_direction_error = r.slip_direction_error.max(1.0 + cos);
                    }
                }
            }
        }
    }
    r
}

/// Tangential force `[G1, G2]` of element `k` (N), zero-filled for missing components.
pub(crate) fn tangential(x: &[f64], offset: usize, ne: usize, n_tan: usize, k: usize) -> [f64; 2] {
    let mut g = [0.0; 2];
    for (c, gc) in g.iter_mut().enumerate().take(n_tan) {
        *gc = x[offset + (c + 1) * ne + k];
    }
    g
}
