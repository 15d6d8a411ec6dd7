//! 2-D real FFTs of values on a finger's grid embedded in a (possibly larger) periodic
//! transform grid: the machinery shared by the compliance operator (a `2 nx x 2 ny` padded
//! grid, [`super::compliance_operator`]) and its circulant preconditioner (the `nx x ny` grid
//! itself, [`super::circulant_inverse`]).
//!
//! Spectra are kept in a transposed layout, `hy x px` (row `q`: the column transform of
//! frequency `q` along `j`), with `hy = py / 2 + 1`: rows are transformed real-to-complex, then
//! the columns complex-to-complex.
//!
//! Between the passes the half-spectra of the rows are kept blocked by tile: per tile of
//! [`TILE`] frequencies, its `n_rows x tile` values, row after row. A task of the row passes
//! then reads or writes a few kilobytes in a row per tile, and a tile's task reads its block
//! whole, instead of every task touching each of a megabytes-long array's rows (and pages) for
//! a few values.
//!
//! A product with a block kernel ([`GridFft::multiply_blocks`]) runs in three passes, each
//! split into independent tasks that run on all cores for large grids:
//!
//! 1. the grid's rows, real-to-complex (a task per few rows), their half-spectra blocked by tile;
//! 2. per tile of [`TILE`] frequencies `q`: the columns gathered, transformed, multiplied by
//!    the kernel's rows and transformed back, all in a tile-sized scratch that stays in cache
//!    (the padded spectrum is never stored whole);
//! 3. the grid's rows back, complex-to-real (a task per few rows, reading each tile's block).
//!
//! Every row, column and product is computed by the same code on any thread, and nothing is
//! summed across tasks, so a product's bits do not depend on the number of threads. Scratch
//! buffers are leased from a pool: after the first product, products allocate nothing.

use std::sync::{Arc, Mutex};

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

use crate::error::OutOfMemory;

/// Transform grids of at least this many points (256 x 256) transform on all cores.
const PARALLEL_POINTS: usize = 256 * 256;

/// Frequencies `q` whose columns one task transforms together (their scratch, `TILE px`
/// complex numbers per component, stays in cache).
const TILE: usize = 16;

/// Grid rows one task transforms together.
const ROWS: usize = 8;

/// Work buffers kept per kind.
const KEPT_BUFFERS: usize = 8;

/// One task's work buffers.
#[derive(Default)]
struct Scratch {
    /// Per component, the gathered columns of a tile, `TILE px`.
    columns: Vec<Vec<Complex<f64>>>,
    /// One output component's spectrum over a tile, `TILE px`.
    sum: Vec<Complex<f64>>,
    /// The transforms' scratch.
    fft: Vec<Complex<f64>>,
    /// A real row of the transform grid, `py`.
    real: Vec<f64>,
    /// Half-spectra of [`ROWS`] rows, `ROWS hy`.
    half: Vec<Complex<f64>>,
}

/// A buffer of `len` from `pool` (its contents arbitrary), or a new one.
fn take<T: Copy + Default + Send + Sync>(pool: &Mutex<Vec<Vec<T>>>, len: usize) -> Vec<T> {
    let mut b = pool
        .lock()
        .ok()
        .and_then(|mut p| p.pop())
        .unwrap_or_default();
    crate::allocation::resize_on_all_cores(&mut b, len, T::default());
    b
}

/// [`take`], or [`OutOfMemory`] when the buffer cannot be grown to `len`.
fn try_take<T: Copy + Default + Send + Sync>(
    pool: &Mutex<Vec<Vec<T>>>,
    len: usize,
) -> Result<Vec<T>, OutOfMemory> {
    let mut b = take(pool, 0);
    let bytes = (len as u64).saturating_mul(std::mem::size_of::<T>() as u64);
    b.try_reserve_exact(len)
        .map_err(|_| OutOfMemory::new("a buffer", bytes))?;
    crate::allocation::resize_on_all_cores(&mut b, len, T::default());
    Ok(b)
}

/// Gives a buffer back to `pool`.
fn give<T>(pool: &Mutex<Vec<Vec<T>>>, b: Vec<T>) {
    if let Ok(mut p) = pool.lock() {
        if p.len() < KEPT_BUFFERS {
            p.push(b);
        }
    }
}

/// A [`Scratch`] leased from a pool, given back when dropped.
struct Lease<'p> {
    pool: &'p Mutex<Vec<Scratch>>,
    scratch: Scratch,
}

impl Drop for Lease<'_> {
    fn drop(&mut self) {
        if let Ok(mut p) = self.pool.lock() {
            p.push(std::mem::take(&mut self.scratch));
        }
    }
}

/// One output component's terms: per source component, the kernel's spectrum and whether it
/// is read conjugated.
type Terms<'k> = Vec<(usize, &'k [Complex<f64>], bool)>;

/// Plans and work buffers for the transforms of an `nx x ny` grid embedded in a `px x py`
/// periodic grid (`px >= nx`, `py >= ny`; the rest zero).
pub(crate) struct GridFft {
    nx: usize,
    ny: usize,
    /// Transform grid.
    pub px: usize,
    pub py: usize,
    /// `py / 2 + 1` complex columns after the real transform.
    pub hy: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
    /// Row and column spectra kept between products: a fresh allocation of this size faults
    /// in new pages at every product.
    buffers: Mutex<Vec<Vec<Complex<f64>>>>,
    /// Tasks' scratch kept between products.
    scratch: Mutex<Vec<Scratch>>,
}

impl GridFft {
    /// Plans for the grid `[nx, ny]` in the transform grid `[px, py]`.
    pub fn new(grid: [usize; 2], transform: [usize; 2]) -> Self {
        let ([nx, ny], [px, py]) = (grid, transform);
        let mut real = RealFftPlanner::<f64>::new();
        let mut complex = FftPlanner::<f64>::new();
        GridFft {
            nx,
            ny,
            px,
            py,
            hy: py / 2 + 1,
            r2c: real.plan_fft_forward(py),
            c2r: real.plan_fft_inverse(py),
            forward: complex.plan_fft_forward(px),
            inverse: complex.plan_fft_inverse(px),
            buffers: Mutex::new(Vec::new()),
            scratch: Mutex::new(Vec::new()),
        }
    }

    /// Frees the work buffers kept between products (the next product allocates them again).
    pub fn release_work(&self) {
        if let Ok(mut b) = self.buffers.lock() {
            *b = Vec::new();
        }
        if let Ok(mut s) = self.scratch.lock() {
            *s = Vec::new();
        }
    }

    /// Entries of a spectrum, `hy px`.
    pub fn spectrum_len(&self) -> usize {
        self.hy * self.px
    }

    /// True when the grid is large enough for the transforms to pay for threads.
    pub fn parallel(&self) -> bool {
        self.px * self.py >= PARALLEL_POINTS
    }

    /// A scratch from the pool (or a new one), sized for `dim` components.
    fn lease(&self, dim: usize) -> Lease<'_> {
        let mut scratch = self
            .scratch
            .lock()
            .ok()
            .and_then(|mut p| p.pop())
            .unwrap_or_default();
        let tile = TILE * self.px;
        if scratch.columns.len() < dim.max(1) {
            scratch.columns.resize_with(dim.max(1), Vec::new);
        }
        for c in &mut scratch.columns {
            c.resize(tile, Complex::default());
        }
        scratch.sum.resize(tile, Complex::default());
        let fft = [
            self.forward.get_inplace_scratch_len(),
            self.inverse.get_inplace_scratch_len(),
            self.r2c.get_scratch_len(),
            self.c2r.get_scratch_len(),
        ];
        scratch
            .fft
            .resize(fft.into_iter().max().unwrap_or(0), Complex::default());
        scratch.real.resize(self.py, 0.0);
        scratch.half.resize(ROWS * self.hy, Complex::default());
        Lease {
            pool: &self.scratch,
            scratch,
        }
    }

    /// `task(scratch, k, chunk)` for every `chunk`-long piece `k` of `data`: on all cores for
    /// a large grid, each task with a leased scratch.
    fn each_chunk<T: Send>(
        &self,
        data: &mut [T],
        chunk: usize,
        dim: usize,
        task: impl Fn(&mut Scratch, usize, &mut [T]) + Sync + Send,
    ) {
        if self.parallel() {
            use rayon::prelude::*;
            data.par_chunks_mut(chunk)
                .enumerate()
                .for_each_init(|| self.lease(dim), |s, (k, c)| task(&mut s.scratch, k, c));
        } else {
            let mut s = self.lease(dim);
            for (k, c) in data.chunks_mut(chunk).enumerate() {
                task(&mut s.scratch, k, c);
            }
        }
    }

    /// `task(scratch, k, tasks[k])` for every task: on all cores for a large grid, each task
    /// with a leased scratch.
    fn each_task<T: Send>(
        &self,
        tasks: Vec<T>,
        task: impl Fn(&mut Scratch, usize, T) + Sync + Send,
    ) {
        if self.parallel() {
            use rayon::prelude::*;
            tasks
                .into_par_iter()
                .enumerate()
                .for_each_init(|| self.lease(1), |s, (k, t)| task(&mut s.scratch, k, t));
        } else {
            let mut s = self.lease(1);
            for (k, t) in tasks.into_iter().enumerate() {
                task(&mut s.scratch, k, t);
            }
        }
    }

    /// Frequencies of the tile starting at `q0`.
    fn tile_width(&self, q0: usize) -> usize {
        TILE.min(self.hy - q0)
    }

    /// `rows` (the half-spectra of `rows.len() / hy` rows, blocked by tile) cut into the
    /// parts of each [`ROWS`] rows: per task, its rows' part of every tile's block.
    fn row_parts<'r>(&self, rows: &'r mut [Complex<f64>]) -> Vec<Vec<&'r mut [Complex<f64>]>> {
        let n_rows = rows.len() / self.hy;
        let mut tasks: Vec<Vec<_>> = (0..n_rows.div_ceil(ROWS)).map(|_| Vec::new()).collect();
        let mut rest = rows;
        for q0 in (0..self.hy).step_by(TILE) {
            let w = self.tile_width(q0);
            let (block, tail) = std::mem::take(&mut rest).split_at_mut(w * n_rows);
            for (task, part) in tasks.iter_mut().zip(block.chunks_mut(ROWS * w)) {
                task.push(part);
            }
            rest = tail;
        }
        tasks
    }

    /// True when some entry of `v` is not zero: on all cores for a large grid (a vector zero
    /// over much of a patch is otherwise scanned on one core at every product).
    fn any_nonzero(&self, v: &[f64]) -> bool {
        let nonzero = |c: &[f64]| c.iter().any(|x| *x != 0.0);
        if self.parallel() {
            use rayon::prelude::*;
            v.par_chunks(ROWS * self.ny.max(1)).any(nonzero)
        } else {
            nonzero(v)
        }
    }

    /// The half-spectra (into `rows`, blocked by tile) of the first `rows.len() / hy` rows of
    /// `src`, whose rows are `stride` long and hold values in their first `width <= py`
    /// entries (zero beyond, up to `py`).
    fn row_spectra(&self, src: &[f64], stride: usize, width: usize, rows: &mut [Complex<f64>]) {
        let hy = self.hy;
        let n_rows = rows.len() / hy;
        self.each_task(self.row_parts(rows), |s, k, mut parts| {
            let count = ROWS.min(n_rows - k * ROWS);
            for r in 0..count {
                let i = k * ROWS + r;
                s.real[..width].copy_from_slice(&src[i * stride..i * stride + width]);
                s.real[width..].fill(0.0);
                let spectrum = &mut s.half[r * hy..(r + 1) * hy];
                // Lengths are the plan's: the transform cannot fail.
                let _ = self
                    .r2c
                    .process_with_scratch(&mut s.real, spectrum, &mut s.fft);
            }
            for (part, q0) in parts.iter_mut().zip((0..hy).step_by(TILE)) {
                let w = self.tile_width(q0);
                for (r, dst) in part.chunks_exact_mut(w).enumerate() {
                    dst.copy_from_slice(&s.half[r * hy + q0..r * hy + q0 + w]);
                }
            }
        });
    }

    /// Columns `q0 .. q0 + tile` of `rows` (`n_rows` half-spectra, blocked by tile), each
    /// zero-padded to `px`, into `dst` (`tile px`, column after column).
    fn gather_columns(
        &self,
        rows: &[Complex<f64>],
        n_rows: usize,
        q0: usize,
        dst: &mut [Complex<f64>],
    ) {
        let px = self.px;
        let tile = dst.len() / px;
        for t in 0..tile {
            dst[t * px + n_rows..(t + 1) * px].fill(Complex::default());
        }
        let block = &rows[q0 * n_rows..(q0 + tile) * n_rows];
        for (i, src) in block.chunks_exact(tile).enumerate() {
            for (t, v) in src.iter().enumerate() {
                dst[t * px + i] = *v;
            }
        }
    }

    /// The 2-D spectrum of a real array on the transform grid (`px x py`, row-major; its
    /// rows from `nonzero_rows` on are zero and not read), in the transposed layout;
    /// [`OutOfMemory`] when the spectrum cannot be allocated.
    pub fn transform(
        &self,
        padded: &mut [f64],
        nonzero_rows: usize,
    ) -> Result<Vec<Complex<f64>>, OutOfMemory> {
        let (px, py, hy) = (self.px, self.py, self.hy);
        let mut rows = try_take(&self.buffers, nonzero_rows * hy)?;
        self.row_spectra(padded, py, py, &mut rows);
        let mut spectrum = crate::allocation::filled(hy * px, Complex::default())?;
        self.each_chunk(&mut spectrum, TILE * px, 1, |s, k, cols| {
            self.gather_columns(&rows, nonzero_rows, k * TILE, cols);
            self.forward.process_with_scratch(cols, &mut s.fft);
        });
        // Not kept: a kernel's rows are the whole transform grid's (four times a product's),
        // and a model transforms its kernels once.
        drop(rows);
        Ok(spectrum)
    }

    /// The tile `k` of frequencies of every output component with terms: the sources' columns
    /// transformed, multiplied by the kernels and transformed back; their first `nx` entries
    /// into `out` (`dim x nx x tile`: per component, row after row).
    fn tile_products(
        &self,
        s: &mut Scratch,
        k: usize,
        rows: &[Complex<f64>],
        terms: &[Terms],
        out: &mut [Complex<f64>],
    ) {
        let (nx, px, hy) = (self.nx, self.px, self.hy);
        let (q0, dim) = (k * TILE, terms.len());
        let tile = out.len() / (dim * nx);
        let len = tile * px;
        let mut sources = [false; 3];
        terms
            .iter()
            .flatten()
            .for_each(|&(c, _, _)| sources[c] = true);
        for (c, cols) in s
            .columns
            .iter_mut()
            .enumerate()
            .filter(|(c, _)| sources[*c])
        {
            let cols = &mut cols[..len];
            self.gather_columns(&rows[c * nx * hy..(c + 1) * nx * hy], nx, q0, cols);
            self.forward.process_with_scratch(cols, &mut s.fft);
        }
        for (r, row_terms) in terms.iter().enumerate().filter(|(_, t)| !t.is_empty()) {
            let sum = &mut s.sum[..len];
            sum.fill(Complex::default());
            for &(c, kernel, conjugate) in row_terms {
                let terms = sum.iter_mut().zip(&kernel[q0 * px..q0 * px + len]);
                let x = &s.columns[c][..len];
                match conjugate {
                    true => terms.zip(x).for_each(|((a, kk), x)| *a += kk.conj() * x),
                    false => terms.zip(x).for_each(|((a, kk), x)| *a += kk * x),
                }
            }
            self.inverse.process_with_scratch(sum, &mut s.fft);
            let out_r = &mut out[r * nx * tile..(r + 1) * nx * tile];
            for (i, o) in out_r.chunks_exact_mut(tile).enumerate() {
                for (t, v) in o.iter_mut().enumerate() {
                    *v = sum[t * px + i];
                }
            }
        }
    }

    /// Output component `r`'s grid values (`nx x ny`, into `out`) from its spectra in
    /// `columns` (per tile of frequencies, `dim x nx x tile`), scaled by `factor / (px py)`.
    fn rows_back(
        &self,
        columns: &[Complex<f64>],
        r: usize,
        dim: usize,
        factor: f64,
        out: &mut [f64],
    ) {
        let (nx, ny, py, hy) = (self.nx, self.ny, self.py, self.hy);
        let scale = factor / (self.px * py) as f64;
        self.each_chunk(out, ROWS * ny, 1, |s, k, out_rows| {
            let n_rows = out_rows.len() / ny;
            let i0 = k * ROWS;
            for q0 in (0..hy).step_by(TILE) {
                let w = self.tile_width(q0);
                let o = q0 * dim * nx + (r * nx + i0) * w;
                for (t, src) in columns[o..o + n_rows * w].chunks_exact(w).enumerate() {
                    s.half[t * hy + q0..t * hy + q0 + w].copy_from_slice(src);
                }
            }
            for (t, out_row) in out_rows.chunks_exact_mut(ny).enumerate() {
                let half = &mut s.half[t * hy..(t + 1) * hy];
                // The zero and Nyquist frequencies of a real signal are real; round-off in
                // their imaginary parts is dropped rather than refused.
                half[0].im = 0.0;
                if py % 2 == 0 {
                    half[hy - 1].im = 0.0;
                }
                let _ = self.c2r.process_with_scratch(half, &mut s.real, &mut s.fft);
                for (o, v) in out_row.iter_mut().zip(&s.real[..ny]) {
                    *o = scale * v;
                }
            }
        });
    }

    /// `out_r = factor sum_c K_rc * v_c` for a vector of `dim` components on the grid
    /// (component-major, `n = nx ny` each). `kernel(r, c)` gives block `(r, c)`'s spectrum
    /// and whether it is read conjugated (a transposed block), or `None` where the block is
    /// zero. Components that are zero are skipped.
    pub fn multiply_blocks<'k>(
        &self,
        v: &[f64],
        out: &mut [f64],
        dim: usize,
        factor: f64,
        kernel: impl Fn(usize, usize) -> Option<(&'k [Complex<f64>], bool)>,
    ) {
        let (nx, ny, hy) = (self.nx, self.ny, self.hy);
        let n = nx * ny;
        if n == 0 {
            return;
        }
        let nonzero: Vec<bool> = (0..dim)
            .map(|c| self.any_nonzero(&v[c * n..(c + 1) * n]))
            .collect();
        let terms: Vec<Terms> = (0..dim)
            .map(|r| {
                (0..dim)
                    .filter(|&c| nonzero[c])
                    .filter_map(|c| kernel(r, c).map(|(k, conj)| (c, k, conj)))
                    .collect()
            })
            .collect();
        let mut rows = take(&self.buffers, dim * nx * hy);
        for c in (0..dim).filter(|&c| nonzero[c]) {
            let part = &mut rows[c * nx * hy..(c + 1) * nx * hy];
            self.row_spectra(&v[c * n..(c + 1) * n], ny, ny, part);
        }
        let mut columns = take(&self.buffers, hy * dim * nx);
        self.each_chunk(&mut columns, TILE * dim * nx, dim, |s, k, tile| {
            self.tile_products(s, k, &rows, &terms, tile)
        });
        // Every output with terms is written whole by its rows; the others are zero.
        for (r, out_r) in out.chunks_exact_mut(n).enumerate().take(dim) {
            match terms[r].is_empty() {
                true => out_r.fill(0.0),
                false => self.rows_back(&columns, r, dim, factor, out_r),
            }
        }
        give(&self.buffers, rows);
        give(&self.buffers, columns);
    }
}
