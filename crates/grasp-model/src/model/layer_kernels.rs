//! The influence coefficients of an elastic layer bonded to a rigid core, as corrections added
//! to the half-space coefficients of its material (the exact rectangle integrals of
//! [`super::influence`]): the difference Green's function of
//! [`super::layer_green_function`] averaged over each source element.
//!
//! An element's average is a tensor Gauss-Legendre rule over sub-elements of at most one
//! thickness, of the order that brings a function analytic within two thicknesses of the real
//! axis (the difference functions' strip) to `AVERAGE_TOLERANCE` (Trefethen, Approximation
//! Theory and Approximation Practice, ch. 19: error `~ rho^-2n` for the Bernstein ellipse
//! `rho` through the singularity). A source element wholly beyond
//! [`super::layer_green_function::cutoff_thicknesses`] gets minus the body's own half-space
//! coefficient: the layered body's coefficient there is zero. The coefficients are even in
//! both offsets but `12` (odd in both), `n1` (odd along `t1`) and `n2` (odd along `t2`): one
//! quadrant is computed and mirrored.

use super::elastic_layer::ElasticLayer;
use super::influence::{
    Block, BlockKernels, GridSpec, KernelTable, PairConstants, RectangleIntegrals,
};
use super::layer_green_function::{
    cutoff_thicknesses, far_field, RadialFunctions, PANEL_POINTS, PANEL_WIDTH,
};
use super::material::Material;
use super::quadrature::gauss_legendre;

/// Target error of an element average, relative to the functions' scale.
const AVERAGE_TOLERANCE: f64 = 1e-11;

/// Which side of the contact a body is on: the coupling blocks enter the pair's compliance
/// with `+` for the object and `-` for the finger (model.md: `kappa_o - kappa_f`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The fingertip.
    Finger,
    /// The object.
    Object,
}

impl Side {
    /// `+1` for the object, `-1` for the finger.
    fn sign(self) -> f64 {
        match self {
            Side::Finger => -1.0,
            Side::Object => 1.0,
        }
    }
}

/// One layer's corrections on one grid.
pub struct LayerKernels<'a> {
    layer: &'a ElasticLayer,
    grid: GridSpec,
    functions: std::sync::Arc<RadialFunctions>,
    /// The cutoff distance, in thicknesses.
    cutoff: f64,
    rule: ElementRule,
}

impl<'a> LayerKernels<'a> {
    /// The corrections of `layer` on `grid` (the radial functions tabulated up to the grid's
    /// reach or the cutoff, whichever is nearer).
    pub fn new(layer: &'a ElasticLayer, grid: &GridSpec) -> Self {
        let h = layer.thickness_m;
        let cutoff = cutoff_thicknesses(layer.poisson_ratio);
        let reach = (grid.nx as f64 * grid.hx).hypot(grid.ny as f64 * grid.hy) / h;
        let panels = (reach.min(cutoff) / PANEL_WIDTH).ceil().max(1.0) as usize;
        LayerKernels {
            layer,
            grid: *grid,
            functions: RadialFunctions::of(layer.poisson_ratio, panels),
            cutoff,
            rule: ElementRule::new(grid, h),
        }
    }

    /// Adds the layer's correction to every offset of `table` (on this grid), the layer being
    /// the body on `side` of the contact (its coupling blocks with that side's sign), and marks
    /// the table's coupling blocks present or not.
    pub fn add_to(&self, table: &mut KernelTable, side: Side) {
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        use rayon::prelude::*;
        let quadrant: Vec<Option<[f64; 6]>> = (0..nx * ny)
            .into_par_iter()
            .map_init(
                || [0.0; PANEL_POINTS],
                |basis, k| {
                    let (di, dj) = (k / ny, k % ny);
                    (!self.beyond(di, dj)).then(|| self.average(di, dj, side.sign(), basis))
                },
            )
            .collect();
        let own = BlockKernels::new(&self.grid, &body_constants(&self.layer.material(), side));
        for (k, v) in quadrant.iter().enumerate() {
            let (di, dj) = (k / ny, k % ny);
            // The offset and its mirrors, each once.
            for sx in if di == 0 { &[1][..] } else { &[1, -1][..] } {
                for sy in if dj == 0 { &[1][..] } else { &[1, -1][..] } {
                    let a = (nx as isize - 1 + sx * di as isize) as usize;
                    let b = (ny as isize - 1 + sy * dj as isize) as usize;
                    let add = match v {
                        Some(v) => std::array::from_fn(|blk| v[blk] * parity(blk, *sx, *sy)),
                        // The layered body's coefficient is zero there: minus its own
                        // half-space one, computed as the table's (same offset, same bits).
                        None => own_coefficients(&own, &self.grid, a, b).map(|x| -x),
                    };
                    let target = table.at_mut(a, b);
                    for (t, v) in target.iter_mut().zip(add) {
                        *t += v;
                    }
                }
            }
        }
        table.refresh_coupled();
    }

    /// True when the source element `(di, dj)` elements away lies wholly beyond the cutoff.
    fn beyond(&self, di: usize, dj: usize) -> bool {
        let gx = (di as f64 - 0.5).max(0.0) * self.grid.hx;
        let gy = (dj as f64 - 0.5).max(0.0) * self.grid.hy;
        gx.hypot(gy) >= self.cutoff * self.layer.thickness_m
    }

    /// The correction's average over the source element `(di, dj)` elements away (`di, dj >=
    /// 0`), m/N, per block, the coupling with the side's `sign`.
    fn average(
        &self,
        di: usize,
        dj: usize,
        sign: f64,
        basis: &mut [f64; PANEL_POINTS],
    ) -> [f64; 6] {
        let h = self.layer.thickness_m;
        let nu = self.layer.poisson_ratio;
        let (cx, cy) = (di as f64 * self.grid.hx / h, dj as f64 * self.grid.hy / h);
        let reach = self.functions.reach();
        let mut sum = [0.0; 6];
        for &(u, wu) in &self.rule.x {
            for &(v, wv) in &self.rule.y {
                let (x, y) = (cx + u, cy + v);
                let rho = x.hypot(y);
                let f = match rho <= reach {
                    true => self.functions.at(rho, basis),
                    false => far_field(nu, rho),
                };
                let w = wu * wv;
                let aniso = (x * x - y * y) * f[2];
                sum[Block::Nn as usize] += w * f[0];
                sum[Block::T11 as usize] += w * (f[1] + aniso);
                sum[Block::T22 as usize] += w * (f[1] - aniso);
                sum[Block::T12 as usize] += w * 2.0 * x * y * f[2];
                sum[Block::N1 as usize] += w * x * f[3];
                sum[Block::N2 as usize] += w * y * f[3];
            }
        }
        // The half-space's `H_zL = -i (1 - 2 nu)/(2 G k)` gives `G_z1 = -(1/2pi) int h_zL J1 k dk
        // = kappa x / r^2`, model.md's object side: the correction's coupling enters with the
        // side's sign, as `kappa` does.
        let scale = 1.0 / (self.layer.shear_modulus_pa() * h);
        std::array::from_fn(|blk| match blk {
            4 | 5 => sign * sum[blk] * scale,
            _ => sum[blk] * scale,
        })
    }
}

/// The body's own half-space coefficients at table index `(a, b)`, computed as
/// [`KernelTable::half_space`] computes them.
fn own_coefficients(k: &BlockKernels, grid: &GridSpec, a: usize, b: usize) -> [f64; 6] {
    let di = a as f64 - (grid.nx as f64 - 1.0);
    let dj = b as f64 - (grid.ny as f64 - 1.0);
    let r = RectangleIntegrals::for_offset(di * grid.hx, dj * grid.hy, grid.hx, grid.hy);
    [
        k.nn(&r),
        k.t11(&r),
        k.t22(&r),
        k.t12(&r),
        k.n1(&r),
        k.n2(&r),
    ]
}

/// The factor a block picks up when the offset is mirrored by `(sx, sy)`: `12` is odd in both
/// directions, `n1` in `x`, `n2` in `y`; the rest are even.
fn parity(block: usize, sx: isize, sy: isize) -> f64 {
    (match block {
        3 => sx * sy,
        4 => sx,
        5 => sy,
        _ => 1,
    }) as f64
}

/// The half-space constants of one body on `side` of a contact whose other body is rigid.
pub fn body_constants(material: &Material, side: Side) -> PairConstants {
    match side {
        Side::Finger => PairConstants::new(material, &Material::Rigid),
        Side::Object => PairConstants::new(&Material::Rigid, material),
    }
}

/// Gauss-Legendre points and weights over one element, in layer thicknesses relative to its
/// centre, the weights dividing by its area (an average).
struct ElementRule {
    x: Vec<(f64, f64)>,
    y: Vec<(f64, f64)>,
}

impl ElementRule {
    fn new(grid: &GridSpec, h: f64) -> Self {
        ElementRule {
            x: composite_rule(grid.hx / h),
            y: composite_rule(grid.hy / h),
        }
    }
}

/// A composite Gauss-Legendre rule averaging over `[-w/2, w/2]` (`w` in layer thicknesses):
/// sub-intervals of at most one thickness, each of the order that brings a function analytic
/// within two thicknesses of the real axis to [`AVERAGE_TOLERANCE`].
fn composite_rule(w: f64) -> Vec<(f64, f64)> {
    let m = w.ceil().max(1.0) as usize;
    let sub = w / m as f64;
    let b = 2.0 / (0.5 * sub);
    let rho = b + (b * b + 1.0).sqrt();
    let n = ((-AVERAGE_TOLERANCE.ln()) / (2.0 * rho.ln()))
        .ceil()
        .clamp(2.0, 16.0) as usize;
    let (nodes, weights) = gauss_legendre(n);
    let mut out = Vec::with_capacity(m * n);
    for s in 0..m {
        let centre = -0.5 * w + (s as f64 + 0.5) * sub;
        for (x, wt) in nodes.iter().zip(&weights) {
            out.push((centre + 0.5 * sub * x, 0.5 * wt / m as f64));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::elastic_layer::{correction, WaveCompliance};
    use std::f64::consts::PI;

    fn layer(nu: f64, h: f64) -> ElasticLayer {
        ElasticLayer {
            youngs_modulus_pa: 2e6,
            poisson_ratio: nu,
            thickness_m: h,
        }
    }

    /// The correction a layer adds to a table on `side`, per offset (the table after minus
    /// before).
    fn correction_table(l: &ElasticLayer, grid: &GridSpec, side: Side) -> KernelTable {
        let pair = body_constants(&l.material(), side);
        let before = KernelTable::half_space(grid, &pair).unwrap();
        let mut out = before.clone();
        LayerKernels::new(l, grid).add_to(&mut out, side);
        for a in 0..2 * grid.nx - 1 {
            for b in 0..2 * grid.ny - 1 {
                let o = out.at_mut(a, b);
                for (v, b) in o.iter_mut().zip(before.at(a, b)) {
                    *v -= b;
                }
            }
        }
        out
    }

    /// The element-averaged correction at offset `(dx, dy)` metres by an independent route:
    /// the 2-D inverse Fourier integral `(1/4 pi^2) int dH(k) S(k) e^{i k.X} d^2k` in polar
    /// coordinates (Gauss-Legendre in `k` up to `k h = 30`, the trapezoid rule in the angle,
    /// spectrally accurate for a periodic integrand), with the wave-frame entries rotated to
    /// the patch's axes and `S` the transform of the element's average,
    /// `sinc(k_x hx/2) sinc(k_y hy/2)`. Blocks in [`Block`] order; the coupling as the object
    /// side's.
    fn fourier_average(l: &ElasticLayer, hx: f64, hy: f64, dx: f64, dy: f64) -> [f64; 6] {
        let h = l.thickness_m;
        let g = l.shear_modulus_pa();
        let sinc = |x: f64| {
            if x.abs() < 1e-8 {
                1.0 - x * x / 6.0
            } else {
                x.sin() / x
            }
        };
        let reach = dx.hypot(dy) + hx + hy;
        let width = (0.2 / h).min(1.0 / reach);
        let kmax = 30.0 / h;
        let panels = (kmax / width).ceil() as usize;
        let width = kmax / panels as f64;
        let (gx, gw) = gauss_legendre(16);
        let m = 720;
        let mut out = [0.0; 6];
        for p in 0..panels {
            for (xi, wi) in gx.iter().zip(&gw) {
                let k = width * (p as f64 + 0.5 * (1.0 + xi));
                let wk = 0.5 * width * wi;
                let c: WaveCompliance = correction(l.poisson_ratio, k * h);
                for j in 0..m {
                    let phi = 2.0 * PI * j as f64 / m as f64;
                    let (cs, sn) = (phi.cos(), phi.sin());
                    let (kx, ky) = (k * cs, k * sn);
                    let s = sinc(0.5 * kx * hx) * sinc(0.5 * ky * hy);
                    let (cosx, sinx) = ((kx * dx + ky * dy).cos(), (kx * dx + ky * dy).sin());
                    // dH = c / (G k); d^2k = k dk dphi: the k cancels.
                    let w = wk * (2.0 * PI / m as f64) * s / g;
                    out[0] += w * c.zz * cosx;
                    out[1] += w * (cs * cs * c.ll + sn * sn * c.tt) * cosx;
                    out[2] += w * (sn * sn * c.ll + cs * cs * c.tt) * cosx;
                    out[3] += w * cs * sn * (c.ll - c.tt) * cosx;
                    // Re(i zl cos(phi) e^{i k.X}) = -zl cos(phi) sin(k.X).
                    out[4] -= w * cs * c.zl * sinx;
                    out[5] -= w * sn * c.zl * sinx;
                }
            }
        }
        out.map(|v| v / (4.0 * PI * PI))
    }

    /// The tabulated, element-averaged correction against the independent Fourier integral,
    /// every block, at offsets from the element itself to six thicknesses, on elements
    /// smaller and larger than the thickness. Tolerance 1e-6 of the half-space self term
    /// (the figure; the two agree to about 1e-9 of it, the Fourier integral's own
    /// accuracy).
    #[test]
    fn corrections_match_an_independent_fourier_integral() {
        for (nu, h, hx, hy) in [
            (0.3, 1e-3, 0.3e-3, 0.45e-3),
            (0.45, 1e-3, 1.7e-3, 1.1e-3),
            (0.0, 2e-3, 0.5e-3, 0.5e-3),
        ] {
            let l = layer(nu, h);
            let grid = GridSpec {
                nx: 7,
                ny: 6,
                hx,
                hy,
            };
            let table = correction_table(&l, &grid, Side::Object);
            let own = KernelTable::half_space(&grid, &body_constants(&l.material(), Side::Object))
                .unwrap();
            let scale = own.centre()[0];
            for (di, dj) in [
                (0_isize, 0_isize),
                (1, 0),
                (0, -1),
                (2, 3),
                (-3, 1),
                (6, -5),
            ] {
                let got = table.at((di + 6) as usize, (dj + 5) as usize);
                let want = fourier_average(&l, hx, hy, di as f64 * hx, dj as f64 * hy);
                for b in 0..6 {
                    assert!(
                        (got[b] - want[b]).abs() <= 1e-6 * scale,
                        "nu {nu}, offset ({di}, {dj}), block {b}: table {:e}, Fourier {:e} (scale {scale:e})",
                        got[b],
                        want[b]
                    );
                }
            }
        }
    }

    /// A layered body's own coefficients (its half-space's plus the correction) vanish far
    /// from the source, every block: its Green's function decays like `K0(beta r/h)`
    /// ([`super::super::layer_green_function::decay_rate`]). At three quarters of the cutoff
    /// they are below 1e-5 of the half-space's normal one there (`e^{-0.75 * 22.5} (r/h)` is
    /// about 2e-6 of it), and beyond the cutoff zero (the pair's own sum, to its round-off).
    /// A correction of the wrong sign (the coupling enters with the side's sign) would leave
    /// twice the half-space's value instead.
    #[test]
    fn a_layered_body_has_no_far_field() {
        for side in [Side::Finger, Side::Object] {
            for nu in [0.0, 0.3, 0.49] {
                let h = 1e-4;
                let l = layer(nu, h);
                let grid = GridSpec {
                    nx: 36,
                    ny: 33,
                    hx: 1e-4,
                    hy: 0.95e-4,
                };
                let own =
                    KernelTable::half_space(&grid, &body_constants(&l.material(), side)).unwrap();
                let mut total = own.clone();
                LayerKernels::new(&l, &grid).add_to(&mut total, side);
                let cutoff = cutoff_thicknesses(nu);
                let c = (0.75 * cutoff).ceil() as isize;
                let d = (0.55 * cutoff).ceil() as isize;
                for (di, dj) in [(c, 0), (0, -c - 1), (-d, d), (c, 3), (-35, -32), (35, 0)] {
                    let (a, b) = ((di + 35) as usize, (dj + 32) as usize);
                    let r = (di as f64 * grid.hx).hypot(dj as f64 * grid.hy) / h;
                    for blk in 0..6 {
                        let half = own.at(a, b)[0].abs();
                        let left = total.at(a, b)[blk].abs();
                        let bound = match r >= cutoff + 1.0 {
                            true => 1e-15 * half,
                            false => 1e-5 * half,
                        };
                        assert!(
                            left <= bound,
                            "{side:?}, nu {nu}, offset ({di}, {dj}) ({r:.1} h), block {blk}: {left:e} left of {half:e}"
                        );
                    }
                }
                // Near the source the layer is stiffer than its half-space, not zero.
                assert!(total.centre()[0] < own.centre()[0] && total.centre()[0] > 0.0);
            }
        }
    }
}
