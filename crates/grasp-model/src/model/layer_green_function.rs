//! The real-space surface Green's function of an elastic layer bonded to a rigid core, as its
//! difference from the half-space of the same material: Hankel transforms of the Fourier
//! compliance of [`super::elastic_layer`], tabulated once per Poisson's ratio.
//!
//! A body's surface Green's function is `G(x) = (1/4 pi^2) int H(k) e^{i k.x} d^2k` with `H`
//! rotated from the wave's frame to the patch's axes. With `x = r (cos th, sin th)` and
//! `int e^{i k r cos(f - th)} cos(m f) df = 2 pi i^m J_m(kr) cos(m th)`, its difference from the
//! half-space's is
//!
//! ```text
//!   G_zz = d_zz(r)                       d_zz = (1/2pi) int dH_zz J0(kr) k dk
//!   G_11 = d_s(r) + (X^2 - Y^2) e_a(r)   d_s  = (1/2pi) int (dH_LL + dH_TT)/2 J0(kr) k dk
//!   G_22 = d_s(r) - (X^2 - Y^2) e_a(r)   e_a  = -(1/2pi) int (dH_LL - dH_TT)/2 J2(kr)/r^2 k dk
//!   G_12 = 2 X Y e_a(r)
//!   G_z1 = X e_c(r),  G_z2 = Y e_c(r)    e_c  = -(1/2pi) int dh_zL J1(kr)/r k dk
//! ```
//!
//! With `k = t/h` and `G k dH` a function of `t` and `nu` alone
//! ([`super::elastic_layer::correction`]), `d_zz` and `d_s` are `1/(G h)`, `e_a` is
//! `1/(G h^3)` and `e_c` is `1/(G h^2)` times functions of `rho = r/h` and `nu`: one table
//! serves every modulus and thickness. The integrands decay like `t^2 e^{-2t}`, so the
//! functions are analytic in the strip `|Im rho| < 2` and are tabulated on Chebyshev panels
//! (error about `rho_B^-n` for `n` points, Trefethen, Approximation Theory and Approximation
//! Practice, ch. 8); each point's transform is a composite Gauss-Legendre sum over `t` in
//! `[0, 18]` with panels of at most one period of the Bessel functions there.
//!
//! Far away the layered body's own Green's function (half-space plus difference) decays like
//! `K0(beta r/h) ~ e^{-beta r/h}`, `t = i beta` the zero of the denominator `D(t)` nearest the
//! real axis (`(3 - 4 nu) cos 2 beta + 8 nu^2 - 12 nu + 5 = 2 beta^2`: `beta` = 1.19 at
//! `nu = 0`, 0.91 at 0.3, 0.74 at 1/2; the anti-plane part's poles `i pi/2` decay faster).
//! Beyond [`cutoff_thicknesses`] (`22.5 / beta` thicknesses) it is below `1e-10` of its value at
//! one thickness, and the tables stop there: the caller takes the layered body's coefficient as
//! zero beyond.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::{Arc, Mutex, OnceLock};

use super::elastic_layer::correction;
use super::quadrature::{
    chebyshev_basis, chebyshev_coefficients, chebyshev_points, gauss_legendre,
};

/// Width of a panel of `rho`, thicknesses.
pub const PANEL_WIDTH: f64 = 2.0;

/// Chebyshev points per panel of `rho`: the Bernstein ellipse of a panel of width 2 through
/// the strip's edge `|Im rho| = 2` has `rho_B = 2 + 5^(1/2)`, so the error is about
/// `4.24^-16 = 1e-10` of the functions' bound in the strip.
pub const PANEL_POINTS: usize = 16;

/// The `t = k h` up to which the transforms integrate: the integrands are below
/// `t^2 e^{-2t} < 1e-13` of their scale beyond.
const T_MAX: f64 = 18.0;

/// Gauss-Legendre points per panel of `t`. A panel spans at most one period of the Bessel
/// functions at the panel's largest `rho` and at most one unit of `t` (the integrands' poles,
/// the zeros of `D(t)`, lie 0.74 or more off the real axis: `3.27^-20`).
const T_PANEL_POINTS: usize = 10;

/// The decay rate `beta` of a layer's Green's function with `r/h`: the smallest positive root
/// of `(3 - 4 nu) cos 2 beta + 8 nu^2 - 12 nu + 5 - 2 beta^2` (`D(i beta) = 0`), by bisection
/// on `(0, pi/2)` where that function falls from `8 (1 - nu)^2` through zero.
pub fn decay_rate(nu: f64) -> f64 {
    let f =
        |b: f64| (3.0 - 4.0 * nu) * (2.0 * b).cos() + 8.0 * nu * nu - 12.0 * nu + 5.0 - 2.0 * b * b;
    let (mut lo, mut hi) = (0.0, 0.5 * PI);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The distance, in layer thicknesses, beyond which a layer's own Green's function is below
/// `1e-10` of its value at one thickness: `22.5 / beta` (17.8 thicknesses at `nu = 0` to 30.4
/// at 1/2, the decay of `K0` included).
pub fn cutoff_thicknesses(nu: f64) -> f64 {
    22.5 / decay_rate(nu)
}

/// The radial functions `[d_zz, d_s, e_a, e_c]` of one Poisson's ratio, dimensionless (units
/// `1/(G h)`, `1/(G h)`, `1/(G h^3)`, `1/(G h^2)`), on Chebyshev panels of `rho` of width
/// [`PANEL_WIDTH`].
#[derive(Debug)]
pub struct RadialFunctions {
    /// Per panel, per function, the Chebyshev coefficients.
    panels: Vec<[[f64; PANEL_POINTS]; 4]>,
}

/// The process's radial functions, by `(nu bits, panels)`.
type Cache = Mutex<HashMap<(u64, usize), Arc<RadialFunctions>>>;

fn cache() -> &'static Cache {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Forgets the radial functions computed so far (a benchmark's run then pays for them as a
/// fresh process does); the next `RadialFunctions::of` computes them again, to the same bits.
pub fn forget_radial_functions() {
    if let Ok(mut c) = cache().lock() {
        c.clear();
    }
}

impl RadialFunctions {
    /// The functions of Poisson's ratio `nu` on `[0, panels PANEL_WIDTH]`, computed once per
    /// process for each `(nu, panels)` and shared (they depend on nothing else).
    pub fn of(nu: f64, panels: usize) -> Arc<RadialFunctions> {
        let cache = cache();
        let key = (nu.to_bits(), panels);
        if let Some(f) = cache.lock().ok().and_then(|c| c.get(&key).cloned()) {
            return f;
        }
        let f = Arc::new(RadialFunctions::compute(nu, panels));
        if let Ok(mut c) = cache.lock() {
            c.insert(key, Arc::clone(&f));
        }
        f
    }

    fn compute(nu: f64, panels: usize) -> Self {
        let x = chebyshev_points(PANEL_POINTS);
        use rayon::prelude::*;
        let panels = (0..panels)
            .into_par_iter()
            .map(|p| {
                let start = p as f64 * PANEL_WIDTH;
                let rule = HankelRule::new(nu, start + PANEL_WIDTH);
                let mut values = [[0.0; PANEL_POINTS]; 4];
                for (j, xj) in x.iter().enumerate() {
                    let f = rule.at(start + 0.5 * PANEL_WIDTH * (1.0 + xj));
                    for (v, fi) in values.iter_mut().zip(f) {
                        v[j] = fi;
                    }
                }
                values.map(|v| {
                    let c = chebyshev_coefficients(&v);
                    std::array::from_fn(|k| c[k])
                })
            })
            .collect();
        RadialFunctions { panels }
    }

    /// Tabulated reach, `rho` (layer thicknesses).
    pub fn reach(&self) -> f64 {
        self.panels.len() as f64 * PANEL_WIDTH
    }

    /// `[d_zz, d_s, e_a, e_c]` at `rho` in `[0, reach]` (dimensionless; module docs), with a
    /// scratch basis.
    pub fn at(&self, rho: f64, basis: &mut [f64; PANEL_POINTS]) -> [f64; 4] {
        let p = ((rho / PANEL_WIDTH).floor() as usize).min(self.panels.len() - 1);
        chebyshev_basis(2.0 * (rho / PANEL_WIDTH - p as f64) - 1.0, basis);
        self.panels[p].map(|c| c.iter().zip(basis.iter()).map(|(c, b)| c * b).sum())
    }
}

/// `d_zz(0)` of Poisson's ratio `nu` in units of `1/(G h)`: the correction of the normal
/// Green's function under the load itself, `(1/2 pi) int g_zz(t) dt` (negative: a layer is
/// stiffer).
pub fn normal_at_source(nu: f64) -> f64 {
    HankelRule::new(nu, 1.0).at(0.0)[0]
}

/// The functions beyond the tables, in the units of [`RadialFunctions::at`]: minus the
/// half-space's (`d_zz = -(1 - nu)/(2 pi rho)`, `d_s = -(2 - nu)/(4 pi rho)`,
/// `e_a = -nu/(4 pi rho^3)`, `e_c = -(1 - 2 nu)/(4 pi rho^2)`: the transforms of
/// [`super::elastic_layer::half_space_wave_compliance`], `int J_m(kr) dk = 1/r`), the layered
/// body's own Green's function being zero there.
pub fn far_field(nu: f64, rho: f64) -> [f64; 4] {
    let q = 1.0 / (4.0 * PI * rho);
    [
        -2.0 * (1.0 - nu) * q,
        -(2.0 - nu) * q,
        -nu * q / (rho * rho),
        -(1.0 - 2.0 * nu) * q / rho,
    ]
}

/// The transforms at the points of one panel of `rho`: composite Gauss-Legendre over `t` in
/// `[0, T_MAX]`, the integrands evaluated once per node.
struct HankelRule {
    /// `(t, weight)`.
    nodes: Vec<(f64, f64)>,
    /// Per node: `[zz, (ll + tt)/2, (ll - tt)/2, zl]` of [`correction`] (`G k dH`).
    g: Vec<[f64; 4]>,
}

impl HankelRule {
    /// The rule for `rho` up to `rho_max`: panels of at most `min(1, 2 pi / rho_max)`.
    fn new(nu: f64, rho_max: f64) -> Self {
        let width = (1.0_f64).min(2.0 * PI / rho_max);
        let n_panels = (T_MAX / width).ceil() as usize;
        let width = T_MAX / n_panels as f64;
        let (x, w) = gauss_legendre(T_PANEL_POINTS);
        let mut nodes = Vec::with_capacity(n_panels * T_PANEL_POINTS);
        for p in 0..n_panels {
            for (xi, wi) in x.iter().zip(&w) {
                nodes.push((width * (p as f64 + 0.5 * (1.0 + xi)), 0.5 * width * wi));
            }
        }
        let g = nodes
            .iter()
            .map(|&(t, _)| {
                let c = correction(nu, t);
                [c.zz, 0.5 * (c.ll + c.tt), 0.5 * (c.ll - c.tt), c.zl]
            })
            .collect();
        HankelRule { nodes, g }
    }

    /// `[d_zz, d_s, e_a, e_c]` at `rho` (module docs, with `k = t/h`): `d_zz = (1/2 pi) int
    /// g_zz J0(t rho) dt`, `e_a = -(1/2 pi) int g_a t^2 J2(t rho)/(t rho)^2 dt`, `e_c = -(1/2
    /// pi) int g_c t J1(t rho)/(t rho) dt`.
    fn at(&self, rho: f64) -> [f64; 4] {
        let mut s = [0.0; 4];
        for (&(t, w), g) in self.nodes.iter().zip(&self.g) {
            let x = t * rho;
            let j0 = libm::j0(x);
            let (j1_over_x, j2_over_x2) = bessel_ratios(x, j0);
            s[0] += w * g[0] * j0;
            s[1] += w * g[1] * j0;
            s[2] += w * g[2] * t * t * j2_over_x2;
            s[3] += w * g[3] * t * j1_over_x;
        }
        let c = 1.0 / (2.0 * PI);
        [c * s[0], c * s[1], -c * s[2], -c * s[3]]
    }
}

/// `(J1(x)/x, J2(x)/x^2)`, by their series below `x = 1/2` (truncation below `1e-12`) and from
/// `J0`, `J1` above (`J2 = 2 J1/x - J0`; Abramowitz and Stegun 9.1.10, 9.1.27).
fn bessel_ratios(x: f64, j0: f64) -> (f64, f64) {
    if x < 0.5 {
        let x2 = x * x;
        let j1 = 0.5 - x2 / 16.0 + x2 * x2 / 384.0 - x2 * x2 * x2 / 18432.0;
        let j2 = 0.125 - x2 / 96.0 + x2 * x2 / 3072.0 - x2 * x2 * x2 / 184320.0;
        (j1, j2)
    } else {
        let j1 = libm::j1(x) / x;
        (j1, (2.0 * j1 - j0) / (x * x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `beta` against the helper values of the module docs and `cos beta = beta` at 1/2
    /// (Dottie's number 0.739085).
    #[test]
    fn decay_rates() {
        assert!((decay_rate(0.5) - 0.739_085_133_2).abs() < 1e-9);
        assert!((decay_rate(0.0) - 1.1896).abs() < 1e-4);
        assert!((decay_rate(0.3) - 0.9128).abs() < 1e-4);
    }

    /// The tables reproduce their own transforms between the Chebyshev points. Tolerance 1e-8
    /// of the functions' scale: the interpolation error bound `4.24^-16 = 1e-10` (the Bernstein
    /// ellipse of a panel through the strip's edge `|Im rho| = 2`) times the functions' bound
    /// in the strip, a few times their scale.
    #[test]
    fn tables_interpolate_their_transforms() {
        for nu in [0.0, 0.3, 0.49] {
            let panels = 6;
            let f = RadialFunctions::compute(nu, panels);
            let mut basis = [0.0; PANEL_POINTS];
            let scale = f.at(0.0, &mut basis)[0].abs();
            for rho in [0.0, 0.37, 1.0, 2.71, 5.5, 9.93] {
                let p = (rho / PANEL_WIDTH).floor() + 1.0;
                let want = HankelRule::new(nu, p * PANEL_WIDTH).at(rho);
                let got = f.at(rho, &mut basis);
                for i in 0..4 {
                    assert!(
                        (got[i] - want[i]).abs() <= 1e-8 * scale,
                        "nu {nu}, rho {rho}, function {i}: {} vs {}",
                        got[i],
                        want[i]
                    );
                }
            }
        }
    }
}
