//! Where a solved contact leaves the half-space theory's assumptions (Johnson 5.1): surfaces
//! whose slope over the contact is not small, and a soft object loaded next to its own edge (a
//! quarter-space there, not a half-space). Warnings on the solution, each naming the finger,
//! the figure and what to change; the forces are still reported.

use crate::model::grasp_model::{FingerModel, GraspModel};
use crate::model::patch::Patch;
use crate::solve::solution::{ElementState, FingerSolution, Solution};

/// Largest slope of the initial gap over the contact (rad, about 17 degrees) within which the
/// half-space compliance is taken to hold: the linear theory neglects terms of the order of the
/// slope squared (Johnson 5.1), under 10 % here; Sneddon's exact sphere at `a/R = 0.3`, slope
/// 0.31, differs from Hertz by 3 % in load.
pub const SLOPE_LIMIT: f64 = 0.3;

/// The warnings of `sol` for the fingers of `model` with exact gaps.
pub(crate) fn validity_warnings(model: &GraspModel, sol: &Solution) -> Vec<String> {
    let mut out = Vec::new();
    for (i, (f, fs)) in model.fingers.iter().zip(&sol.fingers).enumerate() {
        if !f.exact_gaps {
            continue;
        }
        let slope = largest_contact_slope(&f.patch, fs);
        if slope > SLOPE_LIMIT {
            out.push(format!(
                "fingers[{i}] `{}`: the surfaces' slope over the contact reaches {slope:.3} \
                 ({:.0} degrees), beyond the half-space's small slopes ({SLOPE_LIMIT}): its \
                 forces are approximate; use a larger tip radius, a smaller load, or a smoother \
                 texture",
                f.name,
                slope.atan().to_degrees()
            ));
        }
        if let Some(d) = loaded_edge_distance_m(f, fs) {
            out.push(format!(
                "fingers[{i}] `{}`: the object is loaded {:.3} mm from its edge and is the \
                 softer body: it is a quarter-space there, not the half-space the compliance \
                 assumes, and the forces near the edge are approximate; move the finger away \
                 from the edge",
                f.name,
                1e3 * d
            ));
        }
    }
    out
}

/// The largest slope `|grad c|` of the initial gap at the elements in contact.
fn largest_contact_slope(patch: &Patch, fs: &FingerSolution) -> f64 {
    fs.elements
        .iter()
        .enumerate()
        .filter(|(_, e)| matches!(e.state, ElementState::Stick | ElementState::Slip))
        .map(|(k, _)| patch.gap_slope_at(k))
        .fold(0.0, f64::max)
}

/// When the object is at least as compliant as the fingertip and an element in contact
/// borders an element past the object's edge (not past the tip's rim): the distance (m) of the nearest such element's
/// centre from the edge, about half an element.
fn loaded_edge_distance_m(f: &FingerModel, fs: &FingerSolution) -> Option<f64> {
    let object_soft = f.contact.object_material.normal_factor_per_pa()
        >= f.contact.finger_material.normal_factor_per_pa();
    if !object_soft || f.patch.off_object.is_empty() {
        return None;
    }
    let g = &f.patch.grid;
    let off = |i: usize, j: usize| f.patch.off_object[i * g.ny + j];
    let borders_edge = |k: usize| {
        let (i, j) = (k / g.ny, k % g.ny);
        (i > 0 && off(i - 1, j))
            || (i + 1 < g.nx && off(i + 1, j))
            || (j > 0 && off(i, j - 1))
            || (j + 1 < g.ny && off(i, j + 1))
    };
    fs.elements
        .iter()
        .enumerate()
        .any(|(k, e)| {
            e.normal_force_n > 0.0 && e.state != ElementState::Separated && borders_edge(k)
        })
        .then(|| 0.5 * g.hx.min(g.hy))
}
