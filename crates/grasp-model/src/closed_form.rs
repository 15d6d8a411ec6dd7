//! Closed-form contact solutions used as references (Johnson, Contact Mechanics).

use std::f64::consts::PI;

/// Hertz contact of a sphere (radius `R`, m) on a flat under normal force `P` (N), with
/// effective modulus `E*` (Pa, `1/E* = sum_b (1 - nu_b^2)/E_b`; Johnson section 4.2,
/// eqs. 4.22-4.23).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzSphere {
    /// Contact radius `a = (3 P R / (4 E*))^(1/3)`, m.
    pub contact_radius_m: f64,
    /// Peak pressure `p0 = 3 P / (2 pi a^2)`, Pa.
    pub peak_pressure_pa: f64,
    /// Approach `delta = a^2 / R`, m.
    pub approach_m: f64,
}

impl HertzSphere {
    /// Evaluates the Hertz solution.
    pub fn new(load_n: f64, radius_m: f64, effective_modulus_pa: f64) -> Self {
        let a = (3.0 * load_n * radius_m / (4.0 * effective_modulus_pa)).cbrt();
        HertzSphere {
            contact_radius_m: a,
            peak_pressure_pa: 3.0 * load_n / (2.0 * PI * a * a),
            approach_m: a * a / radius_m,
        }
    }

    /// Hertz pressure `p0 sqrt(1 - r^2/a^2)` at radius `r` (0 outside), Pa.
    pub fn pressure_pa(&self, r_m: f64) -> f64 {
        let s = 1.0 - (r_m / self.contact_radius_m).powi(2);
        if s > 0.0 {
            self.peak_pressure_pa * s.sqrt()
        } else {
            0.0
        }
    }
}

/// Cattaneo-Mindlin stick radius `c = a (1 - Q/(mu P))^(1/3)`, m (Johnson section 7.1,
/// eq. 7.39), for `Q < mu P`.
pub fn cattaneo_stick_radius_m(contact_radius_m: f64, q_n: f64, mu: f64, p_n: f64) -> f64 {
    contact_radius_m * (1.0 - q_n / (mu * p_n)).max(0.0).cbrt()
}
