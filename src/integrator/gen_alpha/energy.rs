//! Generalized-alpha's energy check of a step (see [`GenAlpha::energy_gain`]).

use super::*;

impl GenAlpha {
    /// Energy gained by the step just solved, relative to its tolerance: the change of kinetic
    /// plus potential energy plus the energy dissipated minus the work put in (trapezoidal
    /// powers, as the state's balance books them). A passive step gains nothing, up to its
    /// truncation error (`O(h^3)`, like the position error, so the same step controller serves).
    ///
    /// Needed beside the position estimate: where positions are small against their scale (a
    /// contact penetration of 1e-7 m against atol 1e-9 m) the position weight admits relative
    /// errors of 1e-2 in the penetration, and an impact then returns up to several percent more
    /// energy than it took (an elastic 0.01 m/s impact with exponent 0.9 gained 6 %).
    ///
    /// The tolerance is `100 rtol` times the energy in play (kinetic and potential energy, work
    /// and dissipation of the step): the discrete energy of a second-order scheme fluctuates
    /// by more than `rtol` from step to step, and a tighter check (`10 rtol` was tried) keeps
    /// rejecting steps at tight tolerances (rtol 1e-11: 3.7 rejections per step, and a worse
    /// result from the step-size changes). With `100 rtol` the PanelLock runs take the same
    /// steps as without the check, and impacts at rtol 1e-6 gain at most 1.6e-4. The
    /// potential energy counts with its magnitude, zero level included: a scene with a large
    /// gravity potential (a lifted block) is checked loosely. Only passive steps (no work put
    /// in) that exchange potential energy are checked (see the code for why). If the steps keep
    /// gaining however small, the run stops with a message. Only growth rejects a step; the
    /// scheme's numerical damping (energy lost) never does. Speeds are not error-controlled
    /// themselves: on the index-3 form their estimate is polluted by the multipliers' transient
    /// on constrained bodies, and on free stiff structures (rope nodes) it would resolve the
    /// high frequencies the scheme is meant to damp (the RopeBlock lift took 19x the steps).
    pub(super) fn energy_gain(&mut self, sys: &mut System, st: &State, h: f64) -> f64 {
        let t1 = st.t + h;
        let drive = sys.drive_power(&self.lam);
        let (pd, pi) = sys.powers(t1, &self.q1, &self.v1);
        let pi = pi + drive;
        self.p_tried = Some((pd, pi));
        let (pd0, pi0) = self.p_prev;
        if pi0 != 0.0 || pi != 0.0 {
            // work put in (a driven joint, a motor): not a passive step, and the trapezoidal
            // input work (with index-3 multipliers in it) is no reference to check against
            return 0.0;
        }
        let (k0, u0) = match self.e_prev {
            Some(e) => e,
            None => {
                let e = sys.energy_with(st.t, &st.q, &st.v, &mut self.tmp);
                self.e_prev = Some(e);
                e
            }
        };
        let (k1, u1) = sys.energy_with(t1, &self.q1, &self.v1, &mut self.tmp);
        if u1 == u0 {
            // no potential energy exchanged (a free body): nothing for the check to add to the
            // position control
            return 0.0;
        }
        let dissipated = 0.5 * h * (pd0 + pd);
        let input = 0.5 * h * (pi0 + pi);
        let gain = (k1 + u1) - (k0 + u0) + dissipated - input;
        let in_play = k0.max(k1) + u0.abs().max(u1.abs()) + dissipated.abs() + input.abs();
        // round-off of the energy sums
        let floor = 1e3 * f64::EPSILON * (k0 + k1 + u0.abs() + u1.abs());
        let mut tol = 100.0 * self.core.s.rtol * in_play + floor;
        if gain > tol {
            // below the energy the tolerance resolves: the kinetic energy of moving by the
            // position weights per ERROR_TIME_UNIT (a scene nearly at rest, such as slack
            // slings without gravity with 1e-20 J in play, rejected every step for gains of
            // 1e-20 J, mostly the dissipation's quadrature)
            sys.mass_mul(&self.wx, &mut self.tmp);
            let resolution = 0.5
                * self
                    .wx
                    .iter()
                    .zip(&self.tmp)
                    .map(|(w, mw)| w * mw)
                    .sum::<f64>()
                / (crate::integrator::ERROR_TIME_UNIT * crate::integrator::ERROR_TIME_UNIT);
            tol += resolution;
        }
        if tol > 0.0 { gain / tol } else { 0.0 }
    }
}
