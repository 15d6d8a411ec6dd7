//! The constraint sets of the program's elements, the concept every solver shares: one trait
//! of verbs ([`element_set::ElementSet`]: projection, conic rows, Clarabel rows, dual test,
//! support, state margin), one file per set ([`nonnegative_ray`], [`friction_cone`],
//! [`tresca_set`], and [`free_space`] for a shared spring's unconstrained load), the enum of an element's set ([`element_cone`]) and a finger's storage of
//! them with the law that picks them ([`finger_cones`]); below them the forms the sets are
//! written in: a projection with its Jacobian ([`projection`]) and conic rows ([`conic_rows`])
//! in the interior point's symmetric cones ([`symmetric_cones`]).

pub(crate) mod conic_rows;
pub(crate) mod element_cone;
pub(crate) mod element_set;
pub(crate) mod finger_cones;
pub(crate) mod free_space;
pub(crate) mod friction_cone;
pub(crate) mod nonnegative_ray;
pub(crate) mod projection;
pub(crate) mod symmetric_cones;
pub(crate) mod tresca_set;
