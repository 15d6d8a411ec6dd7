//! Friction laws of a contact.
//!
//! The energy model bounds each element's tangential force by a Coulomb cone
//! `||G_k|| <= mu F_k` (thesis eqs. 21-24; model.md "friction cones per element").

use crate::scene::FrictionSpec;

/// A contact's friction law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionLaw {
    /// Constant Coulomb coefficient `mu` (dimensionless, >= 0).
    Constant {
        /// `mu`.
        mu: f64,
    },
}

impl From<&FrictionSpec> for FrictionLaw {
    fn from(f: &FrictionSpec) -> Self {
        FrictionLaw::Constant { mu: f.mu }
    }
}

impl FrictionLaw {
    /// The coefficient at a given finger normal load `P` (N).
    pub fn mu_at(&self, _normal_load_n: f64) -> f64 {
        match *self {
            FrictionLaw::Constant { mu } => mu,
        }
    }

    /// True when the contact is frictionless (then it has no tangential unknowns).
    pub fn is_frictionless(&self) -> bool {
        match *self {
            FrictionLaw::Constant { mu } => mu == 0.0,
        }
    }
}
