//! Friction laws of a contact (thesis section 2.6; model.md "Load-dependent friction").
//!
//! Every law gives a coefficient `mu(P)` as a function of the finger's total normal load `P`
//! (N). The cones bound each element's tangential force by `mu F_k` (thesis eqs. 21-24, 27);
//! a load-dependent `mu` makes the cones non-convex in the forces, so the solver freezes `mu` at
//! the previous iterate's load and iterates to a fixed point (see [`crate::solve::sequential`]).

use std::f64::consts::PI;

use crate::model::material::Material;
use crate::scene::scene_format::FrictionSpec;

/// A contact's friction law.
#[derive(Debug, Clone, PartialEq)]
pub enum FrictionLaw {
    /// Constant Coulomb coefficient `mu` (dimensionless, >= 0).
    Constant {
        /// `mu`.
        mu: f64,
    },
    /// Measured `mu(P)`: piecewise linear between points `(P_j, mu_j)` (N, dimensionless) with
    /// `P_j` strictly increasing; constant beyond the first and last points.
    Table {
        /// `(P_j N, mu_j)`.
        points: Vec<(f64, f64)>,
    },
    /// Villaggio's elastic law, thesis eq. (40): `mu(P) = k sqrt(P)`.
    Elastic(ElasticFriction),
}

/// Thesis eq. (40) (Villaggio's plane-elastic theory of Coulomb friction):
///
/// ```text
///   mu(P) = 8.42/pi^3 * a(P)/R1 * K2/K,   a(P) = sqrt(2 p / (pi K)),   p = P / L
///   K  = (1/R1 - 1/R2) / ((1 - nu1)/E1 + (1 - nu2)/E2)
///   K2 = (1/R2) / (2 (1 - nu2)/G2),       G2 = E2 / (2 (1 + nu2))
/// ```
///
/// with body 1 the finger and body 2 the object (`R1 < R2`). Eq. (40) is a plane-strain result:
/// `p` is a load per unit length (N/m), which is what makes `a` a length and `mu`
/// dimensionless. The scene names the length `L` of the line contact over which the finger's
/// load `P` (N) is spread; the thesis leaves it implicit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticFriction {
    /// `R1`, finger radius of curvature, m.
    pub finger_radius_m: f64,
    /// `R2`, object radius of curvature, m.
    pub object_radius_m: f64,
    /// `L`, length of the line contact, m.
    pub contact_length_m: f64,
    /// `K`, N/m^3.
    pub k_n_per_m3: f64,
    /// `K2`, N/m^3.
    pub k2_n_per_m3: f64,
}

impl ElasticFriction {
    /// Eq. (40)'s constants for a finger of `finger` material on an object of `object`
    /// material (the object must be elastic: `K2` needs its shear modulus).
    pub fn new(
        finger_radius_m: f64,
        object_radius_m: f64,
        contact_length_m: f64,
        finger: &Material,
        object: &Material,
    ) -> Self {
        let soft = |m: &Material| (1.0 - m.poisson()) * m.inverse_modulus_per_pa();
        let k = (1.0 / finger_radius_m - 1.0 / object_radius_m) / (soft(finger) + soft(object));
        // 1/G2 = 2 (1 + nu2) / E2.
        let inv_g2 = 2.0 * (1.0 + object.poisson()) * object.inverse_modulus_per_pa();
        let k2 = (1.0 / object_radius_m) / (2.0 * (1.0 - object.poisson()) * inv_g2);
        ElasticFriction {
            finger_radius_m,
            object_radius_m,
            contact_length_m,
            k_n_per_m3: k,
            k2_n_per_m3: k2,
        }
    }

    /// Half-width `a(P) = sqrt(2 p / (pi K))`, m, of eq. (40), `p = P / L`.
    pub fn half_width_m(&self, normal_load_n: f64) -> f64 {
        let p = normal_load_n.max(0.0) / self.contact_length_m;
        (2.0 * p / (PI * self.k_n_per_m3)).sqrt()
    }

    /// `mu(P)` of eq. (40).
    pub fn mu_at(&self, normal_load_n: f64) -> f64 {
        8.42 / PI.powi(3) * self.half_width_m(normal_load_n) / self.finger_radius_m
            * self.k2_n_per_m3
            / self.k_n_per_m3
    }
}

impl FrictionLaw {
    /// The law of a scene entry; `finger` and `object` are the materials of the pair (used by
    /// the elastic law only).
    pub fn from_spec(spec: &FrictionSpec, finger: &Material, object: &Material) -> Self {
        match spec {
            FrictionSpec::Coefficient(c) => FrictionLaw::Constant { mu: c.mu },
            FrictionSpec::Table(t) => FrictionLaw::Table {
                points: t.table.iter().map(|p| (p[0], p[1])).collect(),
            },
            FrictionSpec::Elastic(e) => FrictionLaw::Elastic(ElasticFriction::new(
                e.elastic.finger_radius,
                e.elastic.object_radius,
                e.elastic.contact_length,
                finger,
                object,
            )),
        }
    }

    /// The coefficient at a finger normal load `P` (N).
    pub fn mu_at(&self, normal_load_n: f64) -> f64 {
        match self {
            FrictionLaw::Constant { mu } => *mu,
            FrictionLaw::Table { points } => interpolate(points, normal_load_n),
            FrictionLaw::Elastic(e) => e.mu_at(normal_load_n),
        }
    }

    /// True when `mu` does not depend on the load (one convex solve suffices in the energy
    /// model).
    pub fn is_constant(&self) -> bool {
        matches!(self, FrictionLaw::Constant { .. })
    }
}

/// Piecewise-linear interpolation in `points` (abscissae increasing), constant outside.
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let Some(&(x0, y0)) = points.first() else {
        return 0.0;
    };
    if x <= x0 {
        return y0;
    }
    for w in points.windows(2) {
        let ((xa, ya), (xb, yb)) = (w[0], w[1]);
        if x <= xb {
            return ya + (yb - ya) * (x - xa) / (xb - xa);
        }
    }
    points.last().map_or(y0, |p| p.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_linearly_and_clamps() {
        let law = FrictionLaw::Table {
            points: vec![(1.0, 0.2), (3.0, 0.6), (4.0, 0.6)],
        };
        assert_eq!(law.mu_at(0.0), 0.2);
        assert_eq!(law.mu_at(1.0), 0.2);
        assert!((law.mu_at(2.0) - 0.4).abs() < 1e-15);
        assert!((law.mu_at(2.5) - 0.5).abs() < 1e-15);
        assert_eq!(law.mu_at(10.0), 0.6);
        assert!(!law.is_constant());
    }

    /// Eq. (40) evaluated by hand for steel on steel, R1 = 10 mm, R2 = 20 mm, L = 10 mm,
    /// P = 1 N: p = 100 N/m, K = 50 / (2 * 0.7 / 210e9) = 7.5e12 N/m^3,
    /// a = sqrt(200 / (pi 7.5e12)) = 2.9135e-6 m, G2 = 80.769e9 Pa,
    /// K2 = 50 / (1.4 / 80.769e9) = 2.8846e12 N/m^3, mu = 0.27156 * 2.9135e-4 * 0.38462.
    #[test]
    fn elastic_law_matches_a_hand_evaluation_of_eq_40() {
        let steel = Material::Elastic {
            youngs_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        };
        let e = ElasticFriction::new(0.01, 0.02, 0.01, &steel, &steel);
        assert!((e.k_n_per_m3 / 7.5e12 - 1.0).abs() < 1e-12);
        assert!((e.k2_n_per_m3 / 2.884_615_384_6e12 - 1.0).abs() < 1e-9);
        let a = (200.0 / (PI * 7.5e12_f64)).sqrt();
        assert!((e.half_width_m(1.0) / a - 1.0).abs() < 1e-12);
        let mu = 8.42 / PI.powi(3) * a / 0.01 * (2.884_615_384_6e12 / 7.5e12);
        assert!((e.mu_at(1.0) / mu - 1.0).abs() < 1e-9);
        // mu grows like sqrt(P).
        assert!((e.mu_at(4.0) / e.mu_at(1.0) - 2.0).abs() < 1e-12);
    }
}
