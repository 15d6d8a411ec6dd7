//! The reduced Newton matrix of one FFT finger over its free directions, as an operator, with
//! its preconditioner: what the conjugate-gradient solves of [`super::reduced_iterative`] and
//! [`super::projected_step`] apply.
//!
//! Over the free directions `d_a` the system matrix is the one of [`super::reduced_factor`],
//!
//! ```text
//!   M[a, b] = d_a' P_i[k_a, k_b] d_b + delta_ab beta_a,      beta = (1 - theta)/(gamma theta),
//! ```
//!
//! symmetric positive definite, applied as `D_F' (P_i (D_F p)) + beta p` with one operator
//! product (Polonsky and Keer's conjugate gradients for the contact pressure, Wear 231, 1999,
//! and Vollebregt's NormCG/TangCG do the same over the contact area).
//!
//! The preconditioner is the inverse of the operator's circulant approximation restricted to
//! the free directions, `D_F' Pc^-1 D_F` ([`crate::model::circulant_inverse`]: it cancels the
//! compliance's `1/|k|` symbol, so the iterations stay nearly constant as the grid is refined,
//! where `M`'s diagonal, the same for every element, does nothing), on the directions where
//! `P` dominates `M`'s diagonal; on those where `beta` does (nearly sliding ones), `M`'s
//! diagonal. Both parts are symmetric positive definite, so the preconditioner is.

use crate::solver::native::finger_block::FingerBlockData;
use rayon::prelude::*;

use crate::solver::native::parallel_vectors::{each_chunk, fill_indices, CHUNK, PARALLEL_LEN};

use super::linearisation::Direction;

/// A sparse matrix stored by rows: row `r`'s entries are `entries[starts[r]..starts[r + 1]]`,
/// each `(column, value)`.
#[derive(Debug, Clone, Default)]
struct SparseRows {
    /// Where each row's entries start (one more than the rows: the last is the end).
    starts: Vec<usize>,
    /// `(column, value)`, row after row.
    entries: Vec<(usize, f64)>,
}

impl SparseRows {
    /// Row `r`'s entries.
    fn row(&self, r: usize) -> &[(usize, f64)] {
        &self.entries[self.starts[r]..self.starts[r + 1]]
    }
}

/// `D_F` as a sparse matrix stored both ways: by free direction (for `D_F' v`) and by local
/// unknown (for `D_F p`), so both products split into independent chunks of their output.
#[derive(Debug, Clone, Default)]
struct Directions {
    /// Per direction `a`, its entries `(local index, d_a[c])`.
    by_direction: SparseRows,
    /// Per local unknown `i`, its entries `(direction, d_a[c])`.
    by_unknown: SparseRows,
}

impl Directions {
    /// `D_F` of `free` in the vectors of `spare` (their storage reused: no pages faulted in
    /// afresh at every Newton step).
    fn reusing(block: &FingerBlockData, free: &[Direction], spare: Self) -> Self {
        let Directions {
            mut by_direction,
            mut by_unknown,
        } = spare;
        by_direction_into(block, free, &mut by_direction);
        let sorted = || free.par_windows(2).all(|w| w[0].element <= w[1].element);
        if block.len() >= PARALLEL_LEN && sorted() {
            by_unknown_sorted(block, free, by_direction.entries.len(), &mut by_unknown);
        } else {
            by_unknown_serial(block.len(), &by_direction, &mut by_unknown);
        }
        Directions {
            by_direction,
            by_unknown,
        }
    }

    /// `full = D_F p` over the directions `keep` accepts (`full` a local vector, written
    /// whole).
    fn scatter(&self, p: &[f64], keep: impl Fn(usize) -> bool + Sync + Send, full: &mut [f64]) {
        each_chunk(full, |s, chunk| {
            for (i, f) in (s..s + chunk.len()).zip(chunk.iter_mut()) {
                *f = self
                    .by_unknown
                    .row(i)
                    .iter()
                    .filter(|(a, _)| keep(*a))
                    .map(|&(a, coef)| coef * p[a])
                    .sum();
            }
        });
    }

    /// `out[a] = d_a' full[k_a]` over the directions `keep` accepts, `other(a)` over the
    /// rest, plus `base(a)` for all.
    fn gather(
        &self,
        full: &[f64],
        keep: impl Fn(usize) -> bool + Sync + Send,
        other: impl Fn(usize) -> f64 + Sync + Send,
        base: impl Fn(usize) -> f64 + Sync + Send,
        out: &mut [f64],
    ) {
        each_chunk(out, |s, chunk| {
            for (a, o) in (s..s + chunk.len()).zip(chunk.iter_mut()) {
                let own = match keep(a) {
                    true => self
                        .by_direction
                        .row(a)
                        .iter()
                        .map(|&(i, coef)| coef * full[i])
                        .sum::<f64>(),
                    false => other(a),
                };
                *o = base(a) + own;
            }
        });
    }
}

/// `D_F` by unknown (`n` of them) from `D_F` by direction, one entry at a time: each
/// unknown's start serves as its fill cursor, which ends at the next unknown's start, and the
/// starts are then shifted back by one.
fn by_unknown_serial(n: usize, by_direction: &SparseRows, by_unknown: &mut SparseRows) {
    let SparseRows {
        starts: unknown_starts,
        entries: by_unknown,
    } = by_unknown;
    let SparseRows {
        starts,
        entries: by_direction,
    } = by_direction;
    fill_indices(unknown_starts, n + 1, |_| 0);
    for &(i, _) in by_direction {
        unknown_starts[i + 1] += 1;
    }
    for i in 0..n {
        unknown_starts[i + 1] += unknown_starts[i];
    }
    fill_indices(by_unknown, by_direction.len(), |_| (0, 0.0));
    for a in 0..starts.len() - 1 {
        for &(i, coef) in &by_direction[starts[a]..starts[a + 1]] {
            by_unknown[unknown_starts[i]] = (a, coef);
            unknown_starts[i] += 1;
        }
    }
    unknown_starts.copy_within(0..n, 1);
    unknown_starts[0] = 0;
}

/// `f(unknown, direction, coefficient)` for the entries of `D_F` of the unknowns
/// `range` (local indices), in order of unknown and then of direction, for `free` sorted by
/// element (an unknown's entries are those of its element's directions, found by bisection).
fn each_entry(
    block: &FingerBlockData,
    free: &[Direction],
    range: std::ops::Range<usize>,
    mut f: impl FnMut(usize, usize, f64),
) {
    let e = block.elements.max(1);
    let mut i = range.start;
    while i < range.end {
        let c = i / e;
        let (first, last) = (i - c * e, range.end.min((c + 1) * e) - c * e);
        let mut a = free.partition_point(|d| d.element < first);
        while a < free.len() && free[a].element < last {
            let d = &free[a];
            if d.dir[c] != 0.0 {
                f(block.index(d.element, c), a, d.dir[c]);
            }
            a += 1;
        }
        i = (c + 1) * e;
    }
}

/// [`by_unknown_serial`]'s arrays for `free` sorted by element (`entries` in all), on all
/// cores: per [`CHUNK`] of unknowns, their counts, then (after the starts' running sum) their
/// entries in their own part of `by_unknown`. The same arrays.
fn by_unknown_sorted(
    block: &FingerBlockData,
    free: &[Direction],
    entries: usize,
    by_unknown: &mut SparseRows,
) {
    let SparseRows {
        starts: unknown_starts,
        entries: by_unknown,
    } = by_unknown;
    let n = block.len();
    fill_indices(unknown_starts, n + 1, |_| 0);
    unknown_starts[1..]
        .par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(j, counts)| {
            let first = j * CHUNK;
            each_entry(block, free, first..first + counts.len(), |i, _, _| {
                counts[i - first] += 1
            });
        });
    for i in 0..n {
        unknown_starts[i + 1] += unknown_starts[i];
    }
    fill_indices(by_unknown, entries, |_| (0, 0.0));
    let parts = parts_by_chunk(by_unknown, unknown_starts);
    parts.into_par_iter().enumerate().for_each(|(j, part)| {
        let first = j * CHUNK;
        let mut at = 0;
        each_entry(block, free, first..(first + CHUNK).min(n), |_, a, coef| {
            part[at] = (a, coef);
            at += 1;
        });
    });
}

/// `entries` cut at the starts of every [`CHUNK`]-th row of `starts` (`n + 1` of them for `n`
/// rows): per chunk of rows, its entries.
fn parts_by_chunk<'e>(
    entries: &'e mut [(usize, f64)],
    starts: &[usize],
) -> Vec<&'e mut [(usize, f64)]> {
    let n = starts.len().saturating_sub(1);
    let mut parts = Vec::with_capacity(n.div_ceil(CHUNK));
    let mut rest = entries;
    for j in 0..n.div_ceil(CHUNK) {
        let (from, to) = (starts[j * CHUNK], starts[((j + 1) * CHUNK).min(n)]);
        let (part, tail) = std::mem::take(&mut rest).split_at_mut(to - from);
        parts.push(part);
        rest = tail;
    }
    parts
}

/// `D_F` by direction (`starts`, `by_direction`): each direction's nonzero components in
/// order. Many directions are written on all cores, per [`CHUNK`] of them in their own part
/// (after the starts' running sum): the same arrays.
fn by_direction_into(block: &FingerBlockData, free: &[Direction], by_direction: &mut SparseRows) {
    let SparseRows {
        starts,
        entries: by_direction,
    } = by_direction;
    fn components(dim: usize, d: &Direction) -> impl Iterator<Item = usize> + '_ {
        (0..dim).filter(move |&c| d.dir[c] != 0.0)
    }
    let entries = |d| components(block.dim, d);
    if free.len() < PARALLEL_LEN {
        starts.clear();
        by_direction.clear();
        for d in free {
            starts.push(by_direction.len());
            by_direction.extend(entries(d).map(|c| (block.index(d.element, c), d.dir[c])));
        }
        starts.push(by_direction.len());
        return;
    }
    fill_indices(starts, free.len() + 1, |a| match a {
        0 => 0,
        _ => entries(&free[a - 1]).count(),
    });
    for a in 0..free.len() {
        starts[a + 1] += starts[a];
    }
    fill_indices(by_direction, starts[free.len()], |_| (0, 0.0));
    let parts = parts_by_chunk(by_direction, starts);
    parts.into_par_iter().enumerate().for_each(|(j, part)| {
        let mut at = 0;
        for d in &free[j * CHUNK..((j + 1) * CHUNK).min(free.len())] {
            for c in entries(d) {
                part[at] = (block.index(d.element, c), d.dir[c]);
                at += 1;
            }
        }
    });
}

/// `M` and its preconditioner for one finger's free directions.
#[derive(Debug, Clone, Default)]
pub(crate) struct FreeOperator {
    /// `beta_a` per free direction.
    beta: Vec<f64>,
    /// `1 / M[a, a]`.
    inverse_diagonal: Vec<f64>,
    /// Per free direction: preconditioned by the circulant inverse (`beta_a` below the
    /// compliance's part of `M[a, a]`), else by `1 / M[a, a]`.
    circulant: Vec<bool>,
    /// True when some direction is circulant-preconditioned.
    any_circulant: bool,
    /// `D_F`.
    directions: Directions,
}

impl FreeOperator {
    /// The operator of `block` over `free`.
    pub fn new(block: &FingerBlockData, free: &[Direction]) -> Self {
        Self::reusing(block, free, Self::default())
    }

    /// [`FreeOperator::new`] in the vectors of `spare` (an operator no longer needed: a
    /// Newton step's operator reuses the last one's storage).
    pub fn reusing(block: &FingerBlockData, free: &[Direction], spare: Self) -> Self {
        let FreeOperator {
            mut beta,
            inverse_diagonal: mut diagonal,
            mut circulant,
            directions,
            ..
        } = spare;
        fill_indices(&mut beta, free.len(), |a| {
            (1.0 - free[a].theta) / (block.gamma * free[a].theta)
        });
        // The compliance's part of `M[a, a]`, `d_a' P_i[k_a, k_a] d_a`, then `1 / M[a, a]`.
        fill_indices(&mut diagonal, free.len(), |a| {
            let d = &free[a];
            let p: f64 = (0..block.dim)
                .map(|c| d.dir[c] * d.dir[c] * block.compliance_diagonal(c * block.elements))
                .sum();
            block.scale * p
        });
        fill_indices(&mut circulant, free.len(), |a| beta[a] <= diagonal[a]);
        each_chunk(&mut diagonal, |s, c| {
            for (v, b) in c.iter_mut().zip(&beta[s..]) {
                *v = 1.0 / (*v + b);
            }
        });
        FreeOperator {
            beta,
            inverse_diagonal: diagonal,
            any_circulant: circulant.iter().any(|c| *c),
            circulant,
            directions: Directions::reusing(block, free, directions),
        }
    }

    /// Free directions, the length of the vectors it applies to.
    pub fn len(&self) -> usize {
        self.beta.len()
    }

    /// `out = M p`.
    pub fn apply(&self, block: &FingerBlockData, p: &[f64], out: &mut [f64]) {
        let mut full = block.work.take(block.len());
        self.directions.scatter(p, |_| true, &mut full);
        let mut pfull = block.work.take(block.len());
        block.apply(&full, &mut pfull);
        self.directions
            .gather(&pfull, |_| true, |_| 0.0, |a| self.beta[a] * p[a], out);
        block.work.give(full);
        block.work.give(pfull);
    }

    /// `z = D_F' Pc^-1 D_F r` on the circulant-preconditioned directions, `r / M[a, a]` on
    /// the others (the module's preconditioner).
    pub fn precondition(&self, block: &FingerBlockData, r: &[f64], z: &mut [f64]) {
        let circulant = |a: usize| self.circulant[a];
        let diagonal = |a: usize| r[a] * self.inverse_diagonal[a];
        let mut full = block.work.take(block.len());
        let mut back = block.work.take(block.len());
        if self.any_circulant {
            self.directions.scatter(r, circulant, &mut full);
            block.precondition(&full, &mut back);
        }
        self.directions
            .gather(&back, circulant, diagonal, |_| 0.0, z);
        block.work.give(full);
        block.work.give(back);
    }

    /// `Et' = D_F' E_i'` as columns (one per equality row, each of length `n_free`), for the
    /// free directions `free` the operator was made with.
    pub fn equality_columns(block: &FingerBlockData, free: &[Direction]) -> Vec<Vec<f64>> {
        (0..block.equality_rows())
            .map(|r| {
                let mut col = block.work.take(free.len());
                each_chunk(&mut col, |s, chunk| {
                    for (d, o) in free[s..].iter().zip(chunk.iter_mut()) {
                        *o = (0..block.dim)
                            .map(|c| d.dir[c] * block.equality(r, block.index(d.element, c)))
                            .sum();
                    }
                });
                col
            })
            .collect()
    }
}
