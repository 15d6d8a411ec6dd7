//! # grasp-model: the elastic contact model of a grasp
//!
//! An object held by fingers; each contact is a patch of rectangular elements carrying a
//! normal force `F_k >= 0` and a friction force `G_k`; fingers and object are linear-elastic
//! half-spaces coupled by exact Boussinesq-Cerruti influence coefficients. The forces are the
//! minimiser of the total complementary energy
//!
//! ```text
//!   1/2 x'Cx + c'F          (C: patch compliance, c: initial gaps)
//! ```
//!
//! subject to force and moment equilibrium of the object, prescribed loads of force-controlled
//! fingers and a Coulomb cone `||G_k|| <= mu F_k` per element: a second-order cone program
//! (Sinha 1989, as corrected in the repository's `docs/model.md`), solved by a native
//! semismooth Newton method that factorises each finger's block and warm-starts from the
//! previous solution, with Clarabel as the reference and fallback (`--solver clarabel`).
//!
//! ## Layout: one folder per layer, imports only downwards (private; the face is below)
//!
//! | folder | what it holds | may import |
//! |---|---|---|
//! | `geometry/` | contact frames, surface points, exact primitives, triangle meshes, posed shapes, tessellation, texture heights | - |
//! | `scene/` | the file format, strict JSON, validation (a path and a fix per problem), shape checks, finger placement, the memory budget | geometry |
//! | `model/` | the immutable [`GraspModel`]: materials, patches, influence coefficients, friction laws, equilibrium map, closed forms | scene, geometry |
//! | `program/` | the solver-neutral [`ConeProgram`] (assembly kept apart from solving) and its element sets (`cones/`: one trait, one file per set) | model |
//! | `solver/` | options, outcomes and certificates, Clarabel, the native semismooth Newton solver, the warm start's prediction | program, model |
//! | `solve/` | [`GraspSolver`] and its strategies (one convex solve, the sequential fixed point), readout, residuals, [`Solution`], contact state, sensitivities | solver, program, model, scene |
//! | `sensors/` | read-outs of a solution: tactile sensors (taxels at depth in the pad, markers on its surface, a gel's image) | solve, model, scene |
//! | `analysis/` | many solves: disturbance margins, refinement studies, patch sizing | all of the above |
//!
//! `error.rs` (one [`InputProblem`] type for every input), `problem_list.rs` (the one
//! collector of an input's problems, [`ProblemList`]), `allocation.rs` (the large buffers
//! allocated fallibly: [`OutOfMemory`] instead of an abort) and [`option_names`] (how messages name
//! options) sit below them all. The folders are private: this page is the crate's whole
//! face, its names grouped below in data-flow order, so a file can move without breaking a caller.
//!
//! ## The workflow
//!
//! [`Scene`] (the file format, validated: plain data) and beside it what reading it found, its
//! [`SceneGeometry`] (the shape's report, the posed object and tip shapes, the object's
//! triangles, the height maps), together a [`LoadedScene`] -> [`GraspModel`] (built once,
//! immutable: frames, patches and gaps, compliance, equilibrium map, scales; the geometry it
//! needs) -> [`GraspSolver`] (keeps the model,
//! assembles the [`ConeProgram`] once; strategy: one convex solve or the sequential fixed
//! point; backend: native or Clarabel) -> [`Solution`] (SI, with [`Residuals`] computed from
//! the solution itself). What changes from one solve to the next travels beside the model:
//! [`StepInputs`] (commanded loads, an extra wrench on the object, commanded approaches, a time
//! history's step) and
//! the [`ContactState`] the solves leave behind (slip memory, warm start, viscoelastic
//! history), as MuJoCo keeps `mjModel` apart from `mjData`.
//!
//! A scene that names files (a mesh shape, a texture's height map) is read with them by the
//! caller (`grasp_io`: this crate does no I/O) through [`SceneFiles`]
//! ([`LoadedScene::from_json_str_with_files`]) and built with [`GraspModel::from_loaded`]; a
//! scene that names none may stay plain, as here ([`GraspModel::from_scene`] loads it:
//! [`LoadedScene::of_plain`]).
//!
//! ```
//! use grasp_model::{ContactState, GraspModel, GraspSolver, Scene, SolveOptions, StepInputs};
//!
//! // A frictionless steel fingertip (R = 10 mm) under a 10 N steel plate: Hertz contact.
//! let text = include_str!("../../../examples/hertz_sphere_on_flat.json");
//! let scene = Scene::from_json_str(text)?;
//! let model = GraspModel::from_scene(&scene)?;
//! let mut solver = GraspSolver::new(model, SolveOptions::default());
//! let solution = solver.solve(&StepInputs::of_scene(solver.model()))?;
//! let tip = solution.finger("tip").expect("the scene's finger");
//! // The fingertip carries the weight; Hertz's peak pressure p0 = 3P/(2 pi a^2) = 0.636 GPa
//! // (Johnson eq. 4.23) is met to the grid's resolution.
//! assert!((tip.normal_force_n - 10.0).abs() < 1e-6);
//! assert!((tip.peak_pressure_pa / 0.636e9 - 1.0).abs() < 0.01);
//!
//! // A loading path: the same model, a push of 1 N along x at the centre of mass added step
//! // by step, each step starting from the state the last one left.
//! let mut state = ContactState::new(solver.model());
//! for push_n in [0.0, 0.5, 1.0] {
//!     let force = nalgebra::Vector3::new(push_n, 0.0, 0.0);
//!     let inputs = StepInputs::of_scene(solver.model()).with_load_at_center_of_mass(
//!         solver.model(),
//!         &force,
//!         &nalgebra::Vector3::zeros(),
//!     );
//!     let step = solver.solve_step(&inputs, &mut state)?;
//!     // Frictionless: nothing resists a sideways push, and the solve says so.
//!     assert_eq!(step.status.has_forces(), push_n == 0.0);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A scene pays only for what it needs: a planar scene has 3 equilibrium rows and one
//! tangential unknown per element; a frictionless finger has no tangential unknowns; equal
//! materials assemble no normal/tangential coupling entries.
//!
//! This crate does no I/O.

#![warn(missing_docs)]

mod allocation;
mod analysis;
mod error;
mod geometry;
mod model;
mod number_text;
pub mod option_names;
mod problem_list;
mod program;
mod scene;
mod sensors;
mod solve;
mod solver;
mod warning_tally;

// ---- The scene: what a user writes (serde types, JSON Schema, validation) ----
pub use scene::finger_placement::STANDARD_GRAVITY;
pub use scene::gel_spec::{
    default_lights, GelSpec, Lattice, LightSpec, LookupSpec, MAX_GEL_KERNEL_EVALUATIONS,
    MAX_LATTICE_POINTS, MAX_LIGHTS, MAX_PIXELS_PER_SIDE,
};
pub use scene::loaded_scene::LoadedScene;
pub use scene::memory_budget::{
    estimate_memory_bytes, estimate_memory_bytes_with, finger_unknowns, SolveSize,
};
pub use scene::mount_checks::MOUNT_SYMMETRY_TOLERANCE;
pub use scene::mount_spec::{MountSpec, MountStiffness};
pub use scene::response_spec::ResponseSpec;
pub use scene::scene_format::{
    scene_json_schema, ApproachSpec, CoefficientSpec, ControlSpec, ElasticLawParams,
    ElasticLawSpec, ElasticSpec, ExternalForceSpec, FingerSpec, FrictionSpec, HeldTag,
    MaterialSpec, ModelKind, NormalLoadSpec, ObjectSpec, PatchSpec, PlanarSpec, PronyTermSpec,
    RadiusSpec, RelaxationSpec, RigidTag, Scene, StandardLinearSolidSpec, TableSpec, Vec3,
};
pub use scene::scene_geometry::{SceneGeometry, SharedShape};
pub use scene::scene_reading::{FileProblem, SceneFiles};
pub use scene::sensor_checks::{MAX_MARKERS_PER_SIDE, MAX_TAXELS_PER_SIDE};
pub use scene::sensor_kind::{ElementGrid, GridLayout, HalfSpaceNeed, SensorKind};
pub use scene::sensor_spec::{
    MarkerGridSpec, SensorSpec, TaxelGridSpec, TaxelLattice, GAUSS_POINTS_PER_CELL_SIDE,
    MAX_MARKER_KERNEL_EVALUATIONS, MAX_TAXEL_CELLS_PER_SIDE, MAX_TAXEL_KERNEL_EVALUATIONS,
    MAX_TAXEL_LATTICE_POINTS,
};
pub use scene::shape_checks::{too_many_triangles, MESH_TOO_FINE_FIX};
pub use scene::shape_report::{DerivedFrame, ShapeReport};
pub use scene::shape_spec::{
    BoxSpec, CylinderSpec, LengthUnit, MeshSpec, PlaceSpec, RaySpec, ShapeSpec, SphereSpec,
    TipCylinderSpec, TipFlatSpec, TipSpec, TipSphereSpec, DEFAULT_SURFACE_TOLERANCE_M,
};
pub use scene::shared_spring_spec::{HandSpec, ServoSpec};
pub use scene::texture_spec::{
    HeightGrid, HeightMapSpec, RandomSurfaceSpec, RidgesSpec, TextureSpec,
};

/// The ranges a scene's numbers may take (physical ranges, patch sizes, the planarity
/// tolerance): what validation checks, for front ends that check their own inputs alike.
pub mod limits {
    pub use crate::scene::limits::*;
}

/// Strict JSON, shared by every input format of the project (scenes, schedules, batch lines):
/// one document, no duplicate keys, nested enum errors with their inner path, syntax errors by
/// line and column.
pub mod strict_json {
    pub use crate::scene::strict_json::{
        describe, from_str_strict, unique_keys, variant, JsonError, StrictValue,
    };
}

// ---- Geometry ----
pub use geometry::contact_frame::ContactFrame;
pub use geometry::mesh_surface::TriangleMesh;
pub use geometry::random_surface::{random_surface, RandomSurface};
pub use geometry::tessellation::{box_mesh, icosphere};
pub use scene::texture_spec::texture_heights_m;

// ---- The model: built once from a scene, immutable ----
pub use model::equilibrium::{MotionPlane, Wrench};
pub use model::finger_mount::FingerMount;
pub use model::grasp_model::{Control, FingerModel, GraspModel, Scales};
pub use model::influence::GridSpec;
pub use model::layer_green_function::forget_radial_functions;
pub use model::material::Material;
pub use model::model_builder::{object_curvatures_per_m, tip_curvatures_per_m};
pub use model::patch::Patch;
pub use model::patch_compliance::{takes_fft, ComplianceChoice, CompliancePath};
pub use model::shared_spring::{SharedSpring, SpringKind};

/// Closed-form references the model is checked against: Hertz (sphere, elliptical, line),
/// Cattaneo, Mindlin and Mindlin-Deresiewicz (Johnson, *Contact Mechanics*, 4.2, 7.2, 7.4).
pub mod closed_form {
    pub use crate::model::closed_form::*;
}

// ---- The program and its solve ----
pub use program::cone_program::ConeProgram;
pub use solve::contact_state::{ContactState, FingerState};
pub use solve::grasp_solver::{solve, GraspSolver};
pub use solve::sensitivity::{LoadDirection, Sensitivities};
pub use solve::step_inputs::StepInputs;
pub use solver::options::{SolveOptions, SolverChoice, DEFAULT_TOLERANCE, DEFAULT_TOLERANCE_TEXT};
pub use solver::outcome::SolverKind;
pub use solver::solve_progress::SolveProgress;

// ---- The solution ----
pub use solve::element_columns::{is_columnar, COLUMNS_ABOVE_ELEMENTS};
pub use solve::solution::{
    ElementSolution, ElementState, FingerSolution, HandSolution, MountDisplacement, Residuals,
    RigidDisplacement, SequentialReport, ServoSolution, Solution, SolveStatus, SolverStats,
    LOADED_FRACTION,
};
pub use warning_tally::{
    IndexRun, SolveAt, TalliedWarning, WarningTally, MAX_LISTED_RUNS, MAX_TALLIED_WARNINGS,
};

// ---- Sensors: read-outs of a solution ----
pub use model::influence_at_depth::{
    overlap_area_m2, reading_per_area_at_depth, ElementOffset, RotatedSquare,
};
pub use sensors::gel_height::{height_map, HeightPath};
pub use sensors::gel_image::{read_gel, GelImage};
pub use sensors::gel_shading::{shade, surface_normals};
pub use sensors::marker_readings::{read_markers, MarkerReadings};
pub use sensors::sensor_readings::{sensor_readings, sensor_readings_drawn, SensorReadings};
pub use sensors::sensor_response::{apply_response, normal_deviate};
pub use sensors::taxel_grid::{QuadraturePoint, TaxelGrid};
pub use sensors::taxel_lattice::taxels_on_lattice;
pub use sensors::taxel_readings::{read_taxels, read_taxels_fastest, TaxelReadings};

// ---- Analyses: many solves ----
pub use analysis::equilibrium_probe::DISTINCT_FRACTION;
pub use analysis::margin_report::{
    holds, margin_for_ordering_n, DirectionMargin, Failure, MarginOptions, MarginReport,
    JUDGED_FRACTION,
};
pub use analysis::margin_search::{disturbance_margins, disturbance_margins_reporting, SolvedStep};
pub use analysis::margin_tracker::MarginTracker;
pub use analysis::patch_sizing::{auto_patch, hertz_suggestion, AutoPatch, HertzSuggestion};
pub use analysis::refinement::{
    estimate_error, grid_with_first_side, hertz_parameters, peak_trend, refinement_study,
    with_grids, ErrorEstimate, NoEstimate, PeakTrend, StudyReference, StudyRow,
    GROWING_PEAK_EXPONENT,
};
pub use analysis::relaxation::{solve_at, solve_at_reporting, TimePoint, TimedSolution};
pub use analysis::wrench_directions::{
    axis_directions, plane_directions, spread_directions, WrenchDirection,
};

// ---- Errors and messages ----
pub use error::{format_problems, InputProblem, ModelError, OptionError, OutOfMemory, SceneError};
pub use number_text::{readable, Readable};
pub use problem_list::{ProblemList, MAX_LISTED_PROBLEMS};
