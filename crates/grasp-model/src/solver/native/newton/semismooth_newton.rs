//! The semismooth Newton iteration on the natural residual of the program's KKT conditions
//! ([`super::linearisation`]), globalised by a non-monotone backtracking line search on the
//! merit `psi = ||Phi||^2 + ||E x - e||^2` (Grippo, Lampariello and Lucidi).
//!
//! A cold start first takes the all-stick step (every element in contact and sticking: an
//! equality-constrained least-energy solve); a warm start begins at a given iterate. Each
//! iteration then linearises at the iterate, repairs force-controlled fingers that have lost
//! every contact (their load row cannot be met by any free direction: the approach is moved
//! until the nearest element touches), takes the Newton step and searches along it.
//! Converged when `max |Phi| <= tol max(1, max |x|)` and `max |E x - e| <= tol max(1, max |e|)`.

use crate::program::cone_program::ConeProgram;
use crate::solver::iterate::Iterate;
use crate::solver::native::finger_block::FingerBlockData;
use crate::solver::native::interior::interior_point;
use crate::solver::native::native_result::{Counts, NativeResult, NativeStatus};
use crate::solver::solve_progress::SolveProgress;

use crate::solver::native::parallel_vectors::{copy_of, each_chunk, max_abs};

use super::linearisation::{
    cold_pattern, linearise_reusing, residual_norms, residual_norms_along, FingerLinearisation,
    LocalPoint,
};
use super::newton_step::{chord_linearisations, newton_step, FactorCache, Step, StepSpace};
use super::projected_step::{projected_step, CgStop};
use super::reduced_iterative::CG_TOLERANCE;

/// Armijo constant of the line search.
const ARMIJO: f64 = 1e-4;
/// Merit values remembered by the non-monotone line search.
const WINDOW: usize = 5;
/// Smallest step length tried.
const MIN_STEP: f64 = 1e-10;
/// Natural residual (relative to `max(1, max |x|)`) below which chord steps are taken.
const CHORD_RESIDUAL: f64 = 1e-3;
/// The Newton iteration aims at this fraction of the tolerance.
const TARGET: f64 = 1e-2;
/// The share of the aimed-at natural residual a projected CG run's error may take: its
/// solves stop there rather than at a relative 1e-12 when the step's right-hand side is
/// already small (a warm hand-off step), so they do not solve past what the iteration checks.
/// Measured on the plate hand-off with 64 x 64 patches: 1e-2 saves a third of the CG
/// iterations but leaves the compatibility residual at 2.7e-9 (6e-11 without a floor); 1e-3,
/// 9.5e-10 and more Newton steps; 1e-4 keeps it at 7.9e-11 and saves a tenth of the time.
const CG_SHARE: f64 = 1e-4;
/// The largest relative accuracy a projected CG run of a Newton step stops at (inexact
/// Newton, Dembo, Eisenstat and Steihaug, SIAM J. Numer. Anal. 19, 1982): a step solves its
/// system to `eta = min(forcing, rho)` of its right-hand side (`forcing` this value unless the
/// solve's [`Limits`] say otherwise: a grid continuation's levels and the fine grid started
/// from them), `rho` the natural residual relative to the forces, so the steps far from the solution (whose contact sets still
/// change) take a few iterations and the last ones, where `rho` is small, converge as the
/// exact steps do (superlinearly: `eta` falls with the residual). The cold start's all-stick
/// step, a first guess only, stops at `forcing` too.
///
/// Measured on the frictionless Hertz patch of 1024 x 1024 elements: exact steps (1e-12) take
/// 4 Newton steps and 68 iterations; 1e-4, 5 and 36; 1e-2, 7 and 37 (each Newton step also
/// costs about ten iterations' worth of setup, so 1e-4 is the fastest).
pub(crate) const FORCING_MAX: f64 = 1e-4;
/// Newton steps before the interior-point method takes over.
const JOINT_ITERATIONS: u32 = 25;

/// The iteration's mutable state.
struct State {
    x: Vec<f64>,
    lambda: Vec<f64>,
    y: Vec<f64>,
}

/// Limits of one solve, and where it reports its progress.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits<'p> {
    /// Relative tolerance of the natural residual and of the equality rows.
    pub tolerance: f64,
    /// Newton iterations (the cold start's all-stick step included).
    pub max_iterations: u32,
    /// The loosest relative accuracy of a Newton step's iterative solve while the contact
    /// pattern settles ([`FORCING_MAX`] from a cold or warm start; looser on a grid
    /// continuation's coarse levels and on the fine grid started from them).
    pub forcing: f64,
    /// Told the counts once per Newton step, when given.
    pub progress: Option<&'p SolveProgress>,
}

impl Limits<'_> {
    /// Tells the progress (if any) the work `counts` done so far.
    fn report(&self, counts: &Counts) {
        if let Some(p) = self.progress {
            p.note(counts.newton_steps, counts.inner_iterations);
        }
    }
}

/// `y = P x + q + E' lambda`.
pub(crate) fn dual_of(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    x: &[f64],
    lambda: &[f64],
) -> Vec<f64> {
    let mut y = copy_of(&program.q);
    add_dual(blocks, x, lambda, &mut y);
    y
}

/// [`dual_of`] written into `y` (no new vector).
fn dual_into(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    x: &[f64],
    lambda: &[f64],
    y: &mut [f64],
) {
    each_chunk(y, |s, c| c.copy_from_slice(&program.q[s..s + c.len()]));
    add_dual(blocks, x, lambda, y);
}

/// `y += P x + E' lambda`, each finger's part formed in one of its kept vectors.
fn add_dual(blocks: &[FingerBlockData], x: &[f64], lambda: &[f64], y: &mut [f64]) {
    for b in blocks {
        let r = b.offset..b.offset + b.len();
        let mut py = b.work.take(b.len());
        b.apply(&x[r.clone()], &mut py);
        b.add_equality_transpose(lambda, &mut py);
        each_chunk(&mut y[r], |s, c| {
            c.iter_mut().zip(&py[s..]).for_each(|(t, v)| *t += v)
        });
        b.work.give(py);
    }
}

/// `E x - e`.
fn equality_residual(blocks: &[FingerBlockData], program: &ConeProgram, x: &[f64]) -> Vec<f64> {
    let mut r: Vec<f64> = program.equality_rhs.iter().map(|v| -v).collect();
    for b in blocks {
        b.add_equality(&x[b.offset..b.offset + b.len()], &mut r);
    }
    r
}

/// True when every finger's compliance is the FFT operator: the steps are then projected
/// ones ([`super::projected_step`]), over the shared springs' small dense blocks too (their
/// preconditioner is their diagonal).
fn every_finger_fft(blocks: &[FingerBlockData], program: &ConeProgram) -> bool {
    blocks[..program.finger_blocks().len()]
        .iter()
        .all(FingerBlockData::is_fft)
}

/// Every finger's linearisation at `s`, in the storage of `spare` (the last step's); without
/// the elements' residuals when every finger is an FFT one (their steps are projected ones,
/// which keep no factors for chord steps).
fn linearise_all(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    s: &State,
    spare: Vec<FingerLinearisation>,
) -> Vec<FingerLinearisation> {
    let residuals = !every_finger_fft(blocks, program);
    let mut spare = spare.into_iter();
    blocks
        .iter()
        .zip(&program.blocks)
        .map(|(b, pb)| {
            let r = b.offset..b.offset + b.len();
            let kept = spare.next().unwrap_or_default();
            let at = LocalPoint {
                x: &s.x[r.clone()],
                y: &s.y[r],
            };
            linearise_reusing(b, &pb.cone, at, residuals, kept)
        })
        .collect()
}

/// Merit and residual maxima at `x + t dx`, `y + t dy`.
fn trial(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    s: &State,
    step: &Step,
    e_res: &[f64],
    t: f64,
) -> (f64, f64, f64) {
    let (mut sq, mut max) = (0.0, 0.0_f64);
    for (b, pb) in blocks.iter().zip(&program.blocks) {
        let r = b.offset..b.offset + b.len();
        let at = LocalPoint {
            x: &s.x[r.clone()],
            y: &s.y[r.clone()],
        };
        let along = LocalPoint {
            x: &step.dx[r.clone()],
            y: &step.dy[r],
        };
        let (q, m) = residual_norms_along(b, &pb.cone, at, along, t);
        sq += q;
        max = max.max(m);
    }
    let et: Vec<f64> = e_res
        .iter()
        .zip(&step.e_dx)
        .map(|(a, b)| a + t * b)
        .collect();
    (
        sq + et.iter().map(|v| v * v).sum::<f64>(),
        max,
        max_abs(&et),
    )
}

/// `v <- v + t dv`, on all cores for a long vector.
fn add_along(v: &mut [f64], dv: &[f64], t: f64) {
    each_chunk(v, |s, c| {
        c.iter_mut().zip(&dv[s..]).for_each(|(a, b)| *a += t * b)
    });
}

fn apply(s: &mut State, step: &Step, t: f64) {
    add_along(&mut s.x, &step.dx, t);
    add_along(&mut s.y, &step.dy, t);
    add_along(&mut s.lambda, &step.dlambda, t);
}

/// Runs the iteration from the candidate in `starts` with the smallest merit (none: cold);
/// when it stalls, the interior-point method takes over and its answer is polished by this
/// iteration.
pub(crate) fn run(
    blocks: &[FingerBlockData],
    caches: &mut [FactorCache],
    program: &ConeProgram,
    starts: &[&Iterate],
    limits: Limits,
) -> NativeResult {
    if let Some(p) = limits.progress {
        p.begin_program();
    }
    let mut states = starts.iter().filter_map(|it| state_of(blocks, program, it));
    let start = match starts.len() {
        0 | 1 => states.next(),
        _ => states
            .map(|s| (merit(blocks, program, &s), s))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, s)| s),
    };
    Newton::new(blocks, program, caches, limits, Counts::default()).iterate(start, true)
}

/// At most `limits.max_iterations` Newton steps from `start`, without the interior-point
/// method after a stall: the result's iterate is where the steps ended, converged or not (a
/// grid continuation's nested step, `crate::solver::grid_continuation`).
pub(crate) fn steps(
    blocks: &[FingerBlockData],
    caches: &mut [FactorCache],
    program: &ConeProgram,
    start: &Iterate,
    limits: Limits,
) -> Option<NativeResult> {
    let start = state_of(blocks, program, start)?;
    Some(
        Newton::new(blocks, program, caches, limits, Counts::default()).iterate(Some(start), false),
    )
}

/// The iteration's state at `it` (`None` for another layout).
fn state_of(blocks: &[FingerBlockData], program: &ConeProgram, it: &Iterate) -> Option<State> {
    let fits = it.x.len() == program.n_unknowns && it.lambda.len() == program.equality_rows();
    fits.then(|| State {
        y: dual_of(blocks, program, &it.x, &it.lambda),
        x: copy_of(&it.x),
        lambda: it.lambda.clone(),
    })
}

/// The merit `psi = ||Phi||^2 + ||E x - e||^2` of a state.
fn merit(blocks: &[FingerBlockData], program: &ConeProgram, s: &State) -> f64 {
    let phi: f64 = blocks
        .iter()
        .zip(&program.blocks)
        .map(|(b, pb)| {
            let r = b.offset..b.offset + b.len();
            residual_norms(b, &pb.cone, &s.x[r.clone()], &s.y[r]).0
        })
        .sum();
    let e_res = equality_residual(blocks, program, &s.x);
    phi + e_res.iter().map(|v| v * v).sum::<f64>()
}

/// One run of the Newton iteration: what it works on (the fingers' fixed data and the
/// program), what it works with (the fingers' factor caches and the long vectors kept from one
/// step to the next), its limits and the work it has counted.
struct Newton<'a, 'p> {
    blocks: &'a [FingerBlockData],
    program: &'a ConeProgram,
    caches: &'a mut [FactorCache],
    limits: Limits<'p>,
    /// The work done so far (a polish counts on from the interior-point method's).
    counts: Counts,
    /// The count of Newton steps when this run began: its steps count from there.
    first: u32,
    space: StepSpace,
}

/// What a Newton step aims at.
#[derive(Debug, Clone, Copy)]
struct StepAim {
    /// The natural residual the iteration aims at (0 for none): projected conjugate
    /// gradients stop once their error moves it by at most [`CG_SHARE`] of that.
    natural_tolerance: f64,
    /// The relative accuracy of the step's iterative solves (its forcing term).
    relative: f64,
}

/// Why a stall at a reduced matrix that cannot be factorised.
const NOT_POSITIVE_DEFINITE: &str = "a reduced matrix is not positive definite, or (FFT \
     compliance) conjugate gradients did not solve a Newton system to 1e-8 of its right-hand \
     side";

impl<'a, 'p> Newton<'a, 'p> {
    /// A run on `blocks` and `program` with the work `counts` done so far.
    fn new(
        blocks: &'a [FingerBlockData],
        program: &'a ConeProgram,
        caches: &'a mut [FactorCache],
        limits: Limits<'p>,
        counts: Counts,
    ) -> Self {
        Newton {
            blocks,
            program,
            caches,
            limits,
            // The cold start's all-stick step counts against the iteration's steps.
            first: counts.newton_steps,
            counts,
            space: StepSpace::new(program.n_unknowns),
        }
    }

    /// The iteration from `start` (`None`: cold); `fallback` hands a stall to the
    /// interior-point method.
    fn iterate(mut self, start: Option<State>, fallback: bool) -> NativeResult {
        let s = match start {
            Some(s) => s,
            None => match self.all_stick_start() {
                Ok(s) => s,
                Err(s) => return stalled(s, self.counts, NOT_POSITIVE_DEFINITE),
            },
        };
        match self.descend(s) {
            Descent::Converged(s) => {
                NativeResult::after(NativeStatus::Converged, s.x, s.lambda, self.counts)
            }
            Descent::Singular(s) => stalled(s, self.counts, NOT_POSITIVE_DEFINITE),
            Descent::Stalled(s) => self.robust(s, fallback),
        }
    }

    /// The Newton step at `lins`: by projected conjugate gradients when every finger's
    /// compliance is the FFT operator ([`projected_step`]), else (or when those do not
    /// converge) through the Schur complement of the fingers' reduced systems
    /// ([`newton_step`]), made in the storage the run keeps.
    fn step_of(
        &mut self,
        lins: &[FingerLinearisation],
        e_res: &[f64],
        aim: StepAim,
    ) -> Option<Step> {
        let blocks = self.blocks;
        if every_finger_fft(blocks, self.program) {
            // A free row is a natural residual over `gamma theta` (`theta <= 1`): an error `r`
            // in it moves the natural residual by at most `gamma_max r`.
            let gamma_max = blocks.iter().map(|b| b.gamma).fold(0.0, f64::max);
            let floor = match gamma_max > 0.0 {
                true => CG_SHARE * aim.natural_tolerance / gamma_max,
                false => 0.0,
            };
            let stop = CgStop {
                relative: aim.relative,
                floor,
            };
            let (space, counts) = (&mut self.space, &mut self.counts);
            if let Some(step) = projected_step(blocks, lins, e_res, space, counts, stop) {
                return Some(step);
            }
        }
        newton_step(
            blocks,
            lins,
            self.caches,
            e_res,
            &mut self.space,
            &mut self.counts,
        )
    }

    /// The cold start: from `x = 0`, `lambda = 0` the all-stick step (every element in
    /// contact and sticking, [`cold_pattern`]), counted; `Err` with the zero state when a
    /// reduced matrix cannot be factorised.
    fn all_stick_start(&mut self) -> Result<State, State> {
        let (blocks, program) = (self.blocks, self.program);
        let n = program.n_unknowns;
        let mut s = State {
            x: vec![0.0; n],
            lambda: vec![0.0; program.equality_rows()],
            y: copy_of(&program.q),
        };
        let lins: Vec<_> = blocks
            .iter()
            .map(|b| cold_pattern(b, &s.y[b.offset..b.offset + b.len()], &b.cold_contact))
            .collect();
        let e_res = equality_residual(blocks, program, &s.x);
        self.counts.newton_steps += 1;
        let aim = StepAim {
            natural_tolerance: 0.0,
            relative: self.limits.forcing,
        };
        match self.step_of(&lins, &e_res, aim) {
            Some(step) => {
                apply(&mut s, &step, 1.0);
                self.space.step = Some(step);
            }
            None => return Err(s),
        }
        self.space.lins = lins;
        dual_into(blocks, program, &s.x, &s.lambda, &mut s.y);
        Ok(s)
    }

    /// Damped Newton steps from `s` until the convergence test holds or the descent stalls,
    /// at the latest when `limits.max_iterations` (at most [`JOINT_ITERATIONS`]) steps have
    /// been taken since the run began. A step is inexact (`limits.forcing`) while the contact
    /// pattern settles (the first step, and whenever the free directions' elements changed
    /// since the last), from any start: a cold one, a coarser grid's answer
    /// (`crate::solver::grid_continuation`), the last solution of another program (a hand-off
    /// step, an iterate of the coulomb fixed point). Measured on the FFT path (29 November
    /// 2026), inexact first steps from warm starts against exact ones: the plate hand-off on
    /// 64 x 64 patches 11 conjugate-gradient iterations a step instead of 17 (0.94 Newton
    /// steps instead of 0.69, the same last residual, 4.6e-11); Cattaneo at 256 x 256 111
    /// instead of 199; the rough pad with friction (`examples/rough_sphere_on_flat_friction.json`
    /// at 256 x 256) 564 instead of 800 over its seven convex solves, the same answer. (Before
    /// the projected step's CG stopped at [`CG_SHARE`] of the aimed-at residual, warm starts
    /// took exact steps: inexact ones then cost the plate hand-off a third more Newton steps and
    /// left 5.4e-9 instead of 6.9e-11.) The dense path's steps are exact whatever this says.
    fn descend(&mut self, mut s: State) -> Descent {
        let (blocks, program, limits) = (self.blocks, self.program, self.limits);
        let mut history: Vec<f64> = Vec::with_capacity(WINDOW);
        let mut previous: Option<Vec<u64>> = None;
        loop {
            limits.report(&self.counts);
            let lins = linearise_all(blocks, program, &s, std::mem::take(&mut self.space.lins));
            let pattern = free_pattern(&lins);
            let settling = previous.as_ref().is_none_or(|p| *p != pattern);
            previous = Some(pattern);
            let e_res = equality_residual(blocks, program, &s.x);
            let res_max = lins.iter().fold(0.0_f64, |a, l| a.max(l.residual_max));
            let tol = Tolerances::at(limits, program, &s);
            let psi = lins.iter().map(|l| l.residual_sq).sum::<f64>()
                + e_res.iter().map(|v| v * v).sum::<f64>();
            if !psi.is_finite() {
                // Not a point the iteration can judge (a start or an interior-point answer
                // with numbers that are not finite, or an overflow): the maxima below would
                // skip its NaNs and read it as converged.
                return Descent::Stalled(s);
            }
            // Aim at TARGET of the tolerance (one more quadratic step, usually without a new
            // factorisation); accept the tolerance itself once progress stalls at round-off.
            let e_max = max_abs(&e_res);
            let stagnant = history.last().is_some_and(|&prev| psi > 1e-4 * prev);
            if tol.within(TARGET, res_max, e_max) || (tol.within(1.0, res_max, e_max) && stagnant) {
                return Descent::Converged(s);
            }
            if self.counts.newton_steps - self.first >= limits.max_iterations.min(JOINT_ITERATIONS)
            {
                return Descent::Stalled(s);
            }
            let reference = remember(&mut history, psi);
            self.counts.newton_steps += 1;
            // Near the solution the directions barely turn: reuse the cached factors (chord
            // step).
            let near =
                res_max <= CHORD_RESIDUAL * max_abs(&s.x[..program.finger_unknowns()]).max(1.0);
            let step_lins = match near {
                true => chord_linearisations(lins, self.caches),
                false => lins,
            };
            let relative = match settling {
                true => (res_max / max_abs(&s.x[..program.finger_unknowns()]).max(1.0))
                    .clamp(CG_TOLERANCE, limits.forcing.max(CG_TOLERANCE)),
                false => CG_TOLERANCE,
            };
            let aim = StepAim {
                natural_tolerance: TARGET * tol.x,
                relative,
            };
            let Some(step) = self.step_of(&step_lins, &e_res, aim) else {
                return Descent::Singular(s);
            };
            self.space.lins = step_lins;
            if max_abs(&step.unreachable) > tol.e {
                // No free direction can meet the equality rows: the contacts must change in a
                // way the joint step cannot see.
                return Descent::Stalled(s);
            }
            let Some(t) = line_search(blocks, program, &s, &step, &e_res, psi, reference) else {
                return Descent::Stalled(s);
            };
            apply(&mut s, &step, t);
            self.space.step = Some(step);
            if t < 1.0 {
                // Keep y exact: the update accumulates round-off over many damped steps.
                dual_into(blocks, program, &s.x, &s.lambda, &mut s.y);
            }
        }
    }

    /// After a stall at `s`: with `fallback`, the interior-point method, then a polish of its
    /// answer by the Newton iteration (which may not fall back again); without, the stall.
    fn robust(self, s: State, fallback: bool) -> NativeResult {
        let (blocks, program, counts) = (self.blocks, self.program, self.counts);
        if !fallback {
            return stalled(s, counts, "the Newton iteration stalled");
        }
        if blocks.iter().any(FingerBlockData::is_matrix_free) {
            return stalled(
                s,
                counts,
                "the Newton iteration stalled (the interior-point method that would take over \
                 needs every patch compliance as a matrix, and an FFT patch has more than 3,072 \
                 unknowns)",
            );
        }
        let ipm = interior_point::run(blocks, program, self.limits.tolerance, counts);
        let ipm_counts = Counts {
            newton_steps: ipm.iterations,
            factorisations: ipm.factorisations,
            inner_iterations: ipm.inner_iterations,
        };
        let start = state_of(blocks, program, &ipm.iterate);
        let polish = Newton::new(blocks, program, self.caches, self.limits, ipm_counts)
            .iterate(start, false);
        if polish.status == NativeStatus::Converged || ipm.status != NativeStatus::Converged {
            polish_or(polish, ipm)
        } else {
            NativeResult {
                iterations: polish.iterations,
                factorisations: polish.factorisations,
                ..ipm
            }
        }
    }
}

/// How a descent ended, at which state.
enum Descent {
    /// The convergence test holds.
    Converged(State),
    /// A reduced matrix is not positive definite.
    Singular(State),
    /// The descent cannot go on: its steps are spent, no free direction can meet the equality
    /// rows, or the line search found no decrease.
    Stalled(State),
}

/// The tolerances of the convergence test at an iterate.
struct Tolerances {
    /// Of the natural residual: `tol max(1, max |x|)`.
    x: f64,
    /// Of the equality rows: `tol max(1, max |e|)`.
    e: f64,
}

impl Tolerances {
    fn at(limits: Limits, program: &ConeProgram, s: &State) -> Self {
        Tolerances {
            x: limits.tolerance * max_abs(&s.x[..program.finger_unknowns()]).max(1.0),
            e: limits.tolerance * max_abs(&program.equality_rhs).max(1.0),
        }
    }

    /// True when both residual maxima are within `f` times the tolerances.
    fn within(&self, f: f64, res_max: f64, e_max: f64) -> bool {
        res_max <= f * self.x && e_max <= f * self.e
    }
}

/// Per finger, a hash of the elements of its free directions in order (their count folded
/// in): equal patterns have equal hashes, and a change of the contact set almost surely
/// changes it.
fn free_pattern(lins: &[FingerLinearisation]) -> Vec<u64> {
    lins.iter()
        .map(|l| {
            l.free.iter().fold(l.free.len() as u64, |h, d| {
                (h ^ d.element as u64).wrapping_mul(0x100000001b3)
            })
        })
        .collect()
}

/// Adds the merit `psi` to those the line search remembers (the last [`WINDOW`]) and returns
/// the largest of them, the line search's reference value.
fn remember(history: &mut Vec<f64>, psi: f64) -> f64 {
    if history.len() == WINDOW {
        history.remove(0);
    }
    history.push(psi);
    history.iter().cloned().fold(0.0_f64, f64::max)
}

/// The non-monotone backtracking line search along `step` from `s` (merit `psi`): the first
/// `t = 1, 1/2, 1/4, ...` with `psi(t) <= reference - 2 ARMIJO t psi`; `None` once `t` falls
/// below [`MIN_STEP`].
fn line_search(
    blocks: &[FingerBlockData],
    program: &ConeProgram,
    s: &State,
    step: &Step,
    e_res: &[f64],
    psi: f64,
    reference: f64,
) -> Option<f64> {
    let mut t = 1.0;
    loop {
        let (psi_t, _, _) = trial(blocks, program, s, step, e_res, t);
        if psi_t <= reference - 2.0 * ARMIJO * t * psi {
            return Some(t);
        }
        t *= 0.5;
        if t < MIN_STEP {
            return None;
        }
    }
}

/// The polished answer when it converged, else the interior-point one (counting all work).
fn polish_or(polish: NativeResult, ipm: NativeResult) -> NativeResult {
    if polish.status == NativeStatus::Converged {
        return polish;
    }
    let status = match &ipm.status {
        NativeStatus::Stalled(why) => NativeStatus::Stalled(format!(
            "the Newton iteration stalled and so did the interior-point method ({why})"
        )),
        other => other.clone(),
    };
    NativeResult {
        status,
        iterations: polish.iterations,
        factorisations: polish.factorisations,
        ..ipm
    }
}

/// A stall at `s` after the work `counts`, for the reason `why`.
fn stalled(s: State, counts: Counts, why: &str) -> NativeResult {
    NativeResult::after(
        NativeStatus::Stalled(why.to_string()),
        s.x,
        s.lambda,
        counts,
    )
}
