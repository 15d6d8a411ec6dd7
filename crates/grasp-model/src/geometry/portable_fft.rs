//! A radix-2 complex FFT that gives the same bits on every machine: its twiddle factors come
//! from the pure-Rust `libm` (not the platform's `sin`/`cos`, which differ in the last bit
//! between C libraries), it picks no SIMD path at run time (rustfft's default planner does),
//! and every sum is taken in one fixed order. It serves the seeded random surfaces
//! ([`super::random_surface`]), whose heights must not depend on the machine; the compliance
//! operator keeps rustfft, where speed matters and the last bit does not.
//!
//! The transform of length `n` (a power of two) is the unnormalised inverse DFT
//!
//! ```text
//!   X_k = sum_j x_j exp(2 pi i j k / n)
//! ```
//!
//! computed by the iterative Cooley-Tukey decimation in time (bit-reversed input order, then
//! `log2 n` passes of butterflies; Press et al., *Numerical Recipes*, 3rd ed., section 12.2).

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

/// A planned inverse transform (`s = +1`, unnormalised) of one length.
#[derive(Debug, Clone)]
pub struct PortableFft {
    n: usize,
    /// `exp(2 pi i k / n)` for `k < n / 2`.
    twiddles: Vec<Complex64>,
}

impl PortableFft {
    /// The inverse transform of length `n` (a power of two, at least 1).
    pub fn inverse(n: usize) -> Result<PortableFft, String> {
        if !n.is_power_of_two() {
            return Err(format!("an FFT length must be a power of two, not {n}"));
        }
        let twiddles = (0..n / 2)
            .map(|k| {
                let angle = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                let (s, c) = libm::sincos(angle);
                Complex64::new(c, s)
            })
            .collect();
        Ok(PortableFft { n, twiddles })
    }

    /// Transforms `data` (of the planned length) in place.
    pub fn process(&self, data: &mut [Complex64]) {
        let n = self.n;
        assert_eq!(data.len(), n, "the planned length");
        if n < 2 {
            return;
        }
        let bits = n.trailing_zeros();
        for i in 0..n {
            let j = i.reverse_bits() >> (usize::BITS - bits);
            if j > i {
                data.swap(i, j);
            }
        }
        let mut len = 2;
        while len <= n {
            let (half, step) = (len / 2, n / len);
            for block in data.chunks_exact_mut(len) {
                let (lo, hi) = block.split_at_mut(half);
                for (k, (a, b)) in lo.iter_mut().zip(hi.iter_mut()).enumerate() {
                    let t = *b * self.twiddles[k * step];
                    *b = *a - t;
                    *a += t;
                }
            }
            len *= 2;
        }
    }

    /// Transforms a square `n x n` row-major array in place along both axes: every row, then
    /// every column (through an in-place transpose). Rows are transformed in parallel; each
    /// row's arithmetic is the same whichever thread runs it, so the result does not depend on
    /// the number of threads.
    pub fn process_square(&self, data: &mut [Complex64]) {
        let n = self.n;
        assert_eq!(data.len(), n * n, "an n x n array");
        for _ in 0..2 {
            data.par_chunks_exact_mut(n)
                .for_each(|row| self.process(row));
            transpose_square(data, n);
        }
    }
}

/// Transposes a square `n x n` row-major array in place.
fn transpose_square(data: &mut [Complex64], n: usize) {
    for i in 0..n {
        for j in i + 1..n {
            data.swap(i * n + j, j * n + i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The DFT by its definition, `O(n^2)`, angles reduced mod `n` exactly.
    fn direct(x: &[Complex64], sign: f64) -> Vec<Complex64> {
        let n = x.len();
        (0..n)
            .map(|k| {
                x.iter()
                    .enumerate()
                    .map(|(j, v)| {
                        let a = sign * 2.0 * std::f64::consts::PI * ((j * k) % n) as f64;
                        v * Complex64::from_polar(1.0, a / n as f64)
                    })
                    .sum()
            })
            .collect()
    }

    fn sample(n: usize) -> Vec<Complex64> {
        // Deterministic, irregular values.
        (0..n)
            .map(|j| Complex64::new((j as f64 * 0.37).sin() + 0.1, (j as f64 * 1.3).cos()))
            .collect()
    }

    #[test]
    fn matches_the_definition() {
        // Round-off of an n-point FFT grows like log2(n) eps times the values' size (about
        // sqrt(n) here); 1e-12 leaves a margin of a hundred over that for n <= 256.
        for n in [1, 2, 4, 8, 32, 256] {
            let x = sample(n);
            let mut y = x.clone();
            PortableFft::inverse(n).unwrap().process(&mut y);
            let want = direct(&x, 1.0);
            for (a, b) in y.iter().zip(&want) {
                assert!((a - b).norm() < 1e-12 * n as f64, "n = {n}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn the_square_transform_is_separable() {
        // A product x_i y_j transforms into X_k Y_l.
        let n = 16;
        let (x, y) = (sample(n), sample(n + 3)[3..].to_vec());
        let mut grid: Vec<Complex64> = (0..n * n).map(|k| x[k / n] * y[k % n]).collect();
        let fft = PortableFft::inverse(n).unwrap();
        fft.process_square(&mut grid);
        let (fx, fy) = (direct(&x, 1.0), direct(&y, 1.0));
        for k in 0..n * n {
            let want = fx[k / n] * fy[k % n];
            assert!((grid[k] - want).norm() < 1e-11, "{k}");
        }
    }

    #[test]
    fn lengths_other_than_powers_of_two_are_refused() {
        assert!(PortableFft::inverse(12).is_err());
        assert!(PortableFft::inverse(0).is_err());
    }
}
