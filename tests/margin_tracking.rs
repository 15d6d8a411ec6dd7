//! Margins along a hand-off, each step's search continued from the last step's
//! (`grasp_model::MarginTracker`, what `grasp transfer --margins` runs), equal the margins
//! searched from scratch at every step (`grasp_model::disturbance_margins`, called by the
//! stepper with `margins_from_scratch`) along every bundled example hand-off, to the
//! bisection's tolerance.
//!
//! Both searches end on a bracket `[held, fails]` no wider than the relative tolerance `tol`
//! of its upper end around the same true margin `m` (the grasp holds below it and fails above
//! it), so each reports a lower end in `[(1 - tol) m, m]`: two reports differ by at most
//! `tol m <= tol / (1 - tol)` times the larger, and the smallest over the directions likewise.
//! Below `1e-6` of the load scale the bisection stops (a margin there counts as zero), which
//! adds that much in absolute terms.

mod support;

use grasp_model::MarginOptions;
use grasp_transfer::{StepMargin, StepRecord, Stepper, TransferOptions};
use support::{example_schedules, scene_and_schedule};

/// At most this many steps of each schedule (every k-th step beyond it): the search from
/// scratch costs 10 to 20 solves per direction and step, and a thinned path is a harder test
/// of the predictions, not an easier one.
const MAX_STEPS: usize = 12;

/// Patches of more elements than this are coarsened to [`COARSE_GRID`] a side: the
/// comparison is between two searches on the same grasp, and the grid sets only the cost of
/// its solves (a 9 x 9 patch costs about 0.1 s a solve near its margins, and a search from
/// scratch makes 10 to 20 solves per direction and step). The plates' 9 x 3 patches stay as
/// written.
const MAX_ELEMENTS: usize = 27;

/// The grid a side of a coarsened patch.
const COARSE_GRID: usize = 5;

/// Below this fraction of the load scale a margin counts as zero (the searches' constant).
const ZERO_MARGIN: f64 = 1e-6;

fn run(
    scene: &grasp_model::LoadedScene,
    schedule: &grasp_transfer::Schedule,
    from_scratch: bool,
) -> Vec<StepRecord> {
    run_with(scene, schedule, from_scratch, MarginOptions::default())
}

fn run_with(
    scene: &grasp_model::LoadedScene,
    schedule: &grasp_transfer::Schedule,
    from_scratch: bool,
    margin_options: MarginOptions,
) -> Vec<StepRecord> {
    let options = TransferOptions {
        margins: true,
        margins_from_scratch: from_scratch,
        margin_options,
        ..TransferOptions::default()
    };
    Stepper::new(scene, schedule, options)
        .map(|r| r.unwrap())
        .collect()
}

/// An example hand-off with its patches coarsened to [`COARSE_GRID`] above [`MAX_ELEMENTS`]
/// (without their textures and sensors) and at most [`MAX_STEPS`] of its steps.
fn thinned(
    scene_name: &str,
    schedule_name: &str,
) -> (grasp_model::LoadedScene, grasp_transfer::Schedule) {
    let (mut scene, mut schedule) = scene_and_schedule(scene_name, schedule_name);
    for f in &mut scene.fingers {
        if f.patch.grid[0] * f.patch.grid[1] > MAX_ELEMENTS {
            f.patch.grid = f.patch.grid.map(|n| n.min(COARSE_GRID));
            // A coarse grid resolves no texture, and a sensor reads nothing the margins use.
            f.texture = None;
            f.sensor = None;
        }
    }
    let stride = schedule.times.len().div_ceil(MAX_STEPS);
    schedule.times = schedule.times.iter().copied().step_by(stride).collect();
    (scene, schedule)
}

/// The difference between two margins of a step allowed by the brackets (module docs).
fn allowed_n(a: &StepMargin, b: &StepMargin, load_scale_n: f64) -> f64 {
    let tol = MarginOptions::default().relative_tolerance;
    tol / (1.0 - tol) * a.known_to_hold_n().max(b.known_to_hold_n()) + ZERO_MARGIN * load_scale_n
}

/// When one of two searches is undetermined: `Some(what was compared)` after checking that its
/// lower bound does not exceed the other's margin (or lower bound) by more than the bracket.
fn undetermined_consistent(a: &StepMargin, b: &StepMargin, load_scale_n: f64) -> Option<String> {
    let (u, other) = match (&a.undetermined, &b.undetermined) {
        (None, None) => return None,
        (Some(_), _) => (a, b),
        (None, Some(_)) => (b, a),
    };
    let tol = MarginOptions::default().relative_tolerance;
    // Against the other's margin; unbounded (held to the cap) or undetermined too, the other
    // bounds nothing above.
    let bound = match other.smallest_n {
        Some(margin) => margin * (1.0 + tol) + ZERO_MARGIN * load_scale_n,
        None => f64::INFINITY,
    };
    assert!(
        u.held_to_n <= bound,
        "held to {} N where the other search's margin is {:?} N: {u:?} {other:?}",
        u.held_to_n,
        other.smallest_n
    );
    Some(format!(
        "undetermined above {} N, the other {:?} N",
        u.held_to_n, other.smallest_n
    ))
}

#[test]
fn continued_margins_equal_the_search_from_scratch_along_every_example_hand_off() {
    let mut compared = 0;
    for (scene_name, schedule_name) in example_schedules() {
        let (scene, schedule) = thinned(&scene_name, &schedule_name);
        let clock = std::time::Instant::now();
        let continued = run(&scene, &schedule, false);
        let continued_s = clock.elapsed().as_secs_f64();
        let scratch = run(&scene, &schedule, true);
        let scratch_s = clock.elapsed().as_secs_f64() - continued_s;
        assert_eq!(continued.len(), scratch.len(), "{schedule_name}");
        let mut solves = (0, 0);
        for (a, b) in continued.iter().zip(&scratch) {
            let what = format!("{schedule_name} on {scene_name}, step {}", a.index);
            let (ma, mb) = match (&a.margin, &b.margin) {
                (Some(ma), Some(mb)) => (ma, mb),
                (None, None) => continue,
                other => panic!("{what}: one search has a margin, the other not: {other:?}"),
            };
            assert_eq!(ma.unresisted, mb.unresisted, "{what}");
            // A search that stalled (no solver answered above a magnitude that held, at the
            // edge of equilibrium or at the relaxing cylinder's cap) says only that the margin
            // is at least that: no more than the other's margin.
            if let Some(why) = undetermined_consistent(ma, mb, a.solution.load_scale_n) {
                println!("{what}: {why}");
                solves = (solves.0 + ma.solves, solves.1 + mb.solves);
                continue;
            }
            assert_eq!(ma.bounded, mb.bounded, "{what}: {ma:?} {mb:?}");
            let allowed = allowed_n(ma, mb, a.solution.load_scale_n);
            assert!(
                (ma.known_to_hold_n() - mb.known_to_hold_n()).abs() <= allowed,
                "{what}: continued {} N, from scratch {} N (allowed {allowed} N): {ma:?}, \
                 {mb:?}",
                ma.known_to_hold_n(),
                mb.known_to_hold_n()
            );
            solves = (solves.0 + ma.solves, solves.1 + mb.solves);
            compared += 1;
        }
        println!(
            "{schedule_name}: {} steps, continued {} solves in {continued_s:.2} s, from \
             scratch {} solves in {scratch_s:.2} s",
            continued.len(),
            solves.0,
            solves.1
        );
    }
    assert!(compared > 100, "{compared} steps compared");
}

/// The load capacity only spares solves: with it and without it (every trial solved, as the
/// search was before it) the continued search finds the same margins to the bisection's
/// tolerance at every step of every bundled example hand-off (module docs), and it never
/// costs more solves in all.
#[test]
fn the_load_capacity_changes_no_margin_along_any_example_hand_off() {
    let without = MarginOptions {
        load_capacity: false,
        ..MarginOptions::default()
    };
    let mut compared = 0;
    for (scene_name, schedule_name) in example_schedules() {
        let (scene, schedule) = thinned(&scene_name, &schedule_name);
        let bounded = run(&scene, &schedule, false);
        let solved = run_with(&scene, &schedule, false, without);
        let mut solves = (0, 0);
        for (a, b) in bounded.iter().zip(&solved) {
            let what = format!("{schedule_name} on {scene_name}, step {}", a.index);
            let (Some(ma), Some(mb)) = (&a.margin, &b.margin) else {
                assert_eq!(a.margin.is_some(), b.margin.is_some(), "{what}");
                continue;
            };
            // Without the capacity a trial past the edge of equilibrium may stall where the
            // capacity proves that it fails: that direction is then undetermined above a
            // magnitude that held, no more than the margin found with the capacity.
            if mb.undetermined.is_some() && ma.undetermined.is_none() {
                let tol = MarginOptions::default().relative_tolerance;
                let margin = ma.known_to_hold_n();
                assert!(
                    mb.held_to_n <= margin * (1.0 + tol) + ZERO_MARGIN * a.solution.load_scale_n,
                    "{what}: held to {} N without the capacity, margin {margin} N with it",
                    mb.held_to_n
                );
                solves = (solves.0 + ma.solves, solves.1 + mb.solves);
                continue;
            }
            assert_eq!(ma.bounded, mb.bounded, "{what}: {ma:?} {mb:?}");
            let allowed = allowed_n(ma, mb, a.solution.load_scale_n);
            // Both undetermined (no solver answers above a magnitude that held, as at the
            // relaxing cylinder's cap), or neither.
            assert_eq!(
                ma.undetermined.is_some(),
                mb.undetermined.is_some(),
                "{what}: one search stalled: {ma:?}, {mb:?}"
            );
            assert!(
                (ma.known_to_hold_n() - mb.known_to_hold_n()).abs() <= allowed,
                "{what}: with the capacity {} N, without {} N (allowed {allowed} N): {ma:?} {mb:?}",
                ma.known_to_hold_n(),
                mb.known_to_hold_n()
            );
            solves = (solves.0 + ma.solves, solves.1 + mb.solves);
            compared += 1;
        }
        println!(
            "{schedule_name}: {} steps, {} solves with the load capacity, {} without",
            bounded.len(),
            solves.0,
            solves.1
        );
        assert!(solves.0 <= solves.1, "{schedule_name}: {solves:?}");
    }
    assert!(compared > 100, "{compared} steps compared");
}
