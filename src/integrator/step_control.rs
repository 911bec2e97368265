//! One step-size controller for the adaptive integrators (gen-alpha, BDF, DOPRI5).
//!
//! The elementary controller: an error estimate `err` (relative to its tolerance, so 1 is the
//! limit) that behaves as `O(h^p)` asks for the step `h * SAFETY * err^(-1/p)`. What differs
//! between the methods is only `p` (the order of their estimate in `h`, which
//! `Settings::error_per_unit_step` lowers by one) and how far one accepted step may grow
//! ([`StepPolicy`]); the rules below are the same for all of them:
//!
//! - a step is rejected when `err > 1` or `err` is not a number at all;
//! - after a rejection the step shrinks to 0.1 .. 0.9 of itself (to [`FAILURE_CUT`] when the
//!   estimate is not finite, and after a Newton failure, which has no estimate);
//! - after an acceptance it shrinks whenever the estimate asks for it, and grows (at most by
//!   the method's `max_growth`) only when the proposal exceeds the step the controller had asked
//!   for (`natural`) by more than the method's hysteresis; a step shortened to end a call keeps
//!   the controller's step unless its own proposal is larger;
//! - a step below [`MIN_STEP_RELATIVE`] of the time (at least 1 s) counts as collapsed: the
//!   integrator stops with a message naming the cause it observed.

/// Share of the step the error estimate allows that is asked for.
pub const SAFETY: f64 = 0.9;

/// Bounds on the factor after a rejected step.
pub const REJECTED_FACTOR: (f64, f64) = (0.1, 0.9);

/// Smallest factor after an accepted step.
pub const MIN_ACCEPTED_FACTOR: f64 = 0.2;

/// Factor after a step whose estimate is not finite or whose Newton iteration failed.
pub const FAILURE_CUT: f64 = 0.25;

/// A step below this share of `max(|t|, 1 s)` has collapsed (a few hundred machine epsilons of
/// the time: the step would no longer change `t` reliably).
pub const MIN_STEP_RELATIVE: f64 = 1e-14;

/// Factor on the step size that an estimate `err` of order `order` in `h` asks for: infinite
/// when nothing limits the step (`err <= 0`, e.g. an exact step or an energy check that saw the
/// energy fall), zero for a non-finite estimate.
pub fn proposal(err: f64, order: f64) -> f64 {
    if !err.is_finite() {
        0.0
    } else if err <= 0.0 {
        f64::INFINITY
    } else {
        SAFETY * err.powf(-1.0 / order)
    }
}

/// Whether an error estimate (relative to its tolerance) rejects the step; NaN rejects.
pub fn rejects(err: f64) -> bool {
    err.is_nan() || err > 1.0
}

/// Whether the step `h` [s] at time `t` [s] has collapsed.
pub fn collapsed(h: f64, t: f64) -> bool {
    h < MIN_STEP_RELATIVE * t.abs().max(1.0)
}

/// Next step [s] after a rejected step `h` [s] whose estimate asked for the factor `factor`
/// (from [`proposal`]; zero or non-finite when the estimate was not finite).
pub fn after_rejection(h: f64, factor: f64) -> f64 {
    if factor.is_finite() && factor > 0.0 {
        h * factor.clamp(REJECTED_FACTOR.0, REJECTED_FACTOR.1)
    } else {
        h * FAILURE_CUT
    }
}

/// Next step [s] after a Newton failure at step `h` [s].
pub fn after_failure(h: f64) -> f64 {
    h * FAILURE_CUT
}

/// How far one method lets an accepted step grow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPolicy {
    /// Largest factor after an accepted step.
    pub max_growth: f64,
    /// A growing proposal replaces the controller's step only beyond `hysteresis` times it (a
    /// new step size costs an implicit method a new Newton matrix); 1 grows at every chance.
    pub hysteresis: f64,
}

impl StepPolicy {
    /// Next step [s] after an accepted step `h` [s]: `natural` [s] is the step the controller
    /// had asked for (`h` is shorter when the step was cut to end a call), `current` [s] the
    /// controller's step before, `factor` the proposal of the step's estimate.
    pub fn after_acceptance(&self, h: f64, natural: f64, current: f64, factor: f64) -> f64 {
        let proposed = h * factor.clamp(MIN_ACCEPTED_FACTOR, self.max_growth);
        if proposed < h || proposed > self.hysteresis * natural {
            proposed
        } else {
            current
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proposal_is_the_elementary_controller() {
        // err = 2^order asks for half the step, times the safety factor
        assert!((proposal(32.0, 5.0) - 0.45).abs() < 1e-15);
        assert!((proposal(1.0 / 8.0, 3.0) - 1.8).abs() < 1e-15);
        assert_eq!(proposal(0.0, 4.0), f64::INFINITY);
        assert_eq!(proposal(-0.5, 3.0), f64::INFINITY);
        assert_eq!(proposal(f64::INFINITY, 4.0), 0.0);
        assert_eq!(proposal(f64::NAN, 4.0), 0.0);
    }

    #[test]
    fn nan_and_large_estimates_reject() {
        assert!(rejects(f64::NAN));
        assert!(rejects(1.0 + 1e-15));
        assert!(!rejects(1.0));
        assert!(!rejects(0.0));
    }

    #[test]
    fn rejection_shrinks_within_its_bounds() {
        assert_eq!(after_rejection(1.0, 0.01), 0.1);
        assert_eq!(after_rejection(1.0, 0.95), 0.9);
        assert_eq!(after_rejection(1.0, 0.5), 0.5);
        assert_eq!(after_rejection(1.0, 0.0), FAILURE_CUT);
        assert_eq!(after_rejection(1.0, f64::NAN), FAILURE_CUT);
    }

    #[test]
    fn acceptance_shrinks_always_and_grows_past_the_hysteresis_only() {
        let p = StepPolicy {
            max_growth: 2.0,
            hysteresis: 1.2,
        };
        // shrink on a full step and on a shortened one
        assert_eq!(p.after_acceptance(1.0, 1.0, 1.0, 0.5), 0.5);
        assert_eq!(p.after_acceptance(0.5, 1.0, 1.0, 0.5), 0.25);
        // a growth of 10 % is not worth a new step size; 50 % is, capped at max_growth
        assert_eq!(p.after_acceptance(1.0, 1.0, 1.0, 1.1), 1.0);
        assert_eq!(p.after_acceptance(1.0, 1.0, 1.0, 1.5), 1.5);
        assert_eq!(p.after_acceptance(1.0, 1.0, 1.0, f64::INFINITY), 2.0);
        // a shortened step keeps the controller's step unless it proposes more
        assert_eq!(p.after_acceptance(0.1, 1.0, 1.0, 3.0), 1.0);
        assert_eq!(p.after_acceptance(0.9, 1.0, 1.0, 2.0), 1.8);
        // tiny factors are limited
        assert_eq!(p.after_acceptance(1.0, 1.0, 1.0, 0.01), MIN_ACCEPTED_FACTOR);
    }
}
