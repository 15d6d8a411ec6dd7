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

/// Largest compression, as a fraction of the surfaces' relative radius of curvature, within
/// which the contact is taken as small-strain: Hertz's `delta / R = (a / R)^2`, so 0.2 is a
/// contact radius of 0.45 R, where Sneddon's exact sphere carries 9 % more than Hertz's
/// (Johnson 4.2; 4 % at the slope limit's 0.32 R).
pub const APPROACH_PER_RADIUS_LIMIT: f64 = 0.2;

/// Largest compression, as a fraction of a bonded layer's thickness, within which the layer's
/// strain is taken as small (a nominal compression of 30 %).
pub const APPROACH_PER_LAYER_LIMIT: f64 = 0.3;

/// The warnings of `sol` for the fingers of `model`: every finger's approach beyond small
/// strain, and, with exact gaps, steep slopes and loads at a soft object's edge.
pub(crate) fn validity_warnings(
    model: &GraspModel,
    sol: &Solution,
    compression_m: &[f64],
) -> Vec<String> {
    let mut out = Vec::new();
    for (k, (f, fs)) in model.fingers.iter().zip(&sol.fingers).enumerate() {
        // Messages name the finger by its place in the scene (a hand-off step's model holds
        // only the active fingers).
        let i = f.scene_index;
        let d = compression_m.get(k).copied().unwrap_or(0.0);
        out.extend(strain_warning(f, d).map(|w| format!("fingers[{i}] `{}`: {w}", f.name)));
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

/// When the finger's contact leaves small strain: its compression `d` (m, the largest elastic
/// closure of the surfaces over the patch, Hertz's approach `delta` at a curved contact)
/// beyond [`APPROACH_PER_LAYER_LIMIT`] of a bonded layer's thickness, or, with the quadratic
/// gap (exact gaps have the slope warning), beyond [`APPROACH_PER_RADIUS_LIMIT`] of the
/// surfaces' relative radius of curvature. Commanded and solved approaches alike.
fn strain_warning(f: &FingerModel, d: f64) -> Option<String> {
    if d.is_nan() || d <= 0.0 {
        return None;
    }
    let layers = [&f.contact.finger_layer, &f.contact.object_layer];
    if let Some(h) = layers
        .iter()
        .filter_map(|l| l.as_ref().map(|l| l.thickness_m))
        .find(|h| d > APPROACH_PER_LAYER_LIMIT * h)
    {
        return Some(format!(
            "its compression {d:.3e} m is {:.0} % of a {h:.3e} m layer's thickness, beyond \
             small strain ({:.0} %): its forces are approximate; give a smaller approach or \
             load, or a thicker layer",
            100.0 * d / h,
            100.0 * APPROACH_PER_LAYER_LIMIT
        ));
    }
    let r = 1.0 / f.patch.curvature_per_m;
    (!f.exact_gaps && f.patch.curved && d > APPROACH_PER_RADIUS_LIMIT * r).then(|| {
        format!(
            "its compression {d:.3e} m is {:.2} of the surfaces' radius of curvature {r:.3e} m \
             (a contact radius near {:.2} of it), beyond small strain \
             ({APPROACH_PER_RADIUS_LIMIT}): its forces are approximate; give a smaller \
             approach or load, or a larger tip radius",
            d / r,
            (d / r).sqrt()
        )
    })
}

/// The largest slope `|grad c|` of the initial gap at the elements in contact.
fn largest_contact_slope(patch: &Patch, fs: &FingerSolution) -> f64 {
    fs.elements
        .iter()
        .enumerate()
        .filter(|(_, e)| {
            matches!(
                e.state,
                ElementState::Stick | ElementState::Slip | ElementState::Frictionless
            )
        })
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
