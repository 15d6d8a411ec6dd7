//! How accurately each convex solve of a sequential solve ([`super::sequential`]) is solved:
//! an inexact fixed-point iteration.
//!
//! An iterate's output only has to be accurate to a share of the change the iteration still
//! makes: while the normal forces still move by `d` between iterates, an output error well
//! below `d` moves the next change by about as much, and the iteration converges as before
//! (linearly, at the same rate). So each convex solve of an inexact sequence stops at a
//! relative tolerance [`ETA`] times the change predicted for it (the last change times the
//! last contraction ratio, in element force units `Fu`), at most [`LOOSEST`] and at least the
//! solve's own tolerance. The solve's tolerance is relative to `max(1, max |x|)` (the native
//! solver's natural residual), so [`ETA`] is an empirical factor, not the share of `d` an
//! output is off by: it was tuned on the frictional rough pad (below), whose changes it leaves
//! as they were. The iteration converges only on an iterate solved to the solve's own
//! tolerance, as before: the accepted answer is one Tresca program's solution to full
//! accuracy, its change from its input within the sequential tolerance. An inexact iterate
//! that meets the sequential tolerance is followed by exact ones (from its output, damped as
//! the iteration damps); a change predicted within [`FINISH_MARGIN`] of the tolerance is
//! solved exactly at once, so that this is rare.
//!
//! Which sequences are inexact ([`crate::solve::sequential`] decides):
//! - a cold coulomb one (no previous step's forces: a single solve, a hand-off's first step, a
//!   step after a cold restart, every step with warm starts off) whose fingers are all FFT
//!   patches too large to write out as matrices, answered by the native solver: from its first
//!   solve (whose change is not known: the energy model's forces, its first input, are not
//!   Coulomb's) to [`LOOSEST`];
//! - not a warm one: a warm hand-off step starts near its fixed point (at it, when its forces
//!   were extrapolated along a ramp) and ends in one to three iterates, so an inexact iterate
//!   there only adds the exact one that must end the sequence (measured on the coulomb plate
//!   hand-off with every iterate but the first inexact: 134 Newton steps instead of 128);
//! - not one Clarabel can answer: with `solver: clarabel` each solve is an interior-point
//!   solve afresh, and a small patch's native stall falls back to Clarabel, which should
//!   not answer at a loose tolerance; a small patch's iterate costs microseconds anyway;
//! - not one whose sequential tolerance is infinite (the first iterate is the answer), and
//!   never the last iterate the iteration limit allows.
//!
//! An inexact sequence that ends without an answer runs again exactly
//! (`crate::solve::sequential`'s `exactly_again`), so inexact iterates do not change a
//! failed outcome.

/// The factor from an iterate's predicted change (element force units) to the relative
/// tolerance its solve stops at. Measured on the frictional rough pad of `grasp bench`
/// (`examples/rough_sphere_on_flat_friction.json` at 256 x 256, cold, seven Tresca iterates,
/// changes 4e-5 N to 4e-14 N), with [`LOOSEST`] 1e-2: 0.1 leaves the seven iterates and their
/// changes as they were and takes 361 conjugate-gradient iterations in all instead of 525
/// (2.1-2.5 s instead of 3.2-3.3 s); 1e-2 with [`LOOSEST`] 1e-3, 397.
pub(crate) const ETA: f64 = 0.1;

/// The loosest tolerance an iterate is solved to (the first of a cold sequence; relative, on
/// the scaled program). Measured as for [`ETA`]: 1e-5 takes 438 conjugate-gradient iterations
/// (its first solves still take four and five Newton steps), 1e-2 361 (four and two).
pub(crate) const LOOSEST: f64 = 1e-2;

/// A change predicted within this factor of the sequential tolerance is solved exactly, so
/// the iterate that meets the tolerance is usually an exact one.
pub(crate) const FINISH_MARGIN: f64 = 10.0;

/// The tolerance of a sequence's next convex solve, from the changes seen so far.
#[derive(Debug, Clone, Copy)]
pub(crate) struct IterateAccuracy {
    /// The solve's own tolerance (relative, scaled program).
    full: f64,
    /// The sequential tolerance, in element force units.
    sequential: f64,
    /// The last change of the normal forces (element force units).
    last: Option<f64>,
    /// The tolerance the next iterate is solved to.
    current: f64,
    /// False when every solve is exact (module docs).
    inexact: bool,
    /// The last solve was given the solve's own tolerance.
    last_exact: bool,
    /// Some solve was given a tolerance looser than the solve's own.
    used_inexact: bool,
    /// An inexact iterate met the sequential tolerance: every later solve is exact.
    finished: bool,
}

impl IterateAccuracy {
    /// The schedule of a sequence with the solve tolerance `full` and the sequential
    /// tolerance `sequential` (element force units); `inexact`: the sequence may be solved
    /// inexactly (module docs: a cold sequence the native solver answers).
    pub(crate) fn new(full: f64, sequential: f64, inexact: bool) -> Self {
        let inexact = inexact && sequential.is_finite();
        IterateAccuracy {
            full,
            sequential,
            last: None,
            current: if inexact { full.max(LOOSEST) } else { full },
            inexact,
            last_exact: true,
            used_inexact: false,
            finished: false,
        }
    }

    /// The tolerance of the next convex solve, noted as the last solve's; `last_allowed`: it
    /// is the last the iteration limit allows (then exact).
    pub(crate) fn tolerance(&mut self, last_allowed: bool) -> f64 {
        if last_allowed || self.finished {
            self.current = self.full;
        }
        self.last_exact = self.current <= self.full;
        self.used_inexact |= !self.last_exact;
        self.current
    }

    /// True when the sequence may solve its iterates inexactly.
    pub(crate) fn inexact(&self) -> bool {
        self.inexact
    }

    /// True when some solve so far was given a tolerance looser than the solve's own.
    pub(crate) fn was_inexact(&self) -> bool {
        self.used_inexact
    }

    /// True when the last solve (the last [`IterateAccuracy::tolerance`] given) was solved
    /// to the solve's own tolerance.
    pub(crate) fn exact(&self) -> bool {
        self.last_exact
    }

    /// Records an iterate's change `change_fu` (element force units, above the sequential
    /// tolerance) and sets the next solve's tolerance from the change predicted for it.
    pub(crate) fn record(&mut self, change_fu: f64) {
        let ratio = match self.last {
            Some(b) if b > 0.0 && b.is_finite() => (change_fu / b).min(1.0),
            _ => 1.0,
        };
        self.last = Some(change_fu);
        let predicted = change_fu * ratio;
        let loosest = self.full.max(LOOSEST);
        self.current = if !self.inexact || predicted <= FINISH_MARGIN * self.sequential {
            self.full
        } else if predicted.is_finite() {
            (ETA * predicted).clamp(self.full, loosest)
        } else {
            loosest
        };
    }

    /// Records that an inexact iterate's change `change_fu` (element force units) met the
    /// sequential tolerance: this and every later solve is exact.
    pub(crate) fn finish(&mut self, change_fu: f64) {
        self.last = Some(change_fu);
        self.finished = true;
        self.current = self.full;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sequence that is not inexact is exact throughout; an inexact one starts at the
    /// loosest tolerance, which never tightens a loose solve tolerance.
    #[test]
    fn first_solve() {
        let mut exact = IterateAccuracy::new(1e-10, 1e-7, false);
        assert_eq!(exact.tolerance(false), 1e-10);
        assert!(exact.exact());
        exact.record(5.2);
        assert_eq!(exact.tolerance(false), 1e-10);
        assert!(!exact.inexact() && !exact.was_inexact());
        assert_eq!(
            IterateAccuracy::new(1e-10, 1e-7, true).tolerance(false),
            LOOSEST
        );
        assert_eq!(IterateAccuracy::new(0.5, 1e-7, true).tolerance(false), 0.5);
        // An infinite sequential tolerance accepts the first iterate: nothing is inexact.
        let mut any = IterateAccuracy::new(1e-10, f64::INFINITY, true);
        assert_eq!(any.tolerance(false), 1e-10);
        any.record(5.2);
        assert_eq!(any.tolerance(false), 1e-10);
    }

    /// The tolerance follows the predicted change (the frictional rough pad's changes in
    /// element force units) and is exact once the prediction nears the sequential tolerance,
    /// or for the last solve the limit allows.
    #[test]
    fn follows_the_change() {
        let mut a = IterateAccuracy::new(1e-10, 1e-7, true);
        a.record(5.2);
        assert_eq!(a.tolerance(false), LOOSEST);
        a.record(0.25);
        let p = 0.25 * (0.25 / 5.2);
        assert!((a.tolerance(false) - ETA * p).abs() <= 1e-15 * p);
        assert!(!a.exact());
        for c in [4.8e-3, 1.4e-4] {
            a.record(c);
            assert!(a.tolerance(false) > 1e-10, "{c}");
            assert!(!a.exact(), "{c}");
        }
        // Predicted 4e-6 * 4e-6 / 1.4e-4 = 1.1e-7, within ten times the tolerance: exact.
        a.record(4e-6);
        assert_eq!(a.tolerance(false), 1e-10);
        assert!(a.exact() && a.was_inexact());
        let mut b = IterateAccuracy::new(1e-10, 1e-7, true);
        assert!(b.inexact());
        b.record(5.2);
        assert_eq!(b.tolerance(true), 1e-10);
        assert!(b.exact() && !b.was_inexact());
    }

    /// A growing change predicts no contraction; a finished schedule stays exact, whatever
    /// change follows.
    #[test]
    fn growth_and_finish() {
        let mut a = IterateAccuracy::new(1e-10, 1e-7, true);
        a.record(1e-3);
        a.record(2e-3);
        assert!((a.tolerance(false) - ETA * 2e-3).abs() <= 1e-18);
        assert!(!a.exact());
        a.finish(5e-8);
        assert_eq!(a.tolerance(false), 1e-10);
        assert!(a.exact());
        a.record(1.0);
        assert_eq!(a.tolerance(false), 1e-10);
    }
}
