//! Patch sizing (thesis section 2.2.1): a candidate patch must contain the whole contact area.
//! A curved contact whose boundary ring of elements carries load is cut off by its patch; the
//! solution says so, and [`auto_patch`] grows such patches (keeping the element size) until
//! their boundary is unloaded. Flat pads are not checked: their patch is the pad itself, whose
//! edge is a real edge of the contact.

use crate::error::ModelError;
use crate::grasp_model::GraspModel;
use crate::scene::Scene;
use crate::solution::Solution;
use crate::solve::{GraspSolver, SolveOptions};
use crate::validation::MAX_ELEMENTS_PER_PATCH;

/// A boundary ring carrying more than this fraction of the finger's load means the patch is
/// too small.
pub const BOUNDARY_LOAD_TOLERANCE: f64 = 1e-4;

/// Growth factor of a patch's size (and element count) per round of [`auto_patch`].
pub const GROWTH: f64 = 1.5;

/// Fingers (index) whose curved patch has a loaded boundary, with the fraction of the load.
pub fn undersized_patches(model: &GraspModel, sol: &Solution) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for (i, f) in model.fingers.iter().enumerate() {
        let curved = f.patch.gap_m.iter().any(|&g| g > 0.0);
        if !curved || f.patch.grid.nx < 3 && f.patch.grid.ny < 3 {
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
        .map(|(i, frac)| {
            format!(
                "fingers[{i}] `{}`: the patch boundary carries {:.2}% of its load, so the patch is too \
                 small for the contact (thesis 2.2.1); enlarge patch.size or use --auto-patch",
                model.fingers[i].name,
                100.0 * frac
            )
        })
        .collect()
}

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
    let mut scene = scene.clone();
    let mut log = Vec::new();
    for round in 0..=rounds {
        let model =
            GraspModel::from_scene(&scene).map_err(|e| ModelError::Solver(e.to_string()))?;
        let solution = GraspSolver::new(&model, options).solve(&model, &model.scene_loads_n())?;
        let under = if solution.status.has_forces() {
            undersized_patches(&model, &solution)
        } else {
            Vec::new()
        };
        if under.is_empty() || round == rounds {
            if !under.is_empty() {
                log.push(format!(
                    "stopped after {rounds} rounds with loaded boundaries"
                ));
            }
            return Ok(AutoPatch {
                scene,
                model,
                solution,
                log,
            });
        }
        let mut grown = scene.clone();
        for &(i, frac) in &under {
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
        if let Err(e) = grown.validate() {
            log.push(format!("cannot grow further: {e}"));
            let model =
                GraspModel::from_scene(&scene).map_err(|e| ModelError::Solver(e.to_string()))?;
            let solution =
                GraspSolver::new(&model, options).solve(&model, &model.scene_loads_n())?;
            return Ok(AutoPatch {
                scene,
                model,
                solution,
                log,
            });
        }
        if grown
            .fingers
            .iter()
            .any(|f| f.patch.grid[0] * f.patch.grid[1] > MAX_ELEMENTS_PER_PATCH)
        {
            log.push("cannot grow further: too many elements".into());
        }
        scene = grown;
    }
    unreachable!("the loop returns")
}
