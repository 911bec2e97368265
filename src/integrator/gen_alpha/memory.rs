//! Generalized-alpha's serialized memory (the step size, powers, pseudo-accelerations and
//! the Newton matrix's point) and monitors, for `Integrator::memory` and its kin.

use super::*;

impl GenAlpha {
    pub(super) fn write_memory(&self) -> Vec<f64> {
        let mut m = vec![
            self.core.h,
            self.p_prev.0,
            self.p_prev.1,
            self.a.len() as f64,
        ];
        m.extend_from_slice(&self.a);
        // the matrix point: the valid one, or a restored one not formed again yet
        JacobianPoint::write_matrix_point(
            &self.jac_point,
            self.core.jac_valid,
            &self.pending,
            &mut m,
        );
        m
    }

    pub(super) fn read_memory(&mut self, m: &[f64]) -> Result<(), String> {
        let bad = || "gen-alpha memory is truncated or corrupt".to_string();
        if m.len() < 5 || !(m[3].is_finite() && m[3] >= 0.0) {
            return Err(bad());
        }
        let na = m[3] as usize;
        if m.len() < 5 + na {
            return Err(bad());
        }
        if !(m[0].is_finite() && m[0] >= 0.0) {
            return Err(bad());
        }
        self.core.h = m[0];
        self.p_prev = (m[1], m[2]);
        self.e_prev = None;
        self.p_tried = None;
        self.a = m[4..4 + na].to_vec();
        self.pending = if m[4 + na] > 0.5 {
            Some(JacobianPoint::read(&m[5 + na..])?.0)
        } else {
            None
        };
        self.core.jac_valid = false;
        self.jac_point = None;
        Ok(())
    }

    pub(super) fn write_monitors(&self) -> Vec<f64> {
        let point =
            JacobianPoint::restore_point(&self.jac_point, self.core.jac_valid, &self.pending);
        crate::integrator::write_monitors(&[&self.rank], &self.lin, point)
    }

    pub(super) fn read_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        crate::integrator::read_monitors(
            m,
            &mut [&mut self.rank],
            &mut self.lin,
            self.pending.as_mut(),
        )
    }
}
