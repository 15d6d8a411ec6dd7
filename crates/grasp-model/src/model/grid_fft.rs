//! 2-D real FFTs of values on a finger's grid embedded in a (possibly larger) periodic
//! transform grid: the machinery shared by the compliance operator (a `2 nx x 2 ny` padded
//! grid, [`super::compliance_operator`]) and its circulant preconditioner (the `nx x ny` grid
//! itself, [`super::circulant_inverse`]).
//!
//! Spectra are kept in a transposed layout, `hy x px` (row `q`: the column transform of
//! frequency `q` along `j`), with `hy = py / 2 + 1`: rows are transformed real-to-complex, then
//! the columns complex-to-complex. Transforms of large grids run on all cores; each row or
//! column is transformed the same way on any thread, so results do not depend on the number
//! of threads.

use std::sync::{Arc, Mutex};

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

/// Transform grids of at least this many points (256 x 256) transform on all cores.
const PARALLEL_POINTS: usize = 256 * 256;

/// Work buffers kept per kind.
const KEPT_BUFFERS: usize = 8;

/// `dst[c dst_stride + r] = src[r src_stride + c]` for `r < rows`, `c < cols`: a transpose, in
/// tiles that stay in cache, writing along `dst`'s rows (strided writes cost far more than
/// strided reads).
fn transpose(
    src: &[Complex<f64>],
    src_stride: usize,
    (rows, cols): (usize, usize),
    dst: &mut [Complex<f64>],
    dst_stride: usize,
) {
    const TILE: usize = 16;
    for r0 in (0..rows).step_by(TILE) {
        let r1 = (r0 + TILE).min(rows);
        for c0 in (0..cols).step_by(TILE) {
            for c in c0..(c0 + TILE).min(cols) {
                let line = &mut dst[c * dst_stride + r0..c * dst_stride + r1];
                for (r, d) in (r0..r1).zip(line) {
                    *d = src[r * src_stride + c];
                }
            }
        }
    }
}

/// A buffer of `len` from `pool` (its contents arbitrary), or a new one.
fn take<T: Copy + Default>(pool: &Mutex<Vec<Vec<T>>>, len: usize) -> Vec<T> {
    let mut b = pool
        .lock()
        .ok()
        .and_then(|mut p| p.pop())
        .unwrap_or_default();
    b.resize(len, T::default());
    b
}

/// Gives a buffer back to `pool`.
fn give<T>(pool: &Mutex<Vec<Vec<T>>>, b: Vec<T>) {
    if let Ok(mut p) = pool.lock() {
        if p.len() < KEPT_BUFFERS {
            p.push(b);
        }
    }
}

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
    /// Work buffers kept between transforms: a fresh allocation of this size faults in new
    /// pages at every product.
    complex_buffers: Mutex<Vec<Vec<Complex<f64>>>>,
    real_buffers: Mutex<Vec<Vec<f64>>>,
}

impl GridFft {
    /// Plans for the grid `nx x ny` in the transform grid `px x py`.
    pub fn new((nx, ny): (usize, usize), (px, py): (usize, usize)) -> Self {
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
            complex_buffers: Mutex::new(Vec::new()),
            real_buffers: Mutex::new(Vec::new()),
        }
    }

    /// Entries of a spectrum, `hy px`.
    pub fn spectrum_len(&self) -> usize {
        self.hy * self.px
    }

    /// A zeroed spectrum-sized buffer (from the pool when one is free).
    pub fn zeroed_spectrum(&self) -> Vec<Complex<f64>> {
        let mut b = take(&self.complex_buffers, self.spectrum_len());
        b.fill(Complex::default());
        b
    }

    /// Gives a spectrum-sized buffer back for reuse.
    pub fn recycle(&self, b: Vec<Complex<f64>>) {
        give(&self.complex_buffers, b);
    }

    /// The 2-D spectrum of a real array on the transform grid (`px x py`, row-major;
    /// overwritten) whose rows from `nonzero_rows` on are zero, in the transposed layout.
    pub fn transform(&self, padded: &mut [f64], nonzero_rows: usize) -> Vec<Complex<f64>> {
        let (px, py, hy) = (self.px, self.py, self.hy);
        let mut rows = take(&self.complex_buffers, px * hy);
        rows[nonzero_rows * hy..].fill(Complex::default());
        let row_transform = |(input, output): (&mut [f64], &mut [Complex<f64>])| {
            // Lengths are the plan's: the transform cannot fail.
            let _ = self.r2c.process(input, output);
        };
        let (inputs, outputs) = (
            &mut padded[..nonzero_rows * py],
            &mut rows[..nonzero_rows * hy],
        );
        if self.parallel() {
            use rayon::prelude::*;
            inputs
                .par_chunks_exact_mut(py)
                .zip(outputs.par_chunks_exact_mut(hy))
                .for_each(row_transform);
        } else {
            inputs
                .chunks_exact_mut(py)
                .zip(outputs.chunks_exact_mut(hy))
                .for_each(row_transform);
        }
        // Every entry is written by the transpose.
        let mut spectrum = take(&self.complex_buffers, hy * px);
        transpose(&rows, hy, (px, hy), &mut spectrum, px);
        give(&self.complex_buffers, rows);
        self.columns(&mut spectrum, &self.forward);
        spectrum
    }

    /// The spectrum of values on the grid (`nx x ny`, row-major), zero elsewhere on the
    /// transform grid.
    pub fn spectrum_of(&self, values: &[f64]) -> Vec<Complex<f64>> {
        let (ny, py) = (self.ny, self.py);
        let mut padded = take(&self.real_buffers, self.px * py);
        for (i, row) in values.chunks_exact(ny).enumerate() {
            padded[i * py..i * py + ny].copy_from_slice(row);
            padded[i * py + ny..(i + 1) * py].fill(0.0);
        }
        // Rows from nx on are not read (the transform skips them).
        let spectrum = self.transform(&mut padded, self.nx);
        give(&self.real_buffers, padded);
        spectrum
    }

    /// The column transforms (length `px`) of a spectrum in the transposed layout.
    fn columns(&self, spectrum: &mut [Complex<f64>], plan: &Arc<dyn Fft<f64>>) {
        if self.parallel() {
            use rayon::prelude::*;
            let chunk = self.px * self.hy.div_ceil(rayon::current_num_threads().max(1));
            spectrum.par_chunks_mut(chunk).for_each(|c| plan.process(c));
        } else {
            plan.process(spectrum);
        }
    }

    /// True when the grid is large enough for the transforms to pay for threads.
    pub fn parallel(&self) -> bool {
        self.px * self.py >= PARALLEL_POINTS
    }

    /// The real array on the grid (`nx x ny`, row-major) whose spectrum on the transform grid
    /// is `spectrum` (transposed layout; overwritten), scaled by `1 / (px py)` (the inverse
    /// transform), added into `out`.
    pub fn add_inverse(&self, spectrum: &mut [Complex<f64>], out: &mut [f64]) {
        let (px, py, hy) = (self.px, self.py, self.hy);
        let (nx, ny) = (self.nx, self.ny);
        self.columns(spectrum, &self.inverse);
        let scale = 1.0 / (px * py) as f64;
        // The grid's rows of the spectrum, each a contiguous half-spectrum for c2r.
        let mut rows = take(&self.complex_buffers, nx * hy);
        transpose(spectrum, px, (hy, nx), &mut rows, hy);
        let row_inverse =
            |real: &mut Vec<f64>, (row, out_row): (&mut [Complex<f64>], &mut [f64])| {
                // The zero and Nyquist frequencies of a real signal are real; round-off in their
                // imaginary parts is dropped rather than refused.
                row[0].im = 0.0;
                if py % 2 == 0 {
                    row[hy - 1].im = 0.0;
                }
                let _ = self.c2r.process(row, real);
                for (o, r) in out_row.iter_mut().zip(&real[..ny]) {
                    *o += scale * r;
                }
            };
        if self.parallel() {
            use rayon::prelude::*;
            rows.par_chunks_exact_mut(hy)
                .zip(out.par_chunks_exact_mut(ny))
                .for_each_init(|| vec![0.0; py], row_inverse);
        } else {
            let mut real = vec![0.0; py];
            rows.chunks_exact_mut(hy)
                .zip(out.chunks_exact_mut(ny))
                .for_each(|pair| row_inverse(&mut real, pair));
        }
        give(&self.complex_buffers, rows);
    }

    /// `out_r = sum_c K_rc * v_c` for a vector of `dim` components on the grid
    /// (component-major, `n = nx ny` each): each component transformed once, each output
    /// accumulated over its blocks in the spectrum and transformed back once. `kernel(r, c)`
    /// gives block `(r, c)`'s spectrum and whether it is read conjugated (a transposed
    /// block), or `None` where the block is zero. Components that are zero are skipped.
    pub fn multiply_blocks<'k>(
        &self,
        v: &[f64],
        out: &mut [f64],
        dim: usize,
        kernel: impl Fn(usize, usize) -> Option<(&'k [Complex<f64>], bool)>,
    ) {
        let n = self.nx * self.ny;
        out.fill(0.0);
        if n == 0 {
            return;
        }
        let spectra: Vec<Option<Vec<Complex<f64>>>> = (0..dim)
            .map(|c| {
                let part = &v[c * n..(c + 1) * n];
                part.iter()
                    .any(|x| *x != 0.0)
                    .then(|| self.spectrum_of(part))
            })
            .collect();
        let mut acc = self.zeroed_spectrum();
        for r in 0..dim {
            acc.fill(Complex::default());
            let mut any = false;
            for (c, vc) in spectra.iter().enumerate() {
                let (Some(vc), Some((k, conjugate))) = (vc, kernel(r, c)) else {
                    continue;
                };
                any = true;
                let terms = acc.iter_mut().zip(k).zip(vc);
                match conjugate {
                    true => terms.for_each(|((a, kk), x)| *a += kk.conj() * x),
                    false => terms.for_each(|((a, kk), x)| *a += kk * x),
                }
            }
            if any {
                self.add_inverse(&mut acc, &mut out[r * n..(r + 1) * n]);
            }
        }
        self.recycle(acc);
        for s in spectra.into_iter().flatten() {
            self.recycle(s);
        }
    }
}
