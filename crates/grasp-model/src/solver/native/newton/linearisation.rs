//! The natural residual of one finger and its linearisation (semismooth Newton, Qi & Sun).
//!
//! The KKT conditions of the program (model.md) are `y = P x + q + E' lambda`, `x_k in K_k`,
//! `y_k in K_k*`, `x_k . y_k = 0` for every element `k`, and `E x = e`. By Moreau's
//! decomposition they hold exactly when the natural residual
//!
//! ```text
//!   Phi_k = x_k - Proj_{K_k}(x_k - gamma y_k)
//! ```
//!
//! vanishes for every element (and `E x = e`), for any `gamma > 0`. With the Jacobian of the
//! projection written `sum_j theta_j d_j d_j'` ([`crate::program::cones::element_cone`]),
//! each direction `d_j` of element `k` contributes one Newton row, in the rotated unknown
//! `xi_j = d_j . dx_k`:
//!
//! - `theta_j = 0` (fixed: separation, or the cone normal of a sliding element): `xi_j = -phi_j`;
//! - `theta_j > 0` (free): `d_j . (P dx + E' dlambda)_k + beta_j xi_j = -phi_j / (gamma theta_j)`,
//!   `beta_j = (1 - theta_j) / (gamma theta_j)`,
//!
//! with `phi_j = d_j . Phi_k`. The free rows form a symmetric positive definite system
//! ([`super::reduced_factor`]).

use crate::program::cones::element_set::ElementSet;
use crate::program::cones::finger_cones::FingerCones;
use crate::solver::native::finger_block::FingerBlockData;
use crate::solver::native::parallel_vectors::{append_in_order, map_indices_coarse, CHUNK};

/// A finger's part of a point of the iteration (local vectors, the finger's own layout): the
/// forces `x` and the duals `y = P x + q + E' lambda`; or, along a step, their changes `dx`
/// and `dy`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LocalPoint<'a> {
    /// Forces (or their change), scaled.
    pub x: &'a [f64],
    /// Duals (or their change), scaled.
    pub y: &'a [f64],
}

/// One Jacobian direction of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Direction {
    /// Element index in the patch.
    pub element: usize,
    /// Unit direction in the element's components `(F, G1, G2)` (first `dim` used).
    pub dir: [f64; 3],
    /// Jacobian weight `theta` in `[0, 1]`.
    pub theta: f64,
    /// Rotated residual `phi = d . Phi_k`.
    pub phi: f64,
}

/// One finger's residual and Jacobian pattern at an iterate.
#[derive(Debug, Clone, Default)]
pub(crate) struct FingerLinearisation {
    /// Directions with `theta > 0`.
    pub free: Vec<Direction>,
    /// Directions with `theta = 0`.
    pub fixed: Vec<Direction>,
    /// Sum of squares of the natural residual over the finger.
    pub residual_sq: f64,
    /// Largest absolute component of the natural residual.
    pub residual_max: f64,
    /// The natural residual `Phi_k` of every element (first `dim` components used).
    pub residuals: Vec<[f64; 3]>,
}

impl FingerLinearisation {
    /// The same residual with the Newton directions of `old` (the directions of a cached
    /// factor): a chord step's linearisation. `None` unless both have the same elements in
    /// the same roles (free, fixed, partly free) and every direction moved by at most
    /// `tolerance`.
    pub fn with_directions_of(
        &self,
        old_free: &[Direction],
        old_fixed: &[Direction],
        tolerance: f64,
    ) -> Option<Self> {
        if self.residuals.is_empty() {
            // Linearised without its elements' residuals ([`linearise_reusing`]).
            return None;
        }
        let close = |a: &[Direction], b: &[Direction]| {
            a.len() == b.len()
                && a.iter().zip(b).all(|(x, y)| {
                    x.element == y.element
                        && (x.theta == 1.0) == (y.theta == 1.0)
                        && (0..3).all(|c| (x.dir[c] - y.dir[c]).abs() <= tolerance)
                })
        };
        if !close(&self.free, old_free) || !close(&self.fixed, old_fixed) {
            return None;
        }
        let rotate = |dirs: &[Direction]| -> Vec<Direction> {
            dirs.iter()
                .map(|d| {
                    let r = self.residuals[d.element];
                    Direction {
                        phi: (0..3).map(|c| d.dir[c] * r[c]).sum(),
                        ..*d
                    }
                })
                .collect()
        };
        Some(FingerLinearisation {
            free: rotate(old_free),
            fixed: rotate(old_fixed),
            residuals: self.residuals.clone(),
            ..*self
        })
    }
}

/// The projection input `v_k = x_k - gamma y_k` of element `k` (local vectors).
pub(crate) fn projection_input(
    block: &FingerBlockData,
    x: &[f64],
    y: &[f64],
    k: usize,
) -> [f64; 3] {
    let (xk, yk) = (block.gather(x, k), block.gather(y, k));
    [
        xk[0] - block.gamma * yk[0],
        xk[1] - block.gamma * yk[1],
        xk[2] - block.gamma * yk[2],
    ]
}

/// Evaluates the natural residual of one finger and the Newton directions of its elements
/// (`x`, `y`: the finger's local parts of the iterate and of `P x + q + E' lambda`).
pub(crate) fn linearise(
    block: &FingerBlockData,
    cone: &FingerCones,
    x: &[f64],
    y: &[f64],
) -> FingerLinearisation {
    let spare = FingerLinearisation::default();
    linearise_reusing(block, cone, LocalPoint { x, y }, true, spare)
}

/// Chunks of elements linearised at once before they are appended to the finger's
/// directions: the chunks' own vectors stay a few megabytes (they were a second copy of the
/// whole linearisation) and their memory is reused from one wave to the next.
const WAVE: usize = 32;

/// [`linearise`] at `point` into the vectors of `spare` (a linearisation no longer needed: its
/// storage is reused, so a Newton step does not fault in its directions afresh), keeping
/// every element's residual only when `residuals` (a chord step reads them,
/// [`FingerLinearisation::with_directions_of`]; the projected step of the FFT path, which
/// keeps no factors, does not: a vector of three per element saved). The
/// elements are linearised in chunks of [`CHUNK`] on all cores, [`WAVE`] chunks at a time,
/// and appended in chunk order: the same directions and sums on any number of threads.
pub(crate) fn linearise_reusing(
    block: &FingerBlockData,
    cone: &FingerCones,
    point: LocalPoint,
    residuals: bool,
    spare: FingerLinearisation,
) -> FingerLinearisation {
    let mut lin = FingerLinearisation {
        residual_sq: 0.0,
        residual_max: 0.0,
        ..spare
    };
    lin.free.clear();
    lin.fixed.clear();
    lin.residuals.clear();
    let chunks = block.elements.div_ceil(CHUNK);
    if chunks <= 1 {
        // One chunk: straight into the kept vectors (the same order and sums, no chunk's own
        // vectors to allocate, grow and copy: on a small patch these were a tenth of a
        // Newton step).
        let directions = block.dim * block.elements;
        lin.free.reserve(directions);
        lin.fixed.reserve(directions);
        lin.residuals
            .reserve(if residuals { block.elements } else { 0 });
        for k in 0..block.elements {
            linearise_element(block, cone, point, k, residuals, &mut lin);
        }
        return lin;
    }
    for wave in (0..chunks).step_by(WAVE) {
        let parts = map_indices_coarse(WAVE.min(chunks - wave), block.elements, |c| {
            let mut part = FingerLinearisation::default();
            let first = (wave + c) * CHUNK;
            for k in first..(first + CHUNK).min(block.elements) {
                linearise_element(block, cone, point, k, residuals, &mut part);
            }
            part
        });
        let blank = Direction {
            element: 0,
            dir: [0.0; 3],
            theta: 0.0,
            phi: 0.0,
        };
        let free: Vec<&[Direction]> = parts.iter().map(|p| p.free.as_slice()).collect();
        append_in_order(&mut lin.free, &free, blank);
        let fixed: Vec<&[Direction]> = parts.iter().map(|p| p.fixed.as_slice()).collect();
        append_in_order(&mut lin.fixed, &fixed, blank);
        let residuals: Vec<&[[f64; 3]]> = parts.iter().map(|p| p.residuals.as_slice()).collect();
        append_in_order(&mut lin.residuals, &residuals, [0.0; 3]);
        for part in &parts {
            lin.residual_sq += part.residual_sq;
            lin.residual_max = lin.residual_max.max(part.residual_max);
        }
    }
    lin
}

/// `f(range)` for consecutive ranges of [`CHUNK`] elements out of `elements`, in order: on all
/// cores for a large patch (each range is computed the same on any thread).
fn for_element_chunks<T: Send>(
    elements: usize,
    f: impl Fn(std::ops::Range<usize>) -> T + Sync + Send,
) -> Vec<T> {
    let range = |c: usize| c * CHUNK..((c + 1) * CHUNK).min(elements);
    map_indices_coarse(elements.div_ceil(CHUNK), elements, |c| f(range(c)))
}

/// Element `k`'s natural residual (kept when `keep`) and Newton directions at `point`,
/// appended to `lin`.
fn linearise_element(
    block: &FingerBlockData,
    cone: &FingerCones,
    point: LocalPoint,
    k: usize,
    keep: bool,
    lin: &mut FingerLinearisation,
) {
    let d = block.dim;
    let xk = block.gather(point.x, k);
    let v = projection_input(block, point.x, point.y, k);
    let p = cone.element(k).project(v, d);
    let mut phi = [xk[0] - p.point[0], xk[1] - p.point[1], xk[2] - p.point[2]];
    phi[d..].fill(0.0);
    if keep {
        lin.residuals.push(phi);
    }
    for &f in phi.iter().take(d) {
        lin.residual_sq += f * f;
        lin.residual_max = lin.residual_max.max(f.abs());
    }
    for j in 0..d {
        let dir = p.dirs[j];
        let dj = Direction {
            element: k,
            dir,
            theta: p.theta[j],
            phi: (0..d).map(|c| dir[c] * phi[c]).sum(),
        };
        if dj.theta > 0.0 {
            lin.free.push(dj);
        } else {
            lin.fixed.push(dj);
        }
    }
}

/// The residual norms of one finger at a point (no Jacobian): `(sum of squares, max)`.
pub(crate) fn residual_norms(
    block: &FingerBlockData,
    cone: &FingerCones,
    x: &[f64],
    y: &[f64],
) -> (f64, f64) {
    norms_at(block, cone, |k| (block.gather(x, k), block.gather(y, k)))
}

/// [`residual_norms`] at the trial point `at + t step` (`x + t dx`, `y + t dy`), each entry
/// formed where it is used (no trial vectors).
pub(crate) fn residual_norms_along(
    block: &FingerBlockData,
    cone: &FingerCones,
    at: LocalPoint,
    step: LocalPoint,
    t: f64,
) -> (f64, f64) {
    let along = |v: &[f64], dv: &[f64], k: usize| {
        let (a, b) = (block.gather(v, k), block.gather(dv, k));
        [a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2]]
    };
    norms_at(block, cone, |k| {
        (along(at.x, step.x, k), along(at.y, step.y, k))
    })
}

/// The residual norms of one finger whose element `k` has the forces and duals `point(k)`.
fn norms_at(
    block: &FingerBlockData,
    cone: &FingerCones,
    point: impl Fn(usize) -> ([f64; 3], [f64; 3]) + Sync + Send,
) -> (f64, f64) {
    let d = block.dim;
    let parts = for_element_chunks(block.elements, |range| {
        let (mut sq, mut max) = (0.0, 0.0_f64);
        for k in range {
            let (xk, yk) = point(k);
            let v = [
                xk[0] - block.gamma * yk[0],
                xk[1] - block.gamma * yk[1],
                xk[2] - block.gamma * yk[2],
            ];
            let p = cone.element(k).project(v, d);
            for (c, &xc) in xk.iter().enumerate().take(d) {
                let f = xc - p.point[c];
                sq += f * f;
                max = max.max(f.abs());
            }
        }
        (sq, max)
    });
    parts
        .iter()
        .fold((0.0, 0.0_f64), |(s, m), &(q, x)| (s + q, m.max(x)))
}

/// The linearisation used by a cold start from `x = 0`: every direction of the elements in
/// `contact` free with `theta = 1` and `phi = gamma y`, the others fixed at zero, so that the
/// Newton step solves `P dx + E' dlambda = -y` over the contact elements with `E dx = e`
/// (every contact element sticking; [`super::cold_start`]).
pub(crate) fn cold_pattern(
    block: &FingerBlockData,
    y: &[f64],
    contact: &[bool],
) -> FingerLinearisation {
    let mut lin = FingerLinearisation::default();
    for (k, &inside) in contact.iter().enumerate() {
        let yk = block.gather(y, k);
        for c in 0..block.dim {
            let mut dir = [0.0; 3];
            dir[c] = 1.0;
            let d = Direction {
                element: k,
                dir,
                theta: if inside { 1.0 } else { 0.0 },
                phi: if inside { block.gamma * yk[c] } else { 0.0 },
            };
            if inside {
                lin.free.push(d);
            } else {
                lin.fixed.push(d);
            }
        }
    }
    lin
}
