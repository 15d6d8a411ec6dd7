//! Solvers of one convex program: the options of a solve, the solver-neutral outcome, the
//! program with its workspaces ([`program_solver`]), Clarabel (the reference), the native
//! semismooth Newton solver, and the warm start's prediction.

pub mod clarabel;
pub mod native;
pub mod options;
pub mod outcome;
pub mod predictor;
pub mod program_solver;
