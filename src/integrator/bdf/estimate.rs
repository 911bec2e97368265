//! BDF's trial step: predictor, corrector (see `newton_step`), the error weights and the error
//! estimates at orders `k - 1`, `k`, `k + 1`.

use super::*;

impl Bdf {
    /// Tries one step of size `h` at the current order. Returns the error estimates at orders
    /// (k-1, k, k+1) (NaN where unavailable) on convergence.
    pub(super) fn try_step(&mut self, sys: &mut System, h: f64) -> Result<[f64; 3], NewtonFailure> {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        let k = self.order.min(self.hist.len());
        let t1 = self.hist[0].t + h;
        let navail = self.hist.len();
        self.chart_history(sys, navail);
        // predictor through k+1 points if available (k otherwise)
        let np = (k + 1).min(navail);
        let mut ts = [0.0; 8];
        for (slot, p) in ts.iter_mut().zip(self.hist.iter().take(np)) {
            *slot = p.t;
        }
        let mut wp = [0.0; 8];
        interp_weights(&ts[..np], t1, &mut wp[..np]);
        // the first step from one point: a Taylor predictor with the known derivatives, so
        // that its difference to the corrector (the error estimate) is O(h^2), as a predictor
        // through k + 1 points makes it; through the point alone it would be the whole change
        // of the speeds over the step, O(h), which a tolerance shared per unit step (also
        // O(h)) never accepts where the accelerations are large against it (the flexible
        // panels' modes at t = 0)
        let taylor = np == 1 && self.start_vdot.len() == nv;
        for i in 0..nv {
            if taylor {
                self.x[i] = self.xs[0][i] + h * self.hist[0].v[i];
                self.v[i] = self.hist[0].v[i] + h * self.start_vdot[i];
                continue;
            }
            let (mut sx, mut sv) = (0.0, 0.0);
            for (j, w) in wp[..np].iter().enumerate() {
                sx += w * self.xs[j][i];
                sv += w * self.hist[j].v[i];
            }
            self.x[i] = sx;
            self.v[i] = sv;
        }
        self.xp.copy_from_slice(&self.x);
        self.vp.copy_from_slice(&self.v);
        self.mu.iter_mut().for_each(|m| *m = 0.0);
        self.predict_multipliers(nc, t1);
        // corrector weights over t1, t_n, ..., t_{n-k+1}
        ts[0] = t1;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(k)) {
            *slot = p.t;
        }
        let mut alpha = [0.0; 8];
        derivative_weights(&ts[..k + 1], &mut alpha[..k + 1]);
        weights(
            sys,
            &self.hist[0].q,
            &self.hist[0].v,
            &self.core.s,
            &mut self.wx,
            &mut self.wv,
        );
        self.scale_weights(h);
        if let Outcome::Failed(e) = self.solve_step(sys, k, t1, &alpha[..k + 1]) {
            return Err(e);
        }
        if self.core.s.fixed_step > 0.0 {
            return Ok([f64::NAN, 0.0, f64::NAN]);
        }
        // error at order k; the Taylor predictor of the first step stands for one through two
        // points a step apart (span 2h)
        let span = t1 - self.hist[np - 1].t;
        let c = if taylor { 0.5 } else { h / span };
        for i in 0..nv {
            self.ex[i] = c * (self.x[i] - self.xp[i]);
            self.ev[i] = c * (self.v[i] - self.vp[i]);
        }
        let err_k = self.combined(wrms(&self.ex, &self.wx), wrms(&self.ev, &self.wv));
        let err_k = if np < k + 1 { err_k.max(1e-300) } else { err_k };
        let err_lo = if k >= 2 {
            self.scaled_divided_difference(k, t1, h, navail) / k as f64
        } else {
            f64::NAN
        };
        let err_hi = if k < self.core.s.max_order && navail >= k + 2 {
            self.scaled_divided_difference(k + 2, t1, h, navail) / (k + 2) as f64
        } else {
            f64::NAN
        };
        Ok([err_lo, err_k, err_hi])
    }

    /// Scales the error weights `wx`, `wv` (built from rtol/atol at the step's start) to the
    /// share of the tolerance a step of `h` [s] may use: `h / ERROR_TIME_UNIT` of it (all of it from
    /// `ERROR_TIME_UNIT` on, with fixed steps and with `Settings::error_per_unit_step` off), never
    /// below the round-off floor
    /// ([`ROUND_OFF_EPSILONS`]).
    pub(super) fn scale_weights(&mut self, h: f64) {
        if self.core.s.fixed_step > 0.0 {
            self.per_unit_step = false;
            self.round_off = [0.0; 2];
            return;
        }
        let f = self.core.s.error_share(h);
        self.per_unit_step = f < 1.0;
        // weights are atol + rtol * scale: recover the largest position scale [m or rad]; a
        // body at the origin still moves by its speed: lengths and speeds scale each other
        let x_scale = self
            .wx
            .iter()
            .map(|w| (w - self.core.s.atol) / self.core.s.rtol)
            .fold(0.0, f64::max);
        let v_max = max_abs(&self.hist[0].v);
        let (x_scale, v_scale) = (
            x_scale.max(v_max * ERROR_TIME_UNIT),
            v_max.max(x_scale / ERROR_TIME_UNIT),
        );
        self.round_off = [f64::EPSILON * x_scale, f64::EPSILON * v_scale];
        // near a singular configuration the solution carries round-off amplified by the
        // factorization (the inverse of its smallest pivot ratio)
        let amp = self.rank.conditioning_amplification();
        let [fx, fv] = self.round_off.map(|r| ROUND_OFF_EPSILONS * r * amp);
        // the floor never loosens a weight beyond its tolerance per step
        self.wx
            .iter_mut()
            .for_each(|w| *w = (f * *w).max(fx.min(*w)));
        self.wv
            .iter_mut()
            .for_each(|w| *w = (f * *w).max(fv.min(*w)));
    }

    /// Order in `h` of the error estimates of an order-`k` step at the current tolerance
    /// fraction: `k + 1` per step, `k` per unit step.
    pub(super) fn estimate_order(&self, k: usize) -> f64 {
        if self.per_unit_step {
            k as f64
        } else {
            k as f64 + 1.0
        }
    }

    /// Weighted norm of the scaled divided difference `j! h^j y[t1, t_n, ...]` of order `j` of the
    /// new solution and the history (about `h^j y^(j)`); NaN when the history is too short.
    pub(super) fn scaled_divided_difference(
        &mut self,
        j: usize,
        t1: f64,
        h: f64,
        navail: usize,
    ) -> f64 {
        if j > navail || j + 1 > 8 {
            return f64::NAN;
        }
        let mut ts = [0.0; 8];
        ts[0] = t1;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(j)) {
            *slot = p.t;
        }
        let scale = (1..=j).map(|m| m as f64).product::<f64>() * h.powi(j as i32);
        for i in 0..self.x.len() {
            let (mut vx, mut vv) = ([0.0; 8], [0.0; 8]);
            vx[0] = self.x[i];
            vv[0] = self.v[i];
            for m in 0..j {
                vx[m + 1] = self.xs[m][i];
                vv[m + 1] = self.hist[m].v[i];
            }
            for lvl in 1..=j {
                for m in 0..=(j - lvl) {
                    let dt = ts[m] - ts[m + lvl];
                    vx[m] = (vx[m] - vx[m + 1]) / dt;
                    vv[m] = (vv[m] - vv[m + 1]) / dt;
                }
            }
            self.ex[i] = scale * vx[0];
            self.ev[i] = scale * vv[0];
        }
        self.combined(wrms(&self.ex, &self.wx), wrms(&self.ev, &self.wv))
    }

    /// The error norm of a step from its weighted position and speed errors: their RMS, or the
    /// position error alone without [`Settings::error_includes_speeds`].
    pub(super) fn combined(&self, position: f64, speed: f64) -> f64 {
        if self.core.s.error_includes_speeds {
            ((position * position + speed * speed) * 0.5).sqrt()
        } else {
            position
        }
    }
}
