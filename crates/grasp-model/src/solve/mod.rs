//! Solving a grasp: the caller's handle ([`grasp_solver::GraspSolver`]), the strategies (one
//! convex solve, the sequential fixed point), the readout of a solver's answer into an SI
//! [`solution::Solution`] with residuals recomputed from it, the contact state carried between
//! solves, patch checks, and sensitivities at the solution.

pub mod contact_state;
pub mod contact_validity;
pub mod convex_solve;
pub mod element_columns;
pub mod grasp_solver;
pub(crate) mod iterate_accuracy;
pub mod patch_check;
pub mod readout;
pub mod residuals;
pub mod sensitivity;
pub mod sequential;
pub mod singular_edge;
pub mod solution;
pub mod step_inputs;
pub mod viscous_history;
