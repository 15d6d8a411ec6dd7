//! The cones of one finger's elements as the program stores them ([`FingerCones`]: one
//! friction coefficient for the whole patch, or one Tresca radius per element), and the law
//! that chooses them ([`ConeLaw`]). Every operation on a cone goes through the element's
//! [`super::element_cone::ElementCone`] ([`FingerCones::element`]).

use super::element_cone::ElementCone;
use super::free_space::FreeSpace;
use super::friction_cone::FrictionCone;
use super::nonnegative_ray::NonnegativeRay;
use super::tresca_set::TrescaSet;

/// Which cones bound the friction forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConeLaw {
    /// `||G_k|| <= mu F_k`: the energy model's associated cones.
    Associated,
    /// `||G_k|| <= r_k` with `r_k` fixed (Tresca): one iterate of the coulomb model.
    Tresca,
}

/// The constraint set of every element of one finger.
#[derive(Debug, Clone, PartialEq)]
pub enum FingerCones {
    /// `F_k >= 0`: a frictionless finger (no tangential unknowns).
    Nonnegative,
    /// `||G_k|| <= mu F_k` (associated friction), `mu` dimensionless and > 0.
    Friction {
        /// Friction coefficient frozen for this solve.
        mu: f64,
    },
    /// `F_k >= 0` and `||G_k|| <= r_k` (Tresca), radii in element force units `Fu`, >= 0.
    Tresca {
        /// `r_k / Fu`, one per element.
        radii: Vec<f64>,
    },
    /// No constraint: the load coordinates of a shared spring (a hand's base, a servo), whose
    /// block follows the fingers' (`crate::model::shared_spring`).
    Free,
}

impl FingerCones {
    /// The cones of a finger with `n_tangential` tangential unknowns per element and
    /// `elements` elements under `law`, friction coefficient `mu` (associated law); Tresca
    /// radii start at 0.
    pub(crate) fn of_law(law: ConeLaw, n_tangential: usize, elements: usize, mu: f64) -> Self {
        match (n_tangential, law) {
            (0, _) => FingerCones::Nonnegative,
            (_, ConeLaw::Associated) => FingerCones::Friction { mu },
            (_, ConeLaw::Tresca) => FingerCones::Tresca {
                radii: vec![0.0; elements],
            },
        }
    }

    /// The constraint set of element `k`.
    pub(crate) fn element(&self, k: usize) -> ElementCone {
        match self {
            FingerCones::Nonnegative => ElementCone::Nonnegative(NonnegativeRay),
            FingerCones::Friction { mu } => ElementCone::Friction(FrictionCone { mu: *mu }),
            FingerCones::Tresca { radii } => ElementCone::Tresca(TrescaSet { radius: radii[k] }),
            FingerCones::Free => ElementCone::Free(FreeSpace),
        }
    }

    /// The friction coefficient of the associated cones (0 for other cones).
    pub(crate) fn mu(&self) -> f64 {
        match self {
            FingerCones::Friction { mu } => *mu,
            _ => 0.0,
        }
    }

    /// True for the Tresca sets of a coulomb iterate.
    pub(crate) fn is_tresca(&self) -> bool {
        matches!(self, FingerCones::Tresca { .. })
    }

    /// The Tresca radii (element force units), `None` for other cones.
    pub(crate) fn radii(&self) -> Option<&[f64]> {
        match self {
            FingerCones::Tresca { radii } => Some(radii),
            _ => None,
        }
    }

    /// Sets the associated cones' friction coefficient (other cones unchanged).
    pub(crate) fn set_mu(&mut self, m: f64) {
        if let FingerCones::Friction { mu } = self {
            *mu = m;
        }
    }

    /// Sets the Tresca radii to `radii_n[k] / fu` (N over the element force unit `Fu`, N;
    /// other cones unchanged).
    pub(crate) fn set_radii(&mut self, radii_n: &[f64], fu: f64) {
        if let FingerCones::Tresca { radii } = self {
            for (dst, rk) in radii.iter_mut().zip(radii_n) {
                *dst = rk / fu;
            }
        }
    }

    /// These cones with each Tresca radius replaced by `radius(k)` (element force units; other
    /// cones as they are).
    pub(crate) fn with_radii(&self, radius: impl Fn(usize) -> f64) -> FingerCones {
        match self {
            FingerCones::Tresca { radii } => FingerCones::Tresca {
                radii: (0..radii.len()).map(radius).collect(),
            },
            other => other.clone(),
        }
    }

    /// The data of these cones that change between solves, appended to `out`: the friction
    /// coefficient, or the radii (the warm start's predictor reads them).
    pub(crate) fn append_data(&self, out: &mut Vec<f64>) {
        match self {
            FingerCones::Nonnegative | FingerCones::Free => {}
            FingerCones::Friction { mu } => out.push(*mu),
            FingerCones::Tresca { radii } => out.extend_from_slice(radii),
        }
    }
}
