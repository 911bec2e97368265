//! The one step loop of the explicit embedded Runge-Kutta integrators ([`super::dopri::Dopri5`]
//! on the maximal form, [`super::tree_rk::TreeRk`] on joint coordinates): the step budget, the
//! trial step's size (the controller's step, shortened to land on the end of the call or on a
//! located contact event), error control per step or per unit step, rejection and collapse, the
//! stiffness and event checks a method supplies, acceptance, the step proposal, the hook and its
//! action, pausing. A method supplies its stages, error estimate and acceptance
//! ([`ExplicitMethod`]); the hooks with a default do nothing for methods without them.

use super::step_control::{self, StepPolicy};
use super::trial;
use super::{Cause, Collapse, IntegratorKind, Settings, SolverError, StepAction, StepHook};
use crate::dae::System;
use crate::state::State;

/// What an explicit embedded pair supplies to [`advance`].
pub(super) trait ExplicitMethod {
    /// The integrator, for messages.
    fn kind(&self) -> IntegratorKind;

    /// The settings.
    fn settings(&self) -> &Settings;

    /// The controller's next step [s] (read and written by the loop).
    fn h_mut(&mut self) -> &mut f64;

    /// The step counters.
    fn stats_mut(&mut self) -> &mut super::Stats;

    /// Order in `h` of the local error estimate (the step proposal's exponent is `1 / order`,
    /// `1 / (order - 1)` with error per unit step).
    fn order(&self) -> f64;

    /// How one accepted step may change the step size.
    fn policy(&self) -> StepPolicy;

    /// Smallest share of the tolerance a step is held to per unit step.
    fn min_error_share(&self) -> f64;

    /// At the start of every call: buffers sized for `sys`, the state read, the first stage
    /// marked stale (inputs may have changed at the communication point).
    fn begin_call(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError>;

    /// Chooses the step size afresh (as [`super::Integrator::start`]).
    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError>;

    /// One trial step of size `h` from `st`: its local error estimate relative to the tolerance
    /// (0 with a fixed step; not finite when the step failed).
    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> f64;

    /// Takes the trial step of size `h` into `st`.
    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64) -> Result<(), SolverError>;

    /// The state's outputs the steps do not keep current, at a return of the call (pause, stop,
    /// end).
    fn finish(&mut self, _sys: &mut System, _st: &mut State) -> Result<(), SolverError> {
        Ok(())
    }

    /// After the hook's action other than `Continue` and `Stop` (`Moved`, `Restart`).
    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
    ) -> Result<(), SolverError>;

    /// Whether this call locates contact events inside adaptive steps (`adaptive`: no fixed
    /// step); the method may start watching its stages for them.
    fn locates_events(&mut self, _sys: &System, _adaptive: bool) -> bool {
        false
    }

    /// The size of a trial step that lands on a located event (`cut`: the step cut to end
    /// there, taken and cleared here), `None` for a step of the controller's size.
    fn landing(&mut self, _cut: &mut Option<f64>) -> Option<f64> {
        None
    }

    /// After a rejected trial step.
    fn rejected(&mut self) {}

    /// The error of a step size that collapsed at `st` (`h` [s] the collapsed size).
    fn collapse(&self, _sys: &System, st: &State, h: f64) -> SolverError {
        SolverError::at(
            self.kind(),
            st.t,
            Cause::StepCollapse {
                h,
                why: Collapse::ErrorEstimate,
            },
        )
    }

    /// After a trial step of size `h` that passed the error test, not itself a landing:
    /// `true` when an event inside it makes the loop try again (the method set the next
    /// trial's `cut` or step size).
    fn retry_for_event(
        &mut self,
        _sys: &mut System,
        _st: &State,
        _h: f64,
        _cut: &mut Option<f64>,
    ) -> bool {
        false
    }

    /// Before accepting an adaptive step of size `h` from `st` (`t_end` [s]: the end of the
    /// call): the error that stops a run held at the stability boundary.
    fn check_stiffness(&mut self, _st: &State, _h: f64, _t_end: f64) -> Result<(), SolverError> {
        Ok(())
    }

    /// Just before the hook sees the accepted state.
    fn before_hook(&mut self, _st: &State) {}

    /// Just after the hook saw the accepted state (before its action is applied).
    fn after_hook(&mut self, _sys: &mut System, _st: &mut State) {}
}

/// Advances `st` to `t_end` [s] with method `m`, calling `hook` after every accepted step.
pub(super) fn advance<M: ExplicitMethod>(
    m: &mut M,
    sys: &mut System,
    st: &mut State,
    t_end: f64,
    hook: &mut dyn StepHook,
) -> Result<(), SolverError> {
    m.begin_call(sys, st)?;
    let s = *m.settings();
    let adaptive = s.fixed_step == 0.0;
    // a step size that cannot advance (a state saved before the start, or a forged one) is
    // chosen afresh, as at the start
    if adaptive && step_control::collapsed(*m.h_mut(), st.t) {
        m.start(sys, st)?;
    }
    let locate = m.locates_events(sys, adaptive);
    // a step cut to end at a located contact event, to be taken next
    let mut cut: Option<f64> = None;
    let mut steps = 0u64;
    while t_end - st.t > super::time_eps(t_end) {
        if hook.pause() {
            return m.finish(sys, st);
        }
        let landing = m.landing(&mut cut);
        let h_ctrl = *m.h_mut();
        let rules = trial::Rules {
            fixed: None,
            adaptive: |natural, _| natural,
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
        let err = m.try_step(sys, st, h);
        let err = if err.is_finite() { err } else { f64::INFINITY };
        let (err, order) = if adaptive && s.error_per_unit_step {
            (
                err / s.error_share(h).max(m.min_error_share()),
                m.order() - 1.0,
            )
        } else {
            (err, m.order())
        };
        if adaptive && step_control::rejects(err) {
            m.rejected();
            let stats = m.stats_mut();
            stats.rejected += 1;
            stats.rejected_error += 1;
            let h_next = step_control::after_rejection(h, step_control::proposal(err, order));
            *m.h_mut() = h_next;
            if step_control::collapsed(h_next, st.t) {
                return Err(m.collapse(sys, st, h_next));
            }
            continue;
        }
        if !err.is_finite() {
            return Err(SolverError::at(m.kind(), st.t, Cause::NonFinite { h }));
        }
        // a contact closing or opening inside the step: the method retries it to end there
        if locate && !landing_trial && m.retry_for_event(sys, st, h, &mut cut) {
            continue;
        }
        if adaptive {
            m.check_stiffness(st, h, t_end)?;
        }
        m.accept(sys, st, h)?;
        // a step cut to land on an event proposes nothing: its estimate is mostly round-off
        if adaptive && !landing_trial {
            let policy = m.policy();
            let h_next = *m.h_mut();
            *m.h_mut() =
                policy.after_acceptance(h, natural, h_next, step_control::proposal(err, order));
        }
        m.before_hook(st);
        let action = hook.after_step(sys, st)?;
        m.after_hook(sys, st);
        match action {
            StepAction::Continue => {}
            StepAction::Stop => return m.finish(sys, st),
            StepAction::Moved | StepAction::Restart => m.on_action(sys, st, action)?,
        }
    }
    st.t = t_end;
    m.finish(sys, st)
}
