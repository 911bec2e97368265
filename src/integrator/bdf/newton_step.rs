//! BDF's Newton iteration on the GGL equations: the matrix, the corrector, the multipliers'
//! predictor.

use super::*;

/// Assembles the GGL Newton matrix at `(t, q, v)` with leading coefficient `a0` (the constraint
/// rows must be evaluated there): unknowns `[dx, dv, dlambda, dmu]`.
fn assemble(sys: &mut System, lin: &mut LinearSolver, t: f64, q: &[f64], v: &[f64], a0: f64) {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    lin.begin(2 * nv + 2 * nc);
    for i in 0..nv {
        lin.push(i, i, a0);
        lin.push(i, nv + i, -1.0);
    }
    sys.add_constraint_blocks(lin, 2 * nv, 0, a0, Some((0, 2 * nv + nc, 1.0)));
    sys.add_dynamics_matrix_at(t, q, v, [a0, 1.0, 0.0], lin, nv, nv);
    sys.add_dynamics_matrix_at(t, q, v, [0.0, 0.0, 1.0], lin, nv, 0);
    sys.add_constraint_blocks(lin, 2 * nv + nc, nv, 1.0, Some((nv, 2 * nv, 1.0)));
}

impl Bdf {
    /// Newton iteration for one step of order `k` to `t1`; leaves the solution in `x`, `v`, ...
    pub(super) fn solve_step(
        &mut self,
        sys: &mut System,
        k: usize,
        t1: f64,
        alpha: &[f64],
    ) -> Outcome {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        let a0 = alpha[0];
        let n = 2 * nv + 2 * nc;
        self.q0.clone_from(&self.hist[0].q);
        let test = NewtonTest {
            fraction: NEWTON_FRACTION,
            first_factor: FIRST_CORRECTION_FACTOR,
        };
        let mut progress = Progress::default();
        let mut slow = false;
        loop {
            sys.model.retract(&self.q0, &self.x, &mut self.q1);
            progress.freeze_if_due(sys, t1, &self.q1, &self.v);
            sys.forces(t1, &self.q1, &self.v, &mut self.f);
            sys.eval_constraints(t1, &self.q1, &self.v);
            self.core.stats.rhs_evaluations += 1;
            self.core.stats.newton_iterations += 1;
            // x rows: -(sum alpha x - dexp_inv(x) v + G^T mu)
            sys.model.chart_rate(&self.x, &self.v, &mut self.tmp);
            for i in 0..nv {
                let mut s = a0 * self.x[i];
                for j in 0..k {
                    s += alpha[j + 1] * self.xs[j][i];
                }
                self.rhs[i] = -(s - self.tmp[i]);
            }
            self.gtmu.fill(0.0);
            sys.gt_mul_add(&self.mu, &mut self.gtmu);
            for (r, g) in self.rhs[..nv].iter_mut().zip(&self.gtmu) {
                *r -= g;
            }
            // v rows: -(M sum alpha v + G^T lambda - f)
            for i in 0..nv {
                let mut s = a0 * self.v[i];
                for j in 0..k {
                    s += alpha[j + 1] * self.hist[j].v[i];
                }
                self.vdot[i] = s;
            }
            sys.mass_mul(&self.vdot, &mut self.tmp);
            for i in 0..nv {
                self.rhs[nv + i] = self.f[i] - self.tmp[i];
            }
            self.lam.iter_mut().for_each(|l| *l = -*l);
            sys.gt_mul_add(&self.lam, &mut self.rhs[nv..2 * nv]);
            self.lam.iter_mut().for_each(|l| *l = -*l);
            let mut phi_max: f64 = 0.0;
            sys.g_mul(&self.v, &mut self.gv);
            let gv = &self.gv;
            for (r, row) in sys.rows.iter().enumerate() {
                self.rhs[2 * nv + r] = -a0 * row.phi;
                self.rhs[2 * nv + nc + r] = -(gv[r] + row.phi_t);
                phi_max = phi_max.max(row.phi.abs());
            }
            if self.rhs[..n].iter().any(|x| !x.is_finite()) {
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NonFinite("Newton residual"),
                });
            }
            let restored = if self.core.jac_valid {
                None
            } else {
                self.pending
                    .take()
                    .filter(|p| (a0 / p.coefficient - 1.0).abs() <= MATRIX_COEFFICIENT_CHANGE)
            };
            let refresh = !self.core.jac_valid
                || (a0 / self.jac_alpha0 - 1.0).abs() > MATRIX_COEFFICIENT_CHANGE;
            if refresh {
                let lin = &mut self.lin;
                match &restored {
                    Some(p) => p.with_recorded(sys, |sys| {
                        sys.eval_constraints(p.t, &p.q, &p.v);
                        assemble(sys, lin, p.t, &p.q, &p.v, p.coefficient);
                        sys.eval_constraints(t1, &self.q1, &self.v);
                    }),
                    None => assemble(sys, lin, t1, &self.q1, &self.v, a0),
                }
                let new = JacobianPoint::keep_or_record(
                    &mut self.jac_point,
                    restored,
                    sys,
                    t1,
                    &self.q1,
                    &self.v,
                    a0,
                );
                if new {
                    self.core.stats.jacobians += 1;
                    self.core.stats.factorizations += 1;
                }
                self.jac_alpha0 = self.jac_point.as_ref().map_or(a0, |p| p.coefficient);
                if let Err(e) = self.lin.factor() {
                    self.core.jac_valid = false;
                    return Outcome::Failed(factor_failure(&self.lin, e, t1));
                }
                self.core.jac_valid = true;
                // a restored matrix was observed when it was first formed: the restored monitors
                // hold that observation (observing again would read the rows evaluated last, at
                // this step's point, not the matrix's)
                if new {
                    let nv = sys.n_v();
                    self.rank.observe_factorization(
                        sys,
                        &self.lin,
                        (2 * nv, 2),
                        t1,
                        &mut self.core.stats,
                    );
                }
            }
            if let Err(e) = self.lin.solve(&mut self.rhs[..n]) {
                self.core.jac_valid = false;
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::SingularMatrix(e),
                });
            }
            for i in 0..nv {
                self.x[i] += self.rhs[i];
                self.v[i] += self.rhs[nv + i];
            }
            for r in 0..nc {
                self.lam[r] += self.rhs[2 * nv + r];
                self.mu[r] += self.rhs[2 * nv + nc + r];
            }
            let norm = wrms(&self.rhs[..nv], &self.wx).max(wrms(&self.rhs[nv..2 * nv], &self.wv));
            let it = progress.iterations();
            let rate = progress.rate(norm);
            let (dx, dv) = (max_abs(&self.rhs[..nv]), max_abs(&self.rhs[nv..2 * nv]));
            // near a singular configuration the factorization amplifies round-off by the
            // inverse of its smallest pivot ratio: the round-off band widens with it (from the
            // approach on, not only inside a passage: at rtol 3e-10 .. 3e-9 the iteration
            // stalled in amplified round-off before the ratio reached the passage threshold)
            let amp = self.rank.conditioning_amplification();
            let round_off = dx <= NEWTON_ROUND_OFF_EPSILONS * self.round_off[0] * amp
                && dv <= NEWTON_ROUND_OFF_EPSILONS * self.round_off[1] * amp;
            // stopped contracting at round-off: converged as far as the arithmetic goes
            let stalled = it >= 1 && rate > DIVERGENCE_RATE && round_off;
            slow |= it >= 2 && rate > REFRESH_RATE;
            // a first correction shows no contraction rate yet: it is taken as converged only
            // when it is negligible (1e-4 of the tolerance, FIRST_CORRECTION_FACTOR); accepting
            // larger first corrections of a reused matrix leaves a per-step error that makes
            // fixed-step BDF first order
            let verdict = progress.judge(&test, norm, stalled);
            if let Verdict::Diverged(_) = verdict {
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::Diverged(None),
                });
            }
            if verdict == Verdict::Converged && (stalled || phi_max <= 10.0 * self.core.s.atol) {
                sys.model.retract(&self.q0, &self.x, &mut self.q1);
                let (rtol, atol) = (self.core.s.rtol, self.core.s.atol);
                match progress.settle_decisions(sys, (t1, &self.q1, &self.v), rtol, atol) {
                    Err(e) => return Outcome::Failed(e),
                    Ok(false) => continue,
                    Ok(true) => {}
                }
                self.set_vdot(k, alpha);
                if slow && !stalled {
                    // the next step forms its matrix afresh
                    self.core.jac_valid = false;
                }
                return Outcome::Converged;
            }
            if progress.iterations() >= MAX_ITERATIONS {
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NoConvergence(MAX_ITERATIONS),
                });
            }
        }
    }

    /// Starts the multipliers at `t1` [s] on the line through those of the last two accepted
    /// points (at those of the last one when only it is known). A constant start leaves a
    /// first-order residual `G^T (lambda_1 - lambda_n)` which a Newton matrix formed at an
    /// earlier configuration turns into large, mostly cancelling speed corrections.
    pub(super) fn predict_multipliers(&mut self, nc: usize, t1: f64) {
        let (t0, last) = (self.lam_last.0, &self.lam_last.1);
        self.lam.clear();
        self.lam.extend_from_slice(last);
        self.lam.resize(nc, 0.0);
        if let Some((tp, lp)) = &self.lam_prev
            && lp.len() == nc
            && last.len() == nc
            && t0 > *tp
        {
            let c = (t1 - t0) / (t0 - tp);
            for (l, p) in self.lam.iter_mut().zip(lp) {
                *l += c * (*l - p);
            }
        }
    }

    /// The BDF derivative of the speeds at the new point (`sum alpha_j v_j`) into `vdot`.
    pub(super) fn set_vdot(&mut self, k: usize, alpha: &[f64]) {
        for i in 0..self.v.len() {
            let mut s = alpha[0] * self.v[i];
            for j in 0..k {
                s += alpha[j + 1] * self.hist[j].v[i];
            }
            self.vdot[i] = s;
        }
    }
}
