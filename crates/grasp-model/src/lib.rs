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
//! solved with Clarabel (Sinha 1989, as corrected in `shared/docs/model.md`).
//!
//! Data flow: [`Scene`] (file format, validated) -> [`GraspModel`] (immutable) ->
//! [`ConeProgram`] (scaled, assembled once) -> [`GraspSolver::solve`] -> [`Solution`] (SI, with
//! [`Residuals`] computed from the solution itself).
//!
//! A scene pays only for what it needs: a planar scene has 3 equilibrium rows and one
//! tangential unknown per element; a frictionless finger has no tangential unknowns; equal
//! materials assemble no normal/tangential coupling entries.
//!
//! This crate does no I/O.

#![warn(missing_docs)]

pub mod closed_form;
pub mod cone_program;
pub mod contact_state;
pub mod equilibrium;
pub mod error;
pub mod friction;
pub mod grasp_model;
pub mod influence;
pub mod material;
pub mod patch;
pub mod patch_sizing;
pub mod refinement;
pub mod residuals;
pub mod scene;
pub mod sequential;
pub mod solution;
pub mod solve;
pub mod validation;

pub use cone_program::ConeProgram;
pub use contact_state::{ContactState, FingerState};
pub use error::{ModelError, SceneError, SceneProblem};
pub use grasp_model::{Control, FingerModel, GraspModel, Scales};
pub use residuals::Residuals;
pub use scene::{scene_json_schema, Scene};
pub use solution::{ElementState, FingerSolution, SequentialReport, Solution, SolveStatus};
pub use solve::{solve, GraspSolver, SolveOptions};
