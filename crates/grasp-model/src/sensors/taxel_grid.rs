//! The layout of a taxel grid on a finger's patch: each taxel's centre and square (along
//! `t1`, `t2`, from the contact point; the centres are the sensor grid's points, laid out as
//! every kind's) and the quadrature over a taxel's area at depth.

use crate::model::influence_at_depth::RotatedSquare;
use crate::model::quadrature::gauss_legendre;
use crate::scene::sensor_kind::SensorKind;
use crate::scene::sensor_spec::{TaxelGridSpec, GAUSS_POINTS_PER_CELL_SIDE};

/// One quadrature point of a taxel: its offset from the taxel's centre in the taxel's own
/// axes and its weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadraturePoint {
    /// Offset from the taxel's centre along the taxel's sides, m.
    pub offset_m: [f64; 2],
    /// Its share of the taxel's area, m^2.
    pub weight_m2: f64,
}

/// A taxel grid laid out on its finger's patch.
#[derive(Debug, Clone, PartialEq)]
pub struct TaxelGrid {
    /// The grid as written.
    pub spec: TaxelGridSpec,
}

impl TaxelGrid {
    /// The grid of `spec` (checked by the scene's validation).
    pub fn new(spec: &TaxelGridSpec) -> TaxelGrid {
        TaxelGrid { spec: spec.clone() }
    }

    /// Every taxel's square, row-major (`k = i ny + j`, `i` along the grid's first side),
    /// centred on the grid's points (`GridLayout::points_m`).
    pub fn squares(&self) -> Vec<RotatedSquare> {
        let s = &self.spec;
        s.layout()
            .points_m()
            .into_iter()
            .map(|centre_m| RotatedSquare {
                centre_m,
                half_side_m: s.size_m / 2.0,
                angle_rad: s.rotation_rad,
            })
            .collect()
    }

    /// The quadrature over one taxel at depth: composite Gauss-Legendre, the taxel cut into
    /// `cells_per_side` squares a side (each no wider than the depth, over which the field at
    /// depth varies smoothly) with 4 x 4 points each; offsets in the taxel's own axes. Its
    /// error, measured against the same rule on cells half as wide under the Hertz example
    /// (cells 0.92 of the depth wide), is 6e-8 of the load per taxel
    /// (tests/taxel_readings.rs, `the_quadrature_over_a_taxel_is_converged`).
    pub fn quadrature(&self) -> Vec<QuadraturePoint> {
        let cells = self.spec.cells_per_side().max(1);
        let cell = self.spec.size_m / cells as f64;
        let half = self.spec.size_m / 2.0;
        let (nodes, weights) = gauss_legendre(GAUSS_POINTS_PER_CELL_SIDE);
        let mut line = Vec::with_capacity(cells * GAUSS_POINTS_PER_CELL_SIDE);
        for c in 0..cells {
            let mid = -half + (c as f64 + 0.5) * cell;
            for (x, &w) in nodes.iter().zip(&weights) {
                line.push((mid + x * cell / 2.0, w * cell / 2.0));
            }
        }
        let mut out = Vec::with_capacity(line.len() * line.len());
        for &(u, wu) in &line {
            for &(v, wv) in &line {
                out.push(QuadraturePoint {
                    offset_m: [u, v],
                    weight_m2: wu * wv,
                });
            }
        }
        out
    }
}
