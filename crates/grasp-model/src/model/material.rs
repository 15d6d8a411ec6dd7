//! Linear-elastic isotropic materials and the compliance constants of the half-space solutions.

use std::f64::consts::PI;

use crate::scene::scene_format::MaterialSpec;

/// A body's material: elastic (`E` in Pa, `nu` dimensionless) or rigid (`1/E = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// Rigid: contributes no compliance.
    Rigid,
    /// Linear-elastic isotropic.
    Elastic {
        /// Young's modulus `E`, Pa (> 0).
        youngs_modulus_pa: f64,
        /// Poisson's ratio `nu`, in `[0, 0.5)`.
        poisson_ratio: f64,
    },
}

impl From<&MaterialSpec> for Material {
    fn from(m: &MaterialSpec) -> Self {
        match m {
            MaterialSpec::Rigid(_) => Material::Rigid,
            MaterialSpec::Elastic(e) => Material::Elastic {
                youngs_modulus_pa: e.youngs_modulus,
                poisson_ratio: e.poisson_ratio,
            },
        }
    }
}

impl Material {
    /// `1/E` in 1/Pa (0 for a rigid body).
    pub fn inverse_modulus_per_pa(&self) -> f64 {
        match *self {
            Material::Rigid => 0.0,
            Material::Elastic {
                youngs_modulus_pa, ..
            } => 1.0 / youngs_modulus_pa,
        }
    }

    /// Poisson's ratio (0 for a rigid body, where it multiplies `1/E = 0` anyway).
    pub fn poisson(&self) -> f64 {
        match *self {
            Material::Rigid => 0.0,
            Material::Elastic { poisson_ratio, .. } => poisson_ratio,
        }
    }

    /// Boussinesq normal factor `(1 - nu^2)/E`, 1/Pa: surface normal displacement
    /// `u_z = (1 - nu^2)/(pi E) P / r` under a normal point load (Johnson, Contact Mechanics,
    /// section 3.2, eq. 3.22c; model.md `Cnn`).
    pub fn normal_factor_per_pa(&self) -> f64 {
        let nu = self.poisson();
        (1.0 - nu * nu) * self.inverse_modulus_per_pa()
    }

    /// Cerruti factors `((1 + nu)(1 - nu)/E, (1 + nu) nu / E)`, 1/Pa: tangential displacement
    /// `u_x = (1 + nu)/(pi E) [(1 - nu)/r + nu x^2/r^3] Q` under a tangential point load `Q`
    /// along x (Johnson section 3.2, eq. 3.86a; model.md `C11`; NOT the thesis's eq. 43 sign).
    pub fn tangential_factors_per_pa(&self) -> (f64, f64) {
        let nu = self.poisson();
        let c = (1.0 + nu) * self.inverse_modulus_per_pa();
        (c * (1.0 - nu), c * nu)
    }

    /// Coupling constant `kappa = (1 + nu)(1 - 2 nu)/(2 pi E)`, 1/Pa: normal displacement
    /// `u_z = kappa Q x / r^2` under a tangential point load, and radial displacement
    /// `u_r = -kappa P / r` under a normal one (Johnson eqs. 3.86c, 3.22a).
    pub fn coupling_kappa_per_pa(&self) -> f64 {
        let nu = self.poisson();
        (1.0 + nu) * (1.0 - 2.0 * nu) / (2.0 * PI) * self.inverse_modulus_per_pa()
    }

    /// Effective contact modulus contribution: `1/E* = sum_b (1 - nu_b^2)/E_b` (Johnson eq.
    /// 4.22); returns `E*` in Pa for the pair `(self, other)` (infinite if both rigid).
    pub fn effective_modulus_pa(&self, other: &Material) -> f64 {
        1.0 / (self.normal_factor_per_pa() + other.normal_factor_per_pa())
    }
}
