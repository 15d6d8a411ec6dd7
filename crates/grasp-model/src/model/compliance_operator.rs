//! The patch compliance as a matrix-free operator: products `C v` by zero-padded 2-D FFT
//! convolutions, in `O(N log N)` time and `O(N)` memory for a patch of `N` elements.
//!
//! On a finger's uniform grid every block of the patch compliance ([`super::influence`]:
//! `nn`, `11`, `22`, `12`, `n1`, `n2`) depends only on the index offset between the field and
//! the source element, so each block is a 2-D discrete convolution with a kernel over the
//! offsets `(-(nx-1)..nx) x (-(ny-1)..ny)`. Padding the grid to `2 nx x 2 ny` and placing the
//! kernel there with wrap-around makes the circular convolution of the FFT equal to the
//! non-periodic one on the grid (the "DC-FFT" construction of Liu, Wang and Liu, Wear 243,
//! 2000). The kernels are the offsets' entries of [`super::influence::KernelTable`] (for half-spaces the exact rectangle integrals),
//! so this operator and the dense matrix discretise the same thing and agree to round-off.
//!
//! The dense matrix is symmetrised (`(C + C')/2`) to remove the collocation round-off of the
//! corner sums; here the diagonal blocks take the symmetrised kernel `(K(d) + K(-d))/2`, and
//! the transposed off-diagonal blocks (`21`, `1n`, `2n`) take `K(-d)`, whose spectrum is the
//! complex conjugate of `K(d)`'s (a real kernel), so only six spectra are kept.

use std::sync::{Arc, OnceLock};

use nalgebra::DMatrix;

use realfft::num_complex::Complex;

use super::circulant_inverse::CirculantInverse;
use super::grid_fft::GridFft;
use super::influence::{Block, GridSpec, KernelTable};
use crate::error::OutOfMemory;

/// One term of an output component: the source component, the kernel and whether it is read
/// conjugated (the transposed block).
type Term = (usize, Block, bool);

/// The FFT compliance operator of one finger's patch (m/N), on the unknowns' layout of the
/// dense matrix: component-major (`normal`, then `t1`, then `t2`), element `k = i ny + j`.
pub struct ComplianceOperator {
    grid: GridSpec,
    n_tangential: usize,
    coupled: bool,
    /// Transforms on the padded grid, `2 nx x 2 ny`.
    fft: GridFft,
    /// Kernel spectra, indexed by [`Block`] (empty where the block is not needed), in the
    /// transposed layout `hy x px` (row `q`: the column transform of frequency `q` along `j`).
    spectra: Vec<Vec<Complex<f64>>>,
    /// `K(0)` of the diagonal blocks (`nn`, `11`, `22`), m/N: the matrix's diagonal.
    diagonal: [f64; 3],
    /// Per kernel (indexed by [`Block`]), the sum of its absolute values over all offsets, m/N.
    abs_sums: [f64; 6],
    /// The inverse of its circulant approximation: the conjugate gradients' preconditioner.
    preconditioner: CirculantInverse,
    /// The operator written out as a matrix, once asked for ([`ComplianceOperator::matrix`]).
    written_out: OnceLock<Arc<DMatrix<f64>>>,
}

impl std::fmt::Debug for ComplianceOperator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ComplianceOperator")
            .field("grid", &self.grid)
            .field("n_tangential", &self.n_tangential)
            .field("coupled", &self.coupled)
            .finish_non_exhaustive()
    }
}

impl ComplianceOperator {
    /// The operator of the offsets' entries `table` (its grid's), truncated to the first
    /// `1 + n_tangential` components as [`super::influence::patch_compliance`] is (model.md,
    /// patch compliance; Johnson 3.22c and 3.86a-c for half-spaces); [`OutOfMemory`] when its
    /// spectra cannot be allocated.
    pub fn new(table: &KernelTable, n_tangential: usize) -> Result<Self, OutOfMemory> {
        let grid = table.grid();
        let coupled = table.coupled() && n_tangential > 0;
        let mut op = ComplianceOperator {
            grid: *grid,
            n_tangential,
            coupled,
            fft: GridFft::new([grid.nx, grid.ny], [2 * grid.nx, 2 * grid.ny]),
            spectra: vec![Vec::new(); 6],
            diagonal: [0.0; 3],
            abs_sums: [0.0; 6],
            preconditioner: CirculantInverse::new(table, n_tangential, coupled)?,
            written_out: OnceLock::new(),
        };
        op.build_spectra(table)?;
        Ok(op)
    }

    /// Elements of the patch.
    pub fn elements(&self) -> usize {
        self.grid.len()
    }

    /// Unknowns, `(1 + n_tangential) N`.
    pub fn len(&self) -> usize {
        self.grid.len() * (1 + self.n_tangential)
    }

    /// Diagonal entry of component `c` (every element has the same, the block being Toeplitz),
    /// m/N.
    pub fn diagonal(&self, c: usize) -> f64 {
        self.diagonal[c]
    }

    /// An upper bound of the largest absolute row sum of the matrix, m/N: per output
    /// component, the absolute sums of its blocks' kernels over every offset (a row sums over
    /// a subset of them).
    pub fn row_sum_bound(&self) -> f64 {
        (0..=self.n_tangential)
            .map(|r| {
                self.terms(r)
                    .iter()
                    .map(|&(_, block, _)| self.abs_sums[block as usize])
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    }

    /// The operator as a matrix (m/N), column by column (one product each), symmetrised like
    /// the dense matrix; computed once and kept. For the solvers that need entries, on small
    /// patches only: it has `len()^2` entries.
    pub fn matrix(&self) -> Arc<DMatrix<f64>> {
        Arc::clone(self.written_out.get_or_init(|| {
            let n = self.len();
            let mut m = DMatrix::zeros(n, n);
            let mut unit = vec![0.0; n];
            for col in 0..n {
                unit[col] = 1.0;
                self.apply(&unit, m.column_mut(col).as_mut_slice());
                unit[col] = 0.0;
            }
            Arc::new((&m + m.transpose()) * 0.5)
        }))
    }

    #[cfg(test)]
    /// Bytes held by the operator (its kernel spectra and its preconditioner), for memory
    /// estimates.
    pub fn memory_bytes(&self) -> usize {
        let entries: usize = self.spectra.iter().map(Vec::len).sum();
        entries * std::mem::size_of::<Complex<f64>>() + self.preconditioner.memory_bytes()
    }

    /// Bytes [`ComplianceOperator::new`] keeps for a grid, before building it: one spectrum
    /// of `2 nx (ny + 1)` complex numbers per block needed, and the preconditioner's.
    pub fn memory_estimate_bytes(grid: &GridSpec, n_tangential: usize, coupled: bool) -> usize {
        let blocks = match n_tangential {
            0 => 1,
            1 => 2 + usize::from(coupled),
            _ => 4 + 2 * usize::from(coupled),
        };
        blocks * 2 * grid.nx * (grid.ny + 1) * std::mem::size_of::<Complex<f64>>()
            + CirculantInverse::memory_estimate_bytes(grid, n_tangential, coupled)
    }

    /// Frees the work buffers its products and its preconditioner's keep between uses (a
    /// solve's, while its answer is read out; the next product allocates them again).
    pub fn release_work(&self) {
        self.fft.release_work();
        self.preconditioner.release_work();
    }

    /// `out = factor C_circ^-1 v`: the inverse of the operator's circulant approximation
    /// ([`CirculantInverse`]), N/m times m, scaled in the same pass; a preconditioner for
    /// systems in this operator.
    pub fn apply_approximate_inverse_scaled(&self, v: &[f64], out: &mut [f64], factor: f64) {
        self.preconditioner.apply(v, out, factor)
    }

    fn build_spectra(&mut self, table: &KernelTable) -> Result<(), OutOfMemory> {
        let sym = |block: Block| {
            move |a: &[f64; 6], b: &[f64; 6]| 0.5 * (a[block as usize] + b[block as usize])
        };
        let plain = |block: Block| move |a: &[f64; 6], _: &[f64; 6]| a[block as usize];
        let centre = table.centre();
        self.diagonal = [
            centre[Block::Nn as usize],
            centre[Block::T11 as usize],
            centre[Block::T22 as usize],
        ];
        self.set(Block::Nn, table, sym(Block::Nn))?;
        if self.n_tangential >= 1 {
            self.set(Block::T11, table, sym(Block::T11))?;
            if self.coupled {
                self.set(Block::N1, table, plain(Block::N1))?;
            }
        }
        if self.n_tangential >= 2 {
            self.set(Block::T22, table, sym(Block::T22))?;
            self.set(Block::T12, table, plain(Block::T12))?;
            if self.coupled {
                self.set(Block::N2, table, plain(Block::N2))?;
            }
        }
        Ok(())
    }

    /// The spectrum of the kernel `value(K(d), K(-d))` placed on the padded grid with
    /// wrap-around.
    fn set(
        &mut self,
        block: Block,
        table: &KernelTable,
        value: impl Fn(&[f64; 6], &[f64; 6]) -> f64 + Sync + Send,
    ) -> Result<(), OutOfMemory> {
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        let wy = 2 * ny - 1;
        let (px, py) = (self.fft.px, self.fft.py);
        let mut padded = crate::allocation::filled(px * py, 0.0)?;
        // Padded row `(a + px + 1 - nx) % px` holds table row `a` (px = 2 nx: every row but
        // one), each row on its own, on all cores for a large grid.
        let fill = |(row, out): (usize, &mut [f64])| {
            let a = (row + nx - 1) % px;
            if a < 2 * nx - 1 {
                for b in 0..wy {
                    let col = (b + py + 1 - ny) % py;
                    out[col] = value(table.at(a, b), table.at(2 * nx - 2 - a, 2 * ny - 2 - b));
                }
            }
        };
        if self.fft.parallel() {
            use rayon::prelude::*;
            padded.par_chunks_mut(py).enumerate().for_each(fill);
        } else {
            padded.chunks_mut(py).enumerate().for_each(fill);
        }
        // The sum in the table's order, as it was taken when the rows were filled in turn.
        let mut abs_sum = 0.0;
        for a in 0..2 * nx - 1 {
            let row = &padded[((a + px + 1 - nx) % px) * py..][..py];
            for b in 0..wy {
                abs_sum += row[(b + py + 1 - ny) % py].abs();
            }
        }
        self.abs_sums[block as usize] = abs_sum;
        self.spectra[block as usize] = self.fft.transform(&mut padded, px)?;
        Ok(())
    }

    /// The terms of output component `r`.
    fn terms(&self, r: usize) -> Vec<Term> {
        let (nt, cp) = (self.n_tangential, self.coupled);
        let mut t = Vec::with_capacity(3);
        match r {
            0 => {
                t.push((0, Block::Nn, false));
                if cp {
                    t.push((1, Block::N1, false));
                    if nt >= 2 {
                        t.push((2, Block::N2, false));
                    }
                }
            }
            1 => {
                if cp {
                    t.push((0, Block::N1, true));
                }
                t.push((1, Block::T11, false));
                if nt >= 2 {
                    t.push((2, Block::T12, false));
                }
            }
            _ => {
                if cp {
                    t.push((0, Block::N2, true));
                }
                t.push((1, Block::T12, true));
                t.push((2, Block::T22, false));
            }
        }
        t
    }

    /// `out = C v`, m/N times N: the relative displacements (gap increase along the normal,
    /// then along `t1`, `t2`) of the dense matrix's product
    /// ([`super::influence::patch_compliance`]), to round-off.
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        self.apply_scaled(v, out, 1.0)
    }

    /// `out = factor C v`: [`ComplianceOperator::apply`] with its result scaled in the same
    /// pass.
    pub fn apply_scaled(&self, v: &[f64], out: &mut [f64], factor: f64) {
        let n = self.grid.len();
        let dim = 1 + self.n_tangential;
        assert_eq!(v.len(), dim * n, "vector length");
        assert_eq!(out.len(), dim * n, "output length");
        let terms: Vec<Vec<Term>> = (0..dim).map(|r| self.terms(r)).collect();
        self.fft.multiply_blocks(v, out, dim, factor, |r, c| {
            let &(_, block, conjugate) = terms[r].iter().find(|t| t.0 == c)?;
            Some((self.spectra[block as usize].as_slice(), conjugate))
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::influence::{offset_table, patch_compliance, BlockKernels, PairConstants};
    use crate::model::material::Material;

    /// The half-space table of `pair` on `grid`.
    fn half_space(grid: &GridSpec, pair: &PairConstants) -> KernelTable {
        KernelTable::half_space(grid, pair).unwrap()
    }

    fn elastic(e: f64, nu: f64) -> Material {
        Material::Elastic {
            youngs_modulus_pa: e,
            poisson_ratio: nu,
        }
    }

    /// The largest difference between `got` and the dense product `C v`, and the scale it is
    /// judged against, `max |C| sum |v|` (a bound of every entry of the product).
    fn product_error(dense: &nalgebra::DMatrix<f64>, v: &[f64], got: &[f64]) -> (f64, f64) {
        let want = dense * nalgebra::DVector::from_column_slice(v);
        let err = got
            .iter()
            .zip(want.iter())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        (
            err,
            dense.abs().max() * v.iter().map(|x| x.abs()).sum::<f64>(),
        )
    }

    /// Seeded pseudo-random numbers in [0, 1) (64-bit LCG).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The FFT product equals the dense matrix's product, every block and reduction (coupled
    /// and uncoupled pairs, frictionless, planar, 3-D; square, oblong and one-row grids).
    /// Tolerance: FFT round-off is about `1e-16 log2(N)` of the largest kernel spectrum times
    /// `|v|`; 1e-12 of `|C| |v|` leaves a wide margin and still catches any misplaced offset or
    /// sign (those change entries by O(1) of their size).
    #[test]
    fn products_equal_the_dense_matrix() {
        let mut seed = 0x2545f4914f6cdd1d;
        let pairs = [
            PairConstants::new(&elastic(5e6, 0.45), &elastic(210e9, 0.3)),
            PairConstants::new(&elastic(70e9, 0.33), &elastic(70e9, 0.33)),
            PairConstants::new(&elastic(1e6, 0.0), &Material::Rigid),
        ];
        let grids = [(7, 5), (1, 9), (6, 1), (12, 12), (3, 8)];
        for (p, pair) in pairs.iter().enumerate() {
            for &(nx, ny) in &grids {
                let grid = GridSpec {
                    nx,
                    ny,
                    hx: 1e-4 * (1.0 + lcg(&mut seed)),
                    hy: 1e-4 * (1.0 + lcg(&mut seed)),
                };
                for nt in 0..=2 {
                    let table = half_space(&grid, pair);
                    let dense = patch_compliance(&table, nt);
                    let op = ComplianceOperator::new(&table, nt).unwrap();
                    let v: Vec<f64> = (0..op.len()).map(|_| lcg(&mut seed) - 0.5).collect();
                    let mut got = vec![0.0; op.len()];
                    op.apply(&v, &mut got);
                    let (err, scale) = product_error(&dense, &v, &got);
                    assert!(
                        err <= 1e-12 * scale,
                        "pair {p}, grid {nx}x{ny}, n_tangential {nt}: error {err:e} of {scale:e}"
                    );
                    for c in 0..=nt {
                        let k = c * grid.len();
                        assert!((op.diagonal(c) - dense[(k, k)]).abs() <= 1e-15 * dense[(k, k)]);
                    }
                    // The bound holds every row's absolute sum (to round-off).
                    let rows = (0..op.len())
                        .map(|r| dense.row(r).iter().map(|x| x.abs()).sum::<f64>())
                        .fold(0.0, f64::max);
                    assert!(rows <= op.row_sum_bound() * (1.0 + 1e-12));
                }
            }
        }
    }

    /// A unit force on one element gives the dense matrix's column (the operator applied to a
    /// basis vector), including the coupling's transposed blocks.
    #[test]
    fn a_unit_force_gives_the_dense_column() {
        let grid = GridSpec {
            nx: 5,
            ny: 4,
            hx: 2e-4,
            hy: 1e-4,
        };
        let pair = PairConstants::new(&elastic(2e6, 0.49), &elastic(200e9, 0.25));
        let table = half_space(&grid, &pair);
        let dense = patch_compliance(&table, 2);
        let op = ComplianceOperator::new(&table, 2).unwrap();
        let mut e = vec![0.0; op.len()];
        let mut got = vec![0.0; op.len()];
        for col in [0, 7, grid.len() + 3, 2 * grid.len() + 19] {
            e.fill(0.0);
            e[col] = 1.0;
            op.apply(&e, &mut got);
            for (r, g) in got.iter().enumerate() {
                let want = dense[(r, col)];
                assert!(
                    (g - want).abs() <= 1e-12 * dense.abs().max(),
                    "entry ({r}, {col}): {g:e} vs {want:e}"
                );
            }
        }
    }

    /// The transforms that run on all cores (padded grids of 256 x 256 points and more) give
    /// the dense matrix's product, and the same bits on one thread as on the default pool.
    /// The dense product of a sparse force (five elements loaded, frictionless block) is summed
    /// here from the rectangle integrals of each offset (the dense matrix's entries,
    /// symmetrised), as the whole matrix would take 2 GB.
    #[test]
    fn large_grids_on_all_cores_equal_the_dense_matrix_and_one_thread() {
        let grid = GridSpec {
            nx: 128,
            ny: 131,
            hx: 1e-4,
            hy: 1.3e-4,
        };
        let pair = PairConstants::new(&elastic(5e6, 0.45), &elastic(210e9, 0.3));
        let mut seed = 0x853c49e6748fea9b;
        for nt in [0, 2] {
            let op = ComplianceOperator::new(&half_space(&grid, &pair), nt).unwrap();
            assert!(op.fft.parallel());
            let v: Vec<f64> = (0..op.len()).map(|_| lcg(&mut seed) - 0.5).collect();
            let mut got = vec![0.0; op.len()];
            op.apply(&v, &mut got);
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let mut alone = vec![0.0; op.len()];
            one.install(|| op.apply(&v, &mut alone));
            assert!(got
                .iter()
                .zip(&alone)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
        }
        let op = ComplianceOperator::new(&half_space(&grid, &pair), 0).unwrap();
        let loaded = [0, 77, 8000, 12345, grid.len() - 1];
        let mut v = vec![0.0; op.len()];
        for (i, &k) in loaded.iter().enumerate() {
            v[k] = 1.0 - 0.3 * i as f64;
        }
        let mut got = vec![0.0; op.len()];
        op.apply(&v, &mut got);
        let table = offset_table(&grid);
        let kernels = BlockKernels::new(&grid, &pair);
        let (wx, wy) = (2 * grid.nx as i64 - 1, 2 * grid.ny as i64 - 1);
        let entry = |field: usize, source: usize| {
            let (ny, cx, cy) = (grid.ny as i64, grid.nx as i64 - 1, grid.ny as i64 - 1);
            let (f, s) = (field as i64, source as i64);
            let (dx, dy) = (f / ny - s / ny, f % ny - s % ny);
            let at = |x: i64, y: i64| &table[((x + cx) * wy + y + cy) as usize];
            assert!((dx + cx) < wx && (dy + cy) < wy);
            0.5 * (kernels.nn(at(dx, dy)) + kernels.nn(at(-dx, -dy)))
        };
        let scale = kernels.nn(&table[(grid.nx - 1) * (2 * grid.ny - 1) + grid.ny - 1])
            * v.iter().map(|x| x.abs()).sum::<f64>();
        for field in (0..grid.len()).step_by(97) {
            let want: f64 = loaded.iter().map(|&k| entry(field, k) * v[k]).sum();
            let err = (got[field] - want).abs();
            assert!(
                err <= 1e-12 * scale,
                "element {field}: error {err:e} of {scale:e}"
            );
        }
    }

    #[test]
    fn memory_is_what_the_estimate_says() {
        let grid = GridSpec {
            nx: 16,
            ny: 10,
            hx: 1e-4,
            hy: 1e-4,
        };
        let pair = PairConstants::new(&elastic(5e6, 0.45), &elastic(210e9, 0.3));
        for nt in 0..=2 {
            let op = ComplianceOperator::new(&half_space(&grid, &pair), nt).unwrap();
            assert_eq!(
                op.memory_bytes(),
                ComplianceOperator::memory_estimate_bytes(&grid, nt, !pair.uncoupled())
            );
        }
    }
}
