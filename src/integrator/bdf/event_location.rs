//! Contact events inside a BDF step, on the step's own polynomial.

use super::*;

impl Bdf {
    /// Sizes the event-location buffers for `sys` (nothing for models without contact events).
    pub(super) fn resize_events(&mut self, sys: &System) {
        self.core
            .events
            .size_for(sys, &mut self.xd, &mut self.vd, &mut self.qd);
    }

    /// The event functions (into `out`) at the fraction `theta` of the converged step of order
    /// `k` and size `h` [s] that ends in `x`, `v`: on the step's own polynomial, through its end
    /// and the `k` newest history points (exact at the step's ends).
    pub(super) fn events_at(
        &mut self,
        sys: &mut System,
        k: usize,
        h: f64,
        theta: f64,
        out: &mut [f64],
    ) {
        let t0 = self.hist[0].t;
        let mut ts = [0.0; 8];
        ts[0] = t0 + h;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(k)) {
            *slot = p.t;
        }
        let mut w = [0.0; 8];
        let tau = t0 + theta * h;
        interp_weights(&ts[..k + 1], tau, &mut w[..k + 1]);
        for i in 0..self.xd.len() {
            let (mut sx, mut sv) = (w[0] * self.x[i], w[0] * self.v[i]);
            for j in 0..k {
                sx += w[j + 1] * self.xs[j][i];
                sv += w[j + 1] * self.hist[j].v[i];
            }
            self.xd[i] = sx;
            self.vd[i] = sv;
        }
        sys.model.retract(&self.hist[0].q, &self.xd, &mut self.qd);
        sys.contact_event_functions(tau, &self.qd, &self.vd, out);
    }

    /// After a converged step of order `k` and size `h` [s] from `st` (its end in `q1`, `v`):
    /// the earliest contact closing or opening inside it as a fraction of the step, located to
    /// 1e-12 of the step; `events.landing` then holds the events at that instant. `None`: no
    /// contact closes or opens.
    pub(super) fn events_in_step(
        &mut self,
        sys: &mut System,
        st: &State,
        k: usize,
        h: f64,
    ) -> Option<f64> {
        let mut ev = std::mem::take(&mut self.core.events);
        sys.contact_event_functions(st.t + h, &self.q1, &self.v, &mut ev.g1);
        let first = ev.locate(sys, st, |sys, m, out| self.events_at(sys, k, h, m, out));
        self.core.events = ev;
        first
    }
}
