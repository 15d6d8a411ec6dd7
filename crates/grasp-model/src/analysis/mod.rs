//! Analyses built on many solves: disturbance margins (of one grasp, and along a loading path;
//! the load capacity that bounds them), grid-refinement studies, patch sizing, and the state at
//! a time of a viscoelastic scene.

pub mod equilibrium_probe;
pub mod load_capacity;
pub mod load_fixed_directions;
pub mod margin_report;
pub mod margin_search;
pub mod margin_tracker;
pub mod margin_trial;
pub mod patch_sizing;
pub mod refinement;
pub mod relaxation;
pub mod trial_forces;
pub mod wrench_directions;
