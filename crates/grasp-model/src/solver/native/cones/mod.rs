//! The constraint set of one element and its projection, the building block of the semismooth
//! Newton method: [`element_cone`] (the set of an element, by its law), [`projection`] (a
//! projection with one element of its generalised Jacobian), and one file per cone
//! ([`cone_nonnegative`], [`cone_friction`], [`cone_tresca`]).

pub(crate) mod cone_friction;
pub(crate) mod cone_nonnegative;
pub(crate) mod cone_tresca;
pub(crate) mod element_cone;
pub(crate) mod projection;
