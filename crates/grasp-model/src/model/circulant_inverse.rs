//! The inverse of a circulant approximation of the patch compliance: the preconditioner of the
//! conjugate-gradient solves over an FFT patch ([`crate::solver`]).
//!
//! Each block of the compliance is a Toeplitz (convolution) operator on the grid; Strang's
//! circulant approximation keeps the kernel's offsets up to half the grid and wraps them
//! around it (G. Strang, "A proposal for Toeplitz matrix calculations", Stud. Appl. Math. 74,
//! 1986; T. Chan, SIAM J. Sci. Stat. Comput. 9, 1988), so on the `nx x ny` grid itself (no
//! padding) it is diagonalised by the 2-D FFT: per frequency a Hermitian `dim x dim` matrix
//! (`dim = 1 + n_tangential`, the blocks `nn`, `11`, `22`, `12`, `n1`, `n2`). Its inverse is
//! applied with `dim` forward and `dim` inverse transforms on a grid a quarter the size of the
//! operator's padded one.
//!
//! As a preconditioner of the compliance restricted to the contact area (Vollebregt, "A new
//! solver for the elastic normal contact problem using conjugate gradients, deflation, and an
//! FFT-based preconditioner", J. Comput. Phys. 257, 2014, uses the same idea in NormCG), the
//! restricted inverse of the whole grid's operator keeps the conjugate-gradient iterations
//! nearly independent of the grid: the compliance's symbol grows like `1/|k|`, so its
//! condition number grows like the square root of the elements and unpreconditioned CG
//! iterations like its fourth root, while the circulant inverse cancels the `1/|k|`.

use realfft::num_complex::Complex;

use super::grid_fft::GridFft;
use super::influence::{Block, KernelTable};
use crate::error::OutOfMemory;

/// Entries of a Hermitian `3 x 3` matrix kept per frequency, upper triangle: `(row, col)`.
const ENTRIES: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// A per-frequency matrix whose pivots fall below this fraction of the largest diagonal entry
/// over all frequencies is not inverted as a whole: its diagonal is (a preconditioner only
/// needs to be positive definite, and round-off could make a nearly singular block
/// indefinite).
const PIVOT_FLOOR: f64 = 1e-12;

/// The inverse of the Strang circulant approximation of one patch's compliance, N/m.
pub struct CirculantInverse {
    dim: usize,
    /// Elements of the grid.
    elements: usize,
    fft: GridFft,
    /// Per [`ENTRIES`] index, the inverse's entry at every frequency (empty where the
    /// compliance has no such block, which the inverse then lacks too).
    inverse: Vec<Vec<Complex<f64>>>,
}

impl std::fmt::Debug for CirculantInverse {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CirculantInverse")
            .field("dim", &self.dim)
            .finish_non_exhaustive()
    }
}

/// The kernel entries a patch needs (per [`ENTRIES`] index): the diagonal blocks of its
/// components, the normal-tangential coupling when `coupled`, and `12` with two tangential
/// components.
fn needed(n_tangential: usize, coupled: bool) -> [bool; 6] {
    let dim = 1 + n_tangential;
    ENTRIES.map(|(r, c)| match (r, c) {
        _ if r == c => r < dim,
        (0, _) => coupled && c < dim,
        _ => c < dim,
    })
}

impl CirculantInverse {
    /// The inverse for the offsets' entries `table` ([`KernelTable`], on its grid), with
    /// `1 + n_tangential` components; [`OutOfMemory`] when its spectra cannot be allocated.
    pub fn new(
        table: &KernelTable,
        n_tangential: usize,
        coupled: bool,
    ) -> Result<Self, OutOfMemory> {
        let grid = table.grid();
        let fft = GridFft::new([grid.nx, grid.ny], [grid.nx, grid.ny]);
        let need = needed(n_tangential, coupled);
        let spectra: Vec<Vec<Complex<f64>>> = (0..ENTRIES.len())
            .map(|e| match need[e] {
                true => wrapped_spectrum(&fft, table, |a, b| kernel(e, a, b)),
                false => Ok(Vec::new()),
            })
            .collect::<Result<_, _>>()?;
        let dim = 1 + n_tangential;
        // The floor of every frequency's pivots: a fraction of the largest diagonal entry over
        // all of them (a block that is zero at one frequency is then not inverted to 1e308).
        let scale = (0..fft.spectrum_len())
            .flat_map(|f| (0..dim).map(move |c| (f, c)))
            .map(|(f, c)| spectra[c][f].re.abs())
            .fold(0.0, f64::max);
        let mut inverse = vec![Vec::new(); ENTRIES.len()];
        for (e, inv) in inverse.iter_mut().enumerate() {
            if need[e] {
                *inv = crate::allocation::filled(fft.spectrum_len(), Complex::default())?;
            }
        }
        let parallel = fft.parallel();
        invert_all(&mut inverse, parallel, |f| {
            invert(&hermitian_at(&spectra, f, dim), dim, PIVOT_FLOOR * scale)
        });
        Ok(CirculantInverse {
            dim,
            elements: grid.len(),
            fft,
            inverse,
        })
    }

    #[cfg(test)]
    /// Bytes kept ([`CirculantInverse::new`]'s per-frequency entries).
    pub fn memory_bytes(&self) -> usize {
        let entries: usize = self.inverse.iter().map(Vec::len).sum();
        entries * std::mem::size_of::<Complex<f64>>()
    }

    /// Bytes [`CirculantInverse::new`] keeps for a grid, before building it.
    pub fn memory_estimate_bytes(
        grid: &super::influence::GridSpec,
        n_tangential: usize,
        coupled: bool,
    ) -> usize {
        let kept = needed(n_tangential, coupled).iter().filter(|n| **n).count();
        kept * grid.nx * (grid.ny / 2 + 1) * std::mem::size_of::<Complex<f64>>()
    }

    /// Frees the transforms' work buffers ([`GridFft::release_work`]).
    pub fn release_work(&self) {
        self.fft.release_work();
    }

    /// `out = factor C_circ^-1 v` (component-major like the compliance's unknowns), N/m
    /// times m.
    pub fn apply(&self, v: &[f64], out: &mut [f64], factor: f64) {
        let dim = self.dim;
        let n = self.elements;
        assert_eq!(v.len(), dim * n, "vector length");
        assert_eq!(out.len(), dim * n, "output length");
        self.fft.multiply_blocks(v, out, dim, factor, |r, c| {
            let (e, conjugate) = entry_of(r, c)?;
            let k = &self.inverse[e];
            (!k.is_empty()).then_some((k.as_slice(), conjugate))
        });
    }
}

/// Frequencies one task inverts.
const FREQUENCIES: usize = 4096;

/// One task's slots: per kept entry (its [`ENTRIES`] index), its values over the task's
/// frequencies.
type TaskSlots<'i> = Vec<(usize, &'i mut [Complex<f64>])>;

/// Per frequency `f`, the kept entries (the non-empty vectors of `inverse`, per [`ENTRIES`]
/// index) of the matrix `inverse_at(f)`: per [`FREQUENCIES`] of them on all cores when
/// `parallel` (each frequency on its own, so the same bits on any number of threads).
fn invert_all(
    inverse: &mut [Vec<Complex<f64>>],
    parallel: bool,
    inverse_at: impl Fn(usize) -> [[Complex<f64>; 3]; 3] + Sync + Send,
) {
    let len = inverse.iter().map(Vec::len).max().unwrap_or(0);
    // Per task, each kept entry's slots over its frequencies.
    let mut tasks: Vec<TaskSlots> = (0..len.div_ceil(FREQUENCIES)).map(|_| Vec::new()).collect();
    for (e, inv) in inverse.iter_mut().enumerate() {
        for (task, part) in tasks.iter_mut().zip(inv.chunks_mut(FREQUENCIES)) {
            task.push((e, part));
        }
    }
    let run = |(k, mut parts): (usize, TaskSlots)| {
        let n = parts.first().map_or(0, |p| p.1.len());
        for i in 0..n {
            let m = inverse_at(k * FREQUENCIES + i);
            for (e, part) in parts.iter_mut() {
                let (r, c) = ENTRIES[*e];
                part[i] = m[r][c];
            }
        }
    };
    if parallel {
        use rayon::prelude::*;
        tasks.into_par_iter().enumerate().for_each(run);
    } else {
        tasks.into_iter().enumerate().for_each(run);
    }
}

/// The [`ENTRIES`] index holding `(r, c)` and whether it is read conjugated (the lower
/// triangle).
fn entry_of(r: usize, c: usize) -> Option<(usize, bool)> {
    let (lo, hi) = (r.min(c), r.max(c));
    ENTRIES
        .iter()
        .position(|&e| e == (lo, hi))
        .map(|e| (e, r > c))
}

/// Kernel of entry `e` at offset `d` (`at`) and `-d` (`mirror`): the diagonal blocks
/// symmetrised like the dense matrix, the off-diagonal ones as they are (their lower triangle
/// is the transposed block, read conjugated).
fn kernel(e: usize, at: &[f64; 6], mirror: &[f64; 6]) -> f64 {
    let sym = |b: Block| 0.5 * (at[b as usize] + mirror[b as usize]);
    match ENTRIES[e] {
        (0, 0) => sym(Block::Nn),
        (1, 1) => sym(Block::T11),
        (2, 2) => sym(Block::T22),
        (0, 1) => at[Block::N1 as usize],
        (0, 2) => at[Block::N2 as usize],
        _ => at[Block::T12 as usize],
    }
}

/// The spectrum of a kernel wrapped on the grid: periodic index `i` holds offset `i` up to
/// `nx / 2` and `i - nx` above (Strang), likewise along `j`.
fn wrapped_spectrum(
    fft: &GridFft,
    table: &KernelTable,
    value: impl Fn(&[f64; 6], &[f64; 6]) -> f64 + Sync + Send,
) -> Result<Vec<Complex<f64>>, OutOfMemory> {
    let (nx, ny) = (table.grid().nx, table.grid().ny);
    // Table index of periodic index `i` of a side of `n` elements (offset `i` or `i - n`).
    let slot = |i: usize, n: usize| if i <= n / 2 { i + n - 1 } else { i - 1 };
    let mut wrapped = crate::allocation::filled(nx * ny, 0.0)?;
    let row = |(i, out): (usize, &mut [f64])| {
        let (a, ma) = (slot(i, nx), 2 * nx - 2 - slot(i, nx));
        for (j, o) in out.iter_mut().enumerate() {
            let (b, mb) = (slot(j, ny), 2 * ny - 2 - slot(j, ny));
            *o = value(table.at(a, b), table.at(ma, mb));
        }
    };
    if fft.parallel() && ny > 0 {
        use rayon::prelude::*;
        wrapped.par_chunks_mut(ny).enumerate().for_each(row);
    } else if ny > 0 {
        wrapped.chunks_mut(ny).enumerate().for_each(row);
    }
    fft.transform(&mut wrapped, nx)
}

/// The Hermitian matrix of the circulant at frequency `f` (`dim x dim`; the diagonal real).
fn hermitian_at(spectra: &[Vec<Complex<f64>>], f: usize, dim: usize) -> [[Complex<f64>; 3]; 3] {
    let mut h = [[Complex::default(); 3]; 3];
    for (e, &(r, c)) in ENTRIES.iter().enumerate() {
        if r < dim && c < dim && !spectra[e].is_empty() {
            let v = spectra[e][f];
            if r == c {
                h[r][r] = Complex::new(v.re, 0.0);
            } else {
                h[r][c] = v;
                h[c][r] = v.conj();
            }
        }
    }
    h
}

/// The inverse of a Hermitian positive definite `dim x dim` matrix by Cholesky
/// (`H = L L*`), or the inverse of its diagonal (its absolute values, raised to `floor`; zero
/// where that is zero too) when a pivot falls below `floor`.
fn invert(h: &[[Complex<f64>; 3]; 3], dim: usize, floor: f64) -> [[Complex<f64>; 3]; 3] {
    let diagonal = || {
        let mut out = [[Complex::default(); 3]; 3];
        for (i, row) in out.iter_mut().enumerate().take(dim) {
            let d = h[i][i].re.abs().max(floor);
            row[i] = Complex::new(if d > 0.0 { 1.0 / d } else { 0.0 }, 0.0);
        }
        out
    };
    let mut l = [[Complex::default(); 3]; 3];
    for j in 0..dim {
        let pivot = h[j][j].re - (0..j).map(|k| l[j][k].norm_sqr()).sum::<f64>();
        if pivot.is_nan() || pivot <= floor {
            return diagonal();
        }
        l[j][j] = Complex::new(pivot.sqrt(), 0.0);
        for i in j + 1..dim {
            let s: Complex<f64> = (0..j).map(|k| l[i][k] * l[j][k].conj()).sum();
            l[i][j] = (h[i][j] - s) / l[j][j].re;
        }
    }
    // H^-1 = L^-* L^-1: columns of L^-1 by forward substitution (`li[c]` is column `c`).
    let li: [[Complex<f64>; 3]; 3] = std::array::from_fn(|c| {
        let mut col = [Complex::default(); 3];
        for i in c..dim {
            let s: Complex<f64> = (c..i).map(|k| l[i][k] * col[k]).sum();
            let rhs = if i == c {
                Complex::new(1.0, 0.0)
            } else {
                Complex::default()
            };
            col[i] = (rhs - s) / l[i][i].re;
        }
        col
    });
    let mut out = [[Complex::default(); 3]; 3];
    for r in 0..dim {
        for c in 0..dim {
            out[r][c] = (0..dim).map(|k| li[r][k].conj() * li[c][k]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::influence::{patch_compliance, GridSpec, PairConstants};
    use crate::model::material::Material;
    use nalgebra::{DMatrix, DVector};

    fn elastic(e: f64, nu: f64) -> Material {
        Material::Elastic {
            youngs_modulus_pa: e,
            poisson_ratio: nu,
        }
    }

    /// Strang's circulant written out from the dense matrix's entries: block `(r, c)`, `r <=
    /// c`, at `(field, source)` holds the dense entry of the offset `field - source` wrapped
    /// into `(-n/2, n/2]` per side, read where both elements lie on the grid; the blocks
    /// below the diagonal are their transposes (an odd kernel's offsets `n/2` and `-n/2`
    /// differ, and the circulant keeps one).
    fn strang_from_dense(dense: &DMatrix<f64>, grid: &GridSpec, dim: usize) -> DMatrix<f64> {
        let (nx, ny) = (grid.nx as i64, grid.ny as i64);
        let n = grid.len();
        let wrap = |d: i64, m: i64| {
            let d = d.rem_euclid(m);
            if d <= m / 2 {
                d
            } else {
                d - m
            }
        };
        let upper = |row: usize, col: usize| {
            let (r, f) = (row / n, (row % n) as i64);
            let (c, s) = (col / n, (col % n) as i64);
            let dx = wrap(f / ny - s / ny, nx);
            let dy = wrap(f % ny - s % ny, ny);
            let (sx, sy) = ((-dx).max(0), (-dy).max(0));
            let (src, fld) = (sx * ny + sy, (sx + dx) * ny + sy + dy);
            dense[(r * n + fld as usize, c * n + src as usize)]
        };
        DMatrix::from_fn(dim * n, dim * n, |row, col| match row / n <= col / n {
            true => upper(row, col),
            false => upper(col, row),
        })
    }

    /// The inverse undoes Strang's circulant written out independently from the dense
    /// matrix (every block and reduction; even and odd sides). Tolerance: the circulant's
    /// condition number (below 1e4 on these grids) times FFT round-off leaves `|v - C^-1 C v|`
    /// near 1e-12 of `|v|`; 1e-9 still catches any wrong wrap, sign or conjugate (those
    /// give O(1) errors).
    #[test]
    fn it_inverts_strangs_circulant() {
        let pairs = [
            PairConstants::new(&elastic(5e6, 0.45), &elastic(210e9, 0.3)),
            PairConstants::new(&elastic(70e9, 0.33), &elastic(70e9, 0.33)),
        ];
        for pair in &pairs {
            for (nx, ny) in [(6, 5), (7, 8), (1, 6), (6, 1), (1, 1)] {
                let grid = GridSpec {
                    nx,
                    ny,
                    hx: 1.2e-4,
                    hy: 0.9e-4,
                };
                let table = KernelTable::half_space(&grid, pair).unwrap();
                for nt in 0..=2 {
                    let dim = 1 + nt;
                    let dense = patch_compliance(&table, nt);
                    let circ = strang_from_dense(&dense, &grid, dim);
                    let coupled = !pair.uncoupled() && nt > 0;
                    let inv = CirculantInverse::new(&table, nt, coupled).unwrap();
                    let v =
                        DVector::from_fn(dim * grid.len(), |i, _| ((i * 7 + 3) % 11) as f64 - 5.0);
                    let cv = &circ * &v;
                    let mut back = vec![0.0; v.len()];
                    inv.apply(cv.as_slice(), &mut back, 1.0);
                    let err = (DVector::from_vec(back) - &v).amax();
                    assert!(err <= 1e-9 * v.amax(), "{nx}x{ny}, nt {nt}: error {err:e}");
                }
            }
        }
    }

    #[test]
    fn memory_is_what_the_estimate_says() {
        let grid = GridSpec {
            nx: 9,
            ny: 6,
            hx: 1e-4,
            hy: 1e-4,
        };
        let pair = PairConstants::new(&elastic(5e6, 0.45), &elastic(210e9, 0.3));
        let table = KernelTable::half_space(&grid, &pair).unwrap();
        for nt in 0..=2 {
            let inv = CirculantInverse::new(&table, nt, nt > 0).unwrap();
            let want = CirculantInverse::memory_estimate_bytes(&grid, nt, nt > 0);
            assert_eq!(inv.memory_bytes(), want);
        }
    }
}
