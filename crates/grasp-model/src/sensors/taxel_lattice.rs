//! The taxels' read-out at depth as a convolution on the element lattice (the FFT path of the
//! taxels): when the grid is unturned and its pitch a whole number of elements
//! (`TaxelGridSpec::lattice`), taxel `t` at lattice point `n_t` (plus the same fraction `phi`
//! of an element for every taxel) reads
//!
//! `R_t = sum_k T(n_t - k) f_k`,  `T(d) = sum_q w_q K((d + phi) h + x_q)`,
//!
//! `K` the reading per area at depth under one element (Love 1929 and Cerruti,
//! `crate::model::influence_at_depth`), `x_q`, `w_q` the taxel's quadrature
//! (`super::taxel_grid`): the same sum as the dense read-out's, taxel by taxel, regrouped. The
//! table `T` over every offset of the lattice is transformed once (zero-padded to `2 Lx x 2
//! Ly`, wrapped as the compliance operator's kernels are: Liu, Wang and Liu, Wear 2000) and,
//! up to 64 MiB, kept for later read-outs of the same geometry (a hand-off's steps, a batch's
//! grasps: `super::readout_cache`): a read-out is then one 3 x 3 block product of real FFTs
//! and a pick of the taxels' points.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::num_complex::Complex;

use crate::error::OutOfMemory;
use crate::model::grid_fft::GridFft;
use crate::model::influence::GridSpec;
use crate::model::influence_at_depth::{reading_per_area_at_depth, ElementOffset};
use crate::scene::sensor_spec::{TaxelGridSpec, TaxelLattice};
use crate::sensors::readout_cache::{taxel_key, ReadoutCache, MAX_KEPT_BYTES};
use crate::sensors::taxel_grid::TaxelGrid;
use crate::solve::solution::ElementSolution;

/// The transformed table of one taxel grid on one patch.
struct TaxelOperator {
    fft: GridFft,
    /// The 9 blocks' spectra, `3 r + c`: reading `r` from force component `c`.
    spectra: Vec<Vec<Complex<f64>>>,
}

/// The tables kept for later read-outs.
static KEPT: ReadoutCache<TaxelOperator> = ReadoutCache::new();

/// The operator of `spec` on `patch` (its `lattice`), built or kept.
fn operator(
    spec: &TaxelGridSpec,
    patch: &GridSpec,
    lattice: &TaxelLattice,
) -> Result<Arc<TaxelOperator>, OutOfMemory> {
    // Nine spectra of `(Lx + 1) 2 Ly` complex numbers.
    let bytes = 9 * (lattice.size[0] + 1) * 2 * lattice.size[1] * 16;
    let keep = bytes <= MAX_KEPT_BYTES;
    KEPT.get_or_build(taxel_key(spec, patch), keep, || build(spec, patch, lattice))
}

/// The table `T(d)` of every lattice offset, transformed block by block.
fn build(
    spec: &TaxelGridSpec,
    patch: &GridSpec,
    lattice: &TaxelLattice,
) -> Result<TaxelOperator, OutOfMemory> {
    let [lx, ly] = lattice.size;
    let (px, py) = (2 * lx, 2 * ly);
    let fft = GridFft::new([lx, ly], [px, py]);
    let quadrature = TaxelGrid::new(spec).quadrature();
    let h = [patch.hx, patch.hy];
    // Row `a` of the padded grid holds offset `di = a` (a < lx) or `a - px` (wrapped).
    let offset = |a: usize, p: usize| {
        if a < p / 2 {
            a as f64
        } else {
            a as f64 - p as f64
        }
    };
    let table = |a: usize, b: usize| -> [[f64; 3]; 3] {
        let d = [offset(a, px), offset(b, py)];
        let mut t = [[0.0; 3]; 3];
        for q in &quadrature {
            let element = ElementOffset {
                offset_m: [
                    (d[0] + lattice.fraction[0]) * h[0] + q.offset_m[0],
                    (d[1] + lattice.fraction[1]) * h[1] + q.offset_m[1],
                ],
                side_m: h,
            };
            let k = reading_per_area_at_depth(&element, spec.depth_m);
            for (tr, kr) in t.iter_mut().zip(&k) {
                for (tc, kc) in tr.iter_mut().zip(kr) {
                    *tc += q.weight_m2 * kc;
                }
            }
        }
        t
    };
    let mut blocks = vec![crate::allocation::filled(px * py, 0.0)?; 9];
    let rows: Vec<Vec<[[f64; 3]; 3]>> = (0..px)
        .into_par_iter()
        .map(|a| (0..py).map(|b| table(a, b)).collect())
        .collect();
    for (a, row) in rows.iter().enumerate() {
        for (b, t) in row.iter().enumerate() {
            for (rc, block) in blocks.iter_mut().enumerate() {
                block[a * py + b] = t[rc / 3][rc % 3];
            }
        }
    }
    let mut spectra = Vec::with_capacity(9);
    for mut block in blocks {
        spectra.push(fft.transform(&mut block, px)?);
    }
    Ok(TaxelOperator { fft, spectra })
}

/// The forces of the taxels of `spec` on its `lattice` over a finger's solved `elements`
/// (their element grid `patch`), row-major over the taxels, `[normal, t1, t2]` N.
pub fn taxels_on_lattice(
    spec: &TaxelGridSpec,
    lattice: &TaxelLattice,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> Result<Vec<[f64; 3]>, OutOfMemory> {
    let op = operator(spec, patch, lattice)?;
    let [lx, ly] = lattice.size;
    let n = lx * ly;
    let mut forces = crate::allocation::filled(3 * n, 0.0)?;
    for e in elements.iter().filter(|e| e.is_loaded()) {
        let at = (lattice.element0[0] + e.index[0]) * ly + lattice.element0[1] + e.index[1];
        for (c, f) in e.force_n().iter().enumerate() {
            forces[c * n + at] = *f;
        }
    }
    let mut out = crate::allocation::filled(3 * n, 0.0)?;
    op.fft.multiply_blocks(&forces, &mut out, 3, 1.0, |r, c| {
        Some((&op.spectra[3 * r + c], false))
    });
    let mut read = Vec::with_capacity(spec.taxel_count());
    for i in 0..spec.count[0] {
        for j in 0..spec.count[1] {
            let a = lattice.taxel0[0] + i * lattice.stride[0];
            let b = lattice.taxel0[1] + j * lattice.stride[1];
            let at = a * ly + b;
            read.push([out[at], out[n + at], out[2 * n + at]]);
        }
    }
    Ok(read)
}
