//! The patch-size check of a solution (thesis section 2.2.1): a candidate patch must contain the
//! whole contact area, so a curved contact whose boundary ring of elements carries load is cut
//! off by its patch. Flat pads are not checked: their patch is the pad itself, whose edge is a
//! real edge of the contact. Growing such patches is [`crate::analysis::patch_sizing::auto_patch`].

use crate::model::grasp_model::GraspModel;
use crate::solve::solution::Solution;

/// A boundary ring carrying more than this fraction of the finger's load means the patch is
/// too small.
pub const BOUNDARY_LOAD_TOLERANCE: f64 = 1e-4;

/// Fingers (index) whose curved patch has a loaded boundary, with the fraction of the load.
pub fn undersized_patches(model: &GraspModel, sol: &Solution) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for (i, f) in model.fingers.iter().enumerate() {
        if !f.patch.curved || f.patch.grid.nx < 3 && f.patch.grid.ny < 3 {
            continue;
        }
        if let Some(s) = sol.finger(&f.name) {
            if s.boundary_load_fraction > BOUNDARY_LOAD_TOLERANCE {
                out.push((i, s.boundary_load_fraction));
            }
        }
    }
    out
}

/// Warnings for undersized patches.
pub fn patch_warnings(model: &GraspModel, sol: &Solution) -> Vec<String> {
    undersized_patches(model, sol)
        .into_iter()
        .map(|(k, frac)| {
            // Named by its place in the scene (a hand-off step's model holds only the active
            // fingers).
            let i = model.fingers[k].scene_index;
            format!(
                "fingers[{i}] `{}`: the patch boundary carries {:.2}% of its load, so the patch is too \
                 small for the contact (thesis 2.2.1); enlarge patch.size or grow it with `{}`",
                model.fingers[k].name,
                100.0 * frac,
                crate::option_names::AUTO_PATCH
            )
        })
        .collect()
}
