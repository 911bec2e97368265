//! The step budget and the size of the next trial step, the same in both step loops
//! ([`super::explicit::advance`], [`super::implicit::advance`]).

use super::{Cause, IntegratorKind, Settings, SolverError, time_eps};

/// The next trial step of a loop.
#[derive(Debug, Clone, Copy)]
pub(super) struct Trial {
    /// The step the controller (adaptive) or the user (fixed step) asks for [s].
    pub(super) natural: f64,
    /// The trial step's size [s].
    pub(super) h: f64,
    /// Whether the step lands on a located contact event.
    pub(super) landing: bool,
}

/// How a family sizes the steps that neither land on an event nor end the call.
pub(super) struct Rules<F: FnOnce(f64, f64) -> f64> {
    /// A fixed step from the step and the remaining time [s] (`None`: the step itself, cut to
    /// the end of the call). The implicit schemes take [`super::fixed_step_size`] (no sliver
    /// at the end of a call); the explicit pairs take the step as it is: unifying would move
    /// the fixed-step sequences of one family.
    pub(super) fixed: Option<fn(f64, f64) -> f64>,
    /// An adaptive step from the controller's step and the remaining time [s] (the method's
    /// own rule: generalized-alpha at most half the rest of the call).
    pub(super) adaptive: F,
}

/// Counts one more step against `s.max_steps` (`steps`: the steps of the call so far) and sizes
/// the trial step from `t` [s] towards `t_end` [s]: the located event's `landing` step if any,
/// otherwise the controller's step `h_ctrl` [s] at most `h_max` (or the fixed step), the rest of
/// the call when it reaches it, else the family's `rules`.
pub(super) fn next<F: FnOnce(f64, f64) -> f64>(
    kind: IntegratorKind,
    s: &Settings,
    steps: &mut u64,
    (t, t_end): (f64, f64),
    h_ctrl: f64,
    landing: Option<f64>,
    rules: Rules<F>,
) -> Result<Trial, SolverError> {
    *steps += 1;
    if *steps > s.max_steps {
        return Err(SolverError::at(
            kind,
            t,
            Cause::StepBudget {
                max_steps: s.max_steps,
            },
        ));
    }
    let adaptive = s.fixed_step == 0.0;
    let natural = if adaptive {
        h_ctrl.min(s.h_max)
    } else {
        s.fixed_step
    };
    let remaining = t_end - t;
    let h = match (landing, rules.fixed) {
        (Some(h_on), _) => h_on,
        (None, Some(fixed)) if !adaptive => fixed(natural, remaining),
        _ if natural >= remaining - time_eps(t_end) => remaining,
        _ => (rules.adaptive)(natural, remaining),
    };
    Ok(Trial {
        natural,
        h,
        landing: landing.is_some(),
    })
}
