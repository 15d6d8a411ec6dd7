//! A certificate that a program has no solution, kept to be checked against the next programs
//! of the same grasp. A margin's search tries one magnitude after another along a direction,
//! and every trial beyond the margin is a program without a solution; proving that costs the
//! native solver's stall, its interior-point method's and then Clarabel's (some 20
//! iterations). The programs of a search share the equality matrix `E` and differ only in the
//! right-hand side `e` (the disturbance grows) and the Tresca radii (the normal forces of the
//! last sequential iterate), and the object's escape motion that proved one of them infeasible
//! usually proves the next one infeasible too, at the cost of a dot product.
//!
//! The proof (Farkas' lemma for the program's constraints, `E x = e`, per element `F >= 0`
//! and `||G|| <= r` (Tresca) or `||G|| <= mu F` (associated friction)): for any multipliers
//! `y` of the equality rows, with `w = E'y`, every feasible `x` has
//!
//! ```text
//!   y'e = w'x >= sum_k inf { w_F F + w_G . G : (F, G) in the element's set },
//! ```
//!
//! and that infimum is `-r ||w_G||` for a Tresca element with `w_F >= 0`, `0` for an
//! associated cone with `w_F >= mu ||w_G||` (and for a frictionless element with `w_F >= 0`),
//! `-inf` otherwise. So `y'e + sum_Tresca r ||w_G|| < 0`, with `w` in the dual cones, proves
//! that no `x` exists. `w` is computed here from `E` and `y`, not taken from the solver. As
//! Clarabel accepts its own certificates, a dual-cone violation of
//! [`DUAL_TOLERANCE`] of `||w||` is allowed (the solver's round-off), and the gap must be
//! negative by [`GAP_TOLERANCE`] of its terms, so that only programs well past the edge are
//! refused this way; the others are solved as before. Tresca radii are raised to the floor
//! Clarabel is given ([`crate::solver::clarabel::radius_floor`]), so the check decides the
//! program Clarabel would decide.

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};

use crate::program::cone_program::ConeProgram;
use crate::program::cones::element_set::ElementSet;
use crate::solver::outcome::Certificate;

/// The dual-cone violation allowed, relative to `||w||_inf` (round-off in the solver's `y`).
const DUAL_TOLERANCE: f64 = 1e-9;

/// How negative the gap must be, relative to the sum of the magnitudes of its terms.
const GAP_TOLERANCE: f64 = 1e-6;

/// Multipliers `y` of the equality rows that proved a program infeasible, with `w = E'y` and
/// the `E` they were found for.
#[derive(Debug, Clone)]
pub(crate) struct KeptCertificate {
    equality: Arc<DMatrix<f64>>,
    y: DVector<f64>,
    w: DVector<f64>,
}

impl KeptCertificate {
    /// Keeps the equality part of `certificate`, found for `program`.
    pub(crate) fn new(program: &ConeProgram, certificate: &Certificate) -> Option<Self> {
        let e = &program.equality;
        (certificate.equality.len() == e.nrows()).then(|| {
            let y = DVector::from_column_slice(&certificate.equality);
            let w = e.tr_mul(&y);
            KeptCertificate {
                equality: Arc::clone(e),
                y,
                w,
            }
        })
    }

    /// The certificate when it proves that `program` (with Tresca radii raised to
    /// `radius_floor`, element force units) has no solution (module docs); `None` when it
    /// does not, or `program` has another equality matrix.
    pub(crate) fn proves(&self, program: &ConeProgram, radius_floor: f64) -> Option<Certificate> {
        if !Arc::ptr_eq(&self.equality, &program.equality) {
            return None;
        }
        // `y'e` and the magnitudes of its terms; the Tresca sum is never negative, so a
        // program with `y'e >= 0` is not proved, and the elements need not be read.
        let (ye, ye_terms) = self
            .y
            .iter()
            .zip(&program.equality_rhs)
            .fold((0.0, 0.0), |(s, a), (y, e)| (s + y * e, a + (y * e).abs()));
        if ye >= 0.0 {
            return None;
        }
        let scale = self.w.amax();
        let slack = DUAL_TOLERANCE * scale;
        let mut tresca = 0.0;
        let mut finger_slip = Vec::with_capacity(program.blocks.len());
        for (b, blk) in program.blocks.iter().enumerate() {
            let (ne, nt) = (blk.elements, blk.n_tangential);
            let mut slip = 0.0;
            for k in 0..ne {
                let w_f = self.w[blk.offset + k];
                let w_g = (0..nt)
                    .map(|j| self.w[blk.offset + (j + 1) * ne + k].powi(2))
                    .sum::<f64>()
                    .sqrt();
                let cone = blk.cone.element(k);
                tresca += cone.support(w_g, radius_floor);
                if !cone.dual_contains(w_f, w_g, slack) {
                    return None;
                }
                slip += w_g;
            }
            if b < program.finger_blocks().len() {
                finger_slip.push(slip);
            }
        }
        let terms = ye_terms + tresca;
        (ye + tresca < -GAP_TOLERANCE * terms && scale > 0.0).then(|| Certificate {
            equality: self.y.as_slice().to_vec(),
            finger_slip,
        })
    }
}
