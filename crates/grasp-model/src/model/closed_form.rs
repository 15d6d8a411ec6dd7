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

    /// Surface displacements of an elastic body (`E`, `nu`) under this Hertz pressure at
    /// radius `r`, m: `(u_z, u_r)`, `u_z` into the body, `u_r` outward (Boussinesq under
    /// `p0 sqrt(1 - r^2/a^2)`; Johnson eqs. 3.41a-b inside, 3.42a-b outside):
    /// - `r <= a`: `u_z = (1 - nu^2)/E pi p0 (2 a^2 - r^2) / (4 a)`,
    ///   `u_r = -(1 - 2 nu)(1 + nu)/(3 E) a^2 / r p0 (1 - (1 - r^2/a^2)^(3/2))`;
    /// - `r >= a`: `u_z = (1 - nu^2)/E p0 / (2 a) ((2 a^2 - r^2) asin(a/r) + a sqrt(r^2 - a^2))`
    ///   (it falls off as Boussinesq's `(1 - nu^2) P / (pi E r)` of the load
    ///   `P = 2 pi a^2 p0 / 3`), `u_r = -(1 - 2 nu)(1 + nu)/(3 E) a^2 p0 / r`.
    ///
    /// With the other body rigid (`E* = E / (1 - nu^2)`), `u_z(0)` is the approach `a^2 / R`.
    pub fn surface_displacement_m(&self, r_m: f64, youngs_modulus_pa: f64, nu: f64) -> (f64, f64) {
        let (a, p0, r) = (self.contact_radius_m, self.peak_pressure_pa, r_m);
        let normal = (1.0 - nu * nu) / youngs_modulus_pa;
        let radial = -(1.0 - 2.0 * nu) * (1.0 + nu) / (3.0 * youngs_modulus_pa) * a * a * p0;
        if r <= a {
            let uz = normal * PI * p0 * (2.0 * a * a - r * r) / (4.0 * a);
            let ur = match r > 0.0 {
                true => radial / r * (1.0 - (1.0 - r * r / (a * a)).powf(1.5)),
                false => 0.0,
            };
            (uz, ur)
        } else {
            let uz = normal * p0 / (2.0 * a)
                * ((2.0 * a * a - r * r) * (a / r).asin() + a * (r * r - a * a).sqrt());
            (uz, radial / r)
        }
    }
}

/// Semi-axes of the elliptical Hertz contact of two bodies whose gap has principal radii
/// `R1`, `R2` (m) under normal force `P` (N), by the equivalent-radius approximation (Johnson
/// section 4.2, eq. 4.36 with `Re = sqrt(R1 R2)`, a few percent for moderate eccentricity):
/// `a1 = c (R1/R2)^(1/3)`, `a2 = c (R2/R1)^(1/3)` with `c` the Hertz radius
/// ([`HertzSphere`]) at `Re`, m. Equal radii give the sphere's circle.
pub fn elliptical_semi_axes_m(
    load_n: f64,
    radii_m: [f64; 2],
    effective_modulus_pa: f64,
) -> [f64; 2] {
    let [r1, r2] = radii_m;
    let c = HertzSphere::new(load_n, (r1 * r2).sqrt(), effective_modulus_pa).contact_radius_m;
    [c * (r1 / r2).cbrt(), c * (r2 / r1).cbrt()]
}

/// Half-width of the line contact of a body curved one way (radius `R`, m) on a flat, pressed
/// with `P` (N) over a length `L` (m): `b = sqrt(4 P R / (pi L E*))` (Johnson section 4.3,
/// eq. 4.43, with `P/L` the load per unit length), m.
pub fn line_contact_half_width_m(
    load_n: f64,
    radius_m: f64,
    length_m: f64,
    effective_modulus_pa: f64,
) -> f64 {
    (4.0 * load_n * radius_m / (PI * length_m * effective_modulus_pa)).sqrt()
}

/// Cattaneo-Mindlin stick radius `c = a (1 - Q/(mu P))^(1/3)`, m (Johnson section 7.1,
/// eq. 7.39), for `Q < mu P`.
pub fn cattaneo_stick_radius_m(contact_radius_m: f64, q_n: f64, mu: f64, p_n: f64) -> f64 {
    contact_radius_m * (1.0 - q_n / (mu * p_n)).max(0.0).cbrt()
}

/// Mindlin's tangential displacement of a Hertz contact under a monotonically increasing
/// tangential force `Q < mu P` at constant `P` (Johnson section 7.2, eq. 7.42, written for two
/// bodies): `delta = 3 mu P / (16 a) * S * (1 - (1 - Q/(mu P))^(2/3))`, m, with the combined
/// tangential compliance `S = sum_b (2 - nu_b)/G_b` (1/Pa) and `a` the Hertz radius, m.
pub fn mindlin_displacement_m(
    contact_radius_m: f64,
    compliance_sum_per_pa: f64,
    q_n: f64,
    mu: f64,
    p_n: f64,
) -> f64 {
    let x = (q_n / (mu * p_n)).min(1.0);
    3.0 * mu * p_n / (16.0 * contact_radius_m)
        * compliance_sum_per_pa
        * (1.0 - (1.0 - x).powf(2.0 / 3.0))
}

/// Energy dissipated per cycle of a tangential force oscillating between `+-Q*` at constant
/// `P` (Mindlin-Deresiewicz; Johnson section 7.4, eq. 7.64, written for two bodies), J:
///
/// ```text
///   dW = 9 mu^2 P^2 / (10 a) * S * (1 - (1 - x)^(5/3) - 5x/6 (1 + (1 - x)^(2/3))),  x = Q*/(mu P)
/// ```
///
/// with `S = sum_b (2 - nu_b)/G_b`. It is the area between the unloading and reloading curves
/// built from [`mindlin_displacement_m`] by Masing's rule (`delta* - 2 delta_m((Q* - Q)/2)`);
/// the unit test integrates them numerically.
pub fn mindlin_deresiewicz_dissipation_j(
    contact_radius_m: f64,
    compliance_sum_per_pa: f64,
    q_amplitude_n: f64,
    mu: f64,
    p_n: f64,
) -> f64 {
    let x = (q_amplitude_n / (mu * p_n)).min(1.0);
    9.0 * mu * mu * p_n * p_n / (10.0 * contact_radius_m)
        * compliance_sum_per_pa
        * (1.0 - (1.0 - x).powf(5.0 / 3.0) - 5.0 * x / 6.0 * (1.0 + (1.0 - x).powf(2.0 / 3.0)))
}

/// Twisting moment that makes a Hertz contact slip completely, `M = 3 pi mu P a / 16`, N m
/// (Johnson section 7.3, Lubkin's result: the Hertz pressure times `mu r` integrated over the
/// contact circle of radius `a`, m, under normal load `P`, N).
pub fn full_slip_torque_nm(mu: f64, load_n: f64, contact_radius_m: f64) -> f64 {
    3.0 * PI * mu * load_n * contact_radius_m / 16.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal radii give the sphere's circle; the semi-axes' product is `c^2` at any ratio
    /// (area of the equivalent circle), both to round-off.
    #[test]
    fn elliptical_contact_reduces_to_the_sphere() {
        let (p, e) = (2.0, 1e6);
        let sphere = HertzSphere::new(p, 0.01, e).contact_radius_m;
        let [a1, a2] = elliptical_semi_axes_m(p, [0.01, 0.01], e);
        assert!((a1 / sphere - 1.0).abs() < 1e-14 && (a2 / sphere - 1.0).abs() < 1e-14);
        let [b1, b2] = elliptical_semi_axes_m(p, [0.04, 0.01], e);
        let c = HertzSphere::new(p, 0.02, e).contact_radius_m;
        assert!((b1 * b2 / (c * c) - 1.0).abs() < 1e-14 && b1 > b2);
    }

    /// The closed-form loop area equals a numerical integration of the Masing loop built from
    /// Mindlin's monotonic curve (trapezoid rule, 2e5 intervals: error ~1e-9 relative).
    #[test]
    fn dissipation_is_the_area_of_the_masing_loop() {
        let (a, s, mu, p) = (1e-4, 2.0 * 1.7 / 80e9, 0.3, 10.0);
        let dm = |q: f64| mindlin_displacement_m(a, s, q, mu, p);
        for x in [0.2, 0.5, 0.8] {
            let qs = x * mu * p;
            let ds = dm(qs);
            let n = 200_000;
            let h = 2.0 * qs / n as f64;
            let mut area = 0.0;
            for i in 0..=n {
                let q = -qs + i as f64 * h;
                let unload = ds - 2.0 * dm((qs - q) / 2.0);
                let reload = -ds + 2.0 * dm((qs + q) / 2.0);
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                area += w * h * (unload - reload).abs();
            }
            let closed = mindlin_deresiewicz_dissipation_j(a, s, qs, mu, p);
            assert!(
                (area / closed - 1.0).abs() < 1e-6,
                "x = {x}: {area} vs {closed}"
            );
        }
    }
}
