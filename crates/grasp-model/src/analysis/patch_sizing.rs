//! Patch sizing (thesis section 2.2.1): a candidate patch must contain the whole contact area.
//! A curved contact whose boundary ring of elements carries load is cut off by its patch; the
//! solution says so, and [`auto_patch`] grows such patches (keeping the element size) until
//! their boundary is unloaded. Flat pads are not checked: their patch is the pad itself, whose
//! edge is a real edge of the contact.

use crate::error::ModelError;
use crate::model::closed_form::{elliptical_semi_axes_m, line_contact_half_width_m};
use crate::model::grasp_model::{FingerModel, GraspModel};
use crate::scene::loaded_scene::LoadedScene;
use crate::scene::scene_format::FingerSpec;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::patch_check::undersized_patches;
use crate::solve::solution::Solution;
use crate::solve::step_inputs::StepInputs;
use crate::solver::options::SolveOptions;

/// Growth factor of a patch's size (and element count) per round of [`auto_patch`].
pub const GROWTH: f64 = 1.5;

/// Result of [`auto_patch`].
#[derive(Debug, Clone)]
pub struct AutoPatch {
    /// The scene with grown patches (its geometry as read).
    pub scene: LoadedScene,
    /// Its model.
    pub model: GraspModel,
    /// Its solution.
    pub solution: Solution,
    /// What was done, one line per change.
    pub log: Vec<String>,
}

/// Solves `scene`, growing every curved patch whose boundary carries load by `GROWTH` in size
/// and element count (element size kept) until no boundary carries load, at most `rounds`
/// times, or until growing would break validation (a patch wider than its radius, too many
/// elements), which the log says.
pub fn auto_patch(
    scene: &LoadedScene,
    options: SolveOptions,
    rounds: usize,
) -> Result<AutoPatch, ModelError> {
    let mut current = solved(scene.clone(), options)?;
    let mut log = Vec::new();
    for _ in 0..rounds {
        let under = if current.solution.status.has_forces() {
            undersized_patches(&current.model, &current.solution)
        } else {
            Vec::new()
        };
        if under.is_empty() {
            current.log = log;
            return Ok(current);
        }
        let grown = grown_scene(&current.scene, &under, &mut log);
        if let Err(e) = grown.validate() {
            log.push(format!("cannot grow further: {e}"));
            current.log = log;
            return Ok(current);
        }
        current = solved(grown, options)?;
    }
    if current.solution.status.has_forces()
        && !undersized_patches(&current.model, &current.solution).is_empty()
    {
        log.push(format!(
            "stopped after {rounds} rounds with loaded boundaries"
        ));
    }
    current.log = log;
    Ok(current)
}

/// Solves a (validated) scene.
fn solved(scene: LoadedScene, options: SolveOptions) -> Result<AutoPatch, ModelError> {
    let model = GraspModel::from_loaded_with(&scene, options.compliance).map_err(|source| {
        ModelError::DerivedScene {
            context: "the scene with grown patches".into(),
            source,
        }
    })?;
    let inputs = StepInputs::of_scene(&model);
    let mut solver = GraspSolver::new(model, options);
    let solution = solver.solve(&inputs)?;
    let model = solver.into_model();
    Ok(AutoPatch {
        scene,
        model,
        solution,
        log: Vec::new(),
    })
}

/// `scene` with the patches of the fingers in `under` grown by [`GROWTH`] (element size kept).
fn grown_scene(scene: &LoadedScene, under: &[(usize, f64)], log: &mut Vec<String>) -> LoadedScene {
    let mut grown = scene.clone();
    for &(i, frac) in under {
        let f = &mut grown.fingers[i];
        let grid = f
            .patch
            .grid
            .map(|n| ((n as f64 * GROWTH).ceil() as usize) | 1);
        let size = [0, 1].map(|k| f.patch.size[k] * grid[k] as f64 / f.patch.grid[k] as f64);
        log.push(format!(
            "{}: boundary carried {:.2}% of the load; patch {:?} m / {:?} -> {:?} m / {:?}",
            f.name,
            100.0 * frac,
            f.patch.size,
            f.patch.grid,
            size,
            grid
        ));
        f.patch.size = size;
        f.patch.grid = grid;
    }
    grown
}

/// The Hertz estimate of a finger's contact at a given load, and the patch it suggests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzSuggestion {
    /// Load of the estimate, N.
    pub load_n: f64,
    /// Contact semi-axes along `t1`, `t2`, m (`None`: straight that way, a line contact along
    /// the whole patch).
    pub semi_axes_m: [Option<f64>; 2],
    /// Suggested patch sides along `t1`, `t2`, m: 2.4 semi-axes (the contact and a ring of free
    /// elements around it), the present side where the contact is a line.
    pub suggested_size_m: [f64; 2],
    /// True when a body is a layer on a rigid core and the semi-axes are Hertz's scaled by the
    /// layered contact's estimate (`crate::model::contact_pair::ContactPair::contact_radius_estimate_m`
    /// at the equivalent radius `sqrt(R1 R2)`); a line contact keeps Hertz's half-width, which
    /// a layer only narrows.
    pub layered: bool,
}

/// Hertz estimate (Johnson 4.2) of finger `f`'s contact at `load_n` from the summed tip and
/// object curvatures along `t1`, `t2` and `E*` of the pair: an ellipse of semi-axes
/// `c (R1/R2)^(1/3)`, `c (R2/R1)^(1/3)` with `c = (3 P sqrt(R1 R2) / 4 E*)^(1/3)` (the
/// equivalent-radius approximation, a few percent for moderate eccentricity), or, curved one
/// way only, a line contact of half-width `sqrt(4 P R / (pi L E*))` over the patch length `L`.
/// On a layered body the ellipse shrinks by the ratio of the layered estimate of the contact
/// radius to Hertz's ([`HertzSuggestion::layered`]). `None` for two flat faces or two rigid
/// bodies.
pub fn hertz_suggestion(
    f: &FingerSpec,
    model: &FingerModel,
    load_n: f64,
) -> Option<HertzSuggestion> {
    let tip = crate::model::model_builder::tip_curvatures_per_m(f, &model.frame);
    let obj = crate::model::model_builder::object_curvatures_per_m(f);
    let k = [tip[0] + obj[0], tip[1] + obj[1]];
    let inv_e = model.contact.constants.normal;
    if !(inv_e > 0.0 && load_n > 0.0) {
        return None;
    }
    let size = f.patch.size;
    let e_star = 1.0 / inv_e;
    let layered = model.contact.is_layered();
    let axes = match (k[0] > 0.0, k[1] > 0.0) {
        (true, true) => {
            let r = 1.0 / (k[0] * k[1]).sqrt();
            let hertz = (3.0 * load_n * r / (4.0 * e_star)).cbrt();
            let shrink = match layered {
                true => model.contact.contact_radius_estimate_m(load_n, r) / hertz,
                false => 1.0,
            };
            elliptical_semi_axes_m(load_n, [1.0 / k[0], 1.0 / k[1]], e_star)
                .map(|a| Some(a * shrink))
        }
        (false, true) => [
            None,
            Some(line_contact_half_width_m(
                load_n,
                1.0 / k[1],
                size[0],
                e_star,
            )),
        ],
        (true, false) => [
            Some(line_contact_half_width_m(
                load_n,
                1.0 / k[0],
                size[1],
                e_star,
            )),
            None,
        ],
        (false, false) => return None,
    };
    Some(HertzSuggestion {
        load_n,
        semi_axes_m: axes,
        suggested_size_m: [0, 1].map(|d| axes[d].map_or(size[d], |a| 2.4 * a)),
        layered,
    })
}
