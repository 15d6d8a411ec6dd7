//! Influence coefficients of a patch: exact integrals of the half-space point-load solutions
//! over rectangular elements carrying uniform traction (collocation at element centres).
//!
//! With `X = x_k - x'`, `Y = y_k - y'` (field point minus source point) and
//! `rho = sqrt(X^2 + Y^2)`, each kernel's integral over a source rectangle
//! `X in [X1, X2], Y in [Y1, Y2]` is the corner sum
//! `I[f] = f(X2, Y2) - f(X1, Y2) - f(X2, Y1) + f(X1, Y1)` of a function `f` with
//! `d^2 f / dX dY` equal to the kernel (model.md, table of corner functions). These are exact,
//! including the self term: the thesis's `0.95/sqrt(A)` self-term approximation (its defect 3)
//! is not used.

use std::f64::consts::PI;

use nalgebra::DMatrix;

use crate::error::OutOfMemory;
use crate::model::material::Material;

/// `a ln(b)` with the convention `0 ln(0) = 0` (and `0 ln(b) = 0` for any `b`).
fn xlog(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        0.0
    } else {
        a * b.ln()
    }
}

/// `X + rho` computed without cancellation when `X < 0` (`Y^2 / (rho - X)`).
fn x_plus_rho(x: f64, y: f64, rho: f64) -> f64 {
    if x >= 0.0 {
        x + rho
    } else {
        y * y / (rho - x)
    }
}

/// Corner functions of the kernels at one corner `(X, Y)`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RectangleIntegrals {
    /// `I[1/rho]`, m.
    pub inv_rho: f64,
    /// `I[X^2/rho^3]`, m.
    pub xx_rho3: f64,
    /// `I[Y^2/rho^3]`, m.
    pub yy_rho3: f64,
    /// `I[XY/rho^3]`, m.
    pub xy_rho3: f64,
    /// `I[X/rho^2]`, m.
    pub x_rho2: f64,
    /// `I[Y/rho^2]`, m.
    pub y_rho2: f64,
}

impl RectangleIntegrals {
    fn corner(x: f64, y: f64) -> Self {
        let rho = (x * x + y * y).sqrt();
        let lx = x_plus_rho(x, y, rho); // X + rho
        let ly = x_plus_rho(y, x, rho); // Y + rho
        let x_atan = if x == 0.0 { 0.0 } else { x * (y / x).atan() };
        let y_atan = if y == 0.0 { 0.0 } else { y * (x / y).atan() };
        RectangleIntegrals {
            inv_rho: xlog(x, ly) + xlog(y, lx),
            xx_rho3: xlog(y, lx),
            yy_rho3: xlog(x, ly),
            xy_rho3: -rho,
            x_rho2: xlog(y, rho) + x_atan,
            y_rho2: xlog(x, rho) + y_atan,
        }
    }

    /// Exact integrals over the source rectangle `X in [x1, x2]`, `Y in [y1, y2]` (metres;
    /// `X`, `Y` are field minus source coordinates), by the corner sum of model.md.
    pub fn over(x1: f64, x2: f64, y1: f64, y2: f64) -> Self {
        let a = Self::corner(x2, y2);
        let b = Self::corner(x1, y2);
        let c = Self::corner(x2, y1);
        let d = Self::corner(x1, y1);
        let s = |f: fn(&Self) -> f64| f(&a) - f(&b) - f(&c) + f(&d);
        RectangleIntegrals {
            inv_rho: s(|r| r.inv_rho),
            xx_rho3: s(|r| r.xx_rho3),
            yy_rho3: s(|r| r.yy_rho3),
            xy_rho3: s(|r| r.xy_rho3),
            x_rho2: s(|r| r.x_rho2),
            y_rho2: s(|r| r.y_rho2),
        }
    }

    /// Integrals for a field element centred `(dx, dy)` metres from a source element of size
    /// `hx x hy`.
    pub fn for_offset(dx: f64, dy: f64, hx: f64, hy: f64) -> Self {
        Self::over(dx - 0.5 * hx, dx + 0.5 * hx, dy - 0.5 * hy, dy + 0.5 * hy)
    }
}

/// Material constants of one contact pair (finger `f`, object `o`) that the kernels need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairConstants {
    /// `sum_b (1 - nu_b^2)/E_b`, 1/Pa.
    pub normal: f64,
    /// `sum_b (1 + nu_b)(1 - nu_b)/E_b`, 1/Pa.
    pub tangential_a: f64,
    /// `sum_b (1 + nu_b) nu_b / E_b`, 1/Pa.
    pub tangential_b: f64,
    /// `kappa_o - kappa_f`, 1/Pa: the coupling is the DIFFERENCE of the bodies (model.md;
    /// the thesis's eqs. 18 and 32 sum them, its defect 2).
    pub coupling: f64,
}

impl PairConstants {
    /// Constants of the pair (finger, object).
    pub fn new(finger: &Material, object: &Material) -> Self {
        let (fa, fb) = finger.tangential_factors_per_pa();
        let (oa, ob) = object.tangential_factors_per_pa();
        PairConstants {
            normal: finger.normal_factor_per_pa() + object.normal_factor_per_pa(),
            tangential_a: fa + oa,
            tangential_b: fb + ob,
            coupling: object.coupling_kappa_per_pa() - finger.coupling_kappa_per_pa(),
        }
    }

    /// True when the normal/tangential coupling vanishes exactly (equal materials, or both
    /// incompressible-like constants equal): then no coupling blocks are assembled.
    pub fn uncoupled(&self) -> bool {
        self.coupling == 0.0
    }
}

/// Grid description needed to build a patch compliance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSpec {
    /// Elements along `t1`.
    pub nx: usize,
    /// Elements along `t2`.
    pub ny: usize,
    /// Element size along `t1`, m.
    pub hx: f64,
    /// Element size along `t2`, m.
    pub hy: f64,
}

impl GridSpec {
    /// Number of elements.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }
    /// True for an empty grid.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Row-major element index `k = i ny + j` (`i` along `t1`, `j` along `t2`).
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * self.ny + j
    }

    /// The grid as a sensor's read-out sees it.
    pub fn element_grid(&self) -> crate::scene::sensor_kind::ElementGrid {
        crate::scene::sensor_kind::ElementGrid {
            count: [self.nx, self.ny],
            element_m: [self.hx, self.hy],
        }
    }
}

/// The blocks of a patch compliance, in the order [`KernelTable`] keeps them: `nn` (normal from
/// normal), `11`, `22`, `12` (tangential from tangential) and `n1`, `n2` (normal from
/// tangential; the tangential-from-normal blocks are their transposes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Block {
    /// `Cnn`.
    Nn = 0,
    /// `C11`.
    T11 = 1,
    /// `C22`.
    T22 = 2,
    /// `C12`.
    T12 = 3,
    /// `Cn1`.
    N1 = 4,
    /// `Cn2`.
    N2 = 5,
}

/// The compliance entries of every index offset of a grid, m/N, block by block: what the dense
/// matrix ([`patch_compliance`]), the FFT operator ([`super::compliance_operator`]) and its
/// preconditioner ([`super::circulant_inverse`]) are all built from, so they discretise the same
/// operator. Offsets `(di, dj)` in `(-(nx-1)..nx) x (-(ny-1)..ny)`, row-major over `di` then
/// `dj` (`(2 nx - 1)(2 ny - 1)` entries); entry `d` is the displacement at a field element
/// `d` elements from a unit force spread over the source element.
#[derive(Debug, Clone, PartialEq)]
pub struct KernelTable {
    grid: GridSpec,
    /// Per offset, the blocks in [`Block`] order.
    values: Vec<[f64; 6]>,
    /// True when the normal/tangential coupling blocks are not all zero.
    coupled: bool,
}

impl KernelTable {
    /// The half-space table of a pair of materials: the exact rectangle integrals of
    /// [`offset_table`] through [`BlockKernels`] (model.md's table; Johnson 3.22c, 3.86a-c);
    /// [`OutOfMemory`] when its `(2 nx - 1)(2 ny - 1)` entries cannot be allocated.
    pub fn half_space(grid: &GridSpec, pair: &PairConstants) -> Result<Self, OutOfMemory> {
        let kernels = BlockKernels::new(grid, pair);
        let (wx, wy) = (2 * grid.nx - 1, 2 * grid.ny - 1);
        let mut values = crate::allocation::filled(wx * wy, [0.0; 6])?;
        // Row `a` of offsets, each entry from its own rectangle integrals: the same on any
        // thread, so the table's bits do not depend on the threads.
        let row = |(a, out): (usize, &mut [[f64; 6]])| {
            for (b, v) in out.iter_mut().enumerate() {
                let r = offset_integrals(grid, a, b);
                *v = [
                    kernels.nn(&r),
                    kernels.t11(&r),
                    kernels.t22(&r),
                    kernels.t12(&r),
                    kernels.n1(&r),
                    kernels.n2(&r),
                ];
            }
        };
        if wx * wy >= PARALLEL_OFFSETS {
            use rayon::prelude::*;
            values.par_chunks_mut(wy).enumerate().for_each(row);
        } else {
            values.chunks_mut(wy).enumerate().for_each(row);
        }
        Ok(KernelTable {
            grid: *grid,
            values,
            coupled: !pair.uncoupled(),
        })
    }

    /// The grid the table belongs to.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// Offsets per row of the table, `2 ny - 1`.
    pub fn row_len(&self) -> usize {
        2 * self.grid.ny - 1
    }

    /// The blocks at table index `(a, b)`: offset `(a - (nx - 1), b - (ny - 1))` elements.
    pub fn at(&self, a: usize, b: usize) -> &[f64; 6] {
        &self.values[a * self.row_len() + b]
    }

    /// The blocks at table index `(a, b)`, to be changed.
    pub fn at_mut(&mut self, a: usize, b: usize) -> &mut [f64; 6] {
        let w = self.row_len();
        &mut self.values[a * w + b]
    }

    /// The blocks of the zero offset (an element on itself).
    pub fn centre(&self) -> &[f64; 6] {
        self.at(self.grid.nx - 1, self.grid.ny - 1)
    }

    /// True when the normal/tangential coupling blocks are not all zero (equal half-spaces:
    /// all zero, and no coupling blocks are assembled).
    pub fn coupled(&self) -> bool {
        self.coupled
    }

    /// `self + c * other` entry by entry (the same grid): a viscoelastic step's compliance,
    /// the pair's plus a body's scaled by its step factor less one.
    pub fn add_scaled(&mut self, c: f64, other: &KernelTable) {
        debug_assert_eq!(self.grid, other.grid);
        for (a, b) in self.values.iter_mut().zip(&other.values) {
            for (x, y) in a.iter_mut().zip(b) {
                *x += c * y;
            }
        }
        self.coupled |= other.coupled;
    }

    /// Marks the coupling blocks present when any of their entries is nonzero (after a
    /// layered body's correction, which fills them even between equal materials, or cancels
    /// between two equal layers).
    pub fn refresh_coupled(&mut self) {
        self.coupled = self
            .values
            .iter()
            .any(|v| v[Block::N1 as usize] != 0.0 || v[Block::N2 as usize] != 0.0);
    }
}

/// The patch compliance matrix `C`, m/N, of model.md:
/// `[[Cnn, Cn1, Cn2], [Cn1', C11, C12], [Cn2', C12', C22]]`, truncated to the first
/// `1 + n_tangential` blocks (`n_tangential` = 0 frictionless, 1 planar, 2 in 3-D), from the
/// offsets' entries `table` ([`KernelTable`]).
///
/// Entry `(k, j)` of each block is the relative displacement (object surface minus finger
/// surface; normal component along `n`, i.e. the increase of the gap) at the centre of element
/// `k` due to a unit force spread uniformly over element `j`; for two half-spaces
/// ([`KernelTable::half_space`]):
/// - `Cnn = (1/(pi A)) sum_b (1 - nu_b^2)/E_b I[1/rho]` (Boussinesq, Johnson 3.22c),
/// - `C11 = (1/(pi A)) sum_b (1 + nu_b)/E_b ((1 - nu_b) I[1/rho] + nu_b I[X^2/rho^3])`,
///   `C22` with `Y^2`, `C12 = (1/(pi A)) sum_b (1 + nu_b) nu_b/E_b I[XY/rho^3]`
///   (Cerruti, Johnson 3.86a-b),
/// - `Cn1 = (kappa_o - kappa_f)/A I[X/rho^2]`, `Cn2` with `Y` (Johnson 3.86c), and the
///   tangential-from-normal blocks their transposes (Betti reciprocity).
///
/// Blocks depend only on the index offset between elements (Toeplitz): each entry is read
/// from the table.
pub fn patch_compliance(table: &KernelTable, n_tangential: usize) -> DMatrix<f64> {
    let grid = table.grid();
    let (nx, ny) = (grid.nx, grid.ny);
    let n = grid.len();
    let at = |k: usize, j: usize| -> &[f64; 6] {
        let (ik, jk) = (k / ny, k % ny);
        let (ij, jj) = (j / ny, j % ny);
        table.at(ik + nx - 1 - ij, jk + ny - 1 - jj)
    };
    let dim = n * (1 + n_tangential);
    let mut c = DMatrix::<f64>::zeros(dim, dim);
    let coupled = table.coupled() && n_tangential > 0;
    // Column by column (j outer): the writes of each block run down contiguous memory.
    for j in 0..n {
        for k in 0..n {
            let r = at(k, j);
            c[(k, j)] = r[Block::Nn as usize];
            if n_tangential >= 1 {
                c[(n + k, n + j)] = r[Block::T11 as usize];
                if coupled {
                    let v = r[Block::N1 as usize];
                    c[(k, n + j)] = v;
                    c[(n + j, k)] = v;
                }
            }
            if n_tangential >= 2 {
                c[(2 * n + k, 2 * n + j)] = r[Block::T22 as usize];
                c[(n + k, 2 * n + j)] = r[Block::T12 as usize];
                if coupled {
                    let v = r[Block::N2 as usize];
                    c[(k, 2 * n + j)] = v;
                    c[(2 * n + j, k)] = v;
                }
            }
        }
    }
    // C12' block: C21(k, j) = C12(j, k); symmetrise collocation round-off of every block.
    if n_tangential >= 2 {
        for k in 0..n {
            for j in 0..n {
                c[(2 * n + k, n + j)] = c[(n + j, 2 * n + k)];
            }
        }
    }
    symmetrise(&mut c);
    c
}

/// The rectangle integrals of every index offset of a grid, `(di, dj)` in
/// `(-(nx-1)..nx) x (-(ny-1)..ny)`, row-major over `di` then `dj` (`(2 nx - 1)(2 ny - 1)`
/// entries): the compliance is block-Toeplitz, so these are all it depends on.
#[cfg(test)]
pub fn offset_table(grid: &GridSpec) -> Vec<RectangleIntegrals> {
    let (wx, wy) = (2 * grid.nx - 1, 2 * grid.ny - 1);
    (0..wx)
        .flat_map(|a| (0..wy).map(move |b| offset_integrals(grid, a, b)))
        .collect()
}

/// Tables of at least this many offsets are computed on all cores.
const PARALLEL_OFFSETS: usize = 1 << 14;

/// The rectangle integrals of table index `(a, b)` (offset `(a - (nx - 1), b - (ny - 1))`
/// elements), the entries of [`offset_table`].
fn offset_integrals(grid: &GridSpec, a: usize, b: usize) -> RectangleIntegrals {
    let di = a as f64 - (grid.nx as f64 - 1.0);
    let dj = b as f64 - (grid.ny as f64 - 1.0);
    RectangleIntegrals::for_offset(di * grid.hx, dj * grid.hy, grid.hx, grid.hy)
}

/// The compliance entries of one index offset, m/N, block by block (the formulas of
/// [`patch_compliance`]): the one place both the dense matrix and the FFT operator
/// ([`super::compliance_operator`]) take them from, so the two discretise the same operator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockKernels {
    /// `1 / (pi A)`, 1/m^2.
    s: f64,
    /// `A`, m^2.
    area: f64,
    pair: PairConstants,
}

impl BlockKernels {
    /// The kernels of a grid's elements for a pair of materials.
    pub fn new(grid: &GridSpec, pair: &PairConstants) -> Self {
        let area = grid.hx * grid.hy;
        BlockKernels {
            s: 1.0 / (PI * area),
            area,
            pair: *pair,
        }
    }
    /// `Cnn` (Boussinesq, Johnson 3.22c).
    pub fn nn(&self, r: &RectangleIntegrals) -> f64 {
        self.s * self.pair.normal * r.inv_rho
    }
    /// `C11` (Cerruti, Johnson 3.86a).
    pub fn t11(&self, r: &RectangleIntegrals) -> f64 {
        self.s * (self.pair.tangential_a * r.inv_rho + self.pair.tangential_b * r.xx_rho3)
    }
    /// `C22` (Cerruti, Johnson 3.86a with `Y`).
    pub fn t22(&self, r: &RectangleIntegrals) -> f64 {
        self.s * (self.pair.tangential_a * r.inv_rho + self.pair.tangential_b * r.yy_rho3)
    }
    /// `C12` (Cerruti, Johnson 3.86b).
    pub fn t12(&self, r: &RectangleIntegrals) -> f64 {
        self.s * self.pair.tangential_b * r.xy_rho3
    }
    /// `Cn1`, normal displacement from a force along `t1` (Johnson 3.86c).
    pub fn n1(&self, r: &RectangleIntegrals) -> f64 {
        self.pair.coupling / self.area * r.x_rho2
    }
    /// `Cn2`, normal displacement from a force along `t2` (Johnson 3.86c).
    pub fn n2(&self, r: &RectangleIntegrals) -> f64 {
        self.pair.coupling / self.area * r.y_rho2
    }
}

/// `C <- (C + C')/2` in place, in square tiles so both the tile and its mirror stay in cache.
fn symmetrise(c: &mut DMatrix<f64>) {
    const TILE: usize = 32;
    let dim = c.nrows();
    for j0 in (0..dim).step_by(TILE) {
        for k0 in (j0..dim).step_by(TILE) {
            for j in j0..(j0 + TILE).min(dim) {
                for k in k0.max(j + 1)..(k0 + TILE).min(dim) {
                    let v = 0.5 * (c[(k, j)] + c[(j, k)]);
                    c[(k, j)] = v;
                    c[(j, k)] = v;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A named kernel as a function of (X, Y).
    type Kernel = (&'static str, fn(f64, f64) -> f64);

    /// Kernels as functions of (X, Y); all are homogeneous of degree -1.
    const KERNELS: [Kernel; 6] = [
        ("1/rho", |x, y| 1.0 / x.hypot(y)),
        ("X^2/rho^3", |x, y| x * x / x.hypot(y).powi(3)),
        ("Y^2/rho^3", |x, y| y * y / x.hypot(y).powi(3)),
        ("XY/rho^3", |x, y| x * y / x.hypot(y).powi(3)),
        ("X/rho^2", |x, y| x / (x * x + y * y)),
        ("Y/rho^2", |x, y| y / (x * x + y * y)),
    ];

    fn pick(r: &RectangleIntegrals, i: usize) -> f64 {
        [
            r.inv_rho, r.xx_rho3, r.yy_rho3, r.xy_rho3, r.x_rho2, r.y_rho2,
        ][i]
    }

    /// Composite Simpson rule on [a, b] with `n` (even) panels.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for i in 1..n {
            s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    /// Integral of a degree -1 kernel over [0, a] x [0, b] (a, b > 0) in polar coordinates
    /// about the corner at the origin: `int g(theta) R(theta) dtheta`, with the signs of the
    /// quadrant `(sx, sy)` applied to the kernel's arguments. Independent of the corner
    /// functions under test; handles the singular corner exactly.
    fn polar_quadrant(k: fn(f64, f64) -> f64, a: f64, b: f64, sx: f64, sy: f64) -> f64 {
        let split = b.atan2(a);
        // k(rho cos, rho sin) * rho = k(cos, sin) for degree -1 kernels.
        let g = |t: f64| k(sx * t.cos(), sy * t.sin());
        simpson(|t| g(t) * a / t.cos(), 0.0, split, 4000)
            + simpson(
                |t| g(t) * b / t.sin(),
                split,
                std::f64::consts::FRAC_PI_2,
                4000,
            )
    }

    /// Integral over [x1, x2] x [y1, y2] by splitting at the axes into quadrant rectangles
    /// with a corner at the origin.
    fn polar_rect(k: fn(f64, f64) -> f64, x1: f64, x2: f64, y1: f64, y2: f64) -> f64 {
        // J(X, Y) = integral over the rectangle between the origin and (X, Y), signed.
        let j = |x: f64, y: f64| -> f64 {
            if x == 0.0 || y == 0.0 {
                return 0.0;
            }
            let s = x.signum() * y.signum();
            s * polar_quadrant(k, x.abs(), y.abs(), x.signum(), y.signum())
        };
        j(x2, y2) - j(x1, y2) - j(x2, y1) + j(x1, y1)
    }

    /// Tensor Gauss-Legendre-free brute force: midpoint rule with `m x m` cells (for sources
    /// well away from the field point only).
    fn midpoint_rect(k: fn(f64, f64) -> f64, x1: f64, x2: f64, y1: f64, y2: f64, m: usize) -> f64 {
        let (hx, hy) = ((x2 - x1) / m as f64, (y2 - y1) / m as f64);
        let mut s = 0.0;
        for i in 0..m {
            for j in 0..m {
                s += k(x1 + (i as f64 + 0.5) * hx, y1 + (j as f64 + 0.5) * hy);
            }
        }
        s * hx * hy
    }

    #[test]
    fn rectangle_integrals_match_polar_quadrature_including_self_terms() {
        // Self term, adjacent, diagonal neighbour, and a field point on the source's edge line.
        let (hx, hy) = (0.02, 0.013);
        for &(dx, dy) in &[
            (0.0, 0.0),
            (hx, 0.0),
            (0.0, -hy),
            (hx, hy),
            (-2.0 * hx, 0.5 * hy),
        ] {
            let r = RectangleIntegrals::for_offset(dx, dy, hx, hy);
            for (i, (name, k)) in KERNELS.iter().enumerate() {
                let q = polar_rect(
                    *k,
                    dx - hx / 2.0,
                    dx + hx / 2.0,
                    dy - hy / 2.0,
                    dy + hy / 2.0,
                );
                let got = pick(&r, i);
                // Simpson with 4000 panels on smooth integrands: ~1e-12 relative; tolerance
                // 1e-9 of the 1/rho scale (the odd kernels vanish by symmetry at the self term).
                let scale = r.inv_rho.abs();
                assert!(
                    (got - q).abs() <= 1e-9 * scale,
                    "{name} at ({dx}, {dy}): closed form {got}, quadrature {q}"
                );
            }
        }
    }

    #[test]
    fn rectangle_integrals_match_brute_force_far_from_the_source() {
        let (hx, hy) = (0.01, 0.02);
        for &(dx, dy) in &[(0.05, 0.03), (-0.04, 0.07), (0.1, -0.1)] {
            let r = RectangleIntegrals::for_offset(dx, dy, hx, hy);
            for (i, (name, k)) in KERNELS.iter().enumerate() {
                let q = midpoint_rect(
                    *k,
                    dx - hx / 2.0,
                    dx + hx / 2.0,
                    dy - hy / 2.0,
                    dy + hy / 2.0,
                    400,
                );
                let got = pick(&r, i);
                // Midpoint rule error ~ h^2 k''/24 per cell: below 1e-7 relative here.
                assert!(
                    (got - q).abs() <= 1e-7 * r.inv_rho.abs(),
                    "{name} at ({dx}, {dy}): closed form {got}, brute force {q}"
                );
            }
        }
    }

    fn steel() -> Material {
        Material::Elastic {
            youngs_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        }
    }
    fn rubber() -> Material {
        Material::Elastic {
            youngs_modulus_pa: 5e6,
            poisson_ratio: 0.45,
        }
    }

    #[test]
    fn compliance_is_symmetric_positive_definite() {
        // Seeded pseudo-random materials and grids (64-bit LCG).
        let mut seed: u64 = 0x9e3779b97f4a7c15;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..12 {
            let f = Material::Elastic {
                youngs_modulus_pa: 10f64.powf(5.0 + 7.0 * next()),
                poisson_ratio: 0.499 * next(),
            };
            let o = if next() < 0.2 {
                Material::Rigid
            } else {
                Material::Elastic {
                    youngs_modulus_pa: 10f64.powf(5.0 + 7.0 * next()),
                    poisson_ratio: 0.499 * next(),
                }
            };
            let grid = GridSpec {
                nx: 1 + (next() * 5.0) as usize,
                ny: 1 + (next() * 5.0) as usize,
                hx: 1e-3 * (0.5 + next()),
                hy: 1e-3 * (0.5 + next()),
            };
            for ntan in 0..=2 {
                let c = patch_compliance(
                    &KernelTable::half_space(&grid, &PairConstants::new(&f, &o)).unwrap(),
                    ntan,
                );
                let asym = (&c - c.transpose()).abs().max();
                assert!(asym <= 1e-14 * c.abs().max(), "not symmetric: {asym}");
                let eig = nalgebra::SymmetricEigen::new(c.clone());
                let min = eig.eigenvalues.min();
                assert!(
                    min > 0.0,
                    "not positive definite: min eigenvalue {min}, grid {grid:?}"
                );
            }
        }
    }

    /// Far-field entries against the point-load formulas written out by hand from Johnson
    /// (3.22c, 3.86a-c) for a rubber finger (E = 5 MPa, nu = 0.45) on a steel object
    /// (E = 210 GPa, nu = 0.3), without the crate's material constants:
    /// - normal: sum_b (1 - nu_b^2)/(pi E_b) / r;
    /// - Cerruti: sum_b (1 + nu_b)/(pi E_b) ((1 - nu_b)/r + nu_b x^2/r^3) (thesis eq. 43 has
    ///   `- nu x^2/r^3`, its defect 1);
    /// - coupling (gap increase from a tangential force on the object along +x):
    ///   (kappa_o - kappa_f) x / r^2, kappa = (1 + nu)(1 - 2 nu)/(2 pi E); for a soft finger
    ///   this is NEGATIVE (the thesis's summed form, its defect 2, would make it positive).
    #[test]
    fn far_field_matches_hand_written_point_load_formulas() {
        let pi = std::f64::consts::PI;
        let (ef, nf, eo, no) = (5e6_f64, 0.45_f64, 210e9_f64, 0.3_f64);
        let pair = PairConstants::new(
            &Material::Elastic {
                youngs_modulus_pa: ef,
                poisson_ratio: nf,
            },
            &Material::Elastic {
                youngs_modulus_pa: eo,
                poisson_ratio: no,
            },
        );
        let grid = GridSpec {
            nx: 41,
            ny: 3,
            hx: 1e-3,
            hy: 1e-3,
        };
        let n = grid.len();
        let c = patch_compliance(&KernelTable::half_space(&grid, &pair).unwrap(), 2);
        let (k, j) = (grid.index(40, 2), grid.index(0, 0));
        let (x, y): (f64, f64) = (40.0e-3, 2.0e-3);
        let r = x.hypot(y);
        let normal = ((1.0 - nf * nf) / ef + (1.0 - no * no) / eo) / (pi * r);
        let cerruti = ((1.0 + nf) / ef * ((1.0 - nf) / r + nf * x * x / r.powi(3))
            + (1.0 + no) / eo * ((1.0 - no) / r + no * x * x / r.powi(3)))
            / pi;
        let kappa = |e: f64, nu: f64| (1.0 + nu) * (1.0 - 2.0 * nu) / (2.0 * pi * e);
        let coupling = (kappa(eo, no) - kappa(ef, nf)) * x / (r * r);
        assert!(coupling < 0.0);
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        // Next term of the far-field expansion: O((h/r)^2 / 24) ~ 3e-5.
        assert!(
            rel(c[(k, j)], normal) < 1e-4,
            "normal {} vs {normal}",
            c[(k, j)]
        );
        assert!(
            rel(c[(n + k, n + j)], cerruti) < 1e-4,
            "Cerruti {} vs {cerruti}",
            c[(n + k, n + j)]
        );
        assert!(
            rel(c[(k, n + j)], coupling) < 1e-4,
            "coupling {} vs {coupling}",
            c[(k, n + j)]
        );
        let c12 = (nf * (1.0 + nf) / ef + no * (1.0 + no) / eo) * x * y / (pi * r.powi(3));
        assert!(
            rel(c[(n + k, 2 * n + j)], c12) < 1e-3,
            "C12 {} vs {c12}",
            c[(n + k, 2 * n + j)]
        );
        // Betti: tangential-from-normal is the transpose of normal-from-tangential.
        assert_eq!(c[(n + j, k)], c[(k, n + j)]);
    }

    #[test]
    fn coupling_is_the_difference_of_the_bodies_and_vanishes_for_equal_materials() {
        let equal = PairConstants::new(&steel(), &steel());
        assert!(equal.uncoupled());
        let grid = GridSpec {
            nx: 3,
            ny: 3,
            hx: 1e-3,
            hy: 1e-3,
        };
        let c = patch_compliance(&KernelTable::half_space(&grid, &equal).unwrap(), 2);
        let n = grid.len();
        assert_eq!(c.view((0, n), (n, 2 * n)).abs().max(), 0.0);
        // Swapping finger and object flips the sign of the coupling (a difference, not a sum).
        let a = PairConstants::new(&rubber(), &steel());
        let b = PairConstants::new(&steel(), &rubber());
        assert!((a.coupling + b.coupling).abs() <= 1e-15 * a.coupling.abs());
        assert!(a.coupling > 0.0 || b.coupling > 0.0);
    }
}
