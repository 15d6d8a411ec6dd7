//! The sequential (SQP-style) strategy: a sequence of convex cone programs iterated to a fixed
//! point (model.md, "coulomb" and "Load-dependent friction"; thesis section 2.6).
//!
//! - **coulomb**: each iterate solves the program with Tresca cones `||G_k|| <= r_k`,
//!   `r_k = mu_i(P_i) F_k` from the iterate's input forces `F_k` (finger loads `P_i`), and the
//!   slip memory `m` in the linear cost. The first input comes from the previous step's forces
//!   (warm start; a force-controlled finger's forces are rescaled to its new load) or, without
//!   them, from an energy-model solve (cold start, whose solution also starts the first Tresca
//!   solve). A warm start that proves infeasible is retried cold once.
//! - **energy** with a load-dependent `mu`: each iterate solves the energy program with `mu_i`
//!   frozen at the input's finger loads.
//!
//! Each convex solve starts from the previous iterate's solution. The fixed-point map `T`
//! (input forces to output normal forces) is iterated as `F <- F + omega (T(F) - F)`, with
//! `omega = 1` until an iterate's program has no solution: the iteration then does not give up
//! but backs off halfway towards the last input whose program was feasible, halving `omega`
//! (down to [`SolveOptions::min_relaxation`]) and letting it grow back after each feasible iterate (a
//! Krasnoselskii-Mann iteration). Converged when `max |T(F) - F| <= sequential_tolerance Fu`
//! on an iterate solved to the solve's tolerance: a cold sequence solves its other iterates
//! only to a share of the change still made ([`IterateAccuracy`], an inexact fixed-point
//! iteration).
//! Outcomes: converged; no equilibrium (for coulomb, with the fingers that lack grip, read from
//! the infeasibility certificate); no convergence within the iteration limit.

use std::time::Instant;

use crate::error::ModelError;
use crate::model::equilibrium::Wrench;
use crate::model::grasp_model::{Control, FingerModel, GraspModel};
use crate::program::cone_program::ConeProgram;
use crate::program::cones::finger_cones::ConeLaw;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::convex_solve::{add_run, start_of};
use crate::solve::iterate_accuracy::IterateAccuracy;
use crate::solve::readout::{build_solution, cannot_hold_reason, escape_reason, failed};
use crate::solve::residuals::{FrictionRule, SolvedWith};
use crate::solve::solution::{
    SequentialReport, Solution, SolveStatus, SolverStats, LOADED_FRACTION,
};
use crate::solver::iterate::Iterate;
use crate::solver::kept_certificate::KeptCertificate;
use crate::solver::options::{SolveOptions, SolverChoice};
use crate::solver::outcome::{Certificate, ConvexOutcome, Start};
use crate::solver::predictor::{affine_coefficients, combine};
use crate::solver::program_solver::ProgramSolver;

/// Element normal forces per finger (N) from a scaled primal.
fn normal_forces(model: &GraspModel, x_scaled: &[f64]) -> Vec<Vec<f64>> {
    let fu = model.scales.element_force_n;
    model
        .fingers
        .iter()
        .map(|f| {
            x_scaled[f.offset..f.offset + f.patch.len()]
                .iter()
                .map(|v| v * fu)
                .collect()
        })
        .collect()
}

fn totals(forces: &[Vec<f64>]) -> Vec<f64> {
    forces.iter().map(|f| f.iter().sum()).collect()
}

fn largest_change(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// `a + w (b - a)`, element by element.
fn relax(a: &[Vec<f64>], b: &[Vec<f64>], w: f64) -> Vec<Vec<f64>> {
    a.iter()
        .zip(b)
        .map(|(ra, rb)| ra.iter().zip(rb).map(|(x, y)| x + w * (y - x)).collect())
        .collect()
}

/// Tresca radii `mu_i max(F_k, 0)` (N) of input forces `forces` (N).
fn radii_of(forces: &[Vec<f64>], mu: &[f64]) -> Vec<Vec<f64>> {
    forces
        .iter()
        .zip(mu)
        .map(|(fi, &m)| fi.iter().map(|v| m * v.max(0.0)).collect())
        .collect()
}

/// The previous steps' forces as a first input: extrapolated along a steady ramp of the
/// commanded loads and approaches ([`extrapolated_forces`]), else the last step's rescaled to
/// the new loads of force-controlled fingers; `None` when the state has none or a
/// force-controlled finger goes from no load to some (its distribution is then unknown).
fn warm_forces(
    model: &GraspModel,
    commanded: &Commanded,
    state: &ContactState,
) -> Option<Vec<Vec<f64>>> {
    if let Some(f) = extrapolated_forces(model, commanded, state) {
        return Some(f);
    }
    let loads_n = commanded.loads_n;
    let loaded = LOADED_FRACTION * model.scales.load_n;
    let mut out = Vec::with_capacity(model.fingers.len());
    let mut j = 0;
    for (f, s) in model.fingers.iter().zip(&state.fingers) {
        let prev = s.normal_forces_n.as_ref()?;
        match f.control {
            Control::Held | Control::Approach { .. } => out.push(prev.clone()),
            Control::NormalLoad { .. } => {
                let p_new = loads_n[j];
                j += 1;
                let p_old: f64 = prev.iter().sum();
                if p_old > loaded {
                    out.push(prev.iter().map(|v| v * p_new / p_old).collect());
                } else if p_new <= loaded {
                    out.push(vec![0.0; prev.len()]);
                } else {
                    return None;
                }
            }
        }
    }
    Some(out)
}

/// What a step commands of its fingers: the loads of the force-controlled ones (N, in model
/// order) and every finger's approach (m; the commanded one of a position-controlled finger).
struct Commanded<'a> {
    loads_n: &'a [f64],
    approaches_m: &'a [f64],
}

/// When the commanded data (the loads of force-controlled fingers and the approaches of
/// position-controlled ones, an approach over the compliance unit `Cu` so both are forces) are
/// an affine combination of the last steps' (`L_now = L_k + sum_j c_j (L_j - L_k)`: a ramp,
/// or two ramps on different curves), the forces combined the same way, clipped at zero.
/// While no element changes between stick, slip and separation and only these data change
/// (the external wrench and the slip memory moving as in the last steps), that is the fixed
/// point itself (the solution is then affine in them) and the sequence ends after one convex
/// solve; otherwise it is a guess the sequence corrects. Data that did not change (to
/// round-off: the last loads are the solved totals) give `None`.
fn extrapolated_forces(
    model: &GraspModel,
    commanded: &Commanded,
    state: &ContactState,
) -> Option<Vec<Vec<f64>>> {
    let depth = state.fingers.iter().map(|s| s.earlier.len()).min()?;
    let stiffness = 1.0 / model.scales.compliance_m_per_n;
    // The commanded data: now, at the last solve, then at the earlier ones, newest first.
    let (mut now, mut last) = (Vec::new(), Vec::new());
    let mut earlier = vec![Vec::new(); depth];
    let mut j = 0;
    for ((f, s), d) in model
        .fingers
        .iter()
        .zip(&state.fingers)
        .zip(commanded.approaches_m)
    {
        match f.control {
            Control::NormalLoad { .. } => {
                now.push(commanded.loads_n[j]);
                j += 1;
                last.push(s.normal_load_n?);
                for (k, e) in earlier.iter_mut().enumerate() {
                    e.push(s.earlier[s.earlier.len() - 1 - k].normal_load_n);
                }
            }
            Control::Approach { .. } => {
                now.push(d * stiffness);
                last.push(s.approach_m? * stiffness);
                for (k, e) in earlier.iter_mut().enumerate() {
                    e.push(s.earlier[s.earlier.len() - 1 - k].approach_m * stiffness);
                }
            }
            Control::Held => {}
        }
    }
    let noise = LOADED_FRACTION * model.scales.load_n;
    if now.iter().zip(&last).all(|(a, b)| (a - b).abs() <= noise) {
        return None;
    }
    let loads_n = now.as_slice();
    // The fewest, newest points first (the likeliest to share the new contact pattern).
    let (c, used) = (1..=depth).find_map(|k| {
        let others: Vec<&[f64]> = earlier[..k].iter().map(Vec::as_slice).collect();
        affine_coefficients(&last, &others, loads_n).map(|c| (c, k))
    })?;
    let mut out = Vec::with_capacity(model.fingers.len());
    for s in &state.fingers {
        let f_last = s.normal_forces_n.as_ref()?;
        let others: Vec<&[f64]> = (0..used)
            .map(|j| {
                s.earlier[s.earlier.len() - 1 - j]
                    .normal_forces_n
                    .as_slice()
            })
            .collect();
        let f = combine(f_last, &others, &c);
        out.push(f.into_iter().map(|v| v.max(0.0)).collect());
    }
    Some(out)
}

/// A finished or failed sequence, or the cold start's forces and solution.
type ColdStart = Result<(Vec<Vec<f64>>, Iterate), (SolveStatus, String)>;

/// What the step's program holds besides its cones that the cold start's energy program takes
/// over: the commanded loads (N), the displacement offsets (m, per unknown) and the external
/// wrench (N, N m about `O`).
struct StepData<'a> {
    loads_n: &'a [f64],
    offsets_m: &'a [f64],
    wrench: &'a Wrench,
}

impl<'a> StepData<'a> {
    /// The data of `main`'s program with the commanded loads `loads_n`.
    fn of(main: &'a ProgramSolver, loads_n: &'a [f64]) -> Self {
        StepData {
            loads_n,
            offsets_m: main.program.offset_m.as_slice(),
            wrench: &main.program.external_wrench,
        }
    }
}

/// The programs a sequence solves: the step's (`main`: Tresca cones for coulomb) and the
/// coulomb model's cold-start energy program, made at its first use.
pub(crate) struct StepPrograms<'a> {
    /// The step's program.
    pub main: &'a mut ProgramSolver,
    /// The energy program of the coulomb model's cold start.
    pub energy: &'a mut Option<ProgramSolver>,
}

/// Cold start of the coulomb model: the energy model's forces (same loads and memory) and its
/// solution, which starts the first Tresca solve.
fn cold_start(
    energy: &mut Option<ProgramSolver>,
    model: &GraspModel,
    data: &StepData,
    memory: &[Vec<[f64; 2]>],
    options: &SolveOptions,
    stats: &mut SolverStats,
) -> Result<ColdStart, ModelError> {
    let StepData {
        loads_n,
        offsets_m,
        wrench,
    } = *data;
    let guess_mu = model.mu_at(&model.guess_loads(loads_n));
    let ps = energy.get_or_insert_with(|| {
        ProgramSolver::new(ConeProgram::assemble(
            model,
            loads_n,
            ConeLaw::Associated,
            &guess_mu,
        ))
    });
    ps.program.set_loads(model, loads_n);
    ps.program.set_external_wrench(model, wrench);
    ps.program.set_mu(&guess_mu);
    ps.program.set_slip_memory(model, memory);
    ps.program.set_offsets(model, offsets_m);
    let run = ps.solve(model, options, start_of(options))?;
    add_run(stats, &run);
    Ok(match run.outcome {
        ConvexOutcome::Solved { x, multipliers, .. } => Ok((
            normal_forces(model, &x),
            Iterate {
                x,
                lambda: multipliers,
            },
        )),
        // Not even the energy model's friction holds the object: Coulomb friction cannot.
        ConvexOutcome::Infeasible(cert) => Err((
            SolveStatus::NoEquilibrium,
            cannot_hold_reason(model, &ps.program, &cert),
        )),
        ConvexOutcome::Failed { reason } => Err((SolveStatus::NoConvergence, reason)),
    })
}

/// The input of an iterate: forces (N; `None` before the first energy iterate of a
/// load-dependent `mu`) and finger loads (N).
#[derive(Debug, Clone)]
struct Input {
    forces: Option<Vec<Vec<f64>>>,
    loads: Vec<f64>,
}

impl Input {
    fn of_forces(forces: Vec<Vec<f64>>) -> Self {
        Input {
            loads: totals(&forces),
            forces: Some(forces),
        }
    }

    /// Halfway (weight `w`) from `self` towards `other`.
    fn towards(&self, other: &Input, w: f64) -> Input {
        Input {
            forces: match (&self.forces, &other.forces) {
                (Some(a), Some(b)) => Some(relax(a, b, w)),
                _ => other.forces.clone(),
            },
            loads: self
                .loads
                .iter()
                .zip(&other.loads)
                .map(|(a, b)| a + w * (b - a))
                .collect(),
        }
    }
}

/// The sequence's bookkeeping.
struct Sequence<'a> {
    model: &'a GraspModel,
    options: &'a SolveOptions,
    coulomb: bool,
    memory: Vec<Vec<[f64; 2]>>,
    stats: SolverStats,
    report: SequentialReport,
    clock: Instant,
    /// The damping of the fixed-point iteration.
    relax: Relaxation,
    /// How accurately the next convex solve is solved.
    accuracy: IterateAccuracy,
    /// The first input and start of an inexact sequence: an inexact sequence that ends
    /// without an answer is run again from them, exactly ([`exactly_again`]).
    first: Option<FirstIterate>,
}

impl Sequence<'_> {
    fn fail(&self, status: SolveStatus, reason: String) -> Solution {
        let mut s = failed(self.model, status, reason, self.clock, self.stats.clone());
        s.sequential = Some(self.report);
        s
    }

    fn infeasible_reason(&self, program: &ConeProgram, cert: &Certificate, mu: &[f64]) -> String {
        if self.coulomb {
            cannot_hold_reason(self.model, program, cert)
        } else {
            format!(
                "{} (mu frozen at iterate {}: {})",
                escape_reason(self.model, program, cert),
                self.report.iterations,
                fmt_mu(self.model, mu)
            )
        }
    }
}

/// Runs the sequential solve of one step (see the module docs) on `programs`, the solve's
/// statistics so far `stats`, its clock started at `clock`.
pub(crate) fn solve_sequential(
    programs: StepPrograms,
    model: &GraspModel,
    loads_n: &[f64],
    state: &mut ContactState,
    options: &SolveOptions,
    stats: SolverStats,
    clock: Instant,
) -> Result<Solution, ModelError> {
    let coulomb = model.kind() == ModelKind::Coulomb;
    let mut seq = Sequence {
        model,
        options,
        coulomb,
        memory: state.slip_memory_m(),
        stats,
        report: SequentialReport {
            iterations: 0,
            last_change_n: f64::INFINITY,
            tolerance_n: options.sequential_tolerance * model.scales.element_force_n,
            converged: false,
            warm_started: false,
            cold_restarts: 0,
            damped_iterations: 0,
        },
        clock,
        relax: Relaxation {
            omega: 1.0,
            last_feasible: None,
        },
        accuracy: IterateAccuracy::new(options.tolerance, options.sequential_tolerance, false),
        first: None,
    };
    let StepPrograms { main, energy } = programs;
    if coulomb {
        main.program.set_slip_memory(model, &seq.memory);
    }
    let commanded = Commanded {
        loads_n,
        approaches_m: &main.program.approach_m,
    };
    let warm = options
        .warm_start
        .then(|| warm_forces(model, &commanded, state))
        .flatten();
    seq.report.warm_started = warm.is_some();
    let inexact = warm.is_none() && may_be_inexact(model, options);
    let mut start_at: Option<Iterate> = None;
    let mut input = match warm {
        Some(f) => Input::of_forces(f),
        None if coulomb => {
            let data = StepData::of(main, loads_n);
            match cold_start(energy, model, &data, &seq.memory, options, &mut seq.stats)? {
                Ok((f, it)) => {
                    start_at = Some(it);
                    Input::of_forces(f)
                }
                Err((status, reason)) => return Ok(seq.fail(status, reason)),
            }
        }
        None => Input {
            forces: None,
            loads: model.guess_loads(loads_n),
        },
    };
    begin(&mut seq, main, &input, start_at.as_ref(), inexact);
    let programs = StepPrograms { main, energy };
    iterate(programs, loads_n, state, &mut seq, &mut input, start_at)
}

/// True when a cold coulomb sequence of `model` under `options` may solve its iterates
/// inexactly ([`IterateAccuracy`]): the native solver answers them and every finger's
/// compliance is an FFT operator too large to write out (an iterate costs a tenth of a second
/// or more, not the microseconds of a small patch, and no stall can fall back to Clarabel at a
/// loose tolerance). Every other sequence stays as it was.
fn may_be_inexact(model: &GraspModel, options: &SolveOptions) -> bool {
    let matrix_free = model.fingers.iter().all(FingerModel::is_matrix_free);
    model.kind() == ModelKind::Coulomb && matrix_free && options.solver != SolverChoice::Clarabel
}

/// Begins a sequence's iteration from `input` and the first solve's start `start`, every
/// iterate exact or, when `inexact`, its accuracy following the changes; an inexact one
/// keeps its beginning for [`exactly_again`].
fn begin(
    seq: &mut Sequence<'_>,
    main: &ProgramSolver,
    input: &Input,
    start: Option<&Iterate>,
    inexact: bool,
) {
    let o = seq.options;
    seq.accuracy = IterateAccuracy::new(o.tolerance, o.sequential_tolerance, inexact);
    seq.first = seq.accuracy.inexact().then(|| FirstIterate {
        input: input.clone(),
        start: start.cloned(),
        kept: main.kept_certificate(),
        fallback: seq.stats.fallback.clone(),
    });
}

/// The damping of the fixed-point iteration: the relaxation `omega` and the last input
/// whose program was feasible (where an infeasible iterate backs off to).
struct Relaxation {
    omega: f64,
    last_feasible: Option<Input>,
}

/// The cones an iterate's program was solved with, and how well.
struct IterateCones<'a> {
    /// Friction coefficient per finger.
    mu: &'a [f64],
    /// Tresca radii per finger and element (N), coulomb model only.
    radii_n: Option<&'a [Vec<f64>]>,
    /// The solver's answer is "almost solved".
    reduced_accuracy: bool,
}

/// What an iterate's outcome asks of the loop.
enum Next {
    /// Iterate again from the new input.
    Again,
    /// Iterate again, the next convex solve starting at this point (a cold restart).
    From(Iterate),
    /// The sequence ended with this solution (boxed: it is large and rare).
    Done(Box<Solution>),
}

/// The fixed-point loop from `input` (see the module docs).
fn iterate(
    programs: StepPrograms,
    loads_n: &[f64],
    state: &mut ContactState,
    seq: &mut Sequence<'_>,
    input: &mut Input,
    mut start_at: Option<Iterate>,
) -> Result<Solution, ModelError> {
    let model = seq.model;
    let StepPrograms { main, energy } = programs;
    loop {
        seq.report.iterations += 1;
        let mu = model.mu_at(&input.loads);
        let radii = seq
            .coulomb
            .then(|| radii_of(input.forces.as_deref().unwrap_or(&[]), &mu));
        match &radii {
            Some(r) => main.program.set_radii(model, r),
            None => main.program.set_mu(&mu),
        }
        let start = match &start_at {
            Some(it) => Start::At(it),
            None => start_of(seq.options),
        };
        let last_allowed = seq.report.iterations >= seq.options.max_sequential_iterations;
        let options = SolveOptions {
            tolerance: seq.accuracy.tolerance(last_allowed),
            ..*seq.options
        };
        let run = main.solve(model, &options, start)?;
        start_at = None;
        add_run(&mut seq.stats, &run);
        let next = match run.outcome {
            ConvexOutcome::Solved {
                reduced_accuracy,
                x,
                multipliers,
            } => {
                let cones = IterateCones {
                    mu: &mu,
                    radii_n: radii.as_deref(),
                    reduced_accuracy,
                };
                let point = SolvedPoint {
                    x: &x,
                    multipliers: &multipliers,
                };
                after_solved(main, seq, state, input, point, cones)
            }
            ConvexOutcome::Infeasible(cert) => {
                let programs = StepPrograms {
                    main: &mut *main,
                    energy: &mut *energy,
                };
                after_infeasible(programs, loads_n, seq, input, &cert, &mu)?
            }
            ConvexOutcome::Failed { reason } => {
                Next::Done(Box::new(seq.fail(SolveStatus::NoConvergence, reason)))
            }
        };
        match next {
            Next::Again => {}
            Next::From(it) => start_at = Some(it),
            Next::Done(sol) if !sol.status.has_forces() && seq.accuracy.was_inexact() => {
                match seq.first.take() {
                    Some(first) => start_at = exactly_again(seq, main, input, first),
                    None => return Ok(*sol),
                }
            }
            Next::Done(sol) => return Ok(*sol),
        }
    }
}

/// Where an inexact sequence began (kept by [`begin`]): two vectors of the unknowns at most.
struct FirstIterate {
    /// The first input.
    input: Input,
    /// The first solve's start (the energy model's solution of a cold start).
    start: Option<Iterate>,
    /// The step program's kept certificate then.
    kept: Option<KeptCertificate>,
    /// The solve's fallback note then.
    fallback: Option<String>,
}

/// An inexact sequence that ended without an answer (no equilibrium, no convergence) runs
/// again from its beginning `first` with every iterate exact, so that inexact iterates do not
/// change such an outcome (an oscillating iteration's path depends on every iterate): the same
/// first input and start, the step program's warm starts forgotten
/// ([`ProgramSolver::forget_solutions`]; at a single solve or a hand-off's first step they
/// had nothing to read either, so the run is the exact iteration's). Returns the first solve's
/// start. The report is the exact run's; the solver work of both runs is counted.
fn exactly_again(
    seq: &mut Sequence<'_>,
    main: &mut ProgramSolver,
    input: &mut Input,
    first: FirstIterate,
) -> Option<Iterate> {
    main.forget_solutions(first.kept);
    seq.stats.fallback = first.fallback;
    *input = first.input;
    seq.report.iterations = 0;
    seq.report.damped_iterations = 0;
    seq.report.last_change_n = f64::INFINITY;
    seq.relax = Relaxation {
        omega: 1.0,
        last_feasible: None,
    };
    let o = seq.options;
    seq.accuracy = IterateAccuracy::new(o.tolerance, o.sequential_tolerance, false);
    first.start
}

/// A solved iterate's point: its scaled primal and equality multipliers.
struct SolvedPoint<'a> {
    x: &'a [f64],
    multipliers: &'a [f64],
}

/// After a feasible iterate: converged when no normal force changed by more than the
/// tolerance; else the next input is the output, damped while `omega < 1` (which then grows
/// back).
fn after_solved(
    main: &ProgramSolver,
    seq: &mut Sequence<'_>,
    state: &mut ContactState,
    input: &mut Input,
    point: SolvedPoint,
    cones: IterateCones<'_>,
) -> Next {
    let SolvedPoint { x, multipliers } = point;
    let out = normal_forces(seq.model, x);
    let change = input
        .forces
        .as_ref()
        .map_or(f64::INFINITY, |f| largest_change(f, &out));
    seq.report.last_change_n = change;
    if change <= seq.report.tolerance_n && seq.accuracy.exact() {
        return Next::Done(Box::new(converged(main, seq, state, x, multipliers, cones)));
    }
    let change_fu = change / seq.model.scales.element_force_n;
    if change <= seq.report.tolerance_n {
        // An inexact iterate met the tolerance: the next, from its output, is solved exactly.
        seq.accuracy.finish(change_fu);
    } else {
        seq.accuracy.record(change_fu);
    }
    if seq.report.iterations >= seq.options.max_sequential_iterations {
        return Next::Done(Box::new(
            seq.fail(SolveStatus::NoConvergence, no_convergence(seq)),
        ));
    }
    seq.relax.last_feasible = Some(input.clone());
    let target = Input::of_forces(out);
    *input = if seq.relax.omega < 1.0 {
        seq.report.damped_iterations += 1;
        input.towards(&target, seq.relax.omega)
    } else {
        target
    };
    seq.relax.omega = (2.0 * seq.relax.omega).min(1.0);
    Next::Again
}

/// After an infeasible iterate: a warm coulomb start that fails at once is retried cold from
/// the energy model (once); otherwise the input backs off halfway towards the last feasible
/// one, halving `omega` down to its minimum, after which the certificate is the outcome.
fn after_infeasible(
    programs: StepPrograms,
    loads_n: &[f64],
    seq: &mut Sequence<'_>,
    input: &mut Input,
    cert: &Certificate,
    mu: &[f64],
) -> Result<Next, ModelError> {
    let StepPrograms { main, energy } = programs;
    let restart = seq.coulomb
        && seq.report.warm_started
        && seq.report.iterations == 1
        && seq.report.cold_restarts == 0;
    if restart {
        // The previous step's forces were a poor guess: restart from the energy model.
        seq.report.cold_restarts += 1;
        let (model, options) = (seq.model, seq.options);
        let data = StepData::of(main, loads_n);
        let cold = cold_start(energy, model, &data, &seq.memory, options, &mut seq.stats)?;
        return Ok(match cold {
            Ok((f, it)) => {
                *input = Input::of_forces(f);
                seq.report.iterations = 0;
                begin(seq, main, input, Some(&it), may_be_inexact(model, options));
                Next::From(it)
            }
            Err((status, reason)) => Next::Done(Box::new(seq.fail(status, reason))),
        });
    }
    match &seq.relax.last_feasible {
        Some(prev) if seq.relax.omega > seq.options.min_relaxation => {
            // Back off halfway towards the last input whose program was feasible.
            seq.relax.omega *= 0.5;
            seq.report.damped_iterations += 1;
            *input = prev.towards(input, 0.5);
        }
        _ => {
            let reason = seq.infeasible_reason(&main.program, cert, mu);
            return Ok(Next::Done(Box::new(
                seq.fail(SolveStatus::NoEquilibrium, reason),
            )));
        }
    }
    if seq.report.iterations >= seq.options.max_sequential_iterations {
        return Ok(Next::Done(Box::new(
            seq.fail(SolveStatus::NoConvergence, no_convergence(seq)),
        )));
    }
    Ok(Next::Again)
}

/// The converged solution of the last iterate; records the contact state.
fn converged(
    main: &ProgramSolver,
    seq: &mut Sequence<'_>,
    state: &mut ContactState,
    x: &[f64],
    multipliers: &[f64],
    cones: IterateCones<'_>,
) -> Solution {
    seq.report.converged = true;
    let rule = if seq.coulomb {
        FrictionRule::Coulomb {
            memory_m: &seq.memory,
        }
    } else {
        FrictionRule::Associated
    };
    let solved_with = SolvedWith {
        rule,
        mu: cones.mu,
        radii_n: cones.radii_n,
    };
    let mut out = build_solution(
        seq.model,
        &main.program,
        x,
        multipliers,
        seq.stats.clone(),
        &solved_with,
    );
    if cones.reduced_accuracy {
        out.mark_reduced_accuracy();
    }
    out.sequential = Some(seq.report);
    state.record(seq.model, &out, seq.coulomb);
    out
}

fn no_convergence(seq: &Sequence<'_>) -> String {
    format!(
        "no convergence: the sequential solve did not reach a fixed point in {} iterations; the \
         element normal forces still changed by {:.3e} N (tolerance {:.3e} N); raise the \
         iteration limit, refine the load steps, or check that mu(P) is not too steep",
        seq.report.iterations, seq.report.last_change_n, seq.report.tolerance_n
    )
}

fn fmt_mu(model: &GraspModel, mu: &[f64]) -> String {
    model
        .fingers
        .iter()
        .zip(mu)
        .map(|(f, m)| format!("{} mu = {m:.4}", f.name))
        .collect::<Vec<_>>()
        .join(", ")
}
