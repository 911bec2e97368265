//! Generalized-alpha's step, rejection and proposal for the implicit step loop.

use super::*;

/// Generalized-alpha's step, rejection and proposal for the step loop
/// ([`implicit::advance`]): halves the last step of a call or divides the call into equal
/// steps, rejects steps that gain energy, stops when the tolerance is below round-off.
impl GenAlpha {
    /// Share of the tolerance the round-off allowance takes at the step the controller asks
    /// for after a rejection of step `h` [s]: the allowance measured at `h` rescaled by the
    /// ratio of the steps' shares of the tolerance to that of their allowances.
    fn roundoff_share(&self, h: f64) -> f64 {
        let s = &self.core.s;
        let (at_h, at_next) = (s.error_share(h), s.error_share(self.core.h));
        self.err_roundoff * at_h / at_next * projected_noise(at_next) / projected_noise(at_h)
    }

    /// Share of the tolerance the whole estimate's round-off allowance takes at the step the
    /// controller asks for after a rejection of step `h` [s].
    fn whole_roundoff_share(&self, h: f64) -> f64 {
        let s = &self.core.s;
        self.whole_roundoff * s.error_share(h) / s.error_share(self.core.h)
    }
}

impl ImplicitMethod for GenAlpha {
    type Estimate = f64;

    fn kind(&self) -> IntegratorKind {
        IntegratorKind::GenAlpha
    }

    fn core(&mut self) -> &mut MethodCore {
        &mut self.core
    }

    fn begin_call(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        self.resize_events(sys);
        // a step size that cannot advance (a forged state) is chosen afresh, as at the start
        if self.core.s.fixed_step == 0.0 && step_control::collapsed(self.core.h, st.t) {
            self.core.h = self.initial_step(sys, st);
        }
        Ok(())
    }

    /// At most half the rest of the call (so the call does not end on a sliver), or equal
    /// steps to its end: the same step size (and Newton matrix) for all of them, and for the
    /// next call when its length is the same.
    fn trial_step(&self, natural: f64, remaining: f64) -> f64 {
        if !self.core.s.equal_steps {
            if natural > 0.5 * remaining {
                0.5 * remaining
            } else {
                natural
            }
        } else {
            remaining / (remaining / natural).ceil()
        }
    }

    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> Result<f64, NewtonFailure> {
        match GenAlpha::try_step(self, sys, st, h) {
            StepOutcome::Converged(err) => Ok(err),
            StepOutcome::Failed(newton) => Err(newton),
        }
    }

    /// A step that gains energy beyond the tolerance is rejected like one with too large an
    /// error; every next step is proposed from the larger of the two estimates (both O(h^3)),
    /// so an energy rejection is not followed by a step grown from the position error alone
    /// that the energy check rejects again.
    fn rejects(&self, err: &f64) -> bool {
        step_control::rejects(err.max(self.gain_ratio))
    }

    fn rejected(&mut self, st: &State, h: f64, err: &f64, _: u32) -> Result<(), SolverError> {
        let err = *err;
        self.core.stats.rejected += 1;
        self.after_rejection = true;
        if self.gain_ratio > err {
            self.core.stats.rejected_energy += 1;
        } else {
            self.core.stats.rejected_error += 1;
        }
        self.core.h = step_control::after_rejection(
            h,
            step_factor(err, self.gain_ratio, self.core.s.error_per_unit_step),
        );
        // inside a singular configuration the positions' round-off grows with the conditioning
        // for a while: the allowance widens the test there instead of stopping the run
        // a step collapse from outside the whole estimate's round-off band into it is a motion
        // the tolerance cannot follow ([`collapses_into_roundoff`])
        let whole_share = self.whole_roundoff_share(h);
        let fast = collapses_into_roundoff(self.whole_err, self.accepted_roundoff, whole_share);
        if err >= self.gain_ratio
            && self.core.s.error_per_unit_step
            && !self.rank.inside()
            && (fast
                || self.roundoff_share(h) >= ROUNDOFF_SHARE_LIMIT
                || step_control::collapsed(self.core.h, st.t))
        {
            return Err(SolverError::at(
                IntegratorKind::GenAlpha,
                st.t,
                Cause::Tolerance {
                    rtol: self.core.s.rtol,
                    atol: self.core.s.atol,
                    h: self.core.h,
                    share: if fast {
                        whole_share
                    } else {
                        self.roundoff_share(h)
                    },
                },
            ));
        }
        if self.gain_ratio > 1.0 && step_control::collapsed(self.core.h, st.t) {
            return Err(SolverError::at(
                IntegratorKind::GenAlpha,
                st.t,
                Cause::StepCollapse {
                    h: self.core.h,
                    why: Collapse::EnergyGain {
                        gain: self.gain_ratio,
                    },
                },
            ));
        }
        Ok(())
    }

    fn event_in_step(&mut self, sys: &mut System, st: &State, h: f64, _: &f64) -> Option<f64> {
        self.events_in_step(sys, st, h)
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, _: &f64) {
        GenAlpha::accept(self, sys, st, h);
    }

    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
        jump: bool,
    ) -> Result<Flow, SolverError> {
        match action {
            // the step starts from the state itself (positions, speeds and the algorithmic
            // accelerations), so a moved state needs nothing
            StepAction::Continue | StepAction::Moved if !jump => {}
            // forces that jump need accelerations consistent with them
            StepAction::Continue | StepAction::Moved | StepAction::Restart => {
                self.restart(sys, st)?
            }
            StepAction::Stop => return Ok(Flow::Stop),
        }
        Ok(Flow::Propose)
    }

    fn propose(&mut self, h: f64, natural: f64, err: &f64) {
        // the run's own steps: not those cut to land on an event or the end of a call, nor
        // the first after a rejection (at the millimetre yoke's latch contact that one took
        // 10x the share of the steps before it)
        if h >= natural && !self.after_rejection {
            self.accepted_roundoff = self.whole_roundoff;
        }
        self.after_rejection = false;
        self.core.h = self.step_policy().after_acceptance(
            h,
            natural,
            self.core.h,
            step_factor(*err, self.gain_ratio, self.core.s.error_per_unit_step),
        );
    }
}
