//! Analyses built on many solves: disturbance margins, grid-refinement studies, patch
//! sizing, the state at a time of a viscoelastic scene, and the record a solution's JSON file
//! holds.

pub mod margin;
pub mod patch_sizing;
pub mod refinement;
pub mod relaxation;
pub mod solution_record;
