//! The backend layer: one assembled [`ConeProgram`] and the workspaces of the solvers that can
//! answer it (the native semismooth Newton solver, Clarabel as the reference), created on first
//! use. Each workspace notices by itself what changed in the program since its last solve.
//!
//! [`ProgramSolver::solve`] runs one convex solve with the chosen backend:
//! - `clarabel`: Clarabel's interior-point method;
//! - `native`: the native solver from the given start; if it does not converge, Clarabel is
//!   asked only to certify: an infeasible program is reported as such (certified by
//!   Clarabel), anything else as no convergence;
//! - `auto`: the native solver, falling back to Clarabel's answer when it does not converge
//!   (the run says why).
//!
//! With `native` and `auto`, the last certificate Clarabel gave that a program has no
//! solution is kept, and a later program it proves infeasible ([`KeptCertificate`]) is
//! answered so without a solve: the trials beyond a margin, one after another.

use std::sync::Arc;
use std::time::Instant;

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::option_names;
use crate::program::cone_program::ConeProgram;
use crate::solver::grid_continuation::{CoarseLevel, CONTINUED_FORCING};
use crate::solver::iterate::Iterate;
use crate::solver::kept_certificate::KeptCertificate;
use crate::solver::native::native_result::{Counts, NativeResult, NativeStatus};
use crate::solver::native::newton::semismooth_newton::{Limits, FORCING_MAX};
use crate::solver::native::NativeSolver;
use crate::solver::options::{SolveOptions, SolverChoice};
use crate::solver::solve_progress::SolveProgress;

use crate::solver::clarabel::{self, ClarabelWorkspace};
use crate::solver::outcome::{
    Certificate, ConvexOutcome, ConvexRun, SolverKind, Start, MAX_NEWTON_ITERATIONS,
};
use crate::solver::predictor::{data_of, Trail};

/// A program and its solver workspaces.
pub(crate) struct ProgramSolver {
    /// The program; change it through its `set_*` methods between solves.
    pub program: ConeProgram,
    native: Option<NativeSolver>,
    /// The coarse levels of a cold native solve ([`CoarseLevel`]), made on the first one
    /// (`Some(None)`: the model does not coarsen).
    coarse: Option<Option<CoarseLevel>>,
    clarabel: Option<ClarabelWorkspace>,
    /// The last solution, whichever backend gave it (the default warm start).
    last: Option<Iterate>,
    /// The last few solutions with their data, for the prediction.
    trail: Trail,
    /// Told the native solver's counts as it goes, when given.
    pub progress: Option<Arc<SolveProgress>>,
    /// The last certificate that a program had no solution ([`KeptCertificate`]).
    kept: Option<KeptCertificate>,
}

impl ProgramSolver {
    pub(crate) fn new(program: ConeProgram) -> Self {
        ProgramSolver {
            program,
            native: None,
            coarse: None,
            clarabel: None,
            last: None,
            trail: Trail::default(),
            progress: None,
            kept: None,
        }
    }

    /// The last solution, whichever backend gave it.
    pub(crate) fn last(&self) -> Option<&Iterate> {
        self.last.as_ref()
    }

    /// A copy of the certificate kept from Clarabel's last proof that a program had no
    /// solution ([`KeptCertificate`]).
    pub(crate) fn kept_certificate(&self) -> Option<KeptCertificate> {
        self.kept.clone()
    }

    /// Forgets the solutions the warm starts read (the last one and the prediction's trail)
    /// and keeps `kept` as the kept certificate: the next solves run as a fresh solver's with
    /// that certificate (a sequence run again from its beginning).
    pub(crate) fn forget_solutions(&mut self, kept: Option<KeptCertificate>) {
        self.last = None;
        self.trail = Trail::default();
        self.kept = kept;
    }

    /// The native solver's workspace (created if no native solve ran yet), with the program.
    pub(crate) fn native_workspace(&mut self, model: &GraspModel) -> (&NativeSolver, &ConeProgram) {
        let program = &self.program;
        let native = self
            .native
            .get_or_insert_with(|| NativeSolver::new(model, program));
        (native, program)
    }

    /// Solves the program as it stands with the backend of `options.solver`; options outside
    /// their ranges are an error ([`SolveOptions::validate`]); data that are not finite (a
    /// load or wrench that overflowed) are no convergence, reported without a solve.
    pub(crate) fn solve(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
        start: Start<'_>,
    ) -> Result<ConvexRun, ModelError> {
        options.validate()?;
        // The program's data: the prediction's input, and recorded with the solution.
        let data = data_of(&self.program);
        if let Some(run) = unsolvable(&data, options) {
            return Ok(run);
        }
        let run = match options.solver {
            SolverChoice::Clarabel => self.solve_clarabel(model, options),
            SolverChoice::Native | SolverChoice::Auto => {
                self.solve_native(model, options, start, &data)
            }
        }?;
        if let ConvexOutcome::Solved { x, multipliers, .. } = &run.outcome {
            let solution = Iterate {
                x: x.clone(),
                lambda: multipliers.clone(),
            };
            self.trail.push(data, solution.clone());
            self.last = Some(solution);
        }
        Ok(run)
    }

    fn solve_clarabel(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
    ) -> Result<ConvexRun, ModelError> {
        let settings = clarabel::settings(
            options.tolerance,
            options.max_iterations,
            options.time_limit_s,
        )?;
        let program = &self.program;
        let ws = self
            .clarabel
            .get_or_insert_with(|| ClarabelWorkspace::new(model, program));
        let run = ws.solve(program, options.tolerance, &settings)?;
        Ok(ConvexRun {
            outcome: run.outcome,
            iterations: run.iterations,
            factorisations: 0,
            inner_iterations: 0,
            solver_time_s: run.solve_time_s,
            answered_by: SolverKind::Clarabel,
            fallback: None,
        })
    }

    fn solve_native(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
        start: Start<'_>,
        data: &[f64],
    ) -> Result<ConvexRun, ModelError> {
        let clock = Instant::now();
        let floor = clarabel::radius_floor(options.tolerance);
        if let Some(proof) = self
            .kept
            .as_ref()
            .and_then(|k| k.proves(&self.program, floor))
        {
            return Ok(kept_run(proof, clock.elapsed().as_secs_f64()));
        }
        let program = &self.program;
        let native = self
            .native
            .get_or_insert_with(|| NativeSolver::new(model, program));
        let limits = Limits {
            tolerance: options.tolerance,
            max_iterations: options.max_iterations.min(MAX_NEWTON_ITERATIONS),
            forcing: FORCING_MAX,
            progress: self.progress.as_deref(),
        };
        let predicted = match start {
            Start::Last => self.trail.predict(data),
            _ => None,
        };
        let starts: Vec<&Iterate> = match start {
            Start::Cold => Vec::new(),
            Start::Last => predicted.iter().chain(self.last.as_ref()).collect(),
            Start::At(it) => vec![it],
        };
        let mut result = match starts.is_empty() {
            true => solve_cold(native, &mut self.coarse, model, program, limits),
            false => native.solve(program, &starts, limits),
        };
        let native_time = clock.elapsed().as_secs_f64();
        let matrix_free = native.is_matrix_free();
        let why = match result.status.clone() {
            NativeStatus::Converged => {
                // The iterate moves into the outcome (no copy on the hot path of a hand-off).
                let solved = ConvexOutcome::Solved {
                    reduced_accuracy: false,
                    x: std::mem::take(&mut result.iterate.x),
                    multipliers: std::mem::take(&mut result.iterate.lambda),
                };
                return Ok(native_run(solved, &result, native_time));
            }
            NativeStatus::Stalled(why) => format!(
                "the native solver did not converge in {} Newton steps ({why})",
                result.iterations
            ),
        };
        if matrix_free {
            // Clarabel needs the matrices: the stall is the outcome.
            return Ok(native_run(fft_stall(&why), &result, native_time));
        }
        let mut run = self.solve_clarabel(model, options)?;
        if let ConvexOutcome::Infeasible(certificate) = &run.outcome {
            self.kept = KeptCertificate::new(&self.program, certificate);
        }
        run.iterations += result.iterations;
        run.factorisations += result.factorisations;
        run.inner_iterations += result.inner_iterations;
        run.solver_time_s += native_time;
        after_native_stall(&mut run, options.solver, &why);
        Ok(run)
    }
}

/// The outcome of a native stall (`why`) that Clarabel cannot take over: a model with the
/// FFT compliance has no matrices.
fn fft_stall(why: &str) -> ConvexOutcome {
    let reason = format!(
        "no convergence: {why}; Clarabel cannot take over a model with the FFT compliance \
         (setting `{}` to dense lets it, for patches of up to about 20,000 unknowns)",
        option_names::COMPLIANCE
    );
    ConvexOutcome::Failed { reason }
}

/// A native solve of `program` without a start: from the coarser grids' answer where the model
/// has them ([`CoarseLevel`], made on the first call and kept in `coarse`; the settling Newton
/// systems then solved to [`CONTINUED_FORCING`]), else cold; and cold
/// again when the solve from the coarse grids' answer does not converge, so that they never
/// lose a solve a cold start finds. All the work is counted.
fn solve_cold(
    native: &mut NativeSolver,
    coarse: &mut Option<Option<CoarseLevel>>,
    model: &GraspModel,
    program: &ConeProgram,
    limits: Limits,
) -> NativeResult {
    let mut counts = Counts::default();
    let guess = coarse
        .get_or_insert_with(|| CoarseLevel::new(model, program))
        .as_mut()
        .and_then(|level| level.start(program, limits, &mut counts));
    let Some(guess) = guess else {
        let mut result = native.solve(program, &[], limits);
        result.add(counts);
        return result;
    };
    let continued = Limits {
        forcing: CONTINUED_FORCING,
        ..limits
    };
    let mut result = native.solve(program, &[&guess], continued);
    if result.status != NativeStatus::Converged {
        counts.add(result.counts());
        result = native.solve(program, &[], limits);
    }
    result.add(counts);
    result
}

/// A program proved infeasible by the certificate kept from an earlier one (Clarabel's), in
/// `time_s`: no solver ran.
fn kept_run(certificate: Certificate, time_s: f64) -> ConvexRun {
    ConvexRun {
        outcome: ConvexOutcome::Infeasible(certificate),
        iterations: 0,
        factorisations: 0,
        inner_iterations: 0,
        solver_time_s: time_s,
        answered_by: SolverKind::Clarabel,
        fallback: Some(
            "the certificate Clarabel gave for an earlier program of this grasp proves that \
             this one has no solution (checked from the equilibrium rows; no solver ran)"
                .into(),
        ),
    }
}

/// A run the native solver answered (or whose stall is the outcome), with its work.
fn native_run(outcome: ConvexOutcome, result: &NativeResult, time_s: f64) -> ConvexRun {
    ConvexRun {
        outcome,
        iterations: result.iterations,
        factorisations: result.factorisations,
        inner_iterations: result.inner_iterations,
        solver_time_s: time_s,
        answered_by: SolverKind::Native,
        fallback: None,
    }
}

/// Clarabel's run after the native solver stalled (`why`): the fallback's reason, and with
/// `SolverChoice::Native` an answer of Clarabel's is no answer (the native solver was asked).
fn after_native_stall(run: &mut ConvexRun, choice: SolverChoice, why: &str) {
    run.fallback = Some(match (&run.outcome, choice) {
        (ConvexOutcome::Infeasible(_), _) => {
            format!("{why}; Clarabel certified that the program has no solution")
        }
        (_, SolverChoice::Auto) => format!("{why}; Clarabel answered"),
        _ => why.to_string(),
    });
    if choice == SolverChoice::Native {
        if let ConvexOutcome::Solved { .. } = run.outcome {
            run.outcome = ConvexOutcome::Failed {
                reason: format!(
                    "no convergence: {why}; Clarabel solves this program, so set `{}` to \
                     auto (or clarabel)",
                    option_names::SOLVER
                ),
            };
        }
    }
}

/// The outcome of a program whose data are not all finite (`None` when they are): no solver
/// is run on them (the native iteration would carry NaN to its iteration limit, Clarabel
/// might not return).
fn unsolvable(data: &[f64], options: &SolveOptions) -> Option<ConvexRun> {
    let bad = data.iter().filter(|v| !v.is_finite()).count();
    (bad > 0).then(|| ConvexRun {
        outcome: ConvexOutcome::Failed {
            reason: format!(
                "no convergence: {bad} of the program's {} data (gaps, loads, the wrench to \
                 balance, friction coefficients) are not finite, so nothing was solved; an \
                 extra wrench or load too large for double precision does this",
                data.len()
            ),
        },
        iterations: 0,
        factorisations: 0,
        inner_iterations: 0,
        solver_time_s: 0.0,
        answered_by: match options.solver {
            SolverChoice::Clarabel => SolverKind::Clarabel,
            SolverChoice::Native | SolverChoice::Auto => SolverKind::Native,
        },
        fallback: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_that_are_not_finite_are_no_convergence_without_a_solve() {
        assert!(unsolvable(&[1.0, -2.0, 1e300], &SolveOptions::default()).is_none());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let run = unsolvable(&[1.0, bad, bad], &SolveOptions::default()).unwrap();
            match run.outcome {
                ConvexOutcome::Failed { reason } => {
                    assert!(
                        reason.starts_with("no convergence: 2 of the program's 3"),
                        "{reason}"
                    )
                }
                other => panic!("{other:?}"),
            }
            assert_eq!((run.iterations, run.factorisations), (0, 0));
        }
    }

    use nalgebra::Vector3;

    use crate::program::cones::finger_cones::ConeLaw;
    use crate::Scene;

    /// Weight of the pad's object, N.
    const WEIGHT_N: f64 = 1.0;

    /// A held pad of two elements (10 mm apart) under an object of weight [`WEIGHT_N`] whose
    /// centre of mass lies on the contact plane above the pad's centre, coulomb model.
    fn pad() -> GraspModel {
        let text = format!(
            r#"{{
            "planar": null,
            "object": {{"weight": {WEIGHT_N}, "center_of_mass": [0, 0, 0],
                        "gravity": [0, 0, -1],
                        "material": {{"youngs_modulus": 2e11, "poisson_ratio": 0.3}}}},
            "fingers": [{{"name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
                         "tangent": [1, 0, 0],
                         "material": {{"youngs_modulus": 1e6, "poisson_ratio": 0.45}},
                         "tip_radius": null, "object_radius": null,
                         "patch": {{"size": [0.02, 0.01], "grid": [2, 1]}},
                         "friction": {{"mu": 0.5}}, "control": "held"}}],
            "model": "coulomb"
        }}"#
        );
        let scene = Scene::from_json_str(&text).expect("a valid scene");
        GraspModel::from_scene(&scene).expect("a usable model")
    }

    /// The pad's program `base` (its law, its equality matrix shared) with the weight plus a horizontal pull `pull_n` (N, along
    /// x) at the centre of mass, and friction that resists a pull of at most `edge_n` (N):
    /// Tresca radii `edge / 2` per element, or `mu = edge / W` on the associated cones (the
    /// held pad carries the weight, so `sum F = W`).
    fn pad_program(
        model: &GraspModel,
        base: &ConeProgram,
        edge_n: f64,
        pull_n: f64,
    ) -> ConeProgram {
        let mut program = base.clone();
        match base.law {
            ConeLaw::Tresca => program.set_radii(model, &[vec![0.5 * edge_n; 2]]),
            ConeLaw::Associated => program.set_mu(&[edge_n / WEIGHT_N]),
        }
        let force = Vector3::new(pull_n, 0.0, -WEIGHT_N);
        let wrench = model.wrench_at_center_of_mass(&force, &Vector3::zeros());
        program.set_external_wrench(model, &wrench);
        program
    }

    /// Clarabel's forces for the pad under a pull of 0.05 N (friction for 0.2 N) at the
    /// tolerances `tolerances`, solved one after another by one workspace: the last solve's.
    fn clarabel_forces(tolerances: &[f64]) -> Vec<f64> {
        let model = pad();
        let base = ConeProgram::assemble(&model, &[], ConeLaw::Tresca, &[0.5]);
        let mut solver = ProgramSolver::new(pad_program(&model, &base, 0.2, 0.05));
        let mut x = Vec::new();
        for &tolerance in tolerances {
            let options = SolveOptions {
                solver: SolverChoice::Clarabel,
                tolerance,
                ..SolveOptions::default()
            };
            match solver.solve(&model, &options, Start::Cold).unwrap().outcome {
                ConvexOutcome::Solved { x: solved, .. } => x = solved,
                other => panic!("{other:?}"),
            }
        }
        x
    }

    /// A workspace's solve answers to its own tolerance, not to the first solve's (a
    /// sequence's inexact iterates change it from solve to solve): after a solve at 1e-2, a
    /// solve at 1e-10 gives the bits a fresh workspace gives at 1e-10 (Clarabel is
    /// deterministic), and they are not the 1e-2 answer's.
    #[test]
    fn a_clarabel_solve_takes_its_own_tolerance() {
        let fresh = clarabel_forces(&[1e-10]);
        let after_loose = clarabel_forces(&[1e-2, 1e-10]);
        let loose = clarabel_forces(&[1e-2]);
        assert_eq!(after_loose, fresh);
        assert_ne!(loose, fresh, "the tolerances must give different answers");
    }

    /// Whether Clarabel, alone and from scratch, finds `program` infeasible.
    fn clarabel_says_infeasible(model: &GraspModel, program: &ConeProgram) -> bool {
        let options = SolveOptions {
            solver: SolverChoice::Clarabel,
            ..SolveOptions::default()
        };
        let mut alone = ProgramSolver::new(program.clone());
        let run = alone.solve(model, &options, Start::Cold).unwrap();
        matches!(run.outcome, ConvexOutcome::Infeasible(_))
    }

    /// The pad resists a pull up to the friction its elements allow (closed form: equilibrium
    /// along x with `|G_k| <= r` or `|G_k| <= mu F_k`). After Clarabel certified one pull
    /// beyond it, the native solver answers every later program the certificate proves
    /// without a solve, and only programs Clarabel alone also finds infeasible: pulls and
    /// friction on both sides of the edge, under both laws; every pull 5 % or more past the
    /// edge is proved; none below it.
    #[test]
    fn a_kept_certificate_answers_only_programs_clarabel_finds_infeasible() {
        let model = pad();
        let options = SolveOptions::default();
        for law in [ConeLaw::Tresca, ConeLaw::Associated] {
            let base = ConeProgram::assemble(&model, &[], law, &[0.5]);
            let mut solver = ProgramSolver::new(pad_program(&model, &base, 0.2, 0.3));
            let first = solver.solve(&model, &options, Start::Last).unwrap();
            assert!(
                matches!(first.outcome, ConvexOutcome::Infeasible(_)),
                "{first:?}"
            );
            assert!(
                first.iterations > 0,
                "the first proof is Clarabel's: {first:?}"
            );
            let mut proved_past_edge = 0;
            for edge_n in [0.1, 0.2, 0.4] {
                for ratio in [0.5, 0.9, 0.99, 1.01, 1.05, 1.2, 2.0, 5.0] {
                    let pull_n = ratio * edge_n;
                    let program = pad_program(&model, &base, edge_n, pull_n);
                    let what = format!("{law:?}, edge {edge_n} N, pull {pull_n} N");
                    let reference = clarabel_says_infeasible(&model, &program);
                    assert_eq!(reference, ratio > 1.0, "Clarabel: {what}");
                    solver.program = program;
                    let run = solver.solve(&model, &options, Start::Last).unwrap();
                    let kept = run.iterations == 0
                        && run.fallback.as_deref().is_some_and(|f| {
                            f.contains("certificate Clarabel gave for an earlier program")
                        });
                    if kept {
                        assert!(reference, "proved infeasible: {what}");
                        assert!(matches!(run.outcome, ConvexOutcome::Infeasible(_)));
                    }
                    if ratio >= 1.05 {
                        assert!(kept, "not proved: {what}: {run:?}");
                        proved_past_edge += 1;
                    }
                }
            }
            assert_eq!(proved_past_edge, 12, "{law:?}");
        }
    }
}
