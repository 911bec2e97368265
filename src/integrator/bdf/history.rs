//! BDF's history of accepted points: the start-up, the accepted step, a moved state, the
//! chart coordinates the step works in.

use super::*;

impl Bdf {
    /// Keeps the state's accelerations for the first step's predictor while the history holds
    /// only the state's own point (after a start, a restart or a restored memory); finite and of
    /// the right length, else none.
    pub(super) fn note_start_vdot(&mut self, st: &State) {
        self.start_vdot.clear();
        if self.hist.len() == 1
            && self.hist[0].t == st.t
            && st.vdot.len() == st.v.len()
            && st.vdot.iter().all(|a| a.is_finite())
        {
            self.start_vdot.extend_from_slice(&st.vdot);
        }
    }

    pub(super) fn push_point(&mut self, st: &State) {
        // recycle the oldest point's storage once the history is full (no allocation per step)
        let mut p = if self.hist.len() >= 7 {
            self.hist.pop_back().unwrap_or(Point {
                t: 0.0,
                q: Vec::new(),
                v: Vec::new(),
                z: [0.0; 2],
            })
        } else {
            Point {
                t: 0.0,
                q: Vec::new(),
                v: Vec::new(),
                z: [0.0; 2],
            }
        };
        p.t = st.t;
        p.q.clone_from(&st.q);
        p.v.clone_from(&st.v);
        p.z = [st.energy_dissipated, st.work_input];
        self.hist.push_front(p);
    }

    /// Translates every history point by the displacement a step hook gave the newest one
    /// (`st.q - q_newest`, coordinate by coordinate; see [`StepAction::Moved`]): the backward
    /// differences, and with them the speeds the next steps infer, stay as they were. Without
    /// it the next step would start from the stored point, not the moved one.
    pub(super) fn translate_history(&mut self, st: &State) {
        if self.hist.is_empty() {
            return;
        }
        for i in 0..st.q.len() {
            let d = st.q[i] - self.hist[0].q[i];
            if d != 0.0 {
                for p in self.hist.iter_mut() {
                    p.q[i] += d;
                }
            }
        }
    }

    /// Chart coordinates of history points `0..m` relative to the newest.
    pub(super) fn chart_history(&mut self, sys: &System, m: usize) {
        let nv = sys.n_v();
        self.xs.resize(m, Vec::new());
        for j in 0..m {
            self.xs[j].resize(nv, 0.0);
            if j == 0 {
                self.xs[0].fill(0.0);
            } else {
                let mut x = std::mem::take(&mut self.xs[j]);
                sys.model.local(&self.hist[0].q, &self.hist[j].q, &mut x);
                self.xs[j] = x;
            }
        }
    }

    pub(super) fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, alpha0_k: usize) {
        let t1 = self.hist[0].t + h;
        // quadrature of powers with the same BDF formula (explicit in z)
        let drive = sys.drive_power(&self.lam);
        let (pd, pi) = sys.powers(t1, &self.q1, &self.v);
        let pi = pi + drive;
        let k = alpha0_k;
        let mut ts = [0.0; 8];
        ts[0] = t1;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(k)) {
            *slot = p.t;
        }
        let mut alpha = [0.0; 8];
        derivative_weights(&ts[..k + 1], &mut alpha[..k + 1]);
        let mut z = [0.0; 2];
        for (c, p) in [pd, pi].into_iter().enumerate() {
            let mut s = 0.0;
            for j in 0..k {
                s += alpha[j + 1] * self.hist[j].z[c];
            }
            z[c] = (p - s) / alpha[0];
        }
        st.t = t1;
        st.q.copy_from_slice(&self.q1);
        st.v.copy_from_slice(&self.v);
        st.vdot.copy_from_slice(&self.vdot);
        st.lambda.clear();
        st.lambda.extend_from_slice(&self.lam);
        // the last multipliers become the previous ones (their storage reused)
        let mut older = self.lam_prev.take().map(|p| p.1).unwrap_or_default();
        std::mem::swap(&mut older, &mut self.lam_last.1);
        self.lam_prev = Some((self.lam_last.0, older));
        self.lam_last.0 = t1;
        self.lam_last.1.clone_from(&self.lam);
        st.energy_dissipated = z[0];
        st.work_input = z[1];
        self.push_point(st);
        self.since_start += 1;
        self.core.stats.steps += 1;
        self.core.stats.last_step = h;
    }

    /// Fixed-step start: fills the history with `order - 1` points from a tight DOPRI5 run.
    pub(super) fn bootstrap(
        &mut self,
        sys: &mut System,
        st: &mut State,
    ) -> Result<(), SolverError> {
        let h = self.core.s.fixed_step;
        let tight = Settings {
            rtol: crate::integrator::MIN_RTOL,
            atol: 1e-15,
            h_max: h,
            fixed_step: 0.0,
            ..self.core.s
        };
        let mut rk = Dopri5::new(tight);
        rk.start(sys, st)?;
        while self.hist.len() < self.core.s.max_order {
            let t = st.t + h;
            rk.advance_to(sys, st, t, &mut MemoryHook)?;
            self.push_point(st);
        }
        self.order = self.core.s.max_order;
        Ok(())
    }
}
