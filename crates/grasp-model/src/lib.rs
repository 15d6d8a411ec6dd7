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
//! (Sinha 1989, as corrected in `shared/docs/model.md`), solved by a native semismooth Newton
//! method that factorises each finger's block and warm-starts from the previous solution
//! ([`native`]), with Clarabel as the reference and fallback ([`backend`]).
//!
//! Data flow: [`Scene`] (file format, validated) -> [`GraspModel`] (immutable) ->
//! [`ConeProgram`] (scaled, assembled once) -> [`GraspSolver::solve`] (strategy: one convex
//! solve or the sequential fixed point; backend: native or Clarabel) -> [`Solution`] (SI, with
//! [`Residuals`] computed from the solution itself, [`readout`]).
//!
//! A scene pays only for what it needs: a planar scene has 3 equilibrium rows and one
//! tangential unknown per element; a frictionless finger has no tangential unknowns; equal
//! materials assemble no normal/tangential coupling entries.
//!
//! This crate does no I/O.

#![warn(missing_docs)]

pub mod backend;
pub mod closed_form;
pub mod cone_program;
pub mod contact_state;
pub mod convex_solve;
pub mod equilibrium;
pub mod error;
pub mod finger_placement;
pub mod friction;
pub mod grasp_model;
pub mod influence;
pub mod json_input;
pub mod margin;
pub mod material;
pub mod mesh_surface;
pub mod native;
pub mod patch;
pub mod patch_check;
pub mod patch_on_shape;
pub mod patch_sizing;
pub mod primitive_surface;
pub mod readout;
pub mod refinement;
pub mod residuals;
pub mod scene;
pub mod sensitivity;
pub mod sequential;
pub mod shape;
pub mod shape_format;
pub mod shape_report;
pub mod shape_spec_check;
pub mod solution;
pub mod solve;
pub mod solve_options;
pub mod surface_point;
pub mod tessellation;
pub mod validation;
pub mod work_bounds;

pub use cone_program::ConeProgram;
pub use contact_state::{ContactState, FingerState};
pub use error::{ModelError, SceneError, SceneProblem};
pub use grasp_model::{Control, FingerModel, GraspModel, Scales};
pub use scene::{scene_json_schema, Scene};
pub use sensitivity::Sensitivities;
pub use solution::{
    ElementState, FingerSolution, Residuals, SequentialReport, Solution, SolveStatus, SolverKind,
};
pub use solve::{solve, GraspSolver};
pub use solve_options::{SolveOptions, SolverChoice};
