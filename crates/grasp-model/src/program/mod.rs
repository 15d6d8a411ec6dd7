//! The solver-neutral cone program assembled from the model (kept apart from solving): the
//! program itself ([`cone_program`]), its twin on coarser grids ([`coarse_program`]) and the constraint sets of its elements with everything a
//! solver does with one ([`cones`]).

pub(crate) mod coarse_program;
pub mod cone_program;
pub(crate) mod cones;
