//! The taxels' read-out at depth as a matrix kept for later read-outs of the same geometry: the
//! taxel-by-taxel sum `R_t = sum_q w_q sum_k K(x_tq - x_k) f_k` (`super::taxel_readings`)
//! regrouped as `R_t = sum_k M_tk f_k`, `M_tk = sum_q w_q K(x_tq - x_k)` (a 3 x 3 block per
//! taxel and element; Love 1929 and Cerruti, `crate::model::influence_at_depth`). Built once
//! per patch and grid when it fits (`super::readout_cache`: up to 64 MiB), so a batch's grasps
//! and a hand-off's steps of one geometry pay the kernel once and then a matrix product.

use std::sync::Arc;

use rayon::prelude::*;

use crate::model::influence::GridSpec;
use crate::model::influence_at_depth::{reading_per_area_at_depth, ElementOffset};
use crate::sensors::readout_cache::{taxel_key, ReadoutCache, MAX_KEPT_BYTES};
use crate::sensors::taxel_grid::TaxelGrid;
use crate::solve::solution::ElementSolution;

/// The blocks `M_tk`, taxel-major (`t n + k`, `n` the patch's elements).
struct TaxelMatrix {
    blocks: Vec<[[f64; 3]; 3]>,
}

/// The matrices kept for later read-outs.
static KEPT: ReadoutCache<TaxelMatrix> = ReadoutCache::new();

/// The bytes of the matrix of `grid` on `patch`.
fn matrix_bytes(grid: &TaxelGrid, patch: &GridSpec) -> usize {
    grid.spec.taxel_count() * patch.len() * std::mem::size_of::<[[f64; 3]; 3]>()
}

/// The matrix of `grid` at depth on `patch`: every element's centre from its grid index (as
/// the patch lays them out, `(i + 1/2) hx - Lx / 2`).
fn build(grid: &TaxelGrid, patch: &GridSpec) -> TaxelMatrix {
    let quadrature = grid.quadrature();
    let depth_m = grid.spec.depth_m;
    let centre = |k: usize| {
        let (i, j) = (k / patch.ny, k % patch.ny);
        [
            (i as f64 + 0.5) * patch.hx - 0.5 * patch.nx as f64 * patch.hx,
            (j as f64 + 0.5) * patch.hy - 0.5 * patch.ny as f64 * patch.hy,
        ]
    };
    let blocks = grid
        .squares()
        .par_iter()
        .flat_map_iter(|sq| {
            let (sin, cos) = sq.angle_rad.sin_cos();
            let points: Vec<([f64; 2], f64)> = quadrature
                .iter()
                .map(|q| {
                    let [u, v] = q.offset_m;
                    let p = [
                        sq.centre_m[0] + u * cos - v * sin,
                        sq.centre_m[1] + u * sin + v * cos,
                    ];
                    (p, q.weight_m2)
                })
                .collect();
            (0..patch.len()).map(move |k| {
                let c = centre(k);
                let mut m = [[0.0; 3]; 3];
                for (p, w) in &points {
                    let offset = ElementOffset {
                        offset_m: [p[0] - c[0], p[1] - c[1]],
                        side_m: [patch.hx, patch.hy],
                    };
                    let kk = reading_per_area_at_depth(&offset, depth_m);
                    for (mr, kr) in m.iter_mut().zip(&kk) {
                        for (mc, kc) in mr.iter_mut().zip(kr) {
                            *mc += w * kc;
                        }
                    }
                }
                m
            })
        })
        .collect();
    TaxelMatrix { blocks }
}

/// The forces of `grid`'s taxels at depth over a finger's solved `elements` (their element
/// grid `patch`), row-major over the taxels, `[normal, t1, t2]` N, by the kept matrix; `None`
/// when the matrix would exceed what is kept (the caller sums taxel by taxel).
pub fn taxels_by_matrix(
    grid: &TaxelGrid,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> Option<Vec<[f64; 3]>> {
    if grid.spec.depth_m <= 0.0 || matrix_bytes(grid, patch) > MAX_KEPT_BYTES {
        return None;
    }
    let key = taxel_key(&grid.spec, patch);
    let matrix: Arc<TaxelMatrix> = KEPT
        .get_or_build(key, true, || Ok::<_, ()>(build(grid, patch)))
        .ok()?;
    let n = patch.len();
    let loaded: Vec<(usize, [f64; 3])> = elements
        .iter()
        .filter(|e| e.is_loaded())
        .map(|e| (patch.index(e.index[0], e.index[1]), e.force_n()))
        .collect();
    let read = (0..grid.spec.taxel_count())
        .map(|t| {
            let row = &matrix.blocks[t * n..(t + 1) * n];
            let mut out = [0.0; 3];
            for (k, f) in &loaded {
                let m = &row[*k];
                for (o, mr) in out.iter_mut().zip(m) {
                    *o += mr[0] * f[0] + mr[1] * f[1] + mr[2] * f[2];
                }
            }
            out
        })
        .collect();
    Some(read)
}
