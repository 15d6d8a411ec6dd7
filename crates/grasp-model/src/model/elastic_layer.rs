//! An elastic layer bonded to a rigid core (a fingertip pad on its phalanx): its surface
//! compliance in the Fourier domain.
//!
//! A layer of thickness `h`, Young's modulus `E`, Poisson's ratio `nu` and shear modulus
//! `G = E / (2 (1 + nu))`, perfectly bonded at depth `h` to a rigid base, carries tractions on
//! its free surface. For a traction wave `exp(i k.x)` of wavenumber `k = |k|`, in the frame of
//! the wave (`L` along `k`, `T` across it, `z` the inward normal) with `t = k h`:
//!
//! ```text
//!   w   = H_zz p + H_zL q_L        H_zz = (1 - nu)/(G k) [(3 - 4 nu) sinh 2t - 2t] / D(t)
//!   u_L = H_Lz p + H_LL q_L        H_LL = (1 - nu)/(G k) [(3 - 4 nu) sinh 2t + 2t] / D(t)
//!   u_T = H_TT q_T                 H_zL = -H_Lz = i [t^2 - (1 - 2 nu)(3 - 4 nu) sinh^2 t] / (G k D(t))
//!                                  H_TT = tanh t / (G k)
//!   D(t) = (3 - 4 nu) cosh 2t + 2 t^2 + 8 nu^2 - 12 nu + 5
//! ```
//!
//! (`p` the pressure pushing into the body, `q` the shear traction on it, `w` the surface
//! displacement into the body, `u` the tangential one). Derived here from the Navier equations
//! of plane strain in `(L, z)` with the general solution `(A + B z) e^{kz} + (C + D z) e^{-kz}`,
//! the surface tractions at `z = 0` and `u = 0` at `z = h` (and the anti-plane equation
//! `u_T'' = k^2 u_T` for `T`); the same route as Carbone and Mangialardi, J. Mech. Phys. Solids
//! 56 (2008) appendix A, whose eq. (A.30) is `1 / H_zz` (the stiffness of a shear-free
//! surface). Limits: as `t -> infinity` the half-space of Boussinesq and Cerruti
//! (`H_zz = H_LL = (1 - nu)/(G k)`, `H_TT = 1/(G k)`, `H_zL = -i (1 - 2 nu)/(2 G k)`, Johnson,
//! Contact Mechanics, 3.22 and 3.86 transformed); as `t -> 0` the thin layer:
//! `H_zz -> h / M` with `M = E (1 - nu)/((1 + nu)(1 - 2 nu))` (uniaxial strain, the Winkler
//! foundation), `H_LL, H_TT -> h / G`, and for `nu -> 1/2` `H_zz -> k^2 h^3 / (3 G)` (the
//! squeeze film of a thin incompressible layer, Johnson 5.9).
//!
//! What the kernels need is the difference from the half-space of the same material, written
//! without overflow or cancellation (`e = exp(-2t)`, `c = 8 nu^2 - 12 nu + 5`,
//! `D' = D e = (3 - 4 nu)(1 + e^2)/2 + (2 t^2 + c) e`):
//!
//! ```text
//!   G k dH_zz = -(1 - nu) [(3 - 4 nu) e + 2t + 2t^2 + c] e / D'
//!   G k dH_LL = -(1 - nu) [(3 - 4 nu) e - 2t + 2t^2 + c] e / D'
//!   G k dH_TT = -2 e / (1 + e)
//!   G k dh_zL =  2 (1 - nu) [t^2 + 2 (1 - 2 nu)(1 - nu)] e / D'      (H_zL = i h_zL)
//! ```
//!
//! each of which is analytic in `t`, equals minus the half-space's `G k H` at `t = 0`, and
//! decays like `t^2 e^{-2t}`.

use crate::model::material::Material;

/// An elastic layer bonded to a rigid core: the material of a body that is a pad, not a
/// half-space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticLayer {
    /// Young's modulus `E`, Pa (> 0).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio `nu`, in `[0, 0.5)`.
    pub poisson_ratio: f64,
    /// Thickness `h` of the layer, m (> 0).
    pub thickness_m: f64,
}

/// The four independent entries of a surface compliance in the frame of a traction wave, as
/// `G k H` (dimensionless): `zz`, `ll` (along the wave), `tt` (across it) and `zl`, the
/// imaginary part of `G k H_zL` (`H_Lz = -H_zL`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WaveCompliance {
    /// `G k H_zz`.
    pub zz: f64,
    /// `G k H_LL`.
    pub ll: f64,
    /// `G k H_TT`.
    pub tt: f64,
    /// `G k Im H_zL`.
    pub zl: f64,
}

impl ElasticLayer {
    /// The layer of an elastic material of thickness `thickness_m`; `None` for a rigid one.
    pub fn of(material: &Material, thickness_m: f64) -> Option<Self> {
        match *material {
            Material::Rigid => None,
            Material::Elastic {
                youngs_modulus_pa,
                poisson_ratio,
            } => Some(ElasticLayer {
                youngs_modulus_pa,
                poisson_ratio,
                thickness_m,
            }),
        }
    }

    /// The layer's material as a half-space.
    pub fn material(&self) -> Material {
        Material::Elastic {
            youngs_modulus_pa: self.youngs_modulus_pa,
            poisson_ratio: self.poisson_ratio,
        }
    }

    /// Shear modulus `G = E / (2 (1 + nu))`, Pa.
    pub fn shear_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }

    #[cfg(test)]
    /// The constrained (uniaxial-strain) modulus `M = E (1 - nu)/((1 + nu)(1 - 2 nu))`, Pa: a
    /// thin layer's normal stiffness per unit area is `M / h` (the Winkler limit).
    pub fn constrained_modulus_pa(&self) -> f64 {
        let nu = self.poisson_ratio;
        self.youngs_modulus_pa * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// The layer's surface compliance at wavenumber `k_per_m` (> 0), as `G k H` (module
    /// docs; Carbone and Mangialardi 2008, eq. A.30 for `zz`).
    pub fn wave_compliance(&self, k_per_m: f64) -> WaveCompliance {
        let half = half_space_wave_compliance(self.poisson_ratio);
        let d = correction(self.poisson_ratio, k_per_m * self.thickness_m);
        WaveCompliance {
            zz: half.zz + d.zz,
            ll: half.ll + d.ll,
            tt: half.tt + d.tt,
            zl: half.zl + d.zl,
        }
    }

    /// The layer's normal surface compliance `H_zz` at wavenumber `k_per_m` (> 0), m/Pa: the
    /// displacement amplitude per pressure amplitude of a wave (`1/K(k)` of Carbone and
    /// Mangialardi 2008, eq. A.30).
    pub fn normal_compliance_m_per_pa(&self, k_per_m: f64) -> f64 {
        self.wave_compliance(k_per_m).zz / (self.shear_modulus_pa() * k_per_m)
    }
}

/// A half-space's surface compliance as `G k H` (Johnson 3.22 and 3.86 in the frame of a
/// wave): `zz = ll = 1 - nu`, `tt = 1`, `zl = -(1 - 2 nu)/2`.
pub fn half_space_wave_compliance(nu: f64) -> WaveCompliance {
    WaveCompliance {
        zz: 1.0 - nu,
        ll: 1.0 - nu,
        tt: 1.0,
        zl: -(1.0 - 2.0 * nu) / 2.0,
    }
}

/// The layer's compliance minus the half-space's, as `G k (H_layer - H_half)` at `t = k h`
/// (module docs, the stable forms): analytic, minus [`half_space_wave_compliance`] at
/// `t = 0`, decaying like `t^2 e^{-2t}`.
pub fn correction(nu: f64, t: f64) -> WaveCompliance {
    let e = (-2.0 * t).exp();
    let a = 3.0 - 4.0 * nu;
    let c = 8.0 * nu * nu - 12.0 * nu + 5.0;
    let d = 0.5 * a * (1.0 + e * e) + (2.0 * t * t + c) * e;
    WaveCompliance {
        zz: -(1.0 - nu) * (a * e + 2.0 * t + 2.0 * t * t + c) * e / d,
        ll: -(1.0 - nu) * (a * e - 2.0 * t + 2.0 * t * t + c) * e / d,
        tt: -2.0 * e / (1.0 + e),
        zl: 2.0 * (1.0 - nu) * (t * t + 2.0 * (1.0 - 2.0 * nu) * (1.0 - nu)) * e / d,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Carbone and Mangialardi (2008), eq. A.30, written out: the stiffness of a bonded layer
    /// with a shear-free surface, `K = (E* k / 2) N / S`.
    fn carbone_stiffness(e: f64, nu: f64, h: f64, k: f64) -> f64 {
        let t = k * h;
        let e_star = e / (1.0 - nu * nu);
        let n = (3.0 - 4.0 * nu) * (2.0 * t).cosh() + 2.0 * t * t + 8.0 * nu * nu - 12.0 * nu + 5.0;
        let s = (3.0 - 4.0 * nu) * (2.0 * t).sinh() - 2.0 * t;
        0.5 * e_star * k * n / s
    }

    /// `H_zz` is `1/K` of Carbone and Mangialardi's eq. A.30 over seven decades of `k h` and
    /// four Poisson's ratios. Tolerance 1e-11: the stable form and A.30 differ by round-off,
    /// A.30's `sinh 2t - 2t/(3 - 4 nu)` losing up to `1e-16 / t^2` at `t = 1e-3`.
    #[test]
    fn normal_compliance_is_carbone_and_mangialardi_a30() {
        for nu in [0.0, 0.3, 0.45, 0.49] {
            for t in [1e-3, 1e-2, 0.1, 0.5, 1.0, 3.0, 10.0, 100.0] {
                let layer = ElasticLayer {
                    youngs_modulus_pa: 2e6,
                    poisson_ratio: nu,
                    thickness_m: 1e-3,
                };
                let k = t / layer.thickness_m;
                let got = layer.normal_compliance_m_per_pa(k);
                let want = 1.0 / carbone_stiffness(2e6, nu, 1e-3, k);
                assert!(
                    (got - want).abs() <= 1e-11 * want,
                    "nu {nu}, kh {t}: {got:e} vs {want:e}"
                );
            }
        }
    }

    /// The surface compliance of a bonded layer by an independent numerical route: the
    /// plane-strain equations as a first-order system in depth, `y' = A y` with
    /// `y = (U, W, S, N)` (`u_x = U sin kx`, `w = W cos kx`, `sigma_xz = S sin kx`,
    /// `sigma_zz = N cos kx`), propagated through the layer by the matrix exponential (a
    /// transfer matrix), with the tractions given at the surface and `U = W = 0` at the base.
    /// Returns `G k [[H_zz, h_zL], [h_zL, H_LL]]` (with `p = P cos kx`, `q = Q sin kx`:
    /// `W(0) = H_zz P + h_zL Q`, `U(0) = h_zL P + H_LL Q`) and `G k H_TT` from the anti-plane
    /// system `(V, T)`.
    fn transfer_matrix_compliance(nu: f64, t: f64) -> ([[f64; 2]; 2], f64) {
        use nalgebra::{Matrix2, Matrix4, Vector4};
        // Units: G = 1, k = 1, h = t.
        let g = 1.0;
        let lambda = 2.0 * g * nu / (1.0 - 2.0 * nu);
        let m = lambda + 2.0 * g;
        // U' = S/G + W; W' = (N - lambda U)/M; S' = M U + lambda W'; N' = -S.
        let a = Matrix4::new(
            0.0,
            1.0,
            1.0 / g,
            0.0,
            -lambda / m,
            0.0,
            0.0,
            1.0 / m,
            m - lambda * lambda / m,
            0.0,
            0.0,
            lambda / m,
            0.0,
            0.0,
            -1.0,
            0.0,
        );
        let phi = (a * t).exp();
        // y(0) = (U0, W0, -Q, -P); y(h)[0..2] = 0 fixes (U0, W0) for given (P, Q).
        let solve = |p: f64, q: f64| {
            let base = phi * Vector4::new(0.0, 0.0, -q, -p);
            let block = Matrix2::new(phi[(0, 0)], phi[(0, 1)], phi[(1, 0)], phi[(1, 1)]);
            let uw = block
                .lu()
                .solve(&nalgebra::Vector2::new(-base[0], -base[1]))
                .unwrap();
            (uw[0], uw[1])
        };
        let (u_p, w_p) = solve(1.0, 0.0);
        let (u_q, w_q) = solve(0.0, 1.0);
        // Anti-plane: V' = T/G, T' = G V; V(h) = 0, T(0) = -q.
        let b = Matrix2::new(0.0, 1.0 / g, g, 0.0);
        let psi = (b * t).exp();
        let v0 = psi[(0, 1)] / psi[(0, 0)]; // V(h) = psi00 V0 + psi01 (-1) = 0
        ([[w_p, w_q], [u_p, u_q]], v0)
    }

    /// Every entry of the closed form (`H_zz`, `H_LL`, `H_TT` and the coupling `h_zL`)
    /// against the transfer-matrix solution, over `k h` from 0.02 to 4 and four Poisson's
    /// ratios; the coupling is symmetric (Betti: `W` from `Q` equals `U` from `P`).
    /// Tolerance 1e-9: the matrix exponential of entries up to `e^{4}` loses a few digits.
    #[test]
    fn closed_form_matches_a_transfer_matrix_solution() {
        for nu in [0.0, 0.25, 0.3, 0.45, 0.49] {
            for t in [0.02, 0.1, 0.5, 1.0, 2.0, 4.0] {
                let layer = ElasticLayer {
                    youngs_modulus_pa: 2.0 * (1.0 + nu),
                    poisson_ratio: nu,
                    thickness_m: t,
                };
                let c = layer.wave_compliance(1.0);
                let (h, tt) = transfer_matrix_compliance(nu, t);
                let check = |name: &str, got: f64, want: f64| {
                    assert!(
                        (got - want).abs() <= 1e-9 * want.abs().max(1e-3),
                        "nu {nu}, kh {t}, {name}: closed form {got:e}, transfer matrix {want:e}"
                    );
                };
                check("zz", c.zz, h[0][0]);
                check("ll", c.ll, h[1][1]);
                check("zl", c.zl, h[0][1]);
                check("lz (Betti)", c.zl, h[1][0]);
                check("tt", c.tt, tt);
            }
        }
    }

    /// The limits of the module docs: the half-space for `k h -> infinity`, the thin layer for
    /// `k h -> 0` (`G k H_zz -> G k h / M`, `G k H_LL = G k H_TT -> k h`) and the squeeze film
    /// of a nearly incompressible one (`H_zz ~ h/M + k^2 h^3 / (3 G)`). Tolerances: the next
    /// terms of the expansions, `(k h)^2` relative at `k h = 1e-3` and `e^{-2 k h} (k h)^2`
    /// at `k h = 30`.
    #[test]
    fn thick_and_thin_limits() {
        for nu in [0.0, 0.3, 0.45] {
            let half = half_space_wave_compliance(nu);
            let thick = correction(nu, 30.0);
            for v in [thick.zz, thick.ll, thick.tt, thick.zl] {
                assert!(v.abs() <= 1e-22, "nu {nu}: {v:e}");
            }
            let t = 1e-3;
            let layer = ElasticLayer {
                youngs_modulus_pa: 1e6,
                poisson_ratio: nu,
                thickness_m: t,
            };
            let g = layer.shear_modulus_pa();
            let c = layer.wave_compliance(1.0);
            let winkler = g * t / layer.constrained_modulus_pa();
            assert!((c.zz - winkler).abs() <= 1e-5 * winkler, "nu {nu}");
            assert!((c.ll - t).abs() <= 1e-5 * t);
            assert!((c.tt - t).abs() <= 1e-5 * t);
            // At t = 0 the correction cancels the half-space.
            let zero = correction(nu, 0.0);
            assert!((zero.zz + half.zz).abs() <= 1e-15);
            assert!((zero.ll + half.ll).abs() <= 1e-15);
            assert!((zero.tt + half.tt).abs() <= 1e-15);
            assert!((zero.zl + half.zl).abs() <= 1e-15);
        }
        // Nearly incompressible: 1 - 2 nu = 2e-6, k h = 0.05: h/M is 2e-6 h / (2 (1 - nu) G)
        // and the squeeze term (k h)^2 h / (3 G) (1 - 9/5 (k h)^2) = 8.3e-4 h / G (the series
        // of (sinh 2t - 2t)/(cosh 2t + 2t^2 + 1) at nu = 1/2 to t^5), so the sum within
        // 5e-5 relative: the next term, O((k h)^4) = 6e-6 times its coefficient, and the
        // compressibility's coupling to the squeeze, O((1 - 2 nu)/(k h)^2) = 8e-4 of h/M.
        let nu = 0.499999;
        let t = 0.05;
        let layer = ElasticLayer {
            youngs_modulus_pa: 3.0,
            poisson_ratio: nu,
            thickness_m: t,
        };
        let g = layer.shear_modulus_pa();
        let h_zz = layer.normal_compliance_m_per_pa(1.0);
        let want = t / layer.constrained_modulus_pa() + t * t * t / (3.0 * g) * (1.0 - 1.8 * t * t);
        assert!((h_zz - want).abs() <= 5e-5 * want, "{h_zz:e} vs {want:e}");
    }
}
