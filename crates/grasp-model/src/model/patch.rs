//! Patch geometry: where each element of a contact's grid is and its initial gap.

use crate::model::influence::GridSpec;

/// Smooth gaps below this fraction of a patch's half diagonal do not make a contact curved.
const CURVED_FRACTION: f64 = 1e-9;

/// A rectangular patch of `nx x ny` elements centred on the contact point.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Grid (counts and element sizes).
    pub grid: GridSpec,
    /// Element centres in patch coordinates `(x along t1, y along t2)`, m, row-major
    /// (`k = i ny + j`).
    pub centres_m: Vec<[f64; 2]>,
    /// Initial gap `c_k`, m, at each element centre (model.md; thesis eqs. 14-16).
    pub gap_m: Vec<f64>,
    /// Per element, true when it faces no surface of the object or of the fingertip (exact
    /// gaps: beyond an edge or a rim); empty when every element does.
    pub off_surface: Vec<bool>,
    /// Per element, true when it lies past the object's edge (a subset of `off_surface`);
    /// empty when none does.
    pub off_object: Vec<bool>,
    /// True when the smooth surfaces curve apart from the contact point (some element facing
    /// a surface has a positive smooth gap): a contact that should end inside its patch
    /// (thesis 2.2.1); false for a flat tip on a flat face, which loads its whole patch.
    pub curved: bool,
    /// The largest curvature of the smooth gap, 1/m: the largest `2 c / r^2` over the
    /// elements facing a surface (the cold start's Hertz estimate; a texture leaves it).
    pub curvature_per_m: f64,
    /// True when a texture's heights are in the gaps ([`Patch::with_texture`]).
    pub(crate) textured: bool,
}

impl Patch {
    /// Builds a patch of size `[lx, ly]` m with `[nx, ny]` elements and curvatures
    /// `[1/R1, 1/R2]` (1/m, summed over finger and object along `t1`, `t2`): the initial gap is
    /// the parabolic separation `c = x^2/2 (1/R1) + y^2/2 (1/R2)` (Johnson section 4.1,
    /// eq. 4.4 with principal curvatures).
    pub fn new(size_m: [f64; 2], grid: [usize; 2], curvature_per_m: [f64; 2]) -> Self {
        let (nx, ny) = (grid[0], grid[1]);
        let (hx, hy) = (size_m[0] / nx as f64, size_m[1] / ny as f64);
        let mut centres_m = Vec::with_capacity(nx * ny);
        let mut gap_m = Vec::with_capacity(nx * ny);
        for i in 0..nx {
            let x = (i as f64 + 0.5) * hx - 0.5 * size_m[0];
            for j in 0..ny {
                let y = (j as f64 + 0.5) * hy - 0.5 * size_m[1];
                centres_m.push([x, y]);
                gap_m.push(0.5 * (curvature_per_m[0] * x * x + curvature_per_m[1] * y * y));
            }
        }
        let curved = gap_m.iter().any(|&g| g > 0.0);
        let curvature_per_m = largest_curvature(&centres_m, &gap_m, &[]);
        Patch {
            grid: GridSpec { nx, ny, hx, hy },
            centres_m,
            gap_m,
            off_surface: Vec::new(),
            off_object: Vec::new(),
            curved,
            curvature_per_m,
            textured: false,
        }
    }

    /// This patch with gaps `gap_m` (m, one per element) in place of its own, the elements
    /// that face no surface (`off_surface`) and those past the object's edge (`off_object`;
    /// either empty: none).
    /// A smooth gap departing from a plane by more than `CURVED_FRACTION` of the patch's half
    /// diagonal counts the contact as curved (below it, the rays' round-off on a flat face; a
    /// plane, a flat pad tilted on a flat face, is a flat contact that loads its whole pad).
    pub(crate) fn with_gaps(
        self,
        gap_m: Vec<f64>,
        off_surface: Vec<bool>,
        off_object: Vec<bool>,
    ) -> Self {
        let any = |v: Vec<bool>| if v.iter().any(|&o| o) { v } else { Vec::new() };
        let half_diagonal =
            0.5 * (self.grid.hx * self.grid.nx as f64).hypot(self.grid.hy * self.grid.ny as f64);
        let floor = CURVED_FRACTION * half_diagonal;
        let on: Vec<usize> = (0..gap_m.len())
            .filter(|&k| !off_surface.get(k).copied().unwrap_or(false))
            .collect();
        let curved = departs_from_a_plane(&self.centres_m, &gap_m, &on, floor);
        let curvature_per_m = largest_curvature(&self.centres_m, &gap_m, &off_surface);
        Patch {
            gap_m,
            off_surface: any(off_surface),
            off_object: any(off_object),
            curved,
            curvature_per_m,
            ..self
        }
    }

    /// This patch with the texture's heights `h` (m, one per element, a peak positive)
    /// taken from its gaps, `c - h`, and every gap shifted so that the first touch (the
    /// smallest gap facing a surface) is at zero: the textured surfaces touch first at their
    /// highest asperity, and the approach counts from there.
    pub(crate) fn with_texture(self, heights_m: &[f64]) -> Self {
        let mut gap_m: Vec<f64> = self
            .gap_m
            .iter()
            .zip(heights_m)
            .map(|(c, h)| c - h)
            .collect();
        let on = |k: usize| !self.is_off_surface(k);
        let lowest = (0..gap_m.len())
            .filter(|&k| on(k))
            .map(|k| gap_m[k])
            .fold(f64::INFINITY, f64::min);
        if lowest.is_finite() {
            for (k, g) in gap_m.iter_mut().enumerate() {
                if on(k) {
                    *g -= lowest;
                }
            }
        }
        Patch {
            gap_m,
            textured: true,
            ..self
        }
    }

    /// The initial gap's slope `|grad c|` at element `k` (dimensionless), by central
    /// differences between neighbours that face a surface (one-sided at the border and next
    /// to elements off the surface; 0 for an element without such neighbours).
    pub fn gap_slope_at(&self, k: usize) -> f64 {
        let g = &self.grid;
        let at = |i: usize, j: usize| -> Option<f64> {
            let k = i * g.ny + j;
            (!self.is_off_surface(k)).then(|| self.gap_m[k])
        };
        let diff = |lo: Option<f64>, hi: Option<f64>, c: f64, h: f64| match (lo, hi) {
            (Some(a), Some(b)) => (b - a) / (2.0 * h),
            (Some(a), None) => (c - a) / h,
            (None, Some(b)) => (b - c) / h,
            (None, None) => 0.0,
        };
        let (i, j) = (k / g.ny, k % g.ny);
        let c = self.gap_m[k];
        let west = i.checked_sub(1).and_then(|i| at(i, j));
        let east = (i + 1 < g.nx).then(|| at(i + 1, j)).flatten();
        let south = j.checked_sub(1).and_then(|j| at(i, j));
        let north = (j + 1 < g.ny).then(|| at(i, j + 1)).flatten();
        diff(west, east, c, g.hx).hypot(diff(south, north, c, g.hy))
    }

    /// The smallest and largest initial gap (m) and the largest gap slope over the elements
    /// that face a surface; `None` when none does.
    pub fn gap_range(&self) -> Option<([f64; 2], f64)> {
        let on: Vec<usize> = (0..self.len())
            .filter(|&k| !self.is_off_surface(k))
            .collect();
        let lo = on.iter().map(|&k| self.gap_m[k]).reduce(f64::min)?;
        let hi = on.iter().map(|&k| self.gap_m[k]).fold(lo, f64::max);
        let slope = on.iter().map(|&k| self.gap_slope_at(k)).fold(0.0, f64::max);
        Some(([lo, hi], slope))
    }

    /// Elements facing no surface.
    pub fn off_surface_count(&self) -> usize {
        self.off_surface.iter().filter(|&&o| o).count()
    }

    /// True when element `k` faces no surface (it can carry nothing).
    pub fn is_off_surface(&self, k: usize) -> bool {
        self.off_surface.get(k).copied().unwrap_or(false)
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.centres_m.len()
    }

    /// True for a patch without elements.
    pub fn is_empty(&self) -> bool {
        self.centres_m.is_empty()
    }

    /// Element area `A = hx hy`, m^2.
    pub fn element_area_m2(&self) -> f64 {
        self.grid.hx * self.grid.hy
    }

    /// True when element `k` lies on the boundary ring of the patch.
    pub fn on_boundary(&self, k: usize) -> bool {
        let (i, j) = (k / self.grid.ny, k % self.grid.ny);
        i == 0 || j == 0 || i + 1 == self.grid.nx || j + 1 == self.grid.ny
    }
}

/// The largest `2 c / r^2` (1/m) over the elements at `centres_m` (m) with gaps `gap_m` (m),
/// those marked in `off` left out: the curvature of a gap `x^2/2 k1 + y^2/2 k2` along its
/// steeper direction, or of an exact profile at its steepest reach.
fn largest_curvature(centres_m: &[[f64; 2]], gap_m: &[f64], off: &[bool]) -> f64 {
    centres_m
        .iter()
        .zip(gap_m)
        .enumerate()
        .filter(|(k, _)| !off.get(*k).copied().unwrap_or(false))
        .map(|(_, (&[x, y], &c))| {
            let r2 = x * x + y * y;
            if r2 > 0.0 {
                2.0 * c / r2
            } else {
                0.0
            }
        })
        .fold(0.0_f64, f64::max)
}

/// True when the gaps `gap_m` at the elements `on` depart from their least-squares plane
/// `a + b x + c y` by more than `floor` (m) anywhere.
fn departs_from_a_plane(centres_m: &[[f64; 2]], gap_m: &[f64], on: &[usize], floor: f64) -> bool {
    let mut normal = nalgebra::Matrix3::<f64>::zeros();
    let mut rhs = nalgebra::Vector3::<f64>::zeros();
    for &k in on {
        let row = nalgebra::Vector3::new(1.0, centres_m[k][0], centres_m[k][1]);
        normal += row * row.transpose();
        rhs += row * gap_m[k];
    }
    // A pseudo-inverse: a one-row patch (planar scenes) fits a line.
    let eps = 1e-12 * normal.amax();
    let plane = normal
        .pseudo_inverse(eps)
        .map_or_else(|_| nalgebra::Vector3::zeros(), |inv| inv * rhs);
    on.iter().any(|&k| {
        let [x, y] = centres_m[k];
        (gap_m[k] - plane[0] - plane[1] * x - plane[2] * y).abs() > floor
    })
}
