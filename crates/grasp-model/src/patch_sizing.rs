//! Patch sizing (thesis section 2.2.1): a candidate patch must contain the whole contact area.
//! A curved contact whose boundary ring of elements carries load is cut off by its patch; the
//! solution says so, and [`auto_patch`] grows such patches (keeping the element size) until
//! their boundary is unloaded. Flat pads are not checked: their patch is the pad itself, whose
//! edge is a real edge of the contact.

use crate::error::ModelError;
use crate::grasp_model::GraspModel;
pub use crate::patch_check::{patch_warnings, undersized_patches, BOUNDARY_LOAD_TOLERANCE};
use crate::scene::Scene;
use crate::solution::Solution;
use crate::solve::GraspSolver;
use crate::solve_options::SolveOptions;

/// Growth factor of a patch's size (and element count) per round of [`auto_patch`].
pub const GROWTH: f64 = 1.5;

/// Result of [`auto_patch`].
#[derive(Debug, Clone)]
pub struct AutoPatch {
    /// The scene with grown patches.
    pub scene: Scene,
    /// Its model.
    pub model: GraspModel,
    /// Its solution.
    pub solution: Solution,
    /// What was done, one line per change.
    pub log: Vec<String>,
}

/// Solves `scene`, growing every curved patch whose boundary carries load by [`GROWTH`] in size
/// and element count (element size kept) until no boundary carries load, at most `rounds`
/// times, or until growing would break validation (a patch wider than its radius, too many
/// elements), which the log says.
pub fn auto_patch(
    scene: &Scene,
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
fn solved(scene: Scene, options: SolveOptions) -> Result<AutoPatch, ModelError> {
    let model = GraspModel::from_scene(&scene).map_err(|e| ModelError::Solver(e.to_string()))?;
    let solution = GraspSolver::new(&model, options).solve(&model, &model.scene_loads_n())?;
    Ok(AutoPatch {
        scene,
        model,
        solution,
        log: Vec::new(),
    })
}

/// `scene` with the patches of the fingers in `under` grown by [`GROWTH`] (element size kept).
fn grown_scene(scene: &Scene, under: &[(usize, f64)], log: &mut Vec<String>) -> Scene {
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
