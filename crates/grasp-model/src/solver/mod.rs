//! Solvers of one convex program: the options of a solve, the solver-neutral outcome and the
//! point of a solution (`iterate`), the program with its workspaces (`program_solver`),
//! Clarabel (the reference), the native semismooth Newton solver (`native`) and its start from coarser grids (`grid_continuation`), the warm
//! start's prediction (`predictor`), the certificate of infeasibility kept for the next
//! programs (`kept_certificate`) and the progress a solve reports (`solve_progress`).

pub mod clarabel;
pub(crate) mod grid_continuation;
pub(crate) mod iterate;
pub(crate) mod kept_certificate;
pub(crate) mod native;
pub mod options;
pub mod outcome;
pub(crate) mod predictor;
pub(crate) mod program_solver;
pub mod solve_progress;
