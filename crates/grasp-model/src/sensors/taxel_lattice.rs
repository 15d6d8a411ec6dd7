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
//! Ly`, wrapped as the compliance operator's kernels are: Liu, Wang and Liu, Wear 2000) and
//! kept for the model's later read-outs (a hand-off's steps): a read-out is then one 3 x 3
//! block product of real FFTs and a pick of the taxels' points.

use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;
use realfft::num_complex::Complex;

use crate::error::OutOfMemory;
use crate::model::grid_fft::GridFft;
use crate::model::influence::GridSpec;
use crate::model::influence_at_depth::{reading_per_area_at_depth, ElementOffset};
use crate::scene::sensor_spec::{TaxelGridSpec, TaxelLattice};
use crate::sensors::taxel_grid::TaxelGrid;
use crate::solve::solution::ElementSolution;

/// Operators kept for later read-outs (the most recent first); a hand-off reads a few sensors
/// over the same patches at every step.
const KEPT_OPERATORS: usize = 8;

/// The transformed table of one taxel grid on one patch.
struct TaxelOperator {
    fft: GridFft,
    /// The 9 blocks' spectra, `3 r + c`: reading `r` from force component `c`.
    spectra: Vec<Vec<Complex<f64>>>,
}

/// What an operator is built from, bit for bit.
type Key = Vec<u64>;

/// The kept operators, each with its key.
type Kept = Mutex<Vec<(Key, Arc<TaxelOperator>)>>;

fn key(spec: &TaxelGridSpec, patch: &GridSpec) -> Key {
    let mut k = vec![
        patch.nx as u64,
        patch.ny as u64,
        patch.hx.to_bits(),
        patch.hy.to_bits(),
    ];
    k.extend(spec.count.map(|c| c as u64));
    for x in [
        spec.pitch_m,
        spec.size_m,
        spec.depth_m,
        spec.offset_m[0],
        spec.offset_m[1],
    ] {
        k.push(x.to_bits());
    }
    k
}

/// The kept operators.
fn kept() -> &'static Kept {
    static KEPT: OnceLock<Kept> = OnceLock::new();
    KEPT.get_or_init(|| Mutex::new(Vec::new()))
}

/// The operator of `spec` on `patch` (its `lattice`), built or kept.
fn operator(
    spec: &TaxelGridSpec,
    patch: &GridSpec,
    lattice: &TaxelLattice,
) -> Result<Arc<TaxelOperator>, OutOfMemory> {
    let k = key(spec, patch);
    if let Ok(list) = kept().lock() {
        if let Some((_, op)) = list.iter().find(|(key, _)| *key == k) {
            return Ok(Arc::clone(op));
        }
    }
    let op = Arc::new(build(spec, patch, lattice)?);
    if let Ok(mut list) = kept().lock() {
        list.insert(0, (k, Arc::clone(&op)));
        list.truncate(KEPT_OPERATORS);
    }
    Ok(op)
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
