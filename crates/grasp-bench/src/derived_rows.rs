//! The table's rows derived from the measured cases: the hand-offs' warm/cold iteration ratios,
//! the bounded time ratios of case pairs ([`LAYER_PAIRS`], [`MARGIN_PAIRS`]), the growth exponent
//! of solve time against unknowns over the cube A series, and the 1024 x 1024 patch's
//! conjugate-gradient iterations and peak memory against their limits.

use grasp_model::SolverChoice;

use crate::case::{CASES, LAYER_PAIRS, MARGIN_PAIRS};
use crate::measurement::{find, Measured};
use crate::statistics::growth_exponent;
use crate::table::{time, verdict, Row};

/// The hand-offs timed warm and cold: the row's label, the warm case, the cold case.
const WARM_COLD: [[&str; 3]; 2] = [
    [
        "plate hand-off warm/cold",
        "plate_handoff_warm",
        "plate_handoff_cold",
    ],
    [
        "coulomb hand-off warm/cold",
        "coulomb_handoff_warm",
        "coulomb_handoff_cold",
    ],
];

/// The servo-released hand-offs against the force-ramped one: the row's label, the servo case,
/// the force-ramped case, and the largest ratio of their iterations per step (warm starts
/// must survive position ramps on mounted fingers, and on fingers sharing a servo or a hand).
const SERVO_PAIRS: [(&str, &str, &str, f64); 2] = [
    (
        "servo / force-ramped hand-off",
        "servo_handoff_warm",
        "coulomb_handoff_warm",
        1.5,
    ),
    (
        "gripper / force-ramped hand-off",
        "gripper_handoff_warm",
        "coulomb_handoff_warm",
        1.5,
    ),
];

/// Largest warm/cold iteration ratio of a hand-off.
const WARM_COLD_TARGET: f64 = 0.2;

/// The 1024 x 1024 patch's largest conjugate-gradient iterations per solve.
const FINE_CG_LIMIT: f64 = 40.0;

/// The 1024 x 1024 patch's largest peak memory, MiB.
const FINE_MEMORY_LIMIT_MIB: f64 = 500.0;

/// Per solver: the warm/cold iteration ratios (target [`WARM_COLD_TARGET`]), the bounded time
/// ratios, and the cube A series' growth exponent.
pub(crate) fn derived_rows(all: &[Measured], solvers: &[SolverChoice]) -> Vec<Row> {
    let mut rows = Vec::new();
    for &solver in solvers {
        rows.extend(warm_cold_rows(all, solver));
        rows.extend(servo_rows(all, solver));
        rows.extend(ratio_rows(all, solver));
        rows.extend(growth_row(all, solver));
    }
    rows
}

/// The iterations (and factorisations) of each hand-off measured warm and cold, warm over cold.
fn warm_cold_rows(all: &[Measured], solver: SolverChoice) -> Vec<Row> {
    let mut rows = Vec::new();
    for [label, warm, cold] in WARM_COLD {
        let (Some(w), Some(c)) = (find(all, warm, solver), find(all, cold, solver)) else {
            continue;
        };
        let ratio = w.first.iterations / c.first.iterations;
        let fact = w.first.factorizations / c.first.factorizations;
        rows.push(Row {
            case: label.into(),
            timed: "iterations ratio".into(),
            solver: solver.to_string(),
            median: format!("{ratio:.3}"),
            iterations: format!("{:.2} / {:.2}", w.first.iterations, c.first.iterations),
            factorizations: match fact.is_finite() {
                true => format!("ratio {fact:.3}"),
                false => "-".into(),
            },
            target: verdict(ratio, WARM_COLD_TARGET, |x| format!("{x:.1}")),
            ..Row::default()
        });
    }
    rows
}

/// Each servo-released hand-off's iterations per step over the force-ramped one's, at most
/// [`SERVO_PAIRS`]' bounds.
fn servo_rows(all: &[Measured], solver: SolverChoice) -> Vec<Row> {
    let mut rows = Vec::new();
    for (label, servo, ramped, bound) in SERVO_PAIRS {
        let (Some(s), Some(r)) = (find(all, servo, solver), find(all, ramped, solver)) else {
            continue;
        };
        let ratio = s.first.iterations / r.first.iterations;
        rows.push(Row {
            case: label.into(),
            timed: "iterations ratio".into(),
            solver: solver.to_string(),
            median: format!("{ratio:.3}"),
            iterations: format!("{:.2} / {:.2}", s.first.iterations, r.first.iterations),
            target: verdict(ratio, bound, |x| format!("{x:.1}")),
            ..Row::default()
        });
    }
    rows
}

/// The bounded time ratios: a layered, viscoelastic or textured pad's time (model build and
/// solve, or per step) over the plain pad's on the same path, at most [`LAYER_PAIRS`]' bound;
/// the margins of a hand-off's steps over the stepping, at most [`MARGIN_PAIRS`]' bound.
fn ratio_rows(all: &[Measured], solver: SolverChoice) -> Vec<Row> {
    let mut rows = Vec::new();
    for (over, under, bound) in LAYER_PAIRS.into_iter().chain(MARGIN_PAIRS) {
        let (Some(o), Some(u)) = (find(all, over, solver), find(all, under, solver)) else {
            continue;
        };
        let ratio = o.median_s / u.median_s;
        rows.push(Row {
            case: format!("{over} / {under}"),
            timed: "time ratio".into(),
            solver: solver.to_string(),
            median: format!("{ratio:.2}x"),
            range: format!("{} / {}", time(o.median_s), time(u.median_s)),
            target: verdict(ratio, bound, |x| format!("{x:.1}x")),
            ..Row::default()
        });
    }
    rows
}

/// The growth exponent `k` of `solve ~ unknowns^k` over the dense cube A series (the solver
/// cases; the FFT case grows differently), with at least three of its sizes measured.
fn growth_row(all: &[Measured], solver: SolverChoice) -> Option<Row> {
    let series: Vec<(f64, f64)> = all
        .iter()
        .filter(|m| m.solver == solver && m.case.name.starts_with("cube_a_"))
        .filter(|m| CASES.iter().any(|c| c.name == m.case.name))
        .map(|m| (m.first.unknowns as f64, m.median_solve_s))
        .collect();
    let k = growth_exponent(&series).filter(|_| series.len() >= 3)?;
    let sizes: Vec<String> = series.iter().map(|p| format!("{}", p.0)).collect();
    Some(Row {
        case: "cube A series growth".into(),
        timed: "solve ~ unknowns^k".into(),
        solver: solver.to_string(),
        median: format!("k = {k:.2}"),
        unknowns: sizes.join(", "),
        ..Row::default()
    })
}

/// The 1024 x 1024 patch's conjugate-gradient iterations and peak memory (native solver)
/// against [`FINE_CG_LIMIT`] and [`FINE_MEMORY_LIMIT_MIB`].
pub(crate) fn fine_limit_rows(all: &[Measured]) -> Vec<Row> {
    let Some(m) = find(all, "hertz_1024x1024_fft", SolverChoice::Native) else {
        return Vec::new();
    };
    let mib = m.first.peak_memory_bytes.map(|b| b as f64 / 1048576.0);
    let limits = [
        (
            "CG iterations",
            Some(m.first.inner_iterations),
            FINE_CG_LIMIT,
        ),
        ("peak MiB", mib, FINE_MEMORY_LIMIT_MIB),
    ];
    let mut rows = Vec::new();
    for (what, value, limit) in limits {
        let Some(value) = value else { continue };
        rows.push(Row {
            case: format!("hertz_1024x1024_fft {what}"),
            timed: "per solve".into(),
            solver: SolverChoice::Native.to_string(),
            median: format!("{value:.0}"),
            target: verdict(value, limit, |x| format!("{x:.0}")),
            ..Row::default()
        });
    }
    rows
}
