//! Discretisation error: coarser and finer grids of the same scene, a Richardson-type estimate
//! of a solution's discretisation error, and grid-refinement studies.
//!
//! The element tractions are piecewise constant (collocation at element centres), so the
//! resultants converge at least like `h^p` with `p = 1`; the estimate assumes `p = 1`, which
//! over-estimates the error when convergence is faster (Hertz approach converges like
//! `h^2`-`h^3`; see docs/results.md), so it errs on the safe side.

use std::sync::Arc;
use std::time::Instant;

use crate::error::ModelError;
use crate::model::closed_form::HertzSphere;
use crate::model::grasp_model::GraspModel;
use crate::scene::limits::{MAX_ELEMENTS_PER_PATCH, MAX_GRID_SIDE};
use crate::scene::loaded_scene::LoadedScene;
use crate::scene::scene_format::{RadiusSpec, Scene};
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::solution::Solution;
use crate::solve::step_inputs::StepInputs;
use crate::solver::options::SolveOptions;

/// Convergence order assumed by the estimate.
pub const ASSUMED_ORDER: f64 = 1.0;

/// The scene with every patch's grid replaced by `grid(i, [nx, ny])` (its geometry as read).
pub fn with_grids(
    scene: &LoadedScene,
    grid: impl Fn(usize, [usize; 2]) -> [usize; 2],
) -> LoadedScene {
    let mut s = scene.clone();
    for (i, f) in s.fingers.iter_mut().enumerate() {
        f.patch.grid = grid(i, f.patch.grid);
    }
    s
}

/// The grid refined so that its first side has `n` elements, the second keeping the aspect
/// ratio of the scene's grid (at least 1; `usize::MAX` where the ratio overflows).
pub fn grid_with_first_side(original: [usize; 2], n: usize) -> [usize; 2] {
    let ny = ((n as f64) * original[1] as f64 / original[0].max(1) as f64)
        .round()
        .max(1.0) as usize;
    [n.max(1), ny]
}

/// Largest differences between two solutions of the same fingers: normal force and friction
/// force vector (N).
fn force_differences_n(a: &Solution, b: &Solution) -> (f64, f64) {
    let (mut dp, mut dq) = (0.0_f64, 0.0_f64);
    for (fa, fb) in a.fingers.iter().zip(&b.fingers) {
        dp = dp.max((fa.normal_force_n - fb.normal_force_n).abs());
        let d: f64 = (0..3)
            .map(|c| (fa.tangential_force_n[c] - fb.tangential_force_n[c]).powi(2))
            .sum::<f64>()
            .sqrt();
        dq = dq.max(d);
    }
    (dp, dq)
}

/// A discretisation error estimate of a solution.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ErrorEstimate {
    /// The coarser grids solved, per finger.
    pub coarse_grids: Vec<[usize; 2]>,
    /// Refinement ratio `r = h_coarse / h_fine` (smallest over fingers and sides).
    pub refinement_ratio: f64,
    /// Estimated error of the finger normal forces, N (largest over fingers).
    pub normal_force_error_n: f64,
    /// Estimated error of the finger friction force vectors, N (largest over fingers).
    pub tangential_force_error_n: f64,
    /// The larger of the two over the load scale.
    pub relative: f64,
    /// Estimated relative error of the peak pressures (largest over loaded fingers).
    pub peak_pressure_relative: f64,
    /// Extra wall time spent on the coarse solve, s.
    pub extra_time_s: f64,
}

/// Why no estimate could be made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NoEstimate {
    /// Every grid is 1 x 1 and cannot be coarsened.
    CannotCoarsen,
    /// The coarse grid gave no forces (its status and reason).
    CoarseFailed(String),
}

/// Estimates the discretisation error of `fine` (the solution of `scene`) from a solve on
/// grids about half as fine: `e ~ |q_fine - q_coarse| / (r^p - 1)` (Richardson, p = 1).
pub fn estimate_error(
    scene: &LoadedScene,
    fine: &Solution,
    options: SolveOptions,
) -> Result<Result<ErrorEstimate, NoEstimate>, ModelError> {
    let start = Instant::now();
    let coarse_scene = with_grids(scene, |_, g| [g[0].div_ceil(2), g[1].div_ceil(2)]);
    if coarse_scene
        .fingers
        .iter()
        .zip(&scene.fingers)
        .all(|(c, f)| c.patch.grid == f.patch.grid)
    {
        return Ok(Err(NoEstimate::CannotCoarsen));
    }
    let model =
        GraspModel::from_loaded_with(&coarse_scene, options.compliance).map_err(|source| {
            ModelError::DerivedScene {
                context: "the grid half as fine".into(),
                source,
            }
        })?;
    let model = Arc::new(model);
    let coarse =
        GraspSolver::new(Arc::clone(&model), options).solve(&StepInputs::of_scene(&model))?;
    if !coarse.status.has_forces() {
        return Ok(Err(NoEstimate::CoarseFailed(
            coarse.reason.unwrap_or_default(),
        )));
    }
    let ratio = scene
        .fingers
        .iter()
        .zip(&coarse_scene.fingers)
        .flat_map(|(f, c)| {
            (0..2)
                .filter(|&k| c.patch.grid[k] < f.patch.grid[k])
                .map(move |k| f.patch.grid[k] as f64 / c.patch.grid[k] as f64)
        })
        .fold(f64::INFINITY, f64::min);
    let denom = ratio.powf(ASSUMED_ORDER) - 1.0;
    let (dp, dq) = force_differences_n(fine, &coarse);
    let mut dpk = 0.0_f64;
    for (a, b) in fine.fingers.iter().zip(&coarse.fingers) {
        if a.peak_pressure_pa > 0.0 {
            dpk = dpk.max((a.peak_pressure_pa - b.peak_pressure_pa).abs() / a.peak_pressure_pa);
        }
    }
    let (ep, eq) = (dp / denom, dq / denom);
    Ok(Ok(ErrorEstimate {
        coarse_grids: coarse_scene.fingers.iter().map(|f| f.patch.grid).collect(),
        refinement_ratio: ratio,
        normal_force_error_n: ep,
        tangential_force_error_n: eq,
        relative: ep.max(eq) / fine.load_scale_n,
        peak_pressure_relative: dpk / denom,
        extra_time_s: start.elapsed().as_secs_f64(),
    }))
}

/// What a study measures its error against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StudyReference {
    /// Hertz closed form (one spherical fingertip on a flat object): peak pressure and approach.
    Hertz,
    /// The finest grid of the study: finger normal and friction forces over the load scale.
    FinestGrid,
}

/// One row of a refinement study.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StudyRow {
    /// Grid of the first finger.
    pub grid: [usize; 2],
    /// Unknowns of the program.
    pub unknowns: usize,
    /// Main error measure (Hertz: peak pressure relative error; finest grid: force error over
    /// the load scale).
    pub error: f64,
    /// Second error measure (Hertz: approach relative error; finest grid: none).
    pub error_2: Option<f64>,
    /// Wall time of model build and solve, s.
    pub wall_time_s: f64,
    /// Peak resident memory after the solve, bytes, when the caller can measure it.
    pub peak_memory_bytes: Option<u64>,
    /// Equilibrium residual of the solve.
    pub equilibrium_residual: f64,
    /// The largest peak pressure of the fingers, Pa.
    pub peak_pressure_pa: f64,
    /// True when that peak lies at a sharp edge of its contact, where the pressure is singular
    /// (`FingerSolution::peak_pressure_grid_dependent`): it then grows with the grid.
    pub peak_pressure_grid_dependent: bool,
    /// The solve's warnings (the scene's first).
    pub warnings: Vec<String>,
}

/// Below this fitted exponent a peak pressure counts as not growing with the grid: a converging
/// peak changes by a few per cent over a study's grids (Hertz: `n^0.0` to `n^0.05`), a peak at a
/// square-root singularity grows as `n^0.5`.
pub const GROWING_PEAK_EXPONENT: f64 = 0.15;

/// How the largest peak pressure changes over a study's grids.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PeakTrend {
    /// The exponent `b` of the least-squares fit `p_max = a n^b` over the grids (`n` elements
    /// along the first side), in log-log.
    pub exponent: f64,
    /// True when the peak lies at a sharp edge of its contact at the finest grid, where the
    /// pressure is singular.
    pub at_sharp_edge: bool,
    /// True when the peak grows with the grid: at a sharp edge, or an exponent of at least
    /// [`GROWING_PEAK_EXPONENT`]. It is then not a converged value.
    pub grid_dependent: bool,
}

/// The trend of the peak pressure over `rows` (a study's grids, ascending): `None` with fewer
/// than two grids or a grid without a positive peak.
pub fn peak_trend(rows: &[StudyRow]) -> Option<PeakTrend> {
    if rows.len() < 2
        || !rows
            .iter()
            .all(|r| r.peak_pressure_pa > 0.0 && r.peak_pressure_pa.is_finite())
    {
        return None;
    }
    let pts: Vec<[f64; 2]> = rows
        .iter()
        .map(|r| [(r.grid[0] as f64).ln(), r.peak_pressure_pa.ln()])
        .collect();
    let m = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p[0]).sum::<f64>() / m,
        pts.iter().map(|p| p[1]).sum::<f64>() / m,
    );
    let sxx: f64 = pts.iter().map(|p| (p[0] - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p[0] - mx) * (p[1] - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let exponent = sxy / sxx;
    let at_sharp_edge = rows.last().is_some_and(|r| r.peak_pressure_grid_dependent);
    Some(PeakTrend {
        exponent,
        at_sharp_edge,
        grid_dependent: at_sharp_edge || exponent >= GROWING_PEAK_EXPONENT,
    })
}

/// Checks that `scene` is a Hertz case (one spherical tip on a flat, both bodies half-spaces)
/// and returns `(R m, E* Pa)`.
pub fn hertz_parameters(scene: &Scene) -> Result<(f64, f64), String> {
    if scene.fingers.len() != 1 {
        return Err(format!(
            "a Hertz study needs exactly one finger, the scene has {}",
            scene.fingers.len()
        ));
    }
    let f = &scene.fingers[0];
    let r = f
        .tip_radius
        .ok_or("fingers[0].tip_radius is null: a Hertz study needs a spherical tip")?;
    if !matches!(
        f.object_radius,
        None | Some(RadiusSpec::Principal([None, None]))
    ) {
        return Err("fingers[0].object_radius is set: a Hertz study needs a flat object".into());
    }
    for (path, m) in [
        ("fingers[0].material", &f.material),
        ("object.material", &scene.object.material),
    ] {
        if m.layer_thickness_m().is_some() {
            return Err(format!(
                "{path}.layer_thickness_m is set: a layer on a rigid core has no Hertz closed \
                 form (model/elastic_layer.rs gives its thin and thick limits)"
            ));
        }
    }
    let fm = crate::model::material::Material::from(&f.material);
    let om = crate::model::material::Material::from(&scene.object.material);
    Ok((r, fm.effective_modulus_pa(&om)))
}

/// Runs a refinement study: the scene solved with the first side of every patch at each of
/// `first_sides` elements (ascending), errors against `reference`. `memory` is called after
/// each solve to read the peak memory (the model crate does no I/O itself).
pub fn refinement_study(
    scene: &LoadedScene,
    first_sides: &[usize],
    reference: StudyReference,
    options: SolveOptions,
    mut memory: impl FnMut() -> Option<u64>,
) -> Result<Vec<StudyRow>, String> {
    let mut sides = first_sides.to_vec();
    sides.sort_unstable();
    sides.dedup();
    if sides.is_empty() {
        return Err("give at least one grid".into());
    }
    let hertz = match reference {
        StudyReference::Hertz => Some(hertz_parameters(scene)?),
        StudyReference::FinestGrid => None,
    };
    let mut sols = Vec::with_capacity(sides.len());
    let mut rows = Vec::with_capacity(sides.len());
    for &n in &sides {
        let s = with_grids(scene, |_, g| grid_with_first_side(g, n));
        check_grid_size(&s, n)?;
        let t = Instant::now();
        let model =
            GraspModel::from_loaded_with(&s, options.compliance).map_err(|e| e.to_string())?;
        let model = Arc::new(model);
        let sol = GraspSolver::new(Arc::clone(&model), options)
            .solve(&StepInputs::of_scene(&model))
            .map_err(|e| e.to_string())?;
        let wall = t.elapsed().as_secs_f64();
        if !sol.status.has_forces() {
            return Err(format!(
                "grid {n}: {}",
                sol.reason.clone().unwrap_or_default()
            ));
        }
        let (error, error_2) = match hertz {
            Some((r, e_star)) => hertz_errors(&model, &sol, r, e_star, n)?,
            None => (f64::NAN, None),
        };
        let peak = sol
            .fingers
            .iter()
            .max_by(|a, b| a.peak_pressure_pa.total_cmp(&b.peak_pressure_pa));
        rows.push(StudyRow {
            grid: s.fingers[0].patch.grid,
            unknowns: model.n_unknowns,
            error,
            error_2,
            wall_time_s: wall,
            peak_memory_bytes: memory(),
            equilibrium_residual: sol.residuals.map_or(f64::NAN, |r| r.equilibrium_relative),
            peak_pressure_pa: peak.map_or(0.0, |f| f.peak_pressure_pa),
            peak_pressure_grid_dependent: peak.is_some_and(|f| f.peak_pressure_grid_dependent),
            warnings: sol.warnings.clone(),
        });
        sols.push(sol);
    }
    if hertz.is_none() {
        let finest = sols.last().ok_or("a study needs at least one grid")?;
        for (row, sol) in rows.iter_mut().zip(&sols) {
            let (dp, dq) = force_differences_n(sol, finest);
            row.error = dp.max(dq) / finest.load_scale_n;
        }
    }
    Ok(rows)
}

/// Refuses the grid with first side `n` when it gives a patch of `s` more than
/// [`MAX_ELEMENTS_PER_PATCH`] elements, or more than [`MAX_GRID_SIDE`] along a side.
fn check_grid_size(s: &Scene, n: usize) -> Result<(), String> {
    let too_big = |g: [usize; 2]| {
        g[0].saturating_mul(g[1]) > MAX_ELEMENTS_PER_PATCH || g.iter().any(|&k| k > MAX_GRID_SIDE)
    };
    if let Some((i, f)) = s
        .fingers
        .iter()
        .enumerate()
        .find(|(_, f)| too_big(f.patch.grid))
    {
        return Err(format!(
            "grid {n} gives fingers[{i}] ({}) a {} x {} patch: at most {MAX_GRID_SIDE} elements \
             a side and {MAX_ELEMENTS_PER_PATCH} in all",
            f.name, f.patch.grid[0], f.patch.grid[1]
        ));
    }
    Ok(())
}

/// The Hertz errors of the solution `sol` of `model` (tip radius `r`, `E*` `e_star`) on the
/// grid with first side `n`: peak pressure and approach, each relative to Hertz's.
fn hertz_errors(
    model: &GraspModel,
    sol: &Solution,
    r: f64,
    e_star: f64,
    n: usize,
) -> Result<(f64, Option<f64>), String> {
    let f = &sol.fingers[0];
    let h = HertzSphere::new(f.normal_force_n, r, e_star);
    let n_i = &model.fingers[0].frame.normal;
    let d = sol
        .rigid_displacement
        .ok_or_else(|| format!("grid {n}: solved without a rigid displacement"))?;
    let t_com = nalgebra::Vector3::from(d.translation_m);
    let theta = nalgebra::Vector3::from(d.rotation_rad);
    let at = model.fingers[0].frame.origin_m - model.center_of_mass_m();
    let approach = f.approach_m - n_i.dot(&(t_com + theta.cross(&at)));
    Ok((
        (f.peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa,
        Some((approach - h.approach_m).abs() / h.approach_m),
    ))
}
