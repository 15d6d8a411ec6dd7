//! Which elements a cold start puts in contact (never one facing no surface). A flat pad
//! starts with every element in contact and sticking (the all-stick step of
//! [`super::semismooth_newton`]). A curved contact starts with the elements whose initial gap
//! lies within [`APPROACH_FACTOR`] Hertz approaches of the smallest gap: Johnson's eq. 4.23,
//! `delta = (9 P^2 / (16 E*^2 R))^(1/3)` with `1/R` the largest curvature of the smooth gap
//! (`Patch::curvature_per_m`; on a textured patch the candidates are then the elements its
//! asperities bring within that approach, the rigid interference's bearing area), `E*` the pair's effective modulus and `P` the finger's
//! expected load (its prescribed load, or the load scale for a held finger). On a layered body
//! the circle is the layered estimate of the contact radius
//! ([`crate::model::contact_pair::ContactPair::contact_radius_estimate_m`]: a layer is stiffer,
//! its contact smaller), with `delta = a^2 / R`. With the factor
//! 1/2 this is Hertz's contact circle itself: inside it the surfaces close by `delta - r^2/2R`
//! and its edge `a^2 = R delta` is where the initial gap `r^2/2R` equals `delta/2` (Johnson
//! 4.2). Elements outside then start separated instead of in deep tension, and the first
//! Newton step already lands near the answer: on the Hertz case at 41x41 two Newton steps
//! instead of six with a factor of 4 (each step factorises a matrix over the contact
//! elements, so this cut the solve from about 390 ms to 100 ms). When the expected load is
//! off (a held finger) the iteration adds or drops elements as usual.

use crate::model::closed_form::HertzSphere;
use crate::model::grasp_model::{Control, FingerModel, GraspModel};

/// Candidate elements lie within this many Hertz approaches of the smallest gap (1/2: the
/// Hertz contact circle).
pub const APPROACH_FACTOR: f64 = 0.5;

/// Per element of `finger`: true when a cold start puts it in contact.
pub(crate) fn initial_contact(model: &GraspModel, finger: &FingerModel) -> Vec<bool> {
    let patch = &finger.patch;
    let gaps = &patch.gap_m;
    let on = |k: &usize| !patch.is_off_surface(*k);
    let c_min = (0..gaps.len())
        .filter(on)
        .map(|k| gaps[k])
        .fold(f64::INFINITY, f64::min);
    let c_max = (0..gaps.len())
        .filter(on)
        .map(|k| gaps[k])
        .fold(f64::NEG_INFINITY, f64::max);
    // Negated on purpose: NaN gaps count as flat.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let flat = !(c_max > c_min);
    let curvature = patch.curvature_per_m;
    let e_star = 1.0 / finger.contact.constants.normal;
    let load = match finger.control {
        Control::NormalLoad { newtons } if newtons > 0.0 => newtons,
        _ => model.scales.load_n,
    };
    if flat || !(curvature > 0.0 && e_star.is_finite() && e_star > 0.0) {
        return (0..gaps.len()).map(|k| on(&k)).collect();
    }
    let delta = match finger.contact.is_layered() {
        // Hertz's relation `delta = a^2 / R` at the layered estimate of the radius: the
        // candidates are then that circle, as on a half-space.
        true => {
            finger
                .contact
                .contact_radius_estimate_m(load, 1.0 / curvature)
                .powi(2)
                * curvature
        }
        false => HertzSphere::new(load, 1.0 / curvature, e_star).approach_m,
    };
    gaps.iter()
        .map(|&c| c <= c_min + APPROACH_FACTOR * delta)
        .collect()
}
