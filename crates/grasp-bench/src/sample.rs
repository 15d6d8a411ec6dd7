//! One run of a prepared case and what it cost: time (as the case's target counts it),
//! unknowns, iterations, factorisations, peak memory, and the run's error.

use std::sync::Arc;
use std::time::Instant;

use grasp_model::hertz_parameters;
use grasp_model::{closed_form::cattaneo_stick_radius_m, closed_form::HertzSphere};
use grasp_model::{GraspModel, GraspSolver, Solution, SolverKind, StepInputs};
use grasp_transfer::Stepper;

use crate::case::{CaseKind, Prepared};
use crate::error::BenchError;
use crate::peak_memory;

/// What one run of a case cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The timed quantity, s: one solve, one model build plus solve, or the mean of a
    /// hand-off's steps (each step's wall time as the stepper reports it, and the model's
    /// build before the first step spread over the steps; for [`CaseKind::Margins`] each
    /// step's margins' wall time instead).
    pub time_s: f64,
    /// The solve alone, s (per step for a hand-off): the growth exponent is fitted to this.
    pub solve_s: f64,
    /// Model build, s (measured at preparation for [`CaseKind::Solve`]).
    pub build_s: f64,
    /// Unknowns of the program (the largest over a hand-off's steps).
    pub unknowns: usize,
    /// Solver iterations per solve (per step for a hand-off): Newton steps for the native
    /// solver, interior-point iterations for Clarabel.
    pub iterations: f64,
    /// Conjugate-gradient iterations per solve (per step) of an FFT patch; 0 for dense ones.
    pub inner_iterations: f64,
    /// Matrix factorisations per solve (per step); 0 where the solver does not count them.
    pub factorizations: f64,
    /// Steps of a hand-off (1 otherwise).
    pub steps: usize,
    /// Solves answered by Clarabel although the native solver was asked (`auto` fallbacks).
    pub fallbacks: usize,
    /// Peak resident memory above the resident memory at the start of the run, bytes.
    pub peak_memory_bytes: Option<u64>,
    /// Error of the run: the relative error of the peak pressure against Hertz's closed form
    /// (Johnson 4.2) for a Hertz scene; the error of the last step's stick radius against
    /// Cattaneo's (Johnson 7.2), in elements, for the Cattaneo scene; otherwise the worst
    /// relative residual of the solve (the worst over the steps of a hand-off).
    pub error: f64,
}

fn run_err(p: &Prepared, message: String) -> BenchError {
    BenchError::Run {
        case: p.case.name.to_string(),
        message,
    }
}

/// Error measure of one solution (see [`Sample::error`]).
fn error_of(p: &Prepared, sol: &Solution) -> f64 {
    if p.case.scene == "hertz_sphere_on_flat" {
        if let Ok((r, e_star)) = hertz_parameters(&p.scene) {
            let f = &sol.fingers[0];
            let h = HertzSphere::new(f.normal_force_n, r, e_star);
            return (f.peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa;
        }
    }
    sol.residuals.map_or(f64::NAN, |r| r.worst())
}

/// The Cattaneo case's error: `|c - a (1 - Q/(mu P))^(1/3)| / h` with `c` the
/// area-equivalent radius of the stick elements, `sqrt(N_stick h^2 / pi)`, `P` and `Q` the
/// forces the finger carries, `a` Hertz's radius under `P` (Johnson 4.2 and 7.2); `None` for
/// other scenes.
fn stick_radius_error(p: &Prepared, sol: &Solution) -> Option<f64> {
    if p.case.scene != "cattaneo_sphere_on_flat" {
        return None;
    }
    let (r, e_star) = hertz_parameters(&p.scene).ok()?;
    let spec = p.scene.fingers.first()?;
    let grasp_model::FrictionSpec::Coefficient(c) = &spec.friction else {
        return None;
    };
    let mu = c.mu;
    let f = sol.fingers.first()?;
    let h = spec.patch.size[0] / spec.patch.grid[0] as f64;
    let a = HertzSphere::new(f.normal_force_n, r, e_star).contact_radius_m;
    let c_exact = cattaneo_stick_radius_m(a, f.tangential_magnitude_n, mu, f.normal_force_n);
    let c = (f.stick_count as f64 * h * h / std::f64::consts::PI).sqrt();
    Some((c - c_exact).abs() / h)
}

fn one_solve(
    p: &Prepared,
    model: Arc<GraspModel>,
    build_s: f64,
    t0: Instant,
) -> Result<Sample, BenchError> {
    let t = Instant::now();
    let inputs = StepInputs::of_scene(&model);
    let sol = GraspSolver::new(model, p.solve_options())
        .solve(&inputs)
        .map_err(|e| run_err(p, e.to_string()))?;
    let solve_s = t.elapsed().as_secs_f64();
    let time_s = t0.elapsed().as_secs_f64();
    if !sol.status.has_forces() {
        return Err(run_err(
            p,
            format!("{:?}: {}", sol.status, sol.reason.unwrap_or_default()),
        ));
    }
    Ok(Sample {
        time_s,
        solve_s,
        build_s,
        unknowns: sol.solver.unknowns,
        iterations: f64::from(sol.solver.iterations),
        inner_iterations: f64::from(sol.solver.inner_iterations),
        factorizations: f64::from(sol.solver.factorizations),
        steps: 1,
        fallbacks: usize::from(fell_back(p, &sol)),
        peak_memory_bytes: None,
        error: error_of(p, &sol),
    })
}

fn fell_back(p: &Prepared, sol: &Solution) -> bool {
    p.solver != grasp_model::SolverChoice::Clarabel && sol.solver.solver == SolverKind::Clarabel
}

fn hand_off(p: &Prepared, warm: bool, margins: bool) -> Result<Sample, BenchError> {
    let schedule = p
        .schedule
        .as_ref()
        .ok_or_else(|| run_err(p, "no schedule".into()))?;
    let mut s = Sample {
        time_s: 0.0,
        solve_s: 0.0,
        build_s: 0.0,
        unknowns: 0,
        iterations: 0.0,
        inner_iterations: 0.0,
        factorizations: 0.0,
        steps: 0,
        fallbacks: 0,
        peak_memory_bytes: None,
        error: 0.0,
    };
    let built = Instant::now();
    let stepper = Stepper::new(&p.scene, schedule, p.transfer_options(warm));
    s.build_s = built.elapsed().as_secs_f64();
    s.time_s = if margins { 0.0 } else { s.build_s };
    let mut last = None;
    for r in stepper {
        let r = r.map_err(|e| run_err(p, e.to_string()))?;
        let sol = &r.solution;
        s.time_s += match (margins, &r.margin) {
            (false, _) => r.wall_time_s,
            (true, Some(m)) => m.time_s,
            (true, None) => 0.0,
        };
        s.solve_s += sol.solve_time_s;
        s.unknowns = s.unknowns.max(sol.solver.unknowns);
        s.iterations += f64::from(sol.solver.iterations);
        s.inner_iterations += f64::from(sol.solver.inner_iterations);
        s.factorizations += f64::from(sol.solver.factorizations);
        s.fallbacks += usize::from(fell_back(p, sol));
        s.error = s.error.max(sol.residuals.map_or(f64::NAN, |x| x.worst()));
        s.steps += 1;
        last = Some(r.solution);
    }
    if let Some(e) = last.and_then(|sol| stick_radius_error(p, &sol)) {
        if !s.error.is_finite() {
            return Err(run_err(p, format!("residual {} is not finite", s.error)));
        }
        s.error = e;
    }
    let n = s.steps.max(1) as f64;
    for v in [
        &mut s.time_s,
        &mut s.solve_s,
        &mut s.iterations,
        &mut s.inner_iterations,
        &mut s.factorizations,
    ] {
        *v /= n;
    }
    Ok(s)
}

/// The planner on the case's hand-off ([`crate::case::PLAN_QUESTION`], the schedule as its
/// template): its time, its runs as iterations, and how far the checked plan falls short of
/// its margin threshold as the error (0: kept).
fn plan(p: &Prepared) -> Result<Sample, BenchError> {
    use grasp_transfer::{PlanOptions, Template};
    let (releasing, receiving, rate) = crate::case::PLAN_QUESTION;
    let text = crate::case::bundled(p.case.scene).and_then(|b| b.1);
    let text = text.ok_or_else(|| run_err(p, "no schedule".into()))?;
    let spec = grasp_model::strict_json::from_str_strict(text)
        .map_err(|e| run_err(p, format!("{}: {}", e.path, e.message)))?;
    let schedule = p
        .schedule
        .as_ref()
        .ok_or_else(|| run_err(p, "no schedule".into()))?;
    let options = PlanOptions {
        releasing: releasing.iter().map(|s| s.to_string()).collect(),
        receiving: receiving.iter().map(|s| s.to_string()).collect(),
        max_rate_n_per_s: Some(rate),
        solve: p.transfer_options(true).solve,
        ..PlanOptions::default()
    };
    let t0 = Instant::now();
    let template = Template {
        spec: &spec,
        schedule,
    };
    let report = grasp_transfer::plan(&p.scene, Some(template), &options)
        .map_err(|e| run_err(p, e.to_string()))?;
    Ok(Sample {
        time_s: t0.elapsed().as_secs_f64(),
        solve_s: 0.0,
        build_s: 0.0,
        unknowns: 0,
        iterations: report.runs as f64,
        inner_iterations: 0.0,
        factorizations: 0.0,
        steps: report.margins.len(),
        fallbacks: 0,
        peak_memory_bytes: None,
        error: report.binding.map_or(0.0, |b| b.short_by),
    })
}

/// The sensors' read-out of the case's solution: its time, the solution's unknowns and its
/// worst residual as the error (the read-out is exact for the element forces; tests/gel_images.rs).
fn readout(p: &Prepared, t0: Instant) -> Result<Sample, BenchError> {
    let (Some(model), Some(sol)) = (&p.model, &p.solution) else {
        return Err(run_err(p, "no solution to read".into()));
    };
    let read = grasp_model::sensor_readings(&p.scene.scene, model, sol)
        .map_err(|e| run_err(p, e.to_string()))?;
    let time_s = t0.elapsed().as_secs_f64();
    if read.is_empty() {
        return Err(run_err(p, "the scene has no sensor".into()));
    }
    Ok(Sample {
        time_s,
        solve_s: 0.0,
        build_s: 0.0,
        unknowns: sol.solver.unknowns,
        iterations: 0.0,
        inner_iterations: 0.0,
        factorizations: 0.0,
        steps: 1,
        fallbacks: 0,
        peak_memory_bytes: None,
        error: error_of(p, sol),
    })
}

impl Prepared {
    /// Runs the case once and measures it; with `memory`, also its peak memory from the start
    /// of this run (three reads of `/proc`, outside the timed part, but leave it off for
    /// timing samples).
    pub fn run(&self, memory: bool) -> Result<Sample, BenchError> {
        let reset = memory && peak_memory::reset_peak();
        let base = peak_memory::rss_bytes().filter(|_| reset);
        // A model build computes a layer's radial functions unless an earlier run of the
        // process did: every sample pays for them, as a one-shot `grasp solve` does.
        grasp_model::forget_radial_functions();
        let t0 = Instant::now();
        let mut sample = match self.case.kind {
            CaseKind::Solve => {
                let model = self
                    .model
                    .as_ref()
                    .ok_or_else(|| run_err(self, "model not built".into()))?;
                one_solve(self, Arc::clone(model), self.build_s, t0)?
            }
            CaseKind::OneShot => {
                let model = GraspModel::from_loaded_with(&self.scene, self.case.compliance())
                    .map_err(|e| run_err(self, e.to_string()))?;
                let build_s = t0.elapsed().as_secs_f64();
                one_solve(self, Arc::new(model), build_s, t0)?
            }
            CaseKind::HandOff { warm } => hand_off(self, warm, false)?,
            CaseKind::Margins => hand_off(self, true, true)?,
            CaseKind::Plan => plan(self)?,
            CaseKind::Readout => readout(self, t0)?,
        };
        sample.peak_memory_bytes = match base {
            Some(b) => peak_memory::peak_rss_bytes().map(|p| p.saturating_sub(b)),
            None => None,
        };
        Ok(sample)
    }
}
