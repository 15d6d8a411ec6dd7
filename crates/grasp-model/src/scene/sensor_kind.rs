//! One kind of tactile sensor in a finger's pad (taxels, markers, a gel image) as its checks and its
//! read-out see it: the grid it lays out on the patch, the work its read-out takes and
//! whether it describes only a half-space pad.
//!
//! Every kind is a grid of points on the patch laid out the same way ([`GridLayout`]): `count`
//! points along the grid's two sides at `pitch_m` (per side: a gel image's pixels may be
//! oblong), centred on the contact point plus
//! `offset_m`, turned by `rotation_rad` from `t1` toward `t2`.

/// A finger's element grid as a sensor's read-out sees it (the model's own, or the scene's
/// patch before the model is built).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementGrid {
    /// Elements along `t1`, `t2`.
    pub count: [usize; 2],
    /// Element size along `t1`, `t2`, m.
    pub element_m: [f64; 2],
}

impl ElementGrid {
    /// The grid of a patch of `size_m` cut into `count` elements.
    pub fn of_patch(size_m: [f64; 2], count: [usize; 2]) -> ElementGrid {
        ElementGrid {
            count,
            element_m: [
                size_m[0] / count[0].max(1) as f64,
                size_m[1] / count[1].max(1) as f64,
            ],
        }
    }

    /// Elements in the grid.
    pub fn len(&self) -> usize {
        self.count[0] * self.count[1]
    }

    /// True for a grid without elements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A sensor grid's layout on its finger's patch, as written in its spec.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridLayout {
    /// Points along the grid's two sides `[nx, ny]`.
    pub count: [usize; 2],
    /// Centre-to-centre distance of neighbouring points along each of the grid's sides, m
    /// (taxels and markers: the same both ways).
    pub pitch_m: [f64; 2],
    /// Angle of the grid's first side to `t1`, rad (counter-clockwise toward `t2`).
    pub rotation_rad: f64,
    /// The grid's centre from the contact point along `t1`, `t2`, m.
    pub offset_m: [f64; 2],
}

impl GridLayout {
    /// Points in the grid.
    pub fn len(&self) -> usize {
        self.count[0] * self.count[1]
    }

    /// True for a grid without points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every point from the contact point along `t1`, `t2`, m, row-major (`k = i ny + j`, `i`
    /// along the grid's first side): `((i - (nx - 1)/2) px, (j - (ny - 1)/2) py)` in the
    /// grid's axes, turned by `rotation_rad`, plus `offset_m`.
    pub fn points_m(&self) -> Vec<[f64; 2]> {
        let (sin, cos) = self.rotation_rad.sin_cos();
        let mut out = Vec::with_capacity(self.len());
        for i in 0..self.count[0] {
            for j in 0..self.count[1] {
                let u = (i as f64 - (self.count[0] as f64 - 1.0) / 2.0) * self.pitch_m[0];
                let v = (j as f64 - (self.count[1] as f64 - 1.0) / 2.0) * self.pitch_m[1];
                out.push([
                    self.offset_m[0] + u * cos - v * sin,
                    self.offset_m[1] + u * sin + v * cos,
                ]);
            }
        }
        out
    }
}

/// A kind of tactile sensor: what the scene's checks and the read-out need to know of it,
/// beside its own numbers' checks.
pub trait SensorKind {
    /// The kind's key in `fingers[i].sensor` (`"taxels"`, `"markers"`, `"gel"`).
    fn key(&self) -> &'static str;

    /// The grid's layout on the patch.
    fn layout(&self) -> GridLayout;

    /// Kernel evaluations of the read-out over the element grid `patch`.
    fn kernel_evaluations(&self, patch: &ElementGrid) -> f64;

    /// The most kernel evaluations the read-out may take; above it the sensor is refused.
    fn most_kernel_evaluations(&self) -> f64;

    /// What one kernel evaluation counts, for the refusal (`"taxels x quadrature points x
    /// elements"`).
    fn work_terms(&self) -> &'static str;

    /// The fix of a read-out of too much work.
    fn work_fix(&self) -> &'static str;

    /// When the read-out describes only a half-space pad (not a bonded layer; not a
    /// viscoelastic pad either, unless it reads stresses): what is read that needs it
    /// (`"taxels at depth"`) and the other way out of the refusal than changing the pad
    /// (`"read the taxels at depth_m 0 (the surface tractions)"`). `None` when any pad is read
    /// right.
    fn half_space_need(&self) -> Option<HalfSpaceNeed>;
}

/// Why a sensor kind needs a half-space pad, for its refusal of another pad.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HalfSpaceNeed {
    /// What is read that needs it, plural (`"taxels at depth"`, `"markers"`).
    pub what: &'static str,
    /// The fix other than changing the pad (`"read the taxels at depth_m 0 (the surface
    /// tractions)"`).
    pub instead: &'static str,
    /// True when the reading is a stress under the solved surface tractions: in a half-space
    /// of constant Poisson's ratio it does not depend on the modulus (Boussinesq's and
    /// Cerruti's stresses hold `nu` only, Johnson 3.2-3.3), so by the correspondence principle
    /// (Lee and Radok 1960) a viscoelastic pad's stress is the elastic one of its tractions at
    /// that time, and the read-out is exact there too. False for displacements, which carry
    /// the pad's creep.
    pub reads_stress: bool,
}
