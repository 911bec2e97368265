//! BDF's step, rejection, order and step selection for the implicit step loop.

use super::*;

/// BDF's step, rejection and order and step selection for the step loop
/// ([`implicit::advance`]); the estimate is the order `k` the step was tried at and the errors
/// at orders `k - 1`, `k`, `k + 1`.
impl ImplicitMethod for Bdf {
    type Estimate = (usize, [f64; 3]);

    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Bdf
    }

    fn core(&mut self) -> &mut MethodCore {
        &mut self.core
    }

    /// Also the start-up of a fixed-step run: its first points from a tight DOPRI5 run.
    fn begin_call(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        if self.hist.is_empty() {
            return Err(SolverError::other("bdf: advance_to before start"));
        }
        let fixed = self.core.s.fixed_step > 0.0;
        self.note_start_vdot(st);
        // a step size that cannot advance (a forged state) is chosen afresh, as at the start
        if !fixed && step_control::collapsed(self.core.h, st.t) {
            self.core.h = self.initial_step(sys, st);
        }
        if fixed && self.hist.len() == 1 && self.core.s.max_order > 1 {
            self.bootstrap(sys, st)?;
        }
        self.resize_events(sys);
        Ok(())
    }

    fn try_step(
        &mut self,
        sys: &mut System,
        _st: &State,
        h: f64,
    ) -> Result<(usize, [f64; 3]), NewtonFailure> {
        let k = self.order.min(self.hist.len());
        Bdf::try_step(self, sys, h).map(|errors| (k, errors))
    }

    fn rejects(&self, est: &(usize, [f64; 3])) -> bool {
        step_control::rejects(est.1[1])
    }

    /// Three rejections in a row drop the order to 1.
    fn rejected(
        &mut self,
        _st: &State,
        h: f64,
        &(k, [_, errk, _]): &(usize, [f64; 3]),
        in_a_row: u32,
    ) -> Result<(), SolverError> {
        self.core.stats.rejected += 1;
        self.core.stats.rejected_error += 1;
        self.core.h =
            step_control::after_rejection(h, step_control::proposal(errk, self.estimate_order(k)));
        if in_a_row >= 3 {
            self.order = 1;
            self.steps_at_order = 0;
        }
        Ok(())
    }

    fn event_in_step(
        &mut self,
        sys: &mut System,
        st: &State,
        h: f64,
        est: &(usize, [f64; 3]),
    ) -> Option<f64> {
        self.events_in_step(sys, st, est.0, h)
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, est: &(usize, [f64; 3])) {
        Bdf::accept(self, sys, st, h, est.0);
    }

    /// A moved state translates the history; a restart (or forces that jump) skips the step
    /// proposal: the history's polynomial no longer describes the motion.
    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
        jump: bool,
    ) -> Result<Flow, SolverError> {
        match action {
            StepAction::Continue if !jump => {}
            StepAction::Moved if !jump => self.translate_history(st),
            StepAction::Continue | StepAction::Moved | StepAction::Restart => {
                self.restart(sys, st)?;
                return Ok(Flow::Next);
            }
            StepAction::Stop => return Ok(Flow::Stop),
        }
        Ok(Flow::Propose)
    }

    /// Order and step selection after every accepted step.
    fn propose(&mut self, h: f64, natural: f64, &(k, [lo, errk, hi]): &(usize, [f64; 3])) {
        self.steps_at_order += 1;
        // error per unit step lowers the estimates' order in h by one
        let shift = if self.per_unit_step { 0.0 } else { 1.0 };
        let ratio = |e: f64, ord: usize| step_control::proposal(e, ord as f64 + shift);
        let mut best = (ratio(errk, k), k);
        if self.steps_at_order > k {
            let rl = ratio(lo, k - 1) / 1.3;
            if k > 1 && rl > best.0 {
                best = (rl, k - 1);
            }
            let rh = ratio(hi, k + 1) / 1.4;
            if k < self.core.s.max_order && rh > best.0 {
                best = (rh, k + 1);
            }
        }
        // startup: raise the order as soon as enough points exist
        if self.since_start < 8 && k < self.core.s.max_order && self.hist.len() > k && best.1 == k {
            best.1 = k + 1;
        }
        if best.1 != self.order {
            self.order = best.1;
            self.steps_at_order = 0;
        }
        self.core.h = STEP_POLICY.after_acceptance(h, natural, self.core.h, best.0);
    }

    /// A Newton failure drops the order to 1.
    fn newton_failed(&mut self) {
        self.order = 1;
        self.steps_at_order = 0;
    }

    fn singular_cause(&mut self, sys: &mut System, st: &State) -> Option<SingularPassage> {
        Bdf::singular_cause(self, sys, st)
    }

    /// The newest history point is at the end of the call.
    fn end_call(&mut self, t_end: f64) {
        if let Some(p) = self.hist.front_mut() {
            p.t = t_end;
        }
    }
}
