//! The robust path of the native solver, where the Newton iteration stalls: a primal-dual
//! interior-point method ([`interior_point`]) on the program written as each element set's
//! conic rows in the symmetric cones (`crate::program::cones`).

pub(crate) mod interior_point;
