//! Bookkeeping of every Newton iteration of the solver: the implicit steps of generalized-alpha
//! and BDF, the projection onto the joints (initial state, DOPRI5 after each step) and the rope
//! statics. One [`Progress`] counts the iterates against a cap, judges them and says why an
//! iteration ended ([`Verdict`]).
//!
//! Two kinds of iteration share it:
//! - A step that corrects a prediction ([`Progress::judge`]): converged when the remaining error
//!   estimated from the contraction rate of the weighted corrections is small ([`NewtonTest`]);
//!   diverged when the corrections stop contracting; the effects' discrete decisions (slip modes)
//!   are frozen within the iteration. Each method supplies its weights (a fraction of the local
//!   error tolerance in adaptive mode, round-off in fixed-step mode) and, where it has one, its
//!   own test of a round-off band in which an iteration that no longer contracts has converged.
//! - A solve from an arbitrary start ([`Progress::judge_residual`]): converged when the residual
//!   is within its tolerance. Such a solve brings its own globalization (the statics' pseudo-time
//!   and backtracking; the projection's Gauss-Newton from poses that may be far off) and may pass
//!   non-contracting iterates on the way, so only a non-finite residual ends it early. Both such
//!   solves run on one driver, [`solve_from_start`].

use super::{NewtonCause, NewtonFailure};
use crate::dae::System;
use crate::dae::linear::LinearSolver;

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

/// Corrections of a projection onto the joints before it fails: a pose far off the joints (an
/// initial state a user wrote down) may take many Gauss-Newton corrections; one near them (after
/// an integration step) takes one or two.
pub const PROJECTION_ITERATIONS: usize = 50;

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
    /// The cap ([`MAX_ITERATIONS`] for a step) reached without convergence.
    Exhausted,
}

/// The state of one step's iteration.
#[derive(Debug, Clone)]
pub struct Progress {
    prev: f64,
    it: usize,
    redecided: usize,
    cap: usize,
}

impl Default for Progress {
    /// The iteration of an implicit step: [`MAX_ITERATIONS`].
    fn default() -> Self {
        Progress::with_cap(MAX_ITERATIONS)
    }
}

impl Progress {
    /// An iteration that ends after `cap` iterates (corrections) without convergence.
    pub fn with_cap(cap: usize) -> Self {
        Progress {
            prev: f64::INFINITY,
            it: 0,
            redecided: 0,
            cap,
        }
    }

    /// The iteration cap.
    pub fn cap(&self) -> usize {
        self.cap
    }

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
        } else if self.it >= self.cap {
            Verdict::Exhausted
        } else {
            Verdict::Continue
        }
    }

    /// Judges a solve from an arbitrary start before its next correction, on its residual
    /// weighted by its tolerance (`norm <= 1`: within it). `Continue` counts one correction;
    /// `Exhausted` once `cap` corrections have not brought the residual within tolerance;
    /// `Diverged` when the residual is not finite.
    pub fn judge_residual(&mut self, norm: f64) -> Verdict {
        if !norm.is_finite() {
            return Verdict::Diverged(norm);
        }
        self.prev = norm;
        if norm <= 1.0 {
            Verdict::Converged
        } else if self.it >= self.cap {
            Verdict::Exhausted
        } else {
            self.it += 1;
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
    ) -> Result<bool, NewtonFailure> {
        if sys.frozen_consistent(t, q, v, rtol, atol) {
            sys.thaw_accepted();
            return Ok(true);
        }
        if self.redecided == MAX_REDECIDE {
            return Err(NewtonFailure {
                t,
                cause: NewtonCause::SlipModes,
            });
        }
        self.redecided += 1;
        sys.freeze_decisions(t, q, v);
        self.prev = f64::INFINITY;
        self.it = 0;
        Ok(false)
    }
}

/// How a solve from an arbitrary start ended ([`solve_from_start`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ended {
    /// The residual is within its tolerance after `iterations` corrections.
    Converged { iterations: usize },
    /// The residual `residual` is not finite after `iterations` corrections.
    Diverged { residual: f64, iterations: usize },
    /// The cap's corrections did not bring the residual within its tolerance, or the solve gave
    /// up on its own.
    Exhausted,
}

/// The one Newton driver of the solves from an arbitrary start (the projection onto the joints,
/// [`super::init`]; the rope statics): before every correction `residual(ctx, k)` gives the
/// iterate's residual over its tolerance (`k`: the corrections so far), judged by
/// [`Progress::judge_residual`] with at most `cap` corrections; `correct(ctx, k)` then takes
/// one correction (`Ok(false)`: the solve gives up, [`Ended::Exhausted`]). The globalization
/// (Gauss-Newton, pseudo-time, backtracking) is the solve's own, in `correct`.
pub fn solve_from_start<C, E>(
    ctx: &mut C,
    cap: usize,
    mut residual: impl FnMut(&mut C, usize) -> f64,
    mut correct: impl FnMut(&mut C, usize) -> Result<bool, E>,
) -> Result<Ended, E> {
    let mut progress = Progress::with_cap(cap);
    loop {
        let k = progress.iterations();
        match progress.judge_residual(residual(ctx, k)) {
            Verdict::Converged => return Ok(Ended::Converged { iterations: k }),
            Verdict::Diverged(residual) => {
                return Ok(Ended::Diverged {
                    residual,
                    iterations: k,
                });
            }
            Verdict::Exhausted => return Ok(Ended::Exhausted),
            Verdict::Continue => {}
        }
        if !correct(ctx, k)? {
            return Ok(Ended::Exhausted);
        }
    }
}

/// The failure of a Newton matrix's factorization at the step ending at `t` [s], typed: a
/// matrix with non-finite entries (a force law evaluated outside its range) or a singular one,
/// with the linear solver's account `detail`.
pub(crate) fn factor_failure(lin: &LinearSolver, detail: String, t: f64) -> NewtonFailure {
    let cause = if lin.has_non_finite_entries() {
        NewtonCause::NonFinite("Newton matrix entries")
    } else {
        NewtonCause::SingularMatrix(detail)
    };
    NewtonFailure { t, cause }
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
    fn a_residual_solve_converges_within_tolerance_and_ends_at_its_cap() {
        // residual 10 x tolerance, falling tenfold per correction: within it after one
        let mut p = Progress::with_cap(5);
        assert_eq!(p.judge_residual(10.0), Verdict::Continue);
        assert_eq!(p.judge_residual(1.0), Verdict::Converged);
        assert_eq!(p.iterations(), 1);
        // a residual that stalls above tolerance: five corrections, then exhausted
        let mut p = Progress::with_cap(5);
        let verdicts: Vec<_> = (0..7).map(|_| p.judge_residual(3.0)).collect();
        assert_eq!(verdicts[..5], [Verdict::Continue; 5]);
        assert_eq!(verdicts[5], Verdict::Exhausted);
        assert_eq!(p.iterations(), 5);
        // a residual that grows is not judged diverged (the solve globalizes itself), a NaN is
        let mut p = Progress::with_cap(5);
        assert_eq!(p.judge_residual(2.0), Verdict::Continue);
        assert_eq!(p.judge_residual(200.0), Verdict::Continue);
        assert!(matches!(p.judge_residual(f64::NAN), Verdict::Diverged(x) if x.is_nan()));
    }

    #[test]
    fn the_driver_corrects_until_the_residual_is_within_tolerance_and_reports_its_end() {
        // a residual 1000 x tolerance that each correction divides by 10: within it after 3
        let mut r = 1000.0;
        let ended = solve_from_start(
            &mut r,
            10,
            |r, _| *r,
            |r, _| -> Result<bool, ()> {
                *r /= 10.0;
                Ok(true)
            },
        );
        assert_eq!(ended, Ok(Ended::Converged { iterations: 3 }));
        // the cap: 2 corrections allowed, 3 needed
        let mut r = 1000.0;
        let ended = solve_from_start(
            &mut r,
            2,
            |r, _| *r,
            |r, _| -> Result<bool, ()> {
                *r /= 10.0;
                Ok(true)
            },
        );
        assert_eq!(ended, Ok(Ended::Exhausted));
        assert_eq!(r, 10.0);
        // a solve that gives up after its first correction; the corrections count from 0
        let mut seen = Vec::new();
        let ended = solve_from_start(
            &mut seen,
            10,
            |_, _| 5.0,
            |seen, k| -> Result<bool, ()> {
                seen.push(k);
                Ok(k < 1)
            },
        );
        assert_eq!(ended, Ok(Ended::Exhausted));
        assert_eq!(seen, [0, 1]);
        // a non-finite residual, and an error of the correction, end it at once
        let mut n = 0;
        let ended = solve_from_start(
            &mut n,
            10,
            |n, _| if *n == 2 { f64::INFINITY } else { 9.0 },
            |n, _| -> Result<bool, ()> {
                *n += 1;
                Ok(true)
            },
        );
        assert_eq!(
            ended,
            Ok(Ended::Diverged {
                residual: f64::INFINITY,
                iterations: 2
            })
        );
        let ended = solve_from_start(&mut 0, 10, |_, _| 9.0, |_, _| Err("no matrix"));
        assert_eq!(ended, Err("no matrix"));
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
