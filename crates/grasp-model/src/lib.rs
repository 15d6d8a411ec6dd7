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
//! previous solution, with Clarabel as the reference and fallback ([`solver::clarabel`]).
//!
//! ## Layout: one folder per layer, imports only downwards
//!
//! | folder | what it holds | may import |
//! |---|---|---|
//! | [`geometry`] | contact frames, surface points, exact primitives, triangle meshes, posed shapes, tessellation | - |
//! | [`scene`] | the file format, strict JSON, validation (a path and a fix per problem), shape checks, finger placement, work bounds | geometry |
//! | [`model`] | the immutable [`GraspModel`]: materials, patches, influence coefficients, friction laws, equilibrium map, closed forms | scene, geometry |
//! | [`program`] | the solver-neutral [`ConeProgram`] (assembly kept apart from solving) | model |
//! | [`solver`] | options, outcomes and certificates, Clarabel, the native semismooth Newton solver, the warm start's prediction | program, model |
//! | [`mod@solve`] | [`GraspSolver`] and its strategies (one convex solve, the sequential fixed point), readout, residuals, [`Solution`], contact state, sensitivities | solver, program, model, scene |
//! | [`analysis`] | many solves: disturbance margins, refinement studies, patch sizing | all of the above |
//!
//! [`error`] (one [`InputProblem`] type for every input) and [`option_names`] (how messages
//! name options) sit below them all.
//!
//! Data flow: [`Scene`] (file format, validated) -> [`GraspModel`] (immutable) ->
//! [`ConeProgram`] (scaled, assembled once) -> [`GraspSolver::solve`] (strategy: one convex
//! solve or the sequential fixed point; backend: native or Clarabel) -> [`Solution`] (SI, with
//! [`Residuals`] computed from the solution itself, [`solve::readout`]).
//!
//! ```
//! use grasp_model::{GraspModel, GraspSolver, Scene, SolveOptions};
//!
//! // A frictionless steel fingertip (R = 10 mm) under a 10 N steel plate: Hertz contact.
//! let text = include_str!("../../../examples/hertz_sphere_on_flat.json");
//! let scene = Scene::from_json_str(text)?;
//! let model = GraspModel::from_scene(&scene)?;
//! let solution = GraspSolver::new(&model, SolveOptions::default())
//!     .solve(&model, &model.scene_loads_n())?;
//! let tip = solution.finger("tip").expect("the scene's finger");
//! // The fingertip carries the weight; Hertz's peak pressure p0 = 3P/(2 pi a^2) = 0.636 GPa
//! // (Johnson eq. 4.23) is met to the grid's resolution.
//! assert!((tip.normal_force_n - 10.0).abs() < 1e-6);
//! assert!((tip.peak_pressure_pa / 0.636e9 - 1.0).abs() < 0.01);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A scene pays only for what it needs: a planar scene has 3 equilibrium rows and one
//! tangential unknown per element; a frictionless finger has no tangential unknowns; equal
//! materials assemble no normal/tangential coupling entries.
//!
//! This crate does no I/O.

#![warn(missing_docs)]

pub mod analysis;
pub mod error;
pub mod geometry;
pub mod model;
pub mod number_text;
pub mod option_names;
pub mod program;
pub mod scene;
pub mod solve;
pub mod solver;

pub use error::{InputProblem, ModelError, OptionError, SceneError};
pub use model::grasp_model::{Control, FingerModel, GraspModel, Scales};
pub use program::cone_program::ConeProgram;
pub use scene::{scene_json_schema, Scene};
pub use solve::contact_state::{ContactState, FingerState};
pub use solve::grasp_solver::{solve, GraspSolver};
pub use solve::sensitivity::Sensitivities;
pub use solve::solution::{
    ElementState, FingerSolution, Residuals, SequentialReport, Solution, SolveStatus,
};
pub use solver::options::{SolveOptions, SolverChoice};
pub use solver::outcome::SolverKind;
