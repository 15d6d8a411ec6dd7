//! Vector arithmetic of the iterative (FFT) path on all cores, with results that do not depend
//! on the number of threads: element-wise updates split into fixed chunks, and sums (dot
//! products, norms) taken as per-chunk partial sums added in chunk order, so a run gives the
//! same bits on one core as on sixteen.
//!
//! Vectors shorter than [`PARALLEL_LEN`] are handled on the calling thread by the same chunks
//! (the same bits again: the split does not depend on who computes it).

use std::sync::Mutex;

use rayon::prelude::*;

/// Entries per chunk (32 KiB of doubles: a chunk's work far exceeds a task's overhead).
pub(crate) const CHUNK: usize = 4096;

/// Vectors at least this long are updated on all cores.
pub(crate) const PARALLEL_LEN: usize = 8 * CHUNK;

/// `f(start, chunk)` for every [`CHUNK`]-long piece of `out` (`start`: its first index), on
/// all cores for a long vector.
pub(crate) fn each_chunk(out: &mut [f64], f: impl Fn(usize, &mut [f64]) + Sync + Send) {
    if out.len() >= PARALLEL_LEN {
        out.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(k, c)| f(k * CHUNK, c));
    } else {
        out.chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(k, c)| f(k * CHUNK, c));
    }
}

/// The sum over `0..len` of `term(start, end)` taken chunk by chunk (`term` sums its range),
/// the chunks' sums added in order.
pub(crate) fn chunked_sum(len: usize, term: impl Fn(usize, usize) -> f64 + Sync + Send) -> f64 {
    let chunks = len.div_ceil(CHUNK);
    let part = |k: usize| term(k * CHUNK, ((k + 1) * CHUNK).min(len));
    if len >= PARALLEL_LEN {
        let parts: Vec<f64> = (0..chunks).into_par_iter().map(part).collect();
        parts.iter().sum()
    } else {
        (0..chunks).map(part).sum()
    }
}

/// `a . b`.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    chunked_sum(a.len().min(b.len()), |s, e| {
        a[s..e].iter().zip(&b[s..e]).map(|(x, y)| x * y).sum()
    })
}

/// `[f(0), .., f(n - 1)]` for `n` pieces of work over `len` entries in all: on all cores when
/// `len` is long.
pub(crate) fn map_indices_coarse<T: Send>(
    n: usize,
    len: usize,
    f: impl Fn(usize) -> T + Sync + Send,
) -> Vec<T> {
    if len >= PARALLEL_LEN {
        (0..n).into_par_iter().map(f).collect()
    } else {
        (0..n).map(f).collect()
    }
}

/// `out = [f(0), .., f(len - 1)]` in `out`'s own storage (no new vector: its pages are not
/// faulted in again), on all cores for a long vector.
pub(crate) fn fill_indices<T: Send + Sync + Copy + Default>(
    out: &mut Vec<T>,
    len: usize,
    f: impl Fn(usize) -> T + Sync + Send,
) {
    out.truncate(len);
    crate::allocation::resize_on_all_cores(out, len, T::default());
    let run = |(k, c): (usize, &mut [T])| {
        for (i, o) in c.iter_mut().enumerate() {
            *o = f(k * CHUNK + i);
        }
    };
    if len >= PARALLEL_LEN {
        out.par_chunks_mut(CHUNK).enumerate().for_each(run);
    } else {
        out.chunks_mut(CHUNK).enumerate().for_each(run);
    }
}

/// Appends `parts` to `dst` in their order, copied on all cores when they are long together
/// (`blank` fills the new entries before the copies overwrite them).
pub(crate) fn append_in_order<T: Copy + Send + Sync>(dst: &mut Vec<T>, parts: &[&[T]], blank: T) {
    let start = dst.len();
    let total: usize = parts.iter().map(|p| p.len()).sum();
    if total < PARALLEL_LEN {
        parts.iter().for_each(|p| dst.extend_from_slice(p));
        return;
    }
    crate::allocation::resize_on_all_cores(dst, start + total, blank);
    let mut rest = &mut dst[start..];
    let mut pairs = Vec::with_capacity(parts.len());
    for p in parts {
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(p.len());
        pairs.push((head, *p));
        rest = tail;
    }
    pairs
        .into_par_iter()
        .for_each(|(d, s)| d.copy_from_slice(s));
}

/// A copy of `v`, written on all cores when it is long (its new pages mapped there).
pub(crate) fn copy_of(v: &[f64]) -> Vec<f64> {
    if v.len() >= PARALLEL_LEN {
        v.par_iter().copied().collect()
    } else {
        v.to_vec()
    }
}

/// `max |a_i|` (0 for an empty vector).
pub(crate) fn max_abs(a: &[f64]) -> f64 {
    if a.len() >= PARALLEL_LEN {
        a.par_chunks(CHUNK)
            .map(|c| c.iter().fold(0.0_f64, |m, x| m.max(x.abs())))
            .reduce(|| 0.0, f64::max)
    } else {
        a.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
    }
}

/// Vectors a [`VectorPool`] keeps at most: a Newton step of the FFT path uses about a dozen
/// at once (the conjugate gradients' seven, the equality columns and their preconditioned
/// copies, the operator's two), one per free direction or per unknown.
const KEPT_VECTORS: usize = 16;

/// Work vectors kept between uses (a fresh allocation of a long vector faults in new pages
/// at every use).
#[derive(Debug, Default)]
pub(crate) struct VectorPool {
    kept: Mutex<Vec<Vec<f64>>>,
}

impl Clone for VectorPool {
    /// A new, empty pool (the vectors are work space, not state).
    fn clone(&self) -> Self {
        VectorPool::default()
    }
}

impl VectorPool {
    /// A vector of `len` entries, whatever a kept vector held (zeros when new): for outputs
    /// that are written whole.
    pub fn take(&self, len: usize) -> Vec<f64> {
        let mut v = self
            .kept
            .lock()
            .ok()
            .and_then(|mut k| k.pop())
            .unwrap_or_default();
        crate::allocation::resize_on_all_cores(&mut v, len, 0.0);
        v
    }

    /// Frees the kept vectors.
    pub fn clear(&self) {
        if let Ok(mut k) = self.kept.lock() {
            *k = Vec::new();
        }
    }

    /// Keeps `v` for a later [`VectorPool::take`].
    pub fn give(&self, v: Vec<f64>) {
        if let Ok(mut k) = self.kept.lock() {
            if k.len() < KEPT_VECTORS {
                k.push(v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sum's bits are the same on one thread as on the default pool, and the sum is the
    /// exact one to round-off (a relative 1e-13 for 100,000 terms of one sign: the chunked
    /// sum's error is below `n eps` of the sum of magnitudes).
    #[test]
    fn sums_do_not_depend_on_the_threads() {
        let n = 100_003;
        let a: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64 * 1e-3).collect();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 13) as f64).collect();
        let here = dot(&a, &b);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert_eq!(one.install(|| dot(&a, &b)).to_bits(), here.to_bits());
        let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert!((here - exact).abs() <= 1e-13 * exact);
        assert_eq!(max_abs(&[-3.0, 2.0]), 3.0);
        assert_eq!(copy_of(&b), b);
    }

    /// Parts appended in order, short and long, after what the vector held.
    #[test]
    fn parts_are_appended_in_order() {
        for n in [3, PARALLEL_LEN] {
            let a: Vec<usize> = (0..n).collect();
            let b: Vec<usize> = (n..3 * n).collect();
            let mut v = vec![usize::MAX];
            append_in_order(&mut v, &[&a, &[], &b], 0);
            assert_eq!(v[0], usize::MAX);
            assert!(v[1..].iter().enumerate().all(|(i, x)| *x == i) && v.len() == 3 * n + 1);
        }
    }

    /// Chunks cover every index once, with their start.
    #[test]
    fn chunks_cover_the_vector() {
        for n in [0, 5, CHUNK, 9 * CHUNK + 17] {
            let mut v = vec![0.0; n];
            each_chunk(&mut v, |s, c| {
                c.iter_mut()
                    .enumerate()
                    .for_each(|(i, x)| *x += (s + i) as f64)
            });
            assert!(v.iter().enumerate().all(|(i, x)| *x == i as f64));
        }
    }
}
