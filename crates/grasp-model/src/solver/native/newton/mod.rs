//! The semismooth Newton method on the natural residual of the program's KKT conditions:
//! [`cold_start`] (which elements start in contact), [`linearisation`] (residual and Newton
//! directions), the reduced system of a finger ([`reduced_system`]: factorised in
//! [`reduced_factor`], by conjugate gradients in [`reduced_iterative`] over
//! [`free_operator`]), one step ([`newton_step`]; [`projected_step`] when every finger is an FFT
//! one), the iteration ([`semismooth_newton`]), and the derivative of its solution at the
//! active set ([`kkt_derivative`]); unit tests in `newton_tests`.

pub(crate) mod cold_start;
pub(crate) mod free_operator;
pub(crate) mod kkt_derivative;
pub(crate) mod linearisation;
pub(crate) mod newton_step;
pub(crate) mod projected_step;
pub(crate) mod reduced_factor;
pub(crate) mod reduced_iterative;
pub(crate) mod reduced_system;
pub(crate) mod semismooth_newton;

#[cfg(test)]
mod newton_tests;
