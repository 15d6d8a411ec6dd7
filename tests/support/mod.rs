//! Shared helpers of the integration tests: load the bundled examples, edit them as JSON.
#![allow(dead_code)]

use grasp_model::solve;
use grasp_model::{GraspModel, LoadedScene, Solution, SolveStatus};
use serde_json::Value;

/// The problems a scene is refused with, one line each (panics when it is accepted).
pub fn problems(v: &Value) -> Vec<String> {
    match LoadedScene::from_json_str(&v.to_string()) {
        Ok(_) => panic!("scene was accepted"),
        Err(e) => e.problems().iter().map(|p| p.to_string()).collect(),
    }
}

/// Asserts that the scene is refused with a problem at `path` that says `words` and gives a
/// fix.
pub fn assert_refused(v: &Value, path: &str, words: &str) {
    let p = problems(v);
    assert!(
        p.iter()
            .any(|m| m.starts_with(path) && m.contains(words) && m.contains("fix")),
        "expected `{path}` ... `{words}` ... fix, got {p:#?}"
    );
}

/// Path of a file in the workspace's `examples/` folder.
pub fn example_path(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// An example scene as JSON, for editing.
pub fn example_json(name: &str) -> Value {
    let text = std::fs::read_to_string(example_path(name)).expect("example exists");
    serde_json::from_str(&text).expect("example is JSON")
}

/// Parses and validates a JSON scene (as read: its shapes, its report).
pub fn scene(v: &Value) -> LoadedScene {
    LoadedScene::from_json_str(&v.to_string()).expect("valid scene")
}

/// Builds and solves a JSON scene.
pub fn solve_json(v: &Value) -> Solution {
    let model = GraspModel::from_loaded(&scene(v)).expect("model");
    solve(&model).expect("solve runs")
}

/// Solves and insists on a solution.
pub fn solved(v: &Value) -> Solution {
    let s = solve_json(v);
    assert_eq!(s.status, SolveStatus::Solved, "{:?}", s.reason);
    s
}

/// Multiplies every Young's modulus in the scene by `k`.
pub fn scale_moduli(v: &mut Value, k: f64) {
    let scale = |m: &mut Value| {
        if let Some(e) = m.get_mut("youngs_modulus") {
            *e = Value::from(e.as_f64().unwrap() * k);
        }
    };
    scale(&mut v["object"]["material"]);
    for f in v["fingers"].as_array_mut().unwrap() {
        scale(&mut f["material"]);
    }
}

/// The five thesis examples.
pub const EXAMPLES: [&str; 5] = [
    "plate_four_fingers.json",
    "disc_three_fingers.json",
    "pipe_three_fingers.json",
    "cube_a.json",
    "cube_b.json",
];

/// The bundled files of `examples/` and `examples/mujoco/` whose names end in `suffix`, as
/// paths relative to `examples/` (`mujoco/pinch.json`), sorted.
fn example_files(suffix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for folder in ["", "mujoco/"] {
        let dir = std::fs::read_dir(example_path(folder)).expect("the examples folder");
        for entry in dir {
            let name = entry.expect("a folder entry").file_name();
            let name = name.to_string_lossy();
            if name.ends_with(suffix) {
                out.push(format!("{folder}{name}"));
            }
        }
    }
    out.sort();
    out
}

/// Every bundled example scene (`examples/*.json` and `examples/mujoco/*.json`, without the
/// schedules, MuJoCo material maps, reports and states), as paths relative to `examples/`.
pub fn example_scenes() -> Vec<String> {
    let not_a_scene = [
        ".schedule.json",
        ".materials.json",
        ".report.json",
        ".state.json",
    ];
    example_files(".json")
        .into_iter()
        .filter(|n| !not_a_scene.iter().any(|s| n.ends_with(s)))
        .collect()
}

/// Schedules that drive a scene whose name is not a prefix of theirs (docs/guide/margins.md: the coulomb
/// plate hand-off with a task-induced load).
const SCHEDULE_SCENES: [(&str, &str); 2] = [
    ("plate_bump.schedule.json", "plate_handoff_coulomb.json"),
    ("plate_pull.schedule.json", "plate_handoff_coulomb.json"),
];

/// Every bundled schedule (`*.schedule.json`, `mujoco/` included) with the scene it drives:
/// `<name>.json` for `<name>.schedule.json`, else the longest scene name its name starts with
/// (`cylinder_handoff_viscoelastic_fast` drives `cylinder_handoff_viscoelastic`), else the
/// scene [`SCHEDULE_SCENES`] names; a schedule with none fails.
pub fn example_schedules() -> Vec<(String, String)> {
    let scenes = example_scenes();
    example_files(".schedule.json")
        .into_iter()
        .map(|schedule| {
            let stem = schedule.trim_end_matches(".schedule.json");
            let prefix = scenes
                .iter()
                .filter(|s| stem.starts_with(s.trim_end_matches(".json")))
                .max_by_key(|s| s.len());
            let named = SCHEDULE_SCENES.iter().find(|(s, _)| *s == schedule);
            let scene = match (prefix, named) {
                (Some(scene), _) => scene.clone(),
                (None, Some((_, scene))) => scene.to_string(),
                (None, None) => panic!("{schedule}: no scene; name it in SCHEDULE_SCENES"),
            };
            (scene, schedule)
        })
        .collect()
}

/// A bundled scene (a path relative to `examples/`) read as the CLI reads it, mesh files
/// resolved in its folder.
pub fn example_scene(name: &str) -> LoadedScene {
    grasp_io::read_scene_file(std::path::Path::new(&example_path(name)))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .scene
}

/// A bundled scene and a schedule for it (paths relative to `examples/`), the schedule's CSV
/// profiles resolved in its folder.
pub fn scene_and_schedule(scene: &str, schedule: &str) -> (LoadedScene, grasp_transfer::Schedule) {
    let path = std::path::PathBuf::from(example_path(schedule));
    let dir = path.parent().expect("a folder");
    let scene = example_scene(scene);
    let names: Vec<String> = scene.fingers.iter().map(|f| f.name.clone()).collect();
    let text = std::fs::read_to_string(&path).unwrap();
    let schedule = grasp_transfer::Schedule::from_json_str(&text, &names, dir)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (scene, schedule)
}

/// A bundled hand-off: its scene and its schedule (`<name>.json`, `<name>.schedule.json`).
pub fn transfer_example(name: &str) -> (LoadedScene, grasp_transfer::Schedule) {
    let dir = std::path::PathBuf::from(example_path(""));
    let text = std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap();
    let scene = LoadedScene::from_json_str(&text).unwrap();
    let names = scene.finger_names();
    let text = std::fs::read_to_string(dir.join(format!("{name}.schedule.json"))).unwrap();
    let schedule = grasp_transfer::Schedule::from_json_str(&text, &names, &dir).unwrap();
    (scene, schedule)
}

/// Steps a bundled hand-off with `options`, insisting that every step runs.
pub fn step_transfer_example(
    name: &str,
    options: grasp_transfer::TransferOptions,
) -> Vec<grasp_transfer::StepRecord> {
    let (scene, schedule) = transfer_example(name);
    grasp_transfer::Stepper::new(&scene, &schedule, options)
        .map(|r| r.unwrap())
        .collect()
}

/// Builds and solves a JSON scene with the given solver (default options otherwise).
pub fn solve_with(v: &Value, solver: grasp_model::SolverChoice) -> Solution {
    solve_with_options(
        v,
        grasp_model::SolveOptions {
            solver,
            ..grasp_model::SolveOptions::default()
        },
    )
}

/// Builds and solves a JSON scene with the given options.
pub fn solve_with_options(v: &Value, options: grasp_model::SolveOptions) -> Solution {
    solve_scene_with_options(&scene(v), options)
}

/// Builds and solves a scene with the given options.
pub fn solve_scene_with_options(
    scene: &LoadedScene,
    options: grasp_model::SolveOptions,
) -> Solution {
    let model = GraspModel::from_loaded_with(scene, options.compliance).expect("model");
    grasp_model::GraspSolver::new(model.clone(), options)
        .solve(&grasp_model::StepInputs::of_scene(&model))
        .expect("solve runs")
}

/// Every element's force components `[F, G1, G2]`, N, finger by finger.
pub fn element_force_components(s: &Solution) -> Vec<f64> {
    s.fingers
        .iter()
        .flat_map(|f| {
            f.elements.iter().flat_map(|e| {
                [
                    e.normal_force_n,
                    e.tangential_force_n[0],
                    e.tangential_force_n[1],
                ]
            })
        })
        .collect()
}

/// Largest difference of any element force component (normal or tangential) between two
/// solutions of the same model, N.
pub fn element_force_difference_n(a: &Solution, b: &Solution) -> f64 {
    let mut d = 0.0_f64;
    for (fa, fb) in a.fingers.iter().zip(&b.fingers) {
        for (ea, eb) in fa.elements.iter().zip(&fb.elements) {
            d = d.max((ea.normal_force_n - eb.normal_force_n).abs());
            for c in 0..2 {
                d = d.max((ea.tangential_force_n[c] - eb.tangential_force_n[c]).abs());
            }
        }
    }
    d
}

/// Agreement required of the native solver and Clarabel: element forces within
/// `1e-8` of the load scale, the same status.
pub const SOLVER_AGREEMENT: f64 = 1e-8;

/// Clarabel's tolerance as the reference of the native solver: at its default (`1e-10`)
/// Clarabel's element forces are only good to about `1e-8` of the load (cube A: `5e-8 N`
/// against `3.7e-9 N` at `1e-13`), the size of the agreement being checked.
pub const REFERENCE_TOLERANCE: f64 = 1e-12;

/// Sequential tolerance of both solvers in the comparison (element force units): the default
/// `1e-7` leaves the fixed point uncertain by about that much, near the agreement checked.
pub const SEQUENTIAL_REFERENCE: f64 = 1e-10;

/// Relative round-off of [`complementary_energy_j`]: a sum of up to `1e5` products in double
/// precision, `1e5 x 1.1e-16`.
pub const ENERGY_ROUNDOFF: f64 = 1e-11;

/// The complementary energy of a solution's forces, `1/2 x'Cx + c'F` (J), computed here from
/// the model's compliance blocks and gaps, independently of both solvers, plus each hand's and
/// servo's `1/2 W' S W` (from the load it carries and the motion it reports, `-S W`).
pub fn complementary_energy_j(model: &GraspModel, sol: &Solution) -> f64 {
    let mut j = 0.0;
    for (f, fs) in model.fingers().iter().zip(&sol.fingers) {
        let ne = f.patch().len();
        let mut x = vec![0.0; f.n_unknowns()];
        for (k, e) in fs.elements.iter().enumerate() {
            x[k] = e.normal_force_n;
            for c in 0..f.n_tangential() {
                x[(c + 1) * ne + k] = e.tangential_force_n[c];
            }
        }
        let c = f.compliance_matrix_m_per_n().expect("a dense compliance");
        for a in 0..x.len() {
            let row: f64 = (0..x.len()).map(|b| c[(a, b)] * x[b]).sum();
            j += 0.5 * x[a] * row;
        }
        for (k, xk) in x.iter().enumerate().take(ne) {
            j += f.patch().gap_m[k] * xk;
        }
    }
    // The shared springs' `1/2 W' S W`: each carries `W` and moves by `-S W`.
    for h in &sol.hands {
        let work: f64 = (0..3)
            .map(|c| h.force_n[c] * h.translation_m[c] + h.moment_nm[c] * h.rotation_rad[c])
            .sum();
        j -= 0.5 * work;
    }
    for s in &sol.servos {
        j -= 0.5 * s.force_n * s.travel_m;
    }
    j
}

/// How the native solver's answer compared with Clarabel's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Agreement {
    /// Same status, element forces within [`SOLVER_AGREEMENT`] of the load (or no forces).
    Within,
    /// Forces differ by more, but the native answer is feasible to `1e-10` and its energy is
    /// no higher than Clarabel's: the program is strictly convex, so the native answer is the
    /// closer one to its unique minimiser (Clarabel stops short along a flat valley).
    NativeIsTheMinimiser,
    /// A coulomb answer: forces differ by more (or Clarabel's sequential solve does not reach
    /// the fixed point), but the native forces solve the Tresca program at their own radii
    /// `mu F` (the definition of a fixed point), checked against one Clarabel solve of that
    /// program: Clarabel reproduces them within [`SOLVER_AGREEMENT`], or they are feasible
    /// for it to `1e-10` and their energy is no higher than Clarabel's answer's.
    FixedPointConfirmed,
    /// Clarabel gives no answer (no convergence; for coulomb also no fully solved answer at the
    /// native radii),
    /// the native solver does: its answer is then checked by the residuals alone, recomputed
    /// from the forces with the model's matrices: equilibrium and cones (coulomb: the Tresca
    /// discs at its own radii) to `1e-10`, penetration, compatibility, complementarity and
    /// stick motion to `1e-8`.
    ReferenceFailedResidualsHold,
}

/// True when `native`'s forces satisfy the Tresca program at their own radii `mu F_k` to
/// `1e-10` element force units, and equilibrium to `1e-10` of the load.
fn tresca_feasible_at_own_radii(model: &GraspModel, native: &Solution) -> bool {
    let fu = model.scales().element_force_n;
    let eq = native
        .residuals
        .is_some_and(|r| r.equilibrium_relative <= 1e-10);
    eq && native.fingers.iter().all(|f| {
        f.elements.iter().all(|e| {
            let g = e.tangential_force_n[0].hypot(e.tangential_force_n[1]);
            let radius = f.friction_coefficient * e.normal_force_n.max(0.0);
            e.normal_force_n >= -1e-10 * fu
                && (f.friction_coefficient == 0.0 || g <= radius + 1e-10 * fu)
        })
    })
}

/// One Clarabel solve of the Tresca program at the radii `mu F` of `native`'s forces (a
/// coulomb solution from a fresh state): the largest element force difference to `native`
/// over the load scale, and that solution (`None` if the solve fails).
pub fn clarabel_at_native_radii(model: &GraspModel, native: &Solution) -> Option<(f64, Solution)> {
    let mut state = grasp_model::ContactState::new(model);
    for (fs, f) in state.fingers.iter_mut().zip(&native.fingers) {
        fs.normal_forces_n = Some(f.elements.iter().map(|e| e.normal_force_n).collect());
        fs.normal_load_n = Some(f.normal_force_n);
    }
    let options = grasp_model::SolveOptions {
        solver: grasp_model::SolverChoice::Clarabel,
        tolerance: REFERENCE_TOLERANCE,
        max_iterations: 500,
        // One iterate: radii from the native forces, one convex solve, no further iteration.
        sequential_tolerance: f64::INFINITY,
        max_sequential_iterations: 1,
        warm_start: true,
        ..grasp_model::SolveOptions::default()
    };
    let sol = grasp_model::GraspSolver::new(model.clone(), options)
        .solve_step(&grasp_model::StepInputs::of_scene(model), &mut state)
        .ok()?;
    let once = sol
        .sequential
        .is_some_and(|q| q.iterations == 1 && q.warm_started);
    (sol.status.has_forces() && once).then(|| {
        (
            element_force_difference_n(native, &sol) / native.load_scale_n,
            sol,
        )
    })
}

/// Checks a coulomb answer `native` as a fixed point with Clarabel, independently of the
/// native solver: one Clarabel solve of the Tresca program at the answer's radii `mu F`
/// ([`clarabel_at_native_radii`]) either reproduces its forces within [`SOLVER_AGREEMENT`]
/// of the load, or the answer is feasible for that program (Tresca discs at its own radii
/// and equilibrium, to `1e-10`) with an energy no higher than Clarabel's answer's (to
/// [`ENERGY_ROUNDOFF`]): the program is strictly convex, so the feasible answer with the lower
/// energy is the closer one to its unique minimiser. Returns the force difference (relative
/// to the load) when confirmed.
pub fn fixed_point_confirmed(model: &GraspModel, native: &Solution) -> Option<f64> {
    if !native.status.has_forces() {
        return None;
    }
    let (d, c) = clarabel_at_native_radii(model, native)?;
    let (jn, jc) = (
        complementary_energy_j(model, native),
        complementary_energy_j(model, &c),
    );
    let lower =
        tresca_feasible_at_own_radii(model, native) && jn <= jc + ENERGY_ROUNDOFF * jc.abs();
    (d <= SOLVER_AGREEMENT || lower).then_some(d)
}

/// Solves `v` with the native solver (default options) and with Clarabel at
/// [`REFERENCE_TOLERANCE`] and compares them: the same status (solved and reduced accuracy
/// count as one) and, with forces, element forces within [`SOLVER_AGREEMENT`] of the load
/// scale or, for the energy model, the native answer shown to be the minimiser (see
/// [`Agreement`]). Returns the native solution and how it agreed, or why they disagree.
pub fn native_agrees_with_clarabel(v: &Value) -> Result<(Solution, Agreement, f64), String> {
    native_agrees_with_clarabel_on(&scene(v))
}

/// [`native_agrees_with_clarabel`] on a scene already read.
pub fn native_agrees_with_clarabel_on(
    scene: &LoadedScene,
) -> Result<(Solution, Agreement, f64), String> {
    let model = GraspModel::from_loaded(scene).expect("model");
    // A sequential (coulomb) answer is a fixed point known to its sequential tolerance; two
    // solvers stopping at neighbouring iterates differ by that much, so both run at
    // SEQUENTIAL_REFERENCE here.
    let sequential_tolerance = SEQUENTIAL_REFERENCE;
    let native = solve_scene_with_options(
        scene,
        grasp_model::SolveOptions {
            solver: grasp_model::SolverChoice::Native,
            sequential_tolerance,
            max_sequential_iterations: 200,
            ..grasp_model::SolveOptions::default()
        },
    );
    let clarabel = solve_scene_with_options(
        scene,
        grasp_model::SolveOptions {
            solver: grasp_model::SolverChoice::Clarabel,
            tolerance: REFERENCE_TOLERANCE,
            max_iterations: 500,
            sequential_tolerance,
            max_sequential_iterations: 200,
            ..grasp_model::SolveOptions::default()
        },
    );
    let class = |s: &Solution| {
        if s.status.has_forces() {
            SolveStatus::Solved
        } else {
            s.status
        }
    };
    let coulomb = model.kind() == grasp_model::ModelKind::Coulomb;
    let confirmed = |native: &Solution| coulomb && fixed_point_confirmed(&model, native).is_some();
    let residuals_hold = |native: &Solution| {
        let cones = if coulomb {
            tresca_feasible_at_own_radii(&model, native)
        } else {
            native
                .residuals
                .is_some_and(|r| r.cone_violation_relative <= 1e-10)
        };
        cones
            && native.residuals.is_some_and(|r| {
                r.equilibrium_relative <= 1e-10
                    && r.penetration_relative <= 1e-8
                    && r.compatibility_relative <= 1e-8
                    && r.stick_motion_relative <= 1e-8
                    && r.complementarity_relative <= 1e-8
            })
    };
    if class(&native) != class(&clarabel) {
        if clarabel.status == SolveStatus::NoConvergence && confirmed(&native) {
            return Ok((native, Agreement::FixedPointConfirmed, f64::NAN));
        }
        // For coulomb, Clarabel has a second chance: the Tresca program at the native radii,
        // solved to its full tolerance (an "almost solved" answer does not count).
        let reference_failed = clarabel.status == SolveStatus::NoConvergence
            && !(coulomb
                && clarabel_at_native_radii(&model, &native)
                    .is_some_and(|(_, c)| c.status == SolveStatus::Solved));
        if native.status.has_forces() && reference_failed && residuals_hold(&native) {
            return Ok((native, Agreement::ReferenceFailedResidualsHold, f64::NAN));
        }
        return Err(format!(
            "status: native {:?} ({:?}), Clarabel {:?} ({:?})",
            native.status, native.reason, clarabel.status, clarabel.reason
        ));
    }
    if !native.status.has_forces() {
        return Ok((native, Agreement::Within, 0.0));
    }
    let d = element_force_difference_n(&native, &clarabel) / native.load_scale_n;
    if d <= SOLVER_AGREEMENT {
        return Ok((native, Agreement::Within, d));
    }
    let r = native.residuals.expect("residuals with forces");
    let feasible = r.equilibrium_relative <= 1e-10 && r.cone_violation_relative <= 1e-10;
    let (jn, jc) = (
        complementary_energy_j(&model, &native),
        complementary_energy_j(&model, &clarabel),
    );
    if !coulomb && feasible && jn <= jc + ENERGY_ROUNDOFF * jc.abs() {
        return Ok((native, Agreement::NativeIsTheMinimiser, d));
    }
    if confirmed(&native) {
        return Ok((native, Agreement::FixedPointConfirmed, d));
    }
    let worst = |s: &Solution| s.residuals.map_or(f64::NAN, |r| r.worst());
    Err(format!(
        "element forces differ by {d:.2e} of the load scale (energy: native {jn:.15e} J, \
         Clarabel {jc:.15e} J; worst residual: native {:.1e}, Clarabel {:.1e}; Clarabel {:?})",
        worst(&native),
        worst(&clarabel),
        clarabel.status
    ))
}

/// Deterministic pseudo-random numbers in [0, 1) (64-bit LCG, top 53 bits), for seeded
/// random scenes.
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    /// Log-uniform in [lo, hi].
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.next()).exp()
    }
    /// Uniform integer in [lo, hi].
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + ((hi - lo + 1) as f64 * self.next()) as usize
    }
    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.next() < p
    }
}

/// The `rerun` CLI of the checker install (`GRASP_RERUN_CLI`, set by scripts/test.sh), or
/// `None` when the external checks are skipped knowingly (`GRASP_SKIP_EXTERNAL_CHECKS=1`, not
/// allowed together with `GRASP_REQUIRE_CHECKERS=1`); a failing test otherwise.
pub fn rerun_cli() -> Option<std::path::PathBuf> {
    if let Ok(p) = std::env::var("GRASP_RERUN_CLI") {
        return Some(std::path::PathBuf::from(p));
    }
    let require = std::env::var("GRASP_REQUIRE_CHECKERS").as_deref() == Ok("1");
    if !require && std::env::var("GRASP_SKIP_EXTERNAL_CHECKS").as_deref() == Ok("1") {
        eprintln!("GRASP_SKIP_EXTERNAL_CHECKS=1: external rerun checks skipped");
        return None;
    }
    panic!(
        "GRASP_RERUN_CLI is not set: run the tests with scripts/test.sh (it installs rerun-sdk==0.36.3), \
         or set GRASP_SKIP_EXTERNAL_CHECKS=1 (without GRASP_REQUIRE_CHECKERS=1) to skip the \
         external checks knowingly"
    );
}

/// Makes a FIFO (named pipe) at `path` with `mkfifo`, replacing what is there: a test case, never
/// skipped (a failure here fails the test).
pub fn fifo(path: &std::path::Path) {
    let _ = std::fs::remove_file(path);
    let made = std::process::Command::new("mkfifo").arg(path).status();
    assert!(
        made.as_ref().is_ok_and(|s| s.success()),
        "mkfifo {}: {made:?}",
        path.display()
    );
}

/// Runs the `rerun` CLI `cli` with `args` on `file` (with `CI=1`), insisting that it succeeds;
/// its standard output and error, in that order.
pub fn rerun_on(cli: &std::path::Path, args: &[&str], file: &std::path::Path) -> String {
    let out = std::process::Command::new(cli)
        .args(args)
        .arg(file)
        .env("CI", "1")
        .output()
        .expect("run the rerun CLI");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "rerun {args:?} {}: {text}",
        file.display()
    );
    text
}

/// The largest `|a_k - b_k|` of two equally long lists of points (`[f64; N]` each).
pub fn largest_difference<const N: usize>(a: &[[f64; N]], b: &[[f64; N]]) -> f64 {
    assert_eq!(a.len(), b.len(), "the two lists differ in length");
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
