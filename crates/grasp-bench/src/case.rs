//! The benchmark cases: which bundled scene, which patch grid, what is timed, and the
//! performance target where there is one. Scenes are compiled in from `examples/`, so `grasp bench`
//! runs anywhere.

use std::path::Path;

use grasp_model::ComplianceChoice;
use grasp_model::{GraspModel, LoadedScene, SolveOptions, SolverChoice};
use grasp_transfer::{Schedule, TransferOptions};

use crate::error::BenchError;

/// What one sample of a case times.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseKind {
    /// One solve of a model built beforehand: program assembly, factorisations and
    /// iterations (a fresh solver each time, no warm start).
    Solve,
    /// Model build (influence coefficients, compliance blocks) and one solve, timed together.
    OneShot,
    /// A whole hand-off, reported per step; `warm` starts each step from the previous one.
    HandOff {
        /// Warm start (the default of `grasp transfer`) or cold (`--cold`).
        warm: bool,
    },
    /// A whole warm hand-off with every step's smallest disturbance margin (`grasp transfer
    /// --margins`): the margins' time per step (the stepping's own is not counted).
    Margins,
    /// The planner on the hand-off (`grasp plan`, its template the case's schedule, the
    /// question [`PLAN_QUESTION`]): the whole planning, checked schedule included; its
    /// iterations column counts hand-off runs.
    Plan,
    /// The tactile sensors' read-out of a solution solved beforehand (`sensor_readings`):
    /// every finger's gel image laid on its patch's element lattice (one pixel an element,
    /// the FFT read-out), per read-out.
    Readout,
}

impl CaseKind {
    /// What a sample of this kind times, in the table's words (its `timed` column).
    pub fn timed(&self) -> &'static str {
        match self {
            Solve => "per solve",
            OneShot => "build + solve",
            HandOff { .. } => "per step",
            Margins => "margins per step",
            Plan => "whole plan (runs)",
            Readout => "per read-out",
        }
    }
}

/// The planning case's question: releasing and receiving fingers and the rate limit (N/s),
/// the plate hand-off's (its template's steepest rate).
pub const PLAN_QUESTION: (&[&str], &[&str], f64) = (&["f1", "f2"], &["f3", "f4"], 1.5);

/// A performance target: the case's time must not exceed `limit_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// Largest acceptable median, s (per solve, per one-shot or per step, as the case times).
    pub limit_s: f64,
}

/// One benchmark case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// Short name (table row, `--case` filter, divan argument).
    pub name: &'static str,
    /// What is timed.
    pub kind: CaseKind,
    /// Bundled example scene (file stem in `examples/`).
    pub scene: &'static str,
    /// Patch grid given to every finger, or `None` for the scene's own.
    pub grid: Option<[usize; 2]>,
    /// Target median, where one is set.
    pub target: Option<Target>,
    /// Part of `--quick` (the CI smoke run): the cases that take well under a second.
    pub quick: bool,
    /// A taxel sensor of `[nx, ny]` taxels given to every finger (square taxels tiling the
    /// patch's shorter side, one pitch deep), or
    /// `None` for the scene's own sensors.
    pub taxels: Option<[usize; 2]>,
}

const fn case(
    name: &'static str,
    kind: CaseKind,
    scene: &'static str,
    grid: Option<[usize; 2]>,
    target_s: Option<f64>,
    quick: bool,
) -> Case {
    let target = match target_s {
        Some(limit_s) => Some(Target { limit_s }),
        None => None,
    };
    Case {
        name,
        kind,
        scene,
        grid,
        target,
        quick,
        taxels: None,
    }
}

impl Case {
    /// This case with a sensor of `count` taxels in every finger's pad: square taxels tiling
    /// the patch's shorter side (pitch = side = that side over the count), one pitch deep.
    const fn with_taxels(mut self, count: [usize; 2]) -> Case {
        self.taxels = Some(count);
        self
    }
}

use CaseKind::{HandOff, Margins, OneShot, Plan, Readout, Solve};

/// Every case, in table order. The cube A series (5x5 to 16x16 per finger) also gives the
/// growth exponent of solve time against unknowns.
pub const CASES: [Case; 14] = [
    case("cube_a_5x5", Solve, "cube_a", None, Some(1e-3), true),
    case("cube_a_8x8", Solve, "cube_a", Some([8, 8]), None, true),
    case("cube_a_12x12", Solve, "cube_a", Some([12, 12]), None, false),
    case(
        "cube_a_16x16",
        OneShot,
        "cube_a",
        Some([16, 16]),
        Some(0.1),
        false,
    ),
    case(
        "hertz_41x41",
        Solve,
        "hertz_sphere_on_flat",
        Some([41, 41]),
        Some(0.3),
        false,
    ),
    case(
        "plate_handoff_warm",
        HandOff { warm: true },
        "plate_transfer",
        None,
        Some(0.5e-3),
        true,
    ),
    case(
        "plate_handoff_cold",
        HandOff { warm: false },
        "plate_transfer",
        None,
        None,
        true,
    ),
    case(
        "coulomb_handoff_warm",
        HandOff { warm: true },
        "plate_handoff_coulomb",
        None,
        Some(2e-3),
        true,
    ),
    case(
        "coulomb_handoff_cold",
        HandOff { warm: false },
        "plate_handoff_coulomb",
        None,
        None,
        true,
    ),
    // The plate handed off by opening servo jaws (position ramps on mounted fingers): its
    // target is a ratio, at most 1.5x the force-ramped coulomb hand-off's iterations per step
    // (a derived row, `SERVO_PAIRS`).
    case(
        "servo_handoff_warm",
        HandOff { warm: true },
        "plate_transfer_servo",
        None,
        None,
        true,
    ),
    // The same between a servo gripper (both jaws on one servo) and a compliant arm (`hands`):
    // the same ratio target.
    case(
        "gripper_handoff_warm",
        HandOff { warm: true },
        "plate_transfer_gripper",
        None,
        None,
        true,
    ),
    // Its target is a ratio, the margins' time at most 20x the stepping's: `grasp bench`
    // prints it as a derived row ([`MARGIN_PAIRS`]).
    case(
        "coulomb_handoff_margins",
        Margins,
        "plate_handoff_coulomb",
        None,
        None,
        false,
    ),
    // The planning bound: at most 5 s (and 30 runs) for the plate hand-off.
    case(
        "coulomb_handoff_plan",
        Plan,
        "plate_handoff_coulomb",
        None,
        Some(5.0),
        true,
    ),
    case(
        "hertz_21x21",
        Solve,
        "hertz_sphere_on_flat",
        None,
        None,
        true,
    ),
];

/// The fine-patch cases, on the FFT compliance (the automatic choice above 1,024
/// unknowns a patch), native solver only (Clarabel needs the matrices these grids do not
/// store). One-shot cases time the model build and one solve together; the hand-offs time
/// every step (the Cattaneo case's two steps: the normal load, then the tangential force).
/// Targets: the fine-patch work's (Cattaneo's 5 s for both steps is 2.5 s a step; 256 x 256
/// within 0.15 s and 1024 x 1024 within 4 s on this project's 2-core machine).
pub const FFT_CASES: [Case; 7] = [
    case(
        "hertz_128x128_fft",
        OneShot,
        "hertz_sphere_on_flat",
        Some([128, 128]),
        Some(0.2),
        false,
    ),
    case(
        "hertz_256x256_fft",
        OneShot,
        "hertz_sphere_on_flat",
        Some([256, 256]),
        Some(0.15),
        false,
    ),
    case(
        "hertz_512x512_fft",
        OneShot,
        "hertz_sphere_on_flat",
        Some([512, 512]),
        Some(5.0),
        false,
    ),
    case(
        "hertz_1024x1024_fft",
        OneShot,
        "hertz_sphere_on_flat",
        Some([1024, 1024]),
        Some(4.0),
        false,
    ),
    case(
        "cattaneo_256x256_fft",
        HandOff { warm: true },
        "cattaneo_sphere_on_flat",
        Some([256, 256]),
        Some(2.5),
        false,
    ),
    case(
        "cube_a_64x64_fft",
        OneShot,
        "cube_a",
        Some([64, 64]),
        Some(2.0),
        false,
    ),
    case(
        "plate_handoff_64x64_warm",
        HandOff { warm: true },
        "plate_transfer",
        Some([64, 64]),
        Some(0.02),
        false,
    ),
];

/// The layered-pad cases: the padded pinch (`pad_pinch`, 1 mm pads) and its twin
/// with half-space pads of the same silicone (`pad_pinch_halfspace`), model build and one solve
/// timed together, on the FFT path (64 x 64 a finger) and the dense one (18 x 18, 972 unknowns
/// a finger), automatic compliance. The target is a ratio, a layered patch at most 1.5x
/// the half-space one on the same path: `grasp bench` prints it as a derived row
/// ([`LAYER_PAIRS`]).
pub const LAYER_CASES: [Case; 11] = [
    case(
        "pad_pinch_64x64_fft",
        OneShot,
        "pad_pinch",
        Some([64, 64]),
        None,
        false,
    ),
    case(
        "pad_pinch_halfspace_64x64_fft",
        OneShot,
        "pad_pinch_halfspace",
        Some([64, 64]),
        None,
        false,
    ),
    case(
        "pad_pinch_18x18_dense",
        OneShot,
        "pad_pinch",
        Some([18, 18]),
        None,
        true,
    ),
    case(
        "pad_pinch_halfspace_18x18_dense",
        OneShot,
        "pad_pinch_halfspace",
        Some([18, 18]),
        None,
        true,
    ),
    // The padded cylinder hand-off with relaxing pads and with elastic ones (the same
    // grids: A's patches on the FFT path, B's dense), the same 41-step schedule, per step.
    case(
        "viscous_handoff_warm",
        HandOff { warm: true },
        "cylinder_handoff_viscoelastic",
        None,
        None,
        false,
    ),
    case(
        "elastic_handoff_warm",
        HandOff { warm: true },
        "cylinder_handoff_pads_halfspace",
        None,
        None,
        false,
    ),
    // Textured surfaces: the half-space pad pinch with ridged pads (20 um ridges of 0.5 mm
    // period) against the smooth pads, 256 x 256 a finger on the FFT path, model build and one
    // solve; the target is a ratio, a textured pad at most 1.5x the smooth one.
    case(
        "ridged_pad_256x256_fft",
        OneShot,
        "ridged_pad_pinch",
        Some([256, 256]),
        None,
        false,
    ),
    case(
        "smooth_pad_256x256_fft",
        OneShot,
        "pad_pinch_halfspace",
        Some([256, 256]),
        None,
        false,
    ),
    // Tactile sensors at every step: the half-space padded cylinder hand-off on four 64 x 64
    // patches (FFT path), per step, with a 16 x 16 taxel grid one pitch deep in every pad and
    // without; the target is a ratio, the read step at most 1.3x the plain one.
    case(
        "taxel_handoff_64x64_fft",
        HandOff { warm: true },
        "cylinder_handoff_pads_halfspace",
        Some([64, 64]),
        None,
        false,
    )
    .with_taxels([16, 16]),
    case(
        "plain_handoff_64x64_fft",
        HandOff { warm: true },
        "cylinder_handoff_pads_halfspace",
        Some([64, 64]),
        None,
        false,
    ),
    // A gel image of 256 x 256 pixels from a 256 x 256 patch (the ridged sphere on the gel,
    // one pixel an element): the height map, its normals and its shading, within 50 ms.
    case(
        "gel_image_256x256_fft",
        Readout,
        "ridged_gel",
        Some([256, 256]),
        Some(0.05),
        false,
    ),
];

/// Rough and ridged contact on fine patches (`examples/rough_sphere_on_flat.json`: a 10 mm
/// silicone pad, E 2 MPa, under 0.5 N, a random surface of rms 20 um; the same pad ridged,
/// `examples/ridged_sphere_on_flat.json`; the rough pad with friction, mu 0.5, and a
/// tangential 0.1 N under the coulomb model, and its smooth twin,
/// `examples/smooth_sphere_on_flat_friction.json`), model build and one solve; and the smooth
/// Hertz sphere at 2048 x 2048, the largest patch. Targets (the rough-contact work's, on the
/// 2-core machine): rough 1024 x 1024 within 5 s, smooth 2048 x 2048 within 15 s; the peer
/// beside the 256 x 256 rough and ridged cases (at least 10x its time for the rough one), the
/// frictional rough case at most 2x the frictionless one and at most 1.5x its smooth twin
/// (the bound of the ridged pad pinch against its smooth pads) ([`LAYER_PAIRS`]).
pub const ROUGH_CASES: [Case; 6] = [
    case(
        "rough_256x256_fft",
        OneShot,
        "rough_sphere_on_flat",
        Some([256, 256]),
        None,
        false,
    ),
    case(
        "ridged_256x256_fft",
        OneShot,
        "ridged_sphere_on_flat",
        Some([256, 256]),
        None,
        false,
    ),
    case(
        "rough_friction_256x256_fft",
        OneShot,
        "rough_sphere_on_flat_friction",
        Some([256, 256]),
        None,
        false,
    ),
    case(
        "smooth_friction_256x256_fft",
        OneShot,
        "smooth_sphere_on_flat_friction",
        Some([256, 256]),
        None,
        false,
    ),
    case(
        "rough_1024x1024_fft",
        OneShot,
        "rough_sphere_on_flat",
        Some([1024, 1024]),
        Some(5.0),
        false,
    ),
    case(
        "hertz_2048x2048_fft",
        OneShot,
        "hertz_sphere_on_flat",
        Some([2048, 2048]),
        Some(15.0),
        false,
    ),
];

/// The (layered, viscoelastic or textured; plain) case pairs whose time ratio is bounded, with
/// the bound.
pub const LAYER_PAIRS: [(&str, &str, f64); 7] = [
    ("pad_pinch_64x64_fft", "pad_pinch_halfspace_64x64_fft", 1.5),
    (
        "pad_pinch_18x18_dense",
        "pad_pinch_halfspace_18x18_dense",
        1.5,
    ),
    ("viscous_handoff_warm", "elastic_handoff_warm", 1.5),
    ("ridged_pad_256x256_fft", "smooth_pad_256x256_fft", 1.5),
    ("taxel_handoff_64x64_fft", "plain_handoff_64x64_fft", 1.3),
    ("rough_friction_256x256_fft", "rough_256x256_fft", 2.0),
    (
        "rough_friction_256x256_fft",
        "smooth_friction_256x256_fft",
        1.5,
    ),
];

/// Margins of a held grasp, which no load capacity bounds (the viscoelastic plate hold: two
/// fingers pressed in and held for 60 s while their pads relax): each trial past the edge is
/// a program with no solution, proved by Clarabel or by the certificate kept from the last
/// one. No target. Native solver only: with Clarabel answering every trial the margins take
/// 217 ms a step, 81 s for the case (27 November 2026), half the rest of the bench again.
pub const HELD_CASES: [Case; 1] = [case(
    "held_hold_margins",
    Margins,
    "plate_hold_viscoelastic",
    None,
    None,
    false,
)];

/// The (margins; stepping) case pairs whose time ratio is bounded, with the bound: the
/// disturbance margins of every step of a hand-off at most 20 times the stepping's time.
pub const MARGIN_PAIRS: [(&str, &str, f64); 1] =
    [("coulomb_handoff_margins", "coulomb_handoff_warm", 20.0)];

/// The cases the peer library solves too, in the same run (`grasp bench`; the fine-patch work compares
/// the time ratio at these two grids; the peer's time grows past a minute above them).
pub const PEER_CASES: [&str; 4] = [
    "hertz_128x128_fft",
    "hertz_256x256_fft",
    "rough_256x256_fft",
    "ridged_256x256_fft",
];

/// Every case in table order: [`CASES`], [`FFT_CASES`], [`ROUGH_CASES`], [`LAYER_CASES`],
/// [`HELD_CASES`].
pub fn all_cases() -> impl Iterator<Item = &'static Case> {
    CASES
        .iter()
        .chain(&FFT_CASES)
        .chain(&ROUGH_CASES)
        .chain(&LAYER_CASES)
        .chain(&HELD_CASES)
}

/// Every finger's gel image laid on its patch's element lattice: as many pixels as elements,
/// the patch's size as the field of view.
fn on_lattice(scene: &mut LoadedScene) {
    for f in &mut scene.fingers {
        let patch = f.patch.clone();
        if let Some(g) = f.sensor.as_mut().and_then(|s| s.gel.as_mut()) {
            g.image_px = patch.grid;
            g.field_of_view_m = patch.size;
        }
    }
}

/// The bundled scene and schedule texts (compiled in) of an example stem, e.g.
/// `plate_transfer`.
pub fn bundled(stem: &str) -> Option<(&'static str, Option<&'static str>)> {
    macro_rules! example {
        ($f:literal) => {
            include_str!(concat!("../../../examples/", $f))
        };
    }
    Some(match stem {
        "cube_a" => (example!("cube_a.json"), None),
        "hertz_sphere_on_flat" => (example!("hertz_sphere_on_flat.json"), None),
        "cattaneo_sphere_on_flat" => (
            example!("cattaneo_sphere_on_flat.json"),
            Some(example!("cattaneo_sphere_on_flat.schedule.json")),
        ),
        "plate_transfer" => (
            example!("plate_transfer.json"),
            Some(example!("plate_transfer.schedule.json")),
        ),
        "plate_handoff_coulomb" => (
            example!("plate_handoff_coulomb.json"),
            Some(example!("plate_handoff_coulomb.schedule.json")),
        ),
        "plate_transfer_gripper" => (
            example!("plate_transfer_gripper.json"),
            Some(example!("plate_transfer_gripper.schedule.json")),
        ),
        "plate_transfer_servo" => (
            example!("plate_transfer_servo.json"),
            Some(example!("plate_transfer_servo.schedule.json")),
        ),
        "plate_hold_viscoelastic" => (
            example!("plate_hold_viscoelastic.json"),
            Some(example!("plate_hold_viscoelastic.schedule.json")),
        ),
        "pad_pinch" => (example!("pad_pinch.json"), None),
        "cylinder_handoff_viscoelastic" => (
            example!("cylinder_handoff_viscoelastic.json"),
            Some(example!("cylinder_handoff_viscoelastic_fast.schedule.json")),
        ),
        "cylinder_handoff_pads_halfspace" => (
            example!("cylinder_handoff_pads_halfspace.json"),
            Some(example!("cylinder_handoff.schedule.json")),
        ),
        "pad_pinch_halfspace" => (example!("pad_pinch_halfspace.json"), None),
        "ridged_pad_pinch" => (example!("ridged_pad_pinch.json"), None),
        "ridged_gel" => (example!("ridged_gel.json"), None),
        "rough_sphere_on_flat" => (example!("rough_sphere_on_flat.json"), None),
        "rough_sphere_on_flat_friction" => (example!("rough_sphere_on_flat_friction.json"), None),
        "smooth_sphere_on_flat_friction" => (example!("smooth_sphere_on_flat_friction.json"), None),
        "ridged_sphere_on_flat" => (example!("ridged_sphere_on_flat.json"), None),
        _ => return None,
    })
}

/// A case made ready to run: inputs parsed, and for [`CaseKind::Solve`] the model built.
pub struct Prepared {
    /// The case.
    pub case: Case,
    /// Solver asked for.
    pub solver: SolverChoice,
    /// The scene as read (grid applied).
    pub scene: LoadedScene,
    /// The model, built once for [`CaseKind::Solve`] and [`CaseKind::Readout`].
    pub model: Option<std::sync::Arc<GraspModel>>,
    /// The solution a [`CaseKind::Readout`] reads, solved once.
    pub solution: Option<grasp_model::Solution>,
    /// Time the model build took when it was built here, s.
    pub build_s: f64,
    /// The schedule of a hand-off.
    pub schedule: Option<Schedule>,
}

impl Case {
    /// The patch compliance of the case's solves: `auto` for the fine-patch cases
    /// ([`FFT_CASES`]) and the layered-pad ones ([`LAYER_CASES`]), the dense matrices for issue
    /// 9's ([`CASES`]), as they were measured before the FFT path existed (`auto` would take it
    /// for `hertz_41x41`).
    pub fn compliance(&self) -> ComplianceChoice {
        let mut auto = FFT_CASES.iter().chain(&ROUGH_CASES).chain(&LAYER_CASES);
        match auto.any(|c| c.name == self.name) {
            true => ComplianceChoice::Auto,
            false => ComplianceChoice::Dense,
        }
    }

    /// Whether only the native solver runs the case: the FFT cases (Clarabel needs the
    /// matrices their grids do not store) and the held grasp's margins ([`HELD_CASES`]).
    pub fn native_only(&self) -> bool {
        let fft = FFT_CASES
            .iter()
            .chain(&ROUGH_CASES)
            .any(|c| c.name == self.name)
            || self.name.ends_with("_fft");
        fft || HELD_CASES.iter().any(|c| c.name == self.name)
    }

    /// Parses the inputs (and builds the model of a [`CaseKind::Solve`] case) for `solver`.
    pub fn prepare(&self, solver: SolverChoice) -> Result<Prepared, BenchError> {
        let err = |message: String| BenchError::Input {
            case: self.name.to_string(),
            message,
        };
        let (scene_text, schedule_text) =
            bundled(self.scene).ok_or_else(|| err(format!("no bundled scene {}", self.scene)))?;
        let mut scene = LoadedScene::from_json_str(scene_text).map_err(|e| err(e.to_string()))?;
        if let Some(grid) = self.grid {
            for f in &mut scene.fingers {
                f.patch.grid = grid;
            }
        }
        if let Some(count) = self.taxels {
            for f in &mut scene.fingers {
                let side = f.patch.size[0].min(f.patch.size[1]);
                let pitch_m = side / count[0].max(count[1]) as f64;
                let taxels = grasp_model::TaxelGridSpec {
                    count,
                    pitch_m,
                    size_m: pitch_m,
                    depth_m: pitch_m,
                    rotation_rad: 0.0,
                    offset_m: [0.0; 2],
                    response: None,
                };
                f.sensor = Some(grasp_model::SensorSpec {
                    taxels: Some(taxels),
                    markers: None,
                    gel: None,
                });
            }
        }
        let schedule = match (self.kind, schedule_text) {
            (HandOff { .. } | Margins | Plan, Some(text)) => {
                let names = scene.finger_names();
                let s = Schedule::from_json_str(text, &names, Path::new("."))
                    .map_err(|e| err(e.to_string()))?;
                Some(s)
            }
            (HandOff { .. } | Margins | Plan, None) => {
                return Err(err("a hand-off needs a schedule".into()))
            }
            _ => None,
        };
        if self.kind == Readout {
            on_lattice(&mut scene);
        }
        let (model, build_s) = match self.kind {
            Solve | Readout => {
                let t = std::time::Instant::now();
                let m = GraspModel::from_loaded_with(&scene, self.compliance())
                    .map_err(|e| err(e.to_string()))?;
                (Some(std::sync::Arc::new(m)), t.elapsed().as_secs_f64())
            }
            _ => (None, 0.0),
        };
        let mut prepared = Prepared {
            case: *self,
            solver,
            scene,
            model,
            build_s,
            schedule,
            solution: None,
        };
        if let (Readout, Some(m)) = (self.kind, &prepared.model) {
            let options = prepared.solve_options();
            let inputs = grasp_model::StepInputs::of_scene(m);
            let solved = grasp_model::GraspSolver::new(std::sync::Arc::clone(m), options)
                .solve(&inputs)
                .map_err(|e| err(e.to_string()))?;
            prepared.solution = Some(solved);
        }
        Ok(prepared)
    }
}

impl Prepared {
    /// The options of every solve of this case: defaults, with the solver asked for and the
    /// case's compliance ([`Case::compliance`]).
    pub fn solve_options(&self) -> SolveOptions {
        SolveOptions {
            solver: self.solver,
            compliance: self.case.compliance(),
            ..SolveOptions::default()
        }
    }

    /// The options of a hand-off case.
    pub fn transfer_options(&self, warm: bool) -> TransferOptions {
        TransferOptions {
            warm_start: warm,
            solve: self.solve_options(),
            margins: self.case.kind == Margins,
            ..TransferOptions::default()
        }
    }
}
