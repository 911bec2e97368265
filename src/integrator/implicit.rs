//! The one step loop of the implicit integrators ([`super::gen_alpha::GenAlpha`],
//! [`super::bdf::Bdf`]): the step budget, the trial step's size (a fixed step, the end of the
//! call, a located contact event, or the method's own rule), the Newton step with its retry
//! (first with a fresh matrix, then with a smaller step), error rejection, contact-event
//! location, acceptance, the hook and its action, the step proposal, pausing and the failures no
//! retry cures. A method supplies its step (predictor, Newton corrector, error estimate), its
//! rejection and step proposal, and the hooks below where the two methods differ
//! ([`ImplicitMethod`]; docs/integrator_drivers.md lists them and why each is kept).

use super::method_core::MethodCore;
use super::step_control;
use super::trial;
use super::{
    Cause, Collapse, IntegratorKind, NewtonFailure, SingularPassage, SolverError, StepAction,
    StepHook, time_eps,
};
use crate::dae::System;
use crate::state::State;

/// What the loop does after the hook's action was applied.
pub(super) enum Flow {
    /// Go on to the step proposal.
    Propose,
    /// Take the next step without a proposal (the method restarted).
    Next,
    /// Return from the call.
    Stop,
}

/// What an implicit integrator supplies to [`advance`].
pub(super) trait ImplicitMethod {
    /// What a converged step's error estimate holds.
    type Estimate: Copy;

    /// The integrator, for messages.
    fn kind(&self) -> IntegratorKind;

    /// The state the loop reads and writes: settings, step size, counters, event location,
    /// the Newton matrix's validity.
    fn core(&mut self) -> &mut MethodCore;

    /// At the start of every call: buffers sized, the step size chosen afresh when it cannot
    /// advance, the method's own preparation.
    fn begin_call(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError>;

    /// The size of an adaptive trial step that does not end the call or land on an event, from
    /// the controller's step `natural` and the `remaining` time of the call [s].
    fn trial_step(&self, natural: f64, _remaining: f64) -> f64 {
        natural
    }

    /// One trial step of size `h` from `st`: its error estimate, or why Newton failed.
    fn try_step(
        &mut self,
        sys: &mut System,
        st: &State,
        h: f64,
    ) -> Result<Self::Estimate, NewtonFailure>;

    /// Whether the estimate rejects an adaptive step.
    fn rejects(&self, est: &Self::Estimate) -> bool;

    /// After a rejected step of size `h` from `st` (`in_a_row`: the rejections since the last
    /// accepted step, this one included): the counters, the next step size, the failures the
    /// rejection makes final.
    fn rejected(
        &mut self,
        st: &State,
        h: f64,
        est: &Self::Estimate,
        in_a_row: u32,
    ) -> Result<(), SolverError>;

    /// The earliest contact event inside the accepted trial step of size `h`, as a fraction of
    /// it (`None`: none).
    fn event_in_step(
        &mut self,
        sys: &mut System,
        st: &State,
        h: f64,
        est: &Self::Estimate,
    ) -> Option<f64>;

    /// Takes the trial step of size `h` into `st`.
    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, est: &Self::Estimate);

    /// Applies the hook's action (`jump`: the step ended on located events, whose forces jump).
    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
        jump: bool,
    ) -> Result<Flow, SolverError>;

    /// The next step size (and order) after an accepted adaptive step of size `h` [s]; `natural`
    /// the controller's step it was cut from.
    fn propose(&mut self, h: f64, natural: f64, est: &Self::Estimate);

    /// After a Newton failure that is retried with a smaller step.
    fn newton_failed(&mut self) {}

    /// What a rank monitor saw when the step collapsed after Newton failures.
    fn singular_cause(&mut self, _sys: &mut System, _st: &State) -> Option<SingularPassage> {
        None
    }

    /// At the end of the call, `st.t` set to `t_end`.
    fn end_call(&mut self, _t_end: f64) {}
}

/// Advances `st` to `t_end` [s] with method `m`, calling `hook` after every accepted step.
pub(super) fn advance<M: ImplicitMethod>(
    m: &mut M,
    sys: &mut System,
    st: &mut State,
    t_end: f64,
    hook: &mut dyn StepHook,
) -> Result<(), SolverError> {
    m.begin_call(sys, st)?;
    let s = m.core().s;
    let adaptive = s.fixed_step == 0.0;
    // contact onset: a step that closes or opens a contact is taken again to end there, so no
    // step straddles the kink of the contact force and a damped law records the approach speed
    // at the onset, not at the end of the first step in contact
    let locate = adaptive && sys.n_contact_events() > 0;
    // a step cut to end at a located contact event, to be taken next
    let mut cut: Option<f64> = None;
    let mut steps = 0u64;
    let mut refreshed = false;
    let mut rejections = 0u32;
    while t_end - st.t > time_eps(t_end) {
        if hook.pause() {
            return Ok(());
        }
        let landing = m.core().events.begin_trial(&mut cut);
        let h_ctrl = m.core().h;
        let rules = trial::Rules {
            fixed: Some(super::fixed_step_size as fn(f64, f64) -> f64),
            adaptive: |natural, remaining| m.trial_step(natural, remaining),
        };
        let trial = trial::next(
            m.kind(),
            &s,
            &mut steps,
            (st.t, t_end),
            h_ctrl,
            landing,
            rules,
        )?;
        let (natural, h, landing_trial) = (trial.natural, trial.h, trial.landing);
        match m.try_step(sys, st, h) {
            Ok(est) => {
                if adaptive && m.rejects(&est) {
                    m.core().events.landing.clear();
                    rejections += 1;
                    m.rejected(st, h, &est, rejections)?;
                    continue;
                }
                if locate && !landing_trial {
                    let located = m.event_in_step(sys, st, h, &est);
                    if let Some(h_on) =
                        located.and_then(|theta| m.core().events.landing_step(theta, st.t, h))
                    {
                        cut = Some(h_on);
                        continue;
                    }
                }
                rejections = 0;
                refreshed = false;
                m.accept(sys, st, h, &est);
                m.core().events.before_hook(st);
                let action = hook.after_step(sys, st)?;
                // the step ended on located events: the contacts close or open here
                let jump = m.core().events.record(sys, st);
                match m.on_action(sys, st, action, jump)? {
                    Flow::Propose => {}
                    Flow::Next => continue,
                    Flow::Stop => return Ok(()),
                }
                if adaptive {
                    m.propose(h, natural, &est);
                }
            }
            Err(newton) => {
                m.core().stats.newton_failures += 1;
                if !refreshed && m.core().jac_valid {
                    m.core().jac_valid = false;
                    refreshed = true;
                    continue;
                }
                refreshed = false;
                if !adaptive {
                    return Err(SolverError::at(
                        m.kind(),
                        st.t,
                        Cause::FixedStepTooLarge { h, newton },
                    ));
                }
                let h_next = step_control::after_failure(h);
                m.core().h = h_next;
                m.newton_failed();
                if step_control::collapsed(h_next, st.t) {
                    let singular = m.singular_cause(sys, st);
                    return Err(SolverError::at(
                        m.kind(),
                        st.t,
                        Cause::StepCollapse {
                            h: h_next,
                            why: Collapse::Newton { newton, singular },
                        },
                    ));
                }
            }
        }
    }
    st.t = t_end;
    m.end_call(t_end);
    Ok(())
}
