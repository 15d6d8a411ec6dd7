//! Analyses built on many solves: disturbance margins, grid-refinement studies, and patch
//! sizing.

pub mod margin;
pub mod patch_sizing;
pub mod refinement;
pub mod relaxation;
