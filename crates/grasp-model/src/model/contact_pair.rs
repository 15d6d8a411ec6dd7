//! The two bodies of one contact as its compliance sees them: each a half-space of its
//! material, or an elastic layer bonded to a rigid core ([`super::elastic_layer`]). The
//! contact's compliance is the sum over its two bodies (model.md): the half-space kernels of
//! both ([`super::influence`]) plus each layered body's correction
//! ([`super::layer_kernels`]).

use super::elastic_layer::ElasticLayer;
use super::influence::{BlockKernels, GridSpec, KernelTable, PairConstants, RectangleIntegrals};
use super::layer_green_function::normal_at_source;
use super::layer_kernels::{body_constants, LayerKernels, Side};
use super::material::Material;
use crate::error::OutOfMemory;

/// The wavenumber, times the contact radius, at which
/// [`ContactPair::contact_radius_estimate_m`] reads a layer's compliance (fitted to two solved
/// contacts on a 1 mm pad; 3.4 would be exact in the Winkler limit, 4.3 on a thin
/// incompressible layer).
pub const CONTACT_WAVENUMBER: f64 = 2.6;

/// A layer whose correction changes its body's largest coefficient by less than this fraction
/// behaves as a half-space: a warning says so.
pub const HALF_SPACE_LIKE: f64 = 1e-6;

/// A contact's two bodies (finger and object).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPair {
    /// The half-space constants of the pair's materials.
    pub constants: PairConstants,
    /// The fingertip's material.
    pub finger_material: Material,
    /// The object's material.
    pub object_material: Material,
    /// The fingertip's layer, when it is a pad on a rigid core.
    pub finger_layer: Option<ElasticLayer>,
    /// The object's layer, when it is a coating on a rigid core.
    pub object_layer: Option<ElasticLayer>,
}

impl ContactPair {
    /// The pair of `finger` and `object`, each with its layer thickness (m) if it has one.
    pub fn new(
        finger: &Material,
        finger_layer_m: Option<f64>,
        object: &Material,
        object_layer_m: Option<f64>,
    ) -> Self {
        ContactPair {
            constants: PairConstants::new(finger, object),
            finger_material: *finger,
            object_material: *object,
            finger_layer: finger_layer_m.and_then(|h| ElasticLayer::of(finger, h)),
            object_layer: object_layer_m.and_then(|h| ElasticLayer::of(object, h)),
        }
    }

    /// True when a body is a layer.
    pub fn is_layered(&self) -> bool {
        self.finger_layer.is_some() || self.object_layer.is_some()
    }

    /// The compliance entries of every offset of `grid` (m/N): the half-space kernels of the
    /// pair plus each layer's correction. Without layers exactly
    /// [`KernelTable::half_space`].
    pub fn kernel_table(&self, grid: &GridSpec) -> Result<KernelTable, OutOfMemory> {
        let mut table = KernelTable::half_space(grid, &self.constants)?;
        if !self.is_layered() {
            return Ok(table);
        }
        for (layer, side) in [
            (self.finger_layer, Side::Finger),
            (self.object_layer, Side::Object),
        ] {
            if let Some(l) = layer {
                LayerKernels::new(&l, grid).add_to(&mut table, side);
            }
        }
        Ok(table)
    }

    /// The compliance entries of one body of the pair alone on `grid` (m/N; the other body
    /// rigid): its half-space kernels plus its layer's correction, the coupling with its side's
    /// sign. The pair's table is the sum of its two bodies' (to round-off).
    pub fn body_table(&self, grid: &GridSpec, side: Side) -> Result<KernelTable, OutOfMemory> {
        let (material, layer) = match side {
            Side::Finger => (&self.finger_material, self.finger_layer),
            Side::Object => (&self.object_material, self.object_layer),
        };
        let mut table = KernelTable::half_space(grid, &body_constants(material, side))?;
        if let Some(l) = layer {
            LayerKernels::new(&l, grid).add_to(&mut table, side);
        }
        Ok(table)
    }

    /// The pair's normal surface compliance for a pressure wave of wavenumber `k_per_m`, m/Pa:
    /// `sum_b H_zz,b(k)` (a half-space's `2 (1 - nu_b^2)/(E_b k)`; a layer's of
    /// [`ElasticLayer::normal_compliance_m_per_pa`]).
    pub fn normal_compliance_m_per_pa(&self, k_per_m: f64) -> f64 {
        let body = |m: &Material, layer: &Option<ElasticLayer>| match layer {
            Some(l) => l.normal_compliance_m_per_pa(k_per_m),
            None => 2.0 * m.normal_factor_per_pa() / k_per_m,
        };
        body(&self.finger_material, &self.finger_layer)
            + body(&self.object_material, &self.object_layer)
    }

    /// An estimate of the contact radius, m, of a body of gap `r^2 / (2 R)` pressed by
    /// `load_n` newtons: Hertz's `a = (3 P R / (4 E*))^(1/3)` (Johnson 4.22) on half-spaces; on
    /// a layer Hertz's with the modulus the pair shows a pressure wave of wavenumber
    /// `k = CONTACT_WAVENUMBER / a`, `E_eff = 2 / (k H_zz(k))` (the half-space's `E*` where
    /// the layer is thick), solved for `a` by a damped fixed-point iteration. An estimate (the
    /// cold start's contact circle, `--explain-frames`): with [`CONTACT_WAVENUMBER`] it is
    /// within 5 % of the solved radius of a 10 mm or 5 mm sphere on a 1 mm pad (`a` about 1.5
    /// to 1.8 thicknesses); in the Winkler limit (`a >> h`) it is 7 % small (exact there with
    /// 3.4), on a thin incompressible layer 20 % small (exact with 4.3).
    pub fn contact_radius_estimate_m(&self, load_n: f64, radius_m: f64) -> f64 {
        let e_star = 1.0 / self.constants.normal;
        let hertz = (3.0 * load_n * radius_m / (4.0 * e_star)).cbrt();
        if !(self.is_layered() && hertz.is_finite() && hertz > 0.0) {
            return hertz;
        }
        let mut a = hertz;
        for _ in 0..100 {
            let k = CONTACT_WAVENUMBER / a;
            let e_eff = 2.0 / (k * self.normal_compliance_m_per_pa(k));
            let next = (3.0 * load_n * radius_m / (4.0 * e_eff)).cbrt();
            // Geometric damping: the map shrinks `a` where the layer stiffens, a contraction
            // in `log a`.
            let damped = (a * next).sqrt();
            if !(damped.is_finite() && damped > 0.0) {
                return hertz;
            }
            if ((damped - a) / a).abs() < 1e-9 {
                return damped;
            }
            a = damped;
        }
        a
    }

    /// Warnings about the layers on `grid`, each naming its field (`finger_path` is the
    /// finger's JSON path, `finger` its name): a layer thinner than the elements, whose
    /// response (spread over about one thickness) the grid cannot resolve, and a layer so thick
    /// that it changes its body's coefficients by less than [`HALF_SPACE_LIKE`] (its element's
    /// self coefficient, the largest: `|d_zz(0)| / (G h)` against the half-space's, for
    /// elements much smaller than the thickness), which is then a half-space.
    pub fn layer_warnings(&self, grid: &GridSpec, finger_path: &str, finger: &str) -> Vec<String> {
        let mut out = Vec::new();
        for (layer, side) in [
            (self.finger_layer, Side::Finger),
            (self.object_layer, Side::Object),
        ] {
            let Some(l) = layer else { continue };
            let path = match side {
                Side::Finger => format!("{finger_path}.material.layer_thickness_m"),
                Side::Object => {
                    format!("object.material.layer_thickness_m (at {finger_path} `{finger}`)")
                }
            };
            let h = l.thickness_m;
            let element = grid.hx.max(grid.hy);
            if element > h {
                let n = [grid.nx as f64 * grid.hx / h, grid.ny as f64 * grid.hy / h]
                    .map(|n| n.ceil() as usize);
                out.push(format!(
                    "{path}: the layer ({h:e} m) is thinner than {finger_path}'s elements \
                     ({element:.3e} m), so the grid cannot resolve its response, which spreads \
                     over about one thickness; use elements of at most the thickness \
                     (patch.grid [{}, {}] or more, or a smaller patch.size)",
                    n[0], n[1]
                ));
            }
            let own = BlockKernels::new(grid, &body_constants(&l.material(), side));
            let self_coefficient =
                own.nn(&RectangleIntegrals::for_offset(0.0, 0.0, grid.hx, grid.hy));
            let d0 = normal_at_source(l.poisson_ratio);
            let change = d0.abs() / (l.shear_modulus_pa() * h) / self_coefficient;
            if change < HALF_SPACE_LIKE {
                out.push(format!(
                    "{path}: the layer ({h:e} m) changes {finger_path}'s coefficients by \
                     {change:.1e} of the largest, less than {HALF_SPACE_LIKE:e}: it is an elastic \
                     half-space to that accuracy; omit layer_thickness_m (the same answer without \
                     the layer's kernels)"
                ));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::influence::patch_compliance;

    /// Seeded pseudo-random numbers in [0, 1) (64-bit LCG).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// With layers on either or both bodies (thin and thick against the elements, every
    /// Poisson's ratio) the patch compliance stays symmetric and positive definite, every block
    /// and reduction: a wrong sign or a mirrored block would break one or the other.
    #[test]
    fn layered_compliance_is_symmetric_positive_definite() {
        let mut seed = 0x9e3779b97f4a7c15;
        for _ in 0..16 {
            let body = |seed: &mut u64| {
                let m = Material::Elastic {
                    youngs_modulus_pa: 10f64.powf(5.0 + 6.0 * lcg(seed)),
                    poisson_ratio: 0.499 * lcg(seed),
                };
                let layer = (lcg(seed) < 0.7).then(|| 1e-4 * 10f64.powf(2.0 * lcg(seed) - 0.5));
                (m, layer)
            };
            let (f, fl) = body(&mut seed);
            let (o, ol) = body(&mut seed);
            let pair = ContactPair::new(&f, fl, &o, ol);
            let grid = GridSpec {
                nx: 1 + (lcg(&mut seed) * 7.0) as usize,
                ny: 1 + (lcg(&mut seed) * 7.0) as usize,
                hx: 1e-4 * (0.3 + lcg(&mut seed)),
                hy: 1e-4 * (0.3 + lcg(&mut seed)),
            };
            let table = pair.kernel_table(&grid).expect("a small table");
            for nt in 0..=2 {
                let c = patch_compliance(&table, nt);
                let asym = (&c - c.transpose()).abs().max();
                assert!(asym <= 1e-14 * c.abs().max(), "not symmetric: {asym}");
                let min = nalgebra::SymmetricEigen::new(c.clone()).eigenvalues.min();
                assert!(
                    min > 0.0,
                    "not positive definite: {min:e}, {pair:?}, {grid:?}"
                );
            }
        }
    }

    /// The contact radius estimate is Hertz's on half-spaces (exactly), and within the
    /// documented bounds of the two thin limits: Winkler (`a^4 = 4 R h P / (pi M)`, 7 % small)
    /// and the squeeze film (`a^6 = 32 R h^3 P / (pi G)`, 20 % small); the layer never makes it
    /// larger than Hertz's.
    #[test]
    fn contact_radius_estimates() {
        let (r, p): (f64, f64) = (0.05, 3.0);
        let pad = |nu: f64| Material::Elastic {
            youngs_modulus_pa: 2e6,
            poisson_ratio: nu,
        };
        let half = ContactPair::new(&pad(0.3), None, &Material::Rigid, None);
        let e_star = 2e6 / (1.0 - 0.09);
        let hertz = (3.0 * p * r / (4.0 * e_star)).cbrt();
        assert_eq!(half.contact_radius_estimate_m(p, r), hertz);
        let h = hertz / 50.0;
        let winkler = ContactPair::new(&pad(0.3), Some(h), &Material::Rigid, None);
        let m = 2e6 * 0.7 / (1.3 * 0.4);
        let exact = (4.0 * r * h * p / (std::f64::consts::PI * m)).powf(0.25);
        let est = winkler.contact_radius_estimate_m(p, r);
        assert!(
            est < hertz && (est / exact - 1.0).abs() < 0.08,
            "{est:e} vs {exact:e}"
        );
        let squeeze = ContactPair::new(&pad(0.4999999), Some(h), &Material::Rigid, None);
        let g = 2e6 / (2.0 * 1.4999999);
        let exact = (32.0 * r * h.powi(3) * p / (std::f64::consts::PI * g)).powf(1.0 / 6.0);
        let est = squeeze.contact_radius_estimate_m(p, r);
        assert!(
            est < hertz && (est / exact - 1.0).abs() < 0.25,
            "{est:e} vs {exact:e}"
        );
    }
}
