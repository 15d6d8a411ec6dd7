//! Options of a solve: which solver, tolerances, limits, warm starts, and their ranges
//! ([`SolveOptions::validate`], the one check every front end calls).

use std::ops::RangeInclusive;

use serde::{Deserialize, Serialize};

use crate::error::OptionError;
use crate::model::patch_compliance::ComplianceChoice;
use crate::number_text::Readable;
use crate::option_names;

/// Which solver answers the convex programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverChoice {
    /// The native solver, falling back to Clarabel when it does not converge (the solution
    /// says so and why).
    #[default]
    Auto,
    /// The native semismooth Newton solver only (Clarabel is asked only to certify a program
    /// without solution).
    Native,
    /// Clarabel's interior-point method, the reference.
    Clarabel,
}

impl SolverChoice {
    /// The solver that checks this one's answers, or takes a step this one does not converge
    /// on: Clarabel for the native solver and `auto`, the native solver for Clarabel.
    pub fn other(self) -> SolverChoice {
        match self {
            SolverChoice::Auto | SolverChoice::Native => SolverChoice::Clarabel,
            SolverChoice::Clarabel => SolverChoice::Native,
        }
    }
}

impl std::str::FromStr for SolverChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(SolverChoice::Auto),
            "native" => Ok(SolverChoice::Native),
            "clarabel" => Ok(SolverChoice::Clarabel),
            other => Err(format!(
                "unknown solver `{other}`; choose auto, native or clarabel"
            )),
        }
    }
}

impl std::fmt::Display for SolverChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SolverChoice::Auto => "auto",
            SolverChoice::Native => "native",
            SolverChoice::Clarabel => "clarabel",
        })
    }
}

/// Default smallest relaxation factor `omega` of the damped fixed-point iteration
/// ([`crate::solve::sequential`]) before an infeasible iterate is reported as the outcome
/// ([`SolveOptions::min_relaxation`]).
pub const MIN_RELAXATION: f64 = 1.0 / 64.0;

/// Options of a solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// Which solver answers.
    pub solver: SolverChoice,
    /// Tolerance of the scaled program: Clarabel's `tol_feas`, `tol_gap_abs`, `tol_gap_rel`;
    /// the native solver's bound on the natural residual relative to `max(1, max |x|)` and on
    /// the equality residual relative to `max(1, max |e|)` (dimensionless, in
    /// `TOLERANCE_RANGE`).
    pub tolerance: f64,
    /// Iteration limit of each convex solve: Clarabel's interior-point iterations; the native
    /// solver's Newton steps (at most `crate::solver::outcome::MAX_NEWTON_ITERATIONS`); in
    /// `ITERATION_RANGE`.
    pub max_iterations: u32,
    /// Time limit of each Clarabel solve, s (> 0; `inf` for none).
    pub time_limit_s: f64,
    /// Sequential solve: converged when no element normal force changes by more than this
    /// many element force units `Fu` between iterates (dimensionless, in
    /// `SEQUENTIAL_TOLERANCE_RANGE`; `inf` accepts the first iterate).
    pub sequential_tolerance: f64,
    /// Sequential solve: largest number of convex solves per run of the fixed-point
    /// iteration (in `ITERATION_RANGE`); a cold restart, and the exact run that follows an
    /// inexact one without an answer, count afresh.
    pub max_sequential_iterations: u32,
    /// Sequential solve: smallest relaxation `omega` of the damped fixed-point iteration
    /// before an iterate without solution is reported as the outcome (dimensionless, in
    /// `MIN_RELAXATION_RANGE`; `1` gives the plain, undamped iteration).
    pub min_relaxation: f64,
    /// Start each solve from the previous solution of the same program (the previous step or
    /// iterate), and a coulomb step from the previous step's forces; `false` starts every
    /// convex solve cold (for comparison).
    pub warm_start: bool,
    /// The form of the patch compliances: a dense matrix or the FFT operator
    /// (`crate::model::patch_compliance`). Read where the model is built
    /// ([`crate::GraspModel::from_scene_with`]): front ends build the model with it.
    pub compliance: ComplianceChoice,
}

/// The default [`SolveOptions::tolerance`]: the relative tolerance of the scaled program.
pub const DEFAULT_TOLERANCE: f64 = 1e-10;

/// [`DEFAULT_TOLERANCE`] as front ends show it (the CLI's flag default, the messages'
/// example); a test checks that it reads as the number.
pub const DEFAULT_TOLERANCE_TEXT: &str = "1e-10";

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            solver: SolverChoice::Auto,
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: 200,
            time_limit_s: f64::INFINITY,
            sequential_tolerance: 1e-7,
            max_sequential_iterations: 50,
            min_relaxation: MIN_RELAXATION,
            warm_start: true,
            compliance: ComplianceChoice::Auto,
        }
    }
}

/// Range of [`SolveOptions::tolerance`] (dimensionless): below 1e-14 the round-off of the
/// program's sums (about 1e-16 per term over up to 1e4 terms of unit size) exceeds it, so no
/// solve could meet it; above 1e-2 an answer is no solution of the program.
pub const TOLERANCE_RANGE: RangeInclusive<f64> = 1e-14..=1e-2;

/// Range of [`SolveOptions::sequential_tolerance`] (element force units): below 1e-14 no
/// fixed point can be told apart from round-off; `+inf` accepts the first iterate.
pub const SEQUENTIAL_TOLERANCE_RANGE: RangeInclusive<f64> = 1e-14..=f64::INFINITY;

/// Range of [`SolveOptions::max_iterations`] and [`SolveOptions::max_sequential_iterations`]:
/// at least one, and a bound on the work a solve may take.
pub const ITERATION_RANGE: RangeInclusive<u32> = 1..=10_000;

/// Range of [`SolveOptions::min_relaxation`]: the damped iteration halves `omega` from 1 down
/// to it before it reports an iterate without solution, so 1e-6 (20 halvings) already damps
/// past any use; below it only solves are added.
pub const MIN_RELAXATION_RANGE: RangeInclusive<f64> = 1e-6..=1.0;

/// `Ok` when `x` lies in `[lo, hi]` (NaN never does), else the error naming `option`; `what`
/// says what the option means and `example` gives a usable value.
pub(crate) fn check_range(
    option: &'static str,
    x: f64,
    range: RangeInclusive<f64>,
    what: &str,
    example: &str,
) -> Result<(), OptionError> {
    let (lo, hi) = range.into_inner();
    if x >= lo && x <= hi {
        return Ok(());
    }
    let upper = match hi {
        h if h == f64::INFINITY => "inf".to_string(),
        h => Readable(h).to_string(),
    };
    Err(OptionError {
        option,
        value: Readable(x).to_string(),
        expected: format!("give {what} in [{}, {upper}], e.g. {example}", Readable(lo)),
    })
}

/// [`check_range`] for a count.
pub(crate) fn check_count(
    option: &'static str,
    n: u32,
    range: RangeInclusive<u32>,
    what: &str,
    example: &str,
) -> Result<(), OptionError> {
    if range.contains(&n) {
        return Ok(());
    }
    let (lo, hi) = range.into_inner();
    Err(OptionError {
        option,
        value: n.to_string(),
        expected: format!("give {what} in [{lo}, {hi}], e.g. {example}"),
    })
}

impl SolveOptions {
    /// Checks every option against its range (the constants above; a time limit > 0 s, `inf`
    /// for none) and returns the first one outside it, named as the API spells it
    /// ([`option_names`]). Every solve checks its options; front ends call this first so that
    /// a bad option is refused before any work.
    pub fn validate(&self) -> Result<(), OptionError> {
        check_range(
            option_names::TOLERANCE,
            self.tolerance,
            TOLERANCE_RANGE,
            "a relative tolerance of the scaled program",
            DEFAULT_TOLERANCE_TEXT,
        )?;
        check_count(
            option_names::MAX_ITERATIONS,
            self.max_iterations,
            ITERATION_RANGE,
            "a number of iterations per convex solve",
            "200",
        )?;
        if self.time_limit_s.is_nan() || self.time_limit_s <= 0.0 {
            return Err(OptionError {
                option: option_names::TIME_LIMIT,
                value: Readable(self.time_limit_s).to_string(),
                expected: "give a time limit > 0 s (inf for none), e.g. 10".into(),
            });
        }
        check_range(
            option_names::SEQUENTIAL_TOLERANCE,
            self.sequential_tolerance,
            SEQUENTIAL_TOLERANCE_RANGE,
            "a change of the normal forces in element force units (inf: the first iterate)",
            "1e-7",
        )?;
        check_count(
            option_names::MAX_SEQUENTIAL_ITERATIONS,
            self.max_sequential_iterations,
            ITERATION_RANGE,
            "a number of convex solves per sequential solve",
            "50",
        )?;
        check_range(
            option_names::MIN_RELAXATION,
            self.min_relaxation,
            MIN_RELAXATION_RANGE,
            "a smallest relaxation factor",
            "0.015625",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default tolerance's text reads as the default tolerance.
    #[test]
    fn the_default_tolerance_text_is_the_default_tolerance() {
        assert_eq!(DEFAULT_TOLERANCE_TEXT.parse::<f64>(), Ok(DEFAULT_TOLERANCE));
        assert_eq!(SolveOptions::default().tolerance, DEFAULT_TOLERANCE);
    }

    #[test]
    fn the_defaults_are_valid() {
        assert_eq!(SolveOptions::default().validate(), Ok(()));
    }

    /// Each option outside its range (below, above, NaN) is refused by its own name, the
    /// value in readable form, and the range; the ends of each range are accepted.
    #[test]
    fn every_option_outside_its_range_is_refused_by_name() {
        type Set = fn(&mut SolveOptions, f64);
        let cases: [(&str, Set, &[f64], &[f64]); 6] = [
            (
                option_names::TOLERANCE,
                |o, x| o.tolerance = x,
                &[
                    2e-16,
                    1e-300,
                    0.0,
                    -1e-10,
                    0.5,
                    1e308,
                    f64::NAN,
                    f64::INFINITY,
                ],
                &[1e-14, 1e-2],
            ),
            (
                option_names::MAX_ITERATIONS,
                |o, x| o.max_iterations = x as u32,
                &[0.0, 10_001.0, 4e9],
                &[1.0, 10_000.0],
            ),
            (
                option_names::TIME_LIMIT,
                |o, x| o.time_limit_s = x,
                &[0.0, -1.0, f64::NAN, f64::NEG_INFINITY],
                &[1e-3, f64::INFINITY],
            ),
            (
                option_names::SEQUENTIAL_TOLERANCE,
                |o, x| o.sequential_tolerance = x,
                &[1e-15, 0.0, -1.0, f64::NAN],
                &[1e-14, f64::INFINITY],
            ),
            (
                option_names::MAX_SEQUENTIAL_ITERATIONS,
                |o, x| o.max_sequential_iterations = x as u32,
                &[0.0, 1e5],
                &[1.0, 10_000.0],
            ),
            (
                option_names::MIN_RELAXATION,
                |o, x| o.min_relaxation = x,
                &[0.0, 1e-7, 1.5, f64::NAN],
                &[1e-6, 1.0],
            ),
        ];
        for (name, set, bad, good) in cases {
            for &x in bad {
                let mut o = SolveOptions::default();
                set(&mut o, x);
                let e = o.validate().expect_err(name);
                assert_eq!(e.option, name);
                let text = e.to_string();
                assert!(text.starts_with(&format!("`{name}` is ")), "{text}");
                assert!(text.contains("e.g. "), "{text}");
                assert!(text.len() < 200, "{text}");
            }
            for &x in good {
                let mut o = SolveOptions::default();
                set(&mut o, x);
                assert_eq!(o.validate(), Ok(()), "{name} = {x}");
            }
        }
    }

    #[test]
    fn the_message_quotes_extreme_values_in_exponent_form() {
        let o = SolveOptions {
            tolerance: 1e308,
            ..SolveOptions::default()
        };
        assert_eq!(
            o.validate().unwrap_err().to_string(),
            "`SolveOptions::tolerance` is 1e308; give a relative tolerance of the scaled \
             program in [1e-14, 0.01], e.g. 1e-10"
        );
    }
}
