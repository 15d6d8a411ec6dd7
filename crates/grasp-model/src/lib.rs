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
