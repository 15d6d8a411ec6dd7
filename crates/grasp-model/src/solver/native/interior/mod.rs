//! The robust path of the native solver, where the Newton iteration stalls: a primal-dual
//! interior-point method ([`interior_point`]) on the program written as conic rows
//! ([`conic_rows`]) in the cones of [`interior_cones`].

pub(crate) mod conic_rows;
pub(crate) mod interior_cones;
pub(crate) mod interior_point;
