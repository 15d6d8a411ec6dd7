//! One semismooth Newton step over all fingers: per finger, the fixed directions are set from
//! their residuals and the free ones solve the reduced system ([`super::reduced_factor`]);
//! the fingers couple only through the `m` equality rows, whose multipliers come from the
//! Schur complement `S = sum_i W_i' W_i` (at most `6 + fingers` rows).
//!
//! With `z_i` the displacement of the fixed directions (`xi_j = -phi_j`), `r_i` the free
//! rows' right-hand side less `D_F' P_i z_i`, and `g_i = L_i^-1 r_i`:
//!
//! ```text
//!   S dlambda = sum_i W_i' g_i + (E x - e) + sum_i E_i z_i
//!   xi_F,i    = L_i^-T (g_i - W_i dlambda),      dx_i = z_i + D_F,i xi_F,i
//! ```
//!
//! `S` is solved through its eigendecomposition; directions with eigenvalues below `1e-12` of
//! the largest are left out (the free set cannot move the equality rows along them).

use nalgebra::{DMatrix, DVector};

use crate::solver::native::finger_block::FingerBlockData;
use crate::solver::native::native_result::Counts;
use crate::solver::native::parallel_vectors::each_chunk;

use super::free_operator::FreeOperator;
use super::linearisation::FingerLinearisation;
use super::reduced_factor::key_of;
use super::reduced_system::ReducedSystem;

/// Relative eigenvalue threshold of the Schur complement.
pub(crate) const SCHUR_CUTOFF: f64 = 1e-12;

/// A Newton direction: `dx` (global), `dlambda`, and `dy = P dx + E' dlambda` (global).
pub(crate) struct Step {
    pub dx: Vec<f64>,
    pub dlambda: Vec<f64>,
    pub dy: Vec<f64>,
    /// `E dx`.
    pub e_dx: Vec<f64>,
    /// The part of the equality right-hand side in the null space of `S`: the equality
    /// residual that no free direction can remove (zero when the step meets every row).
    pub unreachable: Vec<f64>,
}

impl Step {
    /// A step of `n` unknowns with these multipliers and unreachable part, its `dx`, `dy` and
    /// `E dx` still zero (the fingers' parts are written by [`finish_finger`]), in the long
    /// vectors of `spare` (the last step's, zeroed on all cores: no pages faulted in afresh).
    pub fn reusing(
        spare: Option<Step>,
        n: usize,
        dlambda: &DVector<f64>,
        unreachable: &DVector<f64>,
    ) -> Self {
        let (mut dx, mut dy) = spare.map(|s| (s.dx, s.dy)).unwrap_or_default();
        for v in [&mut dx, &mut dy] {
            v.truncate(n);
            each_chunk(v, |_, c| c.fill(0.0));
            v.resize(n, 0.0);
        }
        Step {
            dx,
            dlambda: dlambda.iter().copied().collect(),
            dy,
            e_dx: vec![0.0; dlambda.len()],
            unreachable: unreachable.iter().copied().collect(),
        }
    }
}

/// The long vectors a Newton iteration keeps from one step to the next, freed when it ends:
/// the last step's, its linearisations' and (FFT path) its free operators'.
pub(crate) struct StepSpace {
    /// The program's unknowns, the length of a step's `dx` and `dy`.
    pub unknowns: usize,
    pub step: Option<Step>,
    pub lins: Vec<FingerLinearisation>,
    pub ops: Vec<FreeOperator>,
}

impl StepSpace {
    /// Empty storage for the steps of a program of `unknowns` unknowns.
    pub fn new(unknowns: usize) -> Self {
        StepSpace {
            unknowns,
            step: None,
            lins: Vec::new(),
            ops: Vec::new(),
        }
    }
}

/// Per-finger cache of reduced systems (most recent first).
pub(crate) type FactorCache = Vec<ReducedSystem>;

/// Sum over fingers of `n_free^3` above which the fingers are factorised in parallel.
const PARALLEL_WORK: usize = 20_000_000;

/// How many factors each finger keeps.
const CACHE_SLOTS: usize = 2;

/// Largest change of a Newton direction (per component) for which a cached factor is reused
/// with its own directions: a chord step, whose Jacobian error of this size only slows the
/// quadratic convergence to a linear one of about this rate.
pub(crate) const CHORD_TOLERANCE: f64 = 1e-3;

/// The linearisations with, per finger, the directions of its most recent cached factor where
/// they are within [`CHORD_TOLERANCE`] of the new ones (same pattern): such fingers need no
/// new factorisation this step. The others' linearisations are handed back as they came (no
/// copy: an FFT patch's holds a direction per element).
pub(crate) fn chord_linearisations(
    lins: Vec<FingerLinearisation>,
    caches: &[FactorCache],
) -> Vec<FingerLinearisation> {
    lins.into_iter()
        .zip(caches)
        .map(|(lin, cache)| {
            cache
                .first()
                .and_then(|f| lin.with_directions_of(f.free(), f.fixed(), CHORD_TOLERANCE))
                .unwrap_or(lin)
        })
        .collect()
}

/// The reduced system of `free` from the cache, or a new one (counted in `factorisations`;
/// the conjugate-gradient iterations of an iterative one in `inner`).
pub(crate) fn factor_for<'c>(
    block: &FingerBlockData,
    lin: &FingerLinearisation,
    cache: &'c mut FactorCache,
    factorisations: &mut u32,
    inner: &mut u32,
) -> Option<&'c ReducedSystem> {
    let key = key_of(&lin.free);
    if let Some(pos) = cache.iter().position(|f| f.matches(&key)) {
        let f = cache.remove(pos);
        cache.insert(0, f);
    } else {
        // The factor this one evicts lends it its storage (if the new one cannot be made, the
        // solve stalls and the evicted factor is simply refactorised when next needed).
        let spare = match cache.len() >= CACHE_SLOTS {
            true => cache.pop(),
            false => None,
        };
        let (f, its) = ReducedSystem::new(block, &lin.free, &lin.fixed, key, spare)?;
        *factorisations += 1;
        *inner += its;
        cache.insert(0, f);
    }
    cache.first()
}

/// The first half of a finger's step: `z_i`, `g_i` (`r_i` as [`fixed_part`] gives it, then
/// `L^-1 r_i` factorised, `M^-1 r_i` iterative) and `E_i z_i`.
pub(crate) struct FingerHalf {
    pub z: Vec<f64>,
    pub g: Vec<f64>,
    pub e_z: Vec<f64>,
}

pub(crate) fn first_half(
    block: &FingerBlockData,
    lin: &FingerLinearisation,
    factor: &ReducedSystem,
    inner: &mut u32,
) -> Option<FingerHalf> {
    let mut half = fixed_part(block, lin);
    *inner += factor.first_solve(block, &mut half.g)?;
    Some(half)
}

/// The fixed directions' part of a finger's step: `z_i` (`xi_j = -phi_j`), the free rows'
/// right-hand side `r_i = -phi_a / (gamma theta_a) - d_a' P_i z_i` (in `g`) and `E_i z_i`.
pub(crate) fn fixed_part(block: &FingerBlockData, lin: &FingerLinearisation) -> FingerHalf {
    let n = block.len();
    let mut z = block.work.take(n);
    each_chunk(&mut z, |_, c| c.fill(0.0));
    let mut support = Vec::new();
    for d in &lin.fixed {
        if d.phi != 0.0 {
            for c in 0..block.dim {
                if d.dir[c] != 0.0 {
                    let i = block.index(d.element, c);
                    z[i] -= d.dir[c] * d.phi;
                    support.push(i);
                }
            }
        }
    }
    // A dense block sums the support's columns, each once; the FFT operator applies itself
    // to `z` whole, and needs no order.
    if !block.is_fft() {
        support.sort_unstable();
        support.dedup();
    }
    let mut pz = block.work.take(n);
    each_chunk(&mut pz, |_, c| c.fill(0.0));
    block.apply_columns(&z, &support, &mut pz);
    let mut g = block.work.take(lin.free.len());
    each_chunk(&mut g, |s, c| {
        for (d, o) in lin.free[s..].iter().zip(c.iter_mut()) {
            let ppz: f64 = (0..block.dim)
                .map(|c| d.dir[c] * pz[block.index(d.element, c)])
                .sum();
            *o = -d.phi / (block.gamma * d.theta) - ppz;
        }
    });
    block.work.give(pz);
    let mut e_z = vec![0.0; block.equality_rows()];
    block.add_equality(&z, &mut e_z);
    FingerHalf { z, g, e_z }
}

/// Solves `S v = rhs` in the least-squares sense over the well-conditioned eigendirections;
/// returns `v` and the part of `rhs` in the other directions (the null space of `S`).
fn solve_schur(s: DMatrix<f64>, rhs: DVector<f64>) -> (DVector<f64>, DVector<f64>) {
    let m = rhs.len();
    if m == 0 {
        return (rhs.clone(), rhs);
    }
    let eig = nalgebra::SymmetricEigen::new(s);
    let lmax = eig.eigenvalues.iter().cloned().fold(0.0_f64, f64::max);
    let mut out = DVector::zeros(m);
    let mut null = DVector::zeros(m);
    for j in 0..m {
        let l = eig.eigenvalues[j];
        let u = eig.eigenvectors.column(j);
        if lmax > 0.0 && l > SCHUR_CUTOFF * lmax {
            out += u * (u.dot(&rhs) / l);
        } else {
            null += u * u.dot(&rhs);
        }
    }
    (out, null)
}

/// Computes the Newton step at the linearisations `lins` (one per finger) with equality
/// residual `e_res = E x - e`, made in the storage `space` keeps (the last step's). `None`
/// when a reduced system cannot be factorised or solved.
pub(crate) fn newton_step(
    blocks: &[FingerBlockData],
    lins: &[FingerLinearisation],
    caches: &mut [FactorCache],
    e_res: &[f64],
    space: &mut StepSpace,
    counts: &mut Counts,
) -> Option<Step> {
    let m = e_res.len();
    let mut s = DMatrix::<f64>::zeros(m, m);
    let mut rhs = DVector::from_column_slice(e_res);
    // Fingers are independent until the Schur complement: factorise them in parallel when the
    // work pays for the threads (each finger's arithmetic stays sequential: deterministic).
    let work: usize = lins
        .iter()
        .map(|l| l.free.len().saturating_pow(3))
        .fold(0, usize::saturating_add);
    let per_finger =
        |(block, lin, cache): (&FingerBlockData, &FingerLinearisation, &mut FactorCache)| {
            let (mut count, mut inner) = (0, 0);
            let ok = factor_for(block, lin, cache, &mut count, &mut inner).is_some();
            (ok, count, inner)
        };
    let triples = blocks
        .iter()
        .zip(lins)
        .zip(caches.iter_mut())
        .map(|((b, l), c)| (b, l, c));
    let results: Vec<(bool, u32, u32)> = if work >= PARALLEL_WORK && blocks.len() > 1 {
        use rayon::prelude::*;
        let v: Vec<_> = triples.collect();
        v.into_par_iter().map(per_finger).collect()
    } else {
        triples.map(per_finger).collect()
    };
    for (ok, count, inner) in results {
        counts.factorisations += count;
        counts.inner_iterations += inner;
        if !ok {
            return None;
        }
    }
    let mut halves = Vec::with_capacity(blocks.len());
    for ((block, lin), cache) in blocks.iter().zip(lins).zip(caches.iter()) {
        let factor = &cache[0];
        let half = first_half(block, lin, factor, &mut counts.inner_iterations)?;
        for r in 0..m {
            rhs[r] += half.e_z[r];
        }
        factor.add_schur(&half.g, &mut s, &mut rhs);
        halves.push(half);
    }
    let (dlambda, unreachable) = solve_schur(s, rhs);
    let mut step = Step::reusing(space.step.take(), space.unknowns, &dlambda, &unreachable);
    for (((block, lin), cache), half) in blocks.iter().zip(lins).zip(caches.iter()).zip(halves) {
        second_half(block, lin, &cache[0], half, &mut step);
    }
    Some(step)
}

/// The second half of a finger's step: `xi_F`, `dx_i`, `dy_i` and `E_i dx_i`.
fn second_half(
    block: &FingerBlockData,
    lin: &FingerLinearisation,
    factor: &ReducedSystem,
    half: FingerHalf,
    step: &mut Step,
) {
    let xi = factor.second_solve(half.g, &step.dlambda);
    finish_finger(block, lin, half.z, &xi, step);
}

/// A finger's part of the step from `z_i` and the free directions' `xi_F`: `dx_i = z_i + D_F
/// xi_F`, `dy_i = P_i dx_i + E_i' dlambda` and `E_i dx_i`, written into `step`.
pub(crate) fn finish_finger(
    block: &FingerBlockData,
    lin: &FingerLinearisation,
    z: Vec<f64>,
    xi: &[f64],
    step: &mut Step,
) {
    let mut dx = z;
    for (d, v) in lin.free.iter().zip(xi) {
        for c in 0..block.dim {
            dx[block.index(d.element, c)] += d.dir[c] * v;
        }
    }
    let r = block.offset..block.offset + dx.len();
    let dy = &mut step.dy[r.clone()];
    block.apply(&dx, dy);
    block.add_equality_transpose(&step.dlambda, dy);
    block.add_equality(&dx, &mut step.e_dx);
    each_chunk(&mut step.dx[r], |s, c| {
        c.copy_from_slice(&dx[s..s + c.len()])
    });
    block.work.give(dx);
}
