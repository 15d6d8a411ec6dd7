//! `fingers[i].sensor` as written: a tactile sensor in the finger's pad, of one or more
//! kinds: a grid of taxels at a depth below the pad's surface, a grid of markers on it, an
//! optical gel's image of it (`super::gel_spec`); and the work each read-out takes (each kind
//! a [`SensorKind`]).
//!
//! A taxel reads the three-axis force (normal and two shear, along the contact frame's `n`,
//! `t1`, `t2`, N) that crosses its square at the depth (`crate::model::influence_at_depth`);
//! at depth 0 it reads the surface tractions binned onto it exactly. A marker reads the
//! displacement of the pad's surface at its point relative to the finger's core (the surface
//! influence coefficients of `crate::model::influence`, the finger's half-space alone). Only a
//! half-space pad is read at depth, for markers or for a gel image (`super::sensor_checks`
//! refuses a bonded layer; a viscoelastic pad too for markers and gel images, whose
//! displacements creep, but not for taxels, whose stresses do not depend on the modulus).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::scene::gel_spec::GelSpec;
use crate::scene::response_spec::ResponseSpec;
use crate::scene::sensor_kind::{ElementGrid, GridLayout, HalfSpaceNeed, SensorKind};

/// `fingers[i].sensor`: the finger's tactile sensor, of one or more kinds: taxels, markers, a
/// gel image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// A grid of taxels at a depth in the pad:
    /// `{"count": [nx, ny], "pitch_m": p, "size_m": s, "depth_m": d}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub taxels: Option<TaxelGridSpec>,
    /// A grid of markers on the pad's surface: `{"count": [nx, ny], "pitch_m": p}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub markers: Option<MarkerGridSpec>,
    /// An optical gel sensor's image of the pad: `{"image_px": [nx, ny], "field_of_view_m":
    /// [wx, wy]}` and its shading (`crate::scene::gel_spec`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gel: Option<GelSpec>,
}

impl SensorSpec {
    /// The sensor's kinds present: taxels, markers, gel.
    pub fn kinds(&self) -> Vec<&dyn SensorKind> {
        let mut out: Vec<&dyn SensorKind> = Vec::new();
        if let Some(t) = &self.taxels {
            out.push(t);
        }
        if let Some(m) = &self.markers {
            out.push(m);
        }
        if let Some(g) = &self.gel {
            out.push(g);
        }
        out
    }
}

/// A grid of square taxels in the pad, centred on the contact point (plus `offset_m`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TaxelGridSpec {
    /// Taxels along the grid's two sides `[nx, ny]` (along `t1`, `t2` before `rotation_rad`),
    /// each in `[1, 256]`.
    pub count: [usize; 2],
    /// Centre-to-centre distance of neighbouring taxels, m, in `[1e-9, 1e3]`.
    pub pitch_m: f64,
    /// Side of each (square) taxel, m, in `[1e-9, pitch_m]`.
    pub size_m: f64,
    /// Depth of the taxels' plane below the pad's surface, m: 0 (the surface tractions binned
    /// onto the taxels) or in `[size_m / 32, 1e3]`.
    pub depth_m: f64,
    /// Angle of the grid's first side to `t1`, rad (counter-clockwise toward `t2`), in
    /// `[-2 pi, 2 pi]`; default 0.
    #[serde(default)]
    pub rotation_rad: f64,
    /// The grid's centre from the contact point along `t1`, `t2`, m, each in `[-1e3, 1e3]`;
    /// default `[0, 0]`.
    #[serde(default)]
    pub offset_m: [f64; 2],
    /// How the sensor departs from the ideal reading (gain, noise, saturation, quantisation;
    /// `crate::scene::response_spec`); default none: the ideal reading.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response: Option<ResponseSpec>,
}

/// A grid of markers on the pad's surface, centred on the contact point (plus `offset_m`),
/// laid out as a taxel grid: each reads the displacement of the pad's surface at its point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MarkerGridSpec {
    /// Markers along the grid's two sides `[nx, ny]` (along `t1`, `t2` before
    /// `rotation_rad`), each in `[1, 256]`.
    pub count: [usize; 2],
    /// Centre-to-centre distance of neighbouring markers, m, in `[1e-9, 1e3]`.
    pub pitch_m: f64,
    /// Angle of the grid's first side to `t1`, rad (counter-clockwise toward `t2`), in
    /// `[-2 pi, 2 pi]`; default 0.
    #[serde(default)]
    pub rotation_rad: f64,
    /// The grid's centre from the contact point along `t1`, `t2`, m, each in `[-1e3, 1e3]`;
    /// default `[0, 0]`.
    #[serde(default)]
    pub offset_m: [f64; 2],
    /// How the sensor departs from the ideal reading (gain, noise, saturation, quantisation;
    /// `crate::scene::response_spec`); default none: the ideal reading.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response: Option<ResponseSpec>,
}

/// The read-out at depth integrates over each taxel with cells no wider than the depth: at
/// most this many cells along a taxel's side (so `depth_m >= size_m / 32`).
pub const MAX_TAXEL_CELLS_PER_SIDE: usize = 32;

/// Gauss-Legendre points along each side of a quadrature cell.
pub const GAUSS_POINTS_PER_CELL_SIDE: usize = 4;

/// The most kernel evaluations (taxels x quadrature points x elements) a read-out at depth
/// may take: about 20 s on one core. Above it the sensor is refused (fewer taxels, a larger
/// depth or a coarser patch), on the dense and the FFT path alike.
pub const MAX_TAXEL_KERNEL_EVALUATIONS: f64 = 2e8;

/// The most kernel evaluations (markers x loaded elements, each the surface rectangle
/// integrals of one element at one marker) a marker read-out may take: about 20 s on one
/// core, as the taxels'. Above it the sensor is refused (fewer markers or a coarser patch).
pub const MAX_MARKER_KERNEL_EVALUATIONS: f64 = 2e8;

impl TaxelGridSpec {
    /// Quadrature cells along a taxel's side at depth: `ceil(size_m / depth_m)`, at least 1
    /// (0 at depth 0, which needs no quadrature).
    pub fn cells_per_side(&self) -> usize {
        if self.depth_m <= 0.0 {
            return 0;
        }
        ((self.size_m / self.depth_m).ceil() as usize).max(1)
    }

    /// Taxels in the grid.
    pub fn taxel_count(&self) -> usize {
        self.count[0] * self.count[1]
    }

    /// Kernel evaluations of a read-out at depth over a patch of `elements` elements, summed
    /// taxel by taxel.
    pub fn kernel_evaluations(&self, elements: usize) -> f64 {
        self.taxel_count() as f64 * self.quadrature_points() as f64 * elements as f64
    }

    /// Quadrature points over one taxel at depth.
    pub fn quadrature_points(&self) -> usize {
        (self.cells_per_side() * GAUSS_POINTS_PER_CELL_SIDE).pow(2)
    }

    /// Where the taxels fall on the patch's element lattice, when the read-out at depth is a
    /// convolution there and the cheaper read-out: the grid unturned, at depth, its pitch a
    /// whole number of elements along each side (to 1e-9), the lattice at most
    /// [`MAX_TAXEL_LATTICE_POINTS`], and its kernel table (`(2 Lx - 1)(2 Ly - 1)` taxel
    /// integrals) less work than summing every element at every taxel. Every taxel then sits
    /// at the same fraction of an element from a lattice point.
    pub fn lattice(&self, patch: &ElementGrid) -> Option<TaxelLattice> {
        if self.depth_m <= 0.0 || self.rotation_rad != 0.0 {
            return None;
        }
        let mut out = TaxelLattice::default();
        for k in 0..2 {
            let (n, h) = (patch.count[k] as i64, patch.element_m[k]);
            let stride = (self.pitch_m / h).round();
            if stride < 1.0 || (self.pitch_m - stride * h).abs() > 1e-9 * self.pitch_m {
                return None;
            }
            // Taxel 0's and element 0's centres (`GridLayout::points_m`, unturned).
            let taxel0 = self.offset_m[k] - (self.count[k] as f64 - 1.0) / 2.0 * self.pitch_m;
            let steps = (taxel0 - (-(n as f64 - 1.0) / 2.0 * h)) / h;
            if !steps.is_finite() || steps.abs() > 1e9 {
                return None;
            }
            let base = steps.floor() as i64;
            let last = base + (self.count[k] as i64 - 1) * stride as i64;
            let (low, high) = (base.min(0), last.max(n - 1));
            out.size[k] = (high - low + 1) as usize;
            out.element0[k] = (-low) as usize;
            out.taxel0[k] = (base - low) as usize;
            out.stride[k] = stride as usize;
            out.fraction[k] = steps - base as f64;
        }
        let table = ((2 * out.size[0] - 1) * (2 * out.size[1] - 1)) as f64;
        let dense = (self.taxel_count() * patch.len()) as f64;
        let small = out.size[0] * out.size[1] <= MAX_TAXEL_LATTICE_POINTS;
        (small && table < dense).then_some(out)
    }
}

/// Most points of the element lattice the taxels' read-out at depth convolves on.
pub const MAX_TAXEL_LATTICE_POINTS: usize = 1024 * 1024;

/// A taxel grid on its patch's element lattice (`TaxelGridSpec::lattice`), in elements.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TaxelLattice {
    /// Lattice points along `t1`, `t2`: the patch's elements and the taxels' centres together.
    pub size: [usize; 2],
    /// The lattice index of the patch's element `(0, 0)`.
    pub element0: [usize; 2],
    /// The lattice index nearest below taxel `(0, 0)`'s centre.
    pub taxel0: [usize; 2],
    /// Elements from one taxel to the next.
    pub stride: [usize; 2],
    /// How far every taxel's centre lies past its lattice point, in elements, in `[0, 1)`.
    pub fraction: [f64; 2],
}

impl SensorKind for TaxelGridSpec {
    fn key(&self) -> &'static str {
        "taxels"
    }

    fn layout(&self) -> GridLayout {
        GridLayout {
            count: self.count,
            pitch_m: [self.pitch_m; 2],
            rotation_rad: self.rotation_rad,
            offset_m: self.offset_m,
        }
    }

    /// Zero on the surface (`depth_m` 0: binned by area, no kernel); on the lattice, its
    /// kernel table's taxel integrals.
    fn kernel_evaluations(&self, patch: &ElementGrid) -> f64 {
        match self.lattice(patch) {
            Some(l) => {
                let table = (2 * l.size[0] - 1) * (2 * l.size[1] - 1);
                (table * self.quadrature_points()) as f64
            }
            None => TaxelGridSpec::kernel_evaluations(self, patch.len()),
        }
    }

    fn most_kernel_evaluations(&self) -> f64 {
        MAX_TAXEL_KERNEL_EVALUATIONS
    }

    fn work_terms(&self) -> &'static str {
        "taxels x quadrature points x elements"
    }

    fn work_fix(&self) -> &'static str {
        "use fewer taxels, a larger depth_m (fewer quadrature points) or a coarser patch"
    }

    fn half_space_need(&self) -> Option<HalfSpaceNeed> {
        (self.depth_m > 0.0).then_some(HalfSpaceNeed {
            what: "taxels at depth",
            instead: "read the taxels at depth_m 0 (the surface tractions)",
            reads_stress: true,
        })
    }
}

impl SensorKind for MarkerGridSpec {
    fn key(&self) -> &'static str {
        "markers"
    }

    fn layout(&self) -> GridLayout {
        GridLayout {
            count: self.count,
            pitch_m: [self.pitch_m; 2],
            rotation_rad: self.rotation_rad,
            offset_m: self.offset_m,
        }
    }

    fn kernel_evaluations(&self, patch: &ElementGrid) -> f64 {
        (self.count[0] * self.count[1]) as f64 * patch.len() as f64
    }

    fn most_kernel_evaluations(&self) -> f64 {
        MAX_MARKER_KERNEL_EVALUATIONS
    }

    fn work_terms(&self) -> &'static str {
        "markers x elements"
    }

    fn work_fix(&self) -> &'static str {
        "use fewer markers or a coarser patch"
    }

    fn half_space_need(&self) -> Option<HalfSpaceNeed> {
        Some(HalfSpaceNeed {
            what: "markers",
            instead: "drop the markers",
            reads_stress: false,
        })
    }
}
