//! Bookkeeping of the Newton iteration of an implicit step, shared by generalized-alpha and BDF:
//! the iteration cap, the convergence test on the weighted correction norm (with the contraction
//! rate's estimate of the remaining error), the divergence test, and the freezing of the effects'
//! discrete decisions (slip modes) within the iteration.
//!
//! Each method supplies its own weights (a fraction of the local error tolerance in adaptive mode,
//! round-off in fixed-step mode) and, where it has one, its own test of a round-off band in which
//! an iteration that no longer contracts has converged.

use crate::dae::System;

/// Iterations of one step before it fails (also after the decisions were taken again).
pub const MAX_ITERATIONS: usize = 12;

/// Contraction rate beyond which an iteration (from its third iterate on) diverges.
pub const DIVERGENCE_RATE: f64 = 0.9;

/// Iterate (0: the predictor) at which the effects' discrete decisions are frozen: they are taken
/// freely at the predictor and the first iterate, then held, so a slip reversal cannot switch
/// modes back and forth and stall Newton at rate ~1.
pub const FREEZE_AT: usize = 1;

/// How often a step's frozen decisions may be taken again on a converged iterate.
pub const MAX_REDECIDE: usize = 3;

/// A method's convergence test: the iteration has converged when the estimated remaining error
/// (weighted norm) is at most `fraction`; a first correction, which shows no contraction rate
/// yet, is weighed `first_factor` times.
#[derive(Debug, Clone, Copy)]
pub struct NewtonTest {
    pub fraction: f64,
    pub first_factor: f64,
}

/// What one iterate says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Iterate again.
    Continue,
    /// Converged (the constraint residual is for the caller to check as well).
    Converged,
    /// The corrections no longer contract (rate given).
    Diverged(f64),
    /// [`MAX_ITERATIONS`] iterates without convergence.
    Exhausted,
}

/// The state of one step's iteration.
#[derive(Debug, Clone)]
pub struct Progress {
    prev: f64,
    it: usize,
    redecided: usize,
}

impl Default for Progress {
    fn default() -> Self {
        Progress {
            prev: f64::INFINITY,
            it: 0,
            redecided: 0,
        }
    }
}

impl Progress {
    /// Iterates since the start or since the decisions were last taken again.
    pub fn iterations(&self) -> usize {
        self.it
    }

    /// Contraction rate of an iterate whose weighted correction norm is `norm`.
    pub fn rate(&self, norm: f64) -> f64 {
        norm / self.prev
    }

    /// Freezes the effects' decisions at `(t, q, v)` when this iterate is [`FREEZE_AT`] of the
    /// first pass (call before evaluating the iterate's forces).
    pub fn freeze_if_due(&self, sys: &mut System, t: f64, q: &[f64], v: &[f64]) {
        if self.it == FREEZE_AT && self.redecided == 0 {
            sys.freeze_decisions(t, q, v);
        }
    }

    /// Judges an iterate with weighted correction norm `norm` under `test`; `stalled`: the
    /// method's own finding that the corrections are round-off that no longer contracts.
    pub fn judge(&mut self, test: &NewtonTest, norm: f64, stalled: bool) -> Verdict {
        let rate = self.rate(norm);
        if self.it >= 2 && rate > DIVERGENCE_RATE && !stalled {
            return Verdict::Diverged(rate);
        }
        self.prev = norm;
        let est = if self.it == 0 {
            norm * test.first_factor
        } else {
            norm * rate / (1.0 - rate).max(1e-3)
        };
        self.it += 1;
        if est <= test.fraction || norm <= 1e-12 || stalled {
            Verdict::Converged
        } else if self.it >= MAX_ITERATIONS {
            Verdict::Exhausted
        } else {
            Verdict::Continue
        }
    }

    /// After a converged iterate at `(t, q, v)`: whether the effects take the frozen decisions
    /// there themselves (then they are thawed, kept for the step's memory update by
    /// [`System::thaw_accepted`], and the step may end). If not, they are taken again there and
    /// the iteration restarts (`Ok(false)`), at most [`MAX_REDECIDE`] times.
    pub fn settle_decisions(
        &mut self,
        sys: &mut System,
        (t, q, v): (f64, &[f64], &[f64]),
        rtol: f64,
        atol: f64,
    ) -> Result<bool, String> {
        if sys.frozen_consistent(t, q, v, rtol, atol) {
            sys.thaw_accepted();
            return Ok(true);
        }
        if self.redecided == MAX_REDECIDE {
            return Err(format!("slip modes not settled at t = {t:.9e} s"));
        }
        self.redecided += 1;
        sys.freeze_decisions(t, q, v);
        self.prev = f64::INFINITY;
        self.it = 0;
        Ok(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEST: NewtonTest = NewtonTest {
        fraction: 0.02,
        first_factor: 1.0,
    };

    #[test]
    fn a_linear_contraction_converges_when_its_remaining_error_is_small() {
        // corrections 0.3^k: the remaining error after one is estimated as norm 0.3 / 0.7,
        // 0.129, 0.0386, 0.0116 from the second on: below 0.02 at the fourth
        let mut p = Progress::default();
        let mut verdicts = Vec::new();
        for k in 0..8 {
            let v = p.judge(&TEST, 0.3f64.powi(k), false);
            verdicts.push(v);
            if v != Verdict::Continue {
                break;
            }
        }
        assert_eq!(verdicts.len(), 4, "{verdicts:?}");
        assert_eq!(verdicts[3], Verdict::Converged);
    }

    #[test]
    fn corrections_that_stop_contracting_diverge_unless_stalled_in_round_off() {
        let mut p = Progress::default();
        assert_eq!(p.judge(&TEST, 1.0, false), Verdict::Continue);
        assert_eq!(p.judge(&TEST, 0.5, false), Verdict::Continue);
        assert_eq!(p.judge(&TEST, 0.48, false), Verdict::Diverged(0.96));
        let mut p = Progress::default();
        p.judge(&TEST, 1.0, false);
        p.judge(&TEST, 0.5, false);
        assert_eq!(p.judge(&TEST, 0.48, true), Verdict::Converged);
    }

    #[test]
    fn the_cap_ends_a_slow_iteration() {
        let mut p = Progress::default();
        let mut last = Verdict::Continue;
        for k in 0..MAX_ITERATIONS {
            last = p.judge(&TEST, 0.85f64.powi(k as i32), false);
            if last != Verdict::Continue {
                break;
            }
        }
        assert_eq!(last, Verdict::Exhausted);
        assert_eq!(p.iterations(), MAX_ITERATIONS);
    }
}
