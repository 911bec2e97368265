//! Generalized-alpha's step: kinematics from the accelerations, the Newton iteration on the
//! index-3 equations, the speed projection, the error estimate.

use super::*;

impl GenAlpha {
    /// Error weights (`wx`, `wv`) and Newton weights (`wn`) of an adaptive step of `h` [s]: the
    /// iteration stops at [`NEWTON_FRACTION`] of the step's share of the local error tolerance,
    /// but not below round-off. Returns the constraint violation accepted at convergence and the
    /// largest position scale [m].
    pub(super) fn adaptive_newton_weights(
        &mut self,
        sys: &System,
        st: &State,
        h: f64,
    ) -> (f64, f64) {
        weights(sys, &st.q, &st.v, &self.core.s, &mut self.wx, &mut self.wv);
        let floor = fixed_step_newton_weights(sys, &st.q, &mut self.wn);
        let share = self.core.s.error_share(h);
        let mut scale: f64 = 1e-3;
        for (n, w) in self.wn.iter_mut().zip(&self.wx) {
            // `wn` holds the round-off floor scaled like a weight (see fixed_step_newton_weights)
            *n = n.max(share * w);
        }
        scale = scale.max(floor);
        if !self.core.s.error_per_unit_step {
            // per step: the constraint violation of the whole tolerance, as it always was
            return (10.0 * self.core.s.atol, scale);
        }
        // constraints to round-off as with a fixed step: a violation left by one step is
        // corrected by the next as a velocity jump of `phi / (b h)`, which grows without bound
        // when the step shrinks (an energy rejection then shrank the step further: the step
        // collapsed to 1e-16 s on the double pendulum with a violation of `0.02 h atol`)
        (POSITION_ROUNDOFF * scale, scale)
    }

    /// Fills `a1`, `v1`, `dx`, `q1` from the current `w`.
    pub(super) fn kinematics(&mut self, sys: &System, st: &State, h: f64) {
        let (am, af, g, b) = (self.am, self.af, self.gamma, self.beta);
        for i in 0..self.w.len() {
            self.a1[i] = (af * st.vdot[i] - am * self.a[i] + (1.0 - af) * self.w[i]) / (1.0 - am);
            self.v1[i] = st.v[i] + h * ((1.0 - g) * self.a[i] + g * self.a1[i]);
            self.dx[i] = h * st.v[i] + h * h * ((0.5 - b) * self.a[i] + b * self.a1[i]);
        }
        sys.model.retract(&st.q, &self.dx, &mut self.q1);
    }

    /// Solves step `h` (see [`GenAlpha::solve_step`]) with the discrete decisions of the force
    /// effects thawed again afterwards.
    pub(super) fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> StepOutcome {
        let out = self.solve_step(sys, st, h);
        sys.thaw();
        out
    }

    /// The step's Newton iteration (bookkeeping in [`crate::integrator::newton`]). The effects' discrete
    /// decisions (rope slip modes) are taken freely at the predictor and the first iterate, then
    /// frozen so the remaining iterations solve one smooth branch (without, iterates near a slip
    /// reversal switch modes back and forth and Newton stalls at rate ~1). A converged iterate
    /// counts only if the effects take the frozen decisions there themselves; if not, the
    /// decisions are taken again there and the iteration continues (a few times, then the step
    /// fails and is retried smaller), so the converged state is the one without freezing.
    pub(super) fn solve_step(&mut self, sys: &mut System, st: &State, h: f64) -> StepOutcome {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        let t1 = st.t + h;
        let ca = (1.0 - self.af) / (1.0 - self.am);
        let cx = self.beta * h * h * ca;
        self.w.copy_from_slice(&st.vdot);
        self.lam.copy_from_slice(&st.lambda);
        let fixed = self.core.s.fixed_step > 0.0;
        // adaptive with the error held per unit step: constraints and Newton to round-off,
        // speeds projected, round-off allowed for in the error test (per step: none of these)
        let unit = !fixed && self.core.s.error_per_unit_step;
        // constraint violation accepted at convergence [m, rad]; largest position scale [m]
        let (phi_tol, scale) = if fixed {
            let scale = fixed_step_newton_weights(sys, &st.q, &mut self.wn);
            (POSITION_ROUNDOFF * scale, scale)
        } else {
            self.adaptive_newton_weights(sys, st, h)
        };
        let test = NewtonTest {
            fraction: NEWTON_FRACTION,
            first_factor: 1.0,
        };
        let mut progress = Progress::default();
        loop {
            self.kinematics(sys, st, h);
            progress.freeze_if_due(sys, t1, &self.q1, &self.v1);
            sys.forces(t1, &self.q1, &self.v1, &mut self.f);
            sys.eval_constraints(t1, &self.q1, &self.v1);
            self.core.stats.rhs_evaluations += 1;
            self.core.stats.newton_iterations += 1;
            // residual
            sys.mass_mul(&self.w, &mut self.tmp);
            for i in 0..nv {
                self.rhs[i] = self.f[i] - self.tmp[i];
            }
            let mut lam_neg = std::mem::take(&mut self.lam);
            lam_neg.iter_mut().for_each(|x| *x = -*x);
            sys.gt_mul_add(&lam_neg, &mut self.rhs[..nv]);
            lam_neg.iter_mut().for_each(|x| *x = -*x);
            self.lam = lam_neg;
            let mut phi_max: f64 = 0.0;
            for (r, row) in sys.rows.iter().enumerate() {
                self.rhs[nv + r] = -row.phi / cx;
                phi_max = phi_max.max(row.phi.abs());
            }
            if self.rhs.iter().any(|x| !x.is_finite()) {
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NonFinite("Newton residual"),
                });
            }
            let fresh = fresh_fixed_step_matrix(fixed, progress.iterations());
            if !self.core.jac_valid || !same_step(self.jac_h, h) || fresh {
                // a restored state's matrix is formed again at its recorded point, except where
                // the run it was saved from formed a fresh one (a fixed step's first iterate)
                let restored = if self.core.jac_valid {
                    None
                } else {
                    self.pending
                        .take()
                        .filter(|p| !fresh && same_step(p.coefficient, h))
                };
                // the matrix's own step: a restored point's, so the matrix is formed identically
                let hm = restored.as_ref().map_or(h, |p| p.coefficient);
                let cxm = self.beta * hm * hm * ca;
                let cvm = self.gamma * hm * ca;
                self.lin.begin(nv + nc);
                let lin = &mut self.lin;
                // the joints' geometric stiffness at the step's multipliers
                let stiff = forms_constraint_stiffness(fixed);
                let lam = &self.lam;
                match &restored {
                    Some(p) => p.with_recorded(sys, |sys| {
                        sys.eval_constraints(p.t, &p.q, &p.v);
                        // no stiffness: only adaptive steps form a matrix at a restored point
                        sys.add_dynamics_matrix(p.t, &p.q, &p.v, 1.0, cvm, cxm, lin, 0);
                        sys.add_constraint_blocks(lin, nv, 0, 1.0, Some((0, nv, 1.0)));
                        sys.eval_constraints(t1, &self.q1, &self.v1);
                    }),
                    None => {
                        sys.add_dynamics_matrix(t1, &self.q1, &self.v1, 1.0, cvm, cxm, lin, 0);
                        if stiff {
                            sys.add_constraint_stiffness(lam, cxm, lin, 0, 0);
                        }
                        sys.add_constraint_blocks(lin, nv, 0, 1.0, Some((0, nv, 1.0)));
                    }
                }
                let new = JacobianPoint::keep_or_record(
                    &mut self.jac_point,
                    restored,
                    sys,
                    t1,
                    &self.q1,
                    &self.v1,
                    h,
                );
                if new {
                    self.core.stats.jacobians += 1;
                    self.core.stats.factorizations += 1;
                }
                if let Err(e) = self.lin.factor() {
                    self.core.jac_valid = false;
                    return StepOutcome::Failed(factor_failure(&self.lin, e, t1));
                }
                self.core.jac_valid = true;
                self.jac_h = hm;
                // a restored matrix was observed when it was first formed (the restored
                // monitors hold that observation)
                if new {
                    self.rank
                        .observe(sys, &self.lin, nv, 1, t1, &mut self.core.stats);
                }
            }
            if let Err(e) = self.lin.solve(&mut self.rhs) {
                self.core.jac_valid = false;
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::SingularMatrix(e),
                });
            }
            for i in 0..nv {
                self.w[i] += self.rhs[i];
                self.tmp[i] = cx * self.rhs[i];
            }
            for r in 0..nc {
                self.lam[r] += self.rhs[nv + r];
            }
            // On the index-3 form velocity increments carry round-off of order eps/h, so
            // convergence is judged on the position increments (which the velocities follow).
            let norm = wrms(&self.tmp, &self.wn);
            // largest position correction of this iterate [m, rad]: at convergence, the
            // round-off the positions actually carry
            let last_correction = self.tmp.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let rate = progress.rate(norm);
            // an iteration inside the round-off band that no longer contracts has converged:
            // its corrections are round-off. Adaptive steps take a rate of 0.2 as no longer
            // contracting (at 0.9, corrections of 10-30 epsilons that came and went at random
            // failed the steps of tight tolerances until the step collapsed); a fixed step
            // keeps iterating to 0.9 (at 0.2 the double pendulum's error at h = 1e-4 rose from
            // 5.7e-7 to 1.3e-6 m)
            let stall_rate = if fixed { 0.9 } else { 0.2 };
            // near a singular configuration the factorization amplifies round-off by the
            // inverse of its smallest pivot ratio: the round-off band widens with it
            let band = POSITION_ROUNDOFF * scale * self.rank.round_off_amplification();
            let stalled = (fixed || unit)
                && progress.iterations() >= 1
                && rate > stall_rate
                && self.tmp.iter().all(|x| x.abs() <= band);
            let verdict = progress.judge(&test, norm, stalled);
            if let Verdict::Diverged(rate) = verdict {
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::Diverged(Some(rate)),
                });
            }
            let phi_tol = if unit {
                phi_tol * self.rank.round_off_amplification()
            } else {
                phi_tol
            };
            if verdict == Verdict::Converged && phi_max <= phi_tol {
                self.kinematics(sys, st, h);
                let (rtol, atol) = (self.core.s.rtol, self.core.s.atol);
                match progress.settle_decisions(sys, (t1, &self.q1, &self.v1), rtol, atol) {
                    Err(e) => return StepOutcome::Failed(e),
                    Ok(false) => continue,
                    Ok(true) => {}
                }
                let mut err = 0.0;
                if self.core.s.fixed_step == 0.0 {
                    let projected = if unit {
                        self.project_speeds(sys, t1)
                    } else {
                        Ok(())
                    };
                    if let Err(e) = projected {
                        self.core.jac_valid = false;
                        return StepOutcome::Failed(e);
                    }
                    let c = self.gamma / 2.0 - self.beta - 1.0 / 12.0;
                    for i in 0..nv {
                        self.tmp[i] = c * h * h * (self.a1[i] - self.a[i]);
                    }
                    // the whole estimate (`full`); `tmp` is projected onto the joints' tangent
                    // space below only where the blend uses it
                    self.full.copy_from_slice(&self.tmp);
                    // round-off the estimate carries: accelerations carry the round-off of
                    // positions `dx` (`eps scale`, or the last Newton correction if the
                    // iteration stalled in the round-off band) as `dx / (b h^2)` along the
                    // constraint normals, i.e. `c dx / b` whatever the step; the projection
                    // removes that part up to what [`projected_noise`] leaves
                    let noise = if nc == 0 || !unit {
                        // no constraints: positions are not projected, accelerations carry no
                        // round-off of `1 / h^2`
                        0.0
                    } else if stalled {
                        last_correction.max(f64::EPSILON * scale)
                    } else {
                        f64::EPSILON * scale
                    } * self.rank.round_off_amplification();
                    // the round-off allowance of the whole estimate, and what is left of it
                    // along the tangent space
                    let floor = NOISE_ALLOWANCE * c.abs() * noise / self.beta;
                    let share = self.core.s.error_share(h);
                    let tangent_floor = floor * projected_noise(share);
                    let safety = if self.core.s.error_per_unit_step {
                        ERROR_SAFETY
                    } else {
                        1.0
                    };
                    // the step's share of the tolerance, widened by the round-off: a step
                    // shortened to reach a communication point (down to 1e-12 s in event
                    // location) is not rejected for round-off it cannot remove
                    for (e, w) in self.werr.iter_mut().zip(&self.wx) {
                        *e = share * w + floor;
                    }
                    let whole = safety * wrms(&self.full, &self.werr);
                    for (e, w) in self.werr.iter_mut().zip(&self.wx) {
                        *e = share * w;
                    }
                    // share of the tolerance the whole estimate's round-off allowance takes
                    self.full.fill(floor);
                    let whole_roundoff = wrms(&self.full, &self.werr);
                    (self.whole_err, self.whole_roundoff) = (whole, whole_roundoff);
                    self.full.fill(tangent_floor);
                    self.err_roundoff = wrms(&self.full, &self.werr);
                    // inside a singular configuration the allowance is widened instead
                    // (the tangent space itself is ill-determined there)
                    let g = if self.rank.inside() {
                        1.0
                    } else {
                        whole_weight(whole_roundoff)
                    };
                    err = if g >= 1.0 || !unit {
                        whole
                    } else {
                        if let Err(e) = self.project_estimate(sys, t1) {
                            self.core.jac_valid = false;
                            return StepOutcome::Failed(e);
                        }
                        for (e, w) in self.werr.iter_mut().zip(&self.wx) {
                            *e = share * w + tangent_floor;
                        }
                        let tangential = TANGENT_SAFETY * safety * wrms(&self.tmp, &self.werr);
                        g * whole + (1.0 - g) * tangential
                    };
                    self.gain_ratio = self.energy_gain(sys, st, h);
                }
                return StepOutcome::Converged(err);
            }
            if progress.iterations() >= MAX_ITERATIONS {
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NoConvergence(MAX_ITERATIONS),
                });
            }
        }
    }

    /// Projects the step's speeds `v1` onto the velocity constraints `G v + Phi_t = 0` at `q1`
    /// (adaptive mode), with the step's Newton matrix as the metric (one more solve, no new
    /// factorization). The index-3 update leaves `G v1` off by the step's truncation error; a much
    /// smaller next step then corrects the predictor's normal motion `h G v1` through
    /// `a1 ~ G v1 / (b h)`, and the error estimate `h^2 (a1 - a0)`, taken per unit step, no longer
    /// falls with the step: after a rejection the step collapsed (double pendulum, rtol 1e-4).
    pub(super) fn project_speeds(
        &mut self,
        sys: &mut System,
        t1: f64,
    ) -> Result<(), NewtonFailure> {
        if sys.n_c() == 0 {
            return Ok(());
        }
        sys.eval_constraints(t1, &self.q1, &self.v1);
        let mut v1 = std::mem::take(&mut self.v1);
        let done = self.project_onto_joints(sys, t1, &mut v1, true);
        self.v1 = v1;
        done
    }

    /// Projects the error estimate in `tmp` [m, rad] onto the joints' tangent space at `q1`
    /// (`G e = 0`), with the step's Newton matrix as the metric (one more solve, no new
    /// factorization; call after [`GenAlpha::project_speeds`], which evaluated the constraints
    /// at `q1`). Both the exact and the computed positions lie on the joints, so the true local
    /// error has no first-order component along the constraint normals; that component of
    /// `c h^2 (a1 - a0)` is the positions' round-off amplified by `1 / (b h^2)` (the index-3
    /// form's round-off floor: before, rtol 1e-9 was refused on the four-bar and 1e-10 on the
    /// chains, docs/integrator_error_control.md).
    pub(super) fn project_estimate(
        &mut self,
        sys: &mut System,
        t1: f64,
    ) -> Result<(), NewtonFailure> {
        if sys.n_c() == 0 {
            return Ok(());
        }
        let mut e = std::mem::take(&mut self.tmp);
        let done = self.project_onto_joints(sys, t1, &mut e, false);
        self.tmp = e;
        done
    }

    /// `x += dx`, the correction that puts `x` on the joints' tangent space, `G (x + dx) + c = 0`
    /// with `c` the constraints' explicit time rates (`with_time_rates`) or 0, in the metric of
    /// the step's Newton matrix (one solve with its factors; the constraints evaluated at `q1`).
    fn project_onto_joints(
        &mut self,
        sys: &mut System,
        t1: f64,
        x: &mut [f64],
        with_time_rates: bool,
    ) -> Result<(), NewtonFailure> {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        self.rhs[..nv].fill(0.0);
        self.lam_scratch.resize(nc, 0.0);
        sys.g_mul(x, &mut self.lam_scratch);
        for (r, row) in sys.rows.iter().enumerate() {
            let g_x = self.lam_scratch[r];
            self.rhs[nv + r] = if with_time_rates {
                -(g_x + row.phi_t)
            } else {
                -g_x
            };
        }
        self.lin.solve(&mut self.rhs).map_err(|e| NewtonFailure {
            t: t1,
            cause: NewtonCause::SingularMatrix(e),
        })?;
        for (xi, dx) in x.iter_mut().zip(&self.rhs[..nv]) {
            *xi += dx;
        }
        Ok(())
    }
}
