//! Contact events inside a generalized-alpha step, on the step's own update formulas.

use super::*;

impl GenAlpha {
    /// Sizes the event-location buffers for `sys` (nothing for models without contact events).
    pub(super) fn resize_events(&mut self, sys: &System) {
        self.core
            .events
            .size_for(sys, &mut self.xd, &mut self.vd, &mut self.qd);
    }

    /// The event functions (into `out`) at the fraction `theta` of the converged step of `h` [s]
    /// from `st`, on the step's own update formulas evaluated at `theta h` with the step's
    /// accelerations (exact at both ends, and for motion of constant acceleration before a
    /// contact).
    pub(super) fn events_at(
        &mut self,
        sys: &mut System,
        st: &State,
        h: f64,
        theta: f64,
        out: &mut [f64],
    ) {
        let (g, b) = (self.gamma, self.beta);
        let tau = theta * h;
        for k in 0..self.xd.len() {
            let (a0, a1) = (self.a[k], self.a1[k]);
            self.xd[k] = tau * st.v[k] + tau * tau * ((0.5 - b) * a0 + b * a1);
            self.vd[k] = st.v[k] + tau * ((1.0 - g) * a0 + g * a1);
        }
        sys.model.retract(&st.q, &self.xd, &mut self.qd);
        sys.contact_event_functions(st.t + tau, &self.qd, &self.vd, out);
    }

    /// After a converged step of `h` [s] from `st` (its end in `q1`, `v1`): the earliest contact
    /// closing or opening inside it as a fraction of the step, located to 1e-12 of the step;
    /// `events.landing` then holds the events at that instant. `None`: no contact closes or
    /// opens.
    pub(super) fn events_in_step(&mut self, sys: &mut System, st: &State, h: f64) -> Option<f64> {
        let mut ev = std::mem::take(&mut self.core.events);
        sys.contact_event_functions(st.t + h, &self.q1, &self.v1, &mut ev.g1);
        let first = ev.locate(sys, st, |sys, m, out| self.events_at(sys, st, h, m, out));
        self.core.events = ev;
        first
    }
}
