//! A point of the program's solution, scaled: the forces and the equality multipliers, as a
//! native solve starts from and returns them, the predictor combines them and a workspace keeps
//! its last one.

/// A point of the iteration, scaled: forces `x` and equality multipliers `lambda`.
#[derive(Debug, Clone, PartialEq)]
pub struct Iterate {
    /// Scaled forces (program layout).
    pub x: Vec<f64>,
    /// Scaled equality multipliers (equilibrium rows, then load rows).
    pub lambda: Vec<f64>,
}
