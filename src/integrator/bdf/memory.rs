//! BDF's serialized memory (step size, order, history, multipliers, the Newton matrix's
//! point) and monitors, for `Integrator::memory` and its kin.

use super::*;

impl Bdf {
    pub(super) fn write_memory(&self) -> Vec<f64> {
        let mut m = vec![
            self.core.h,
            self.order as f64,
            self.steps_at_order as f64,
            self.since_start as f64,
            self.hist.len() as f64,
        ];
        for p in &self.hist {
            m.push(p.t);
            m.push(p.q.len() as f64);
            m.extend_from_slice(&p.q);
            m.push(p.v.len() as f64);
            m.extend_from_slice(&p.v);
            m.extend_from_slice(&p.z);
        }
        m.push(self.lam.len() as f64);
        m.extend_from_slice(&self.lam);
        // the matrix point: the valid one, or a restored one not formed again yet
        JacobianPoint::write_matrix_point(
            &self.jac_point,
            self.core.jac_valid,
            &self.pending,
            &mut m,
        );
        // optional (states written before it have none): the previous multipliers
        if let Some((t, l)) = &self.lam_prev {
            m.push(*t);
            m.push(l.len() as f64);
            m.extend_from_slice(l);
        }
        m
    }

    pub(super) fn read_memory(&mut self, m: &[f64]) -> Result<(), String> {
        let bad = || "bdf memory is truncated or corrupt".to_string();
        let mut pos = 0usize;
        let next = |pos: &mut usize| -> Result<f64, String> {
            let v = *m.get(*pos).ok_or_else(bad)?;
            *pos += 1;
            Ok(v)
        };
        // a length of what follows: at most what is left
        let count = |x: f64| {
            if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= m.len() as f64 {
                Ok(x as usize)
            } else {
                Err(bad())
            }
        };
        // a step counter: any whole number up to 2^53 (not bounded by the memory's length)
        let counter = |x: f64| {
            if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= 9.007_199_254_740_992e15 {
                Ok(x as usize)
            } else {
                Err(bad())
            }
        };
        let h = next(&mut pos)?;
        let order = count(next(&mut pos)?)?;
        let sao = counter(next(&mut pos)?)?;
        let since = counter(next(&mut pos)?)?;
        let n = count(next(&mut pos)?)?;
        if !(1..=5).contains(&order) || n > 7 || !(h.is_finite() && h > 0.0) {
            return Err(bad());
        }
        let mut hist = VecDeque::new();
        for _ in 0..n {
            let t = next(&mut pos)?;
            let nq = count(next(&mut pos)?)?;
            let q = (0..nq)
                .map(|_| next(&mut pos))
                .collect::<Result<Vec<_>, _>>()?;
            let nv = count(next(&mut pos)?)?;
            let v = (0..nv)
                .map(|_| next(&mut pos))
                .collect::<Result<Vec<_>, _>>()?;
            let z = [next(&mut pos)?, next(&mut pos)?];
            hist.push_back(Point { t, q, v, z });
        }
        let nl = count(next(&mut pos)?)?;
        let lam = (0..nl)
            .map(|_| next(&mut pos))
            .collect::<Result<Vec<_>, _>>()?;
        let has_jac = next(&mut pos)? > 0.5;
        self.pending = if has_jac {
            let (p, used) = JacobianPoint::read(&m[pos..])?;
            pos += used;
            Some(p)
        } else {
            None
        };
        let lam_prev = if pos < m.len() {
            let t = next(&mut pos)?;
            let n = count(next(&mut pos)?)?;
            let l = (0..n)
                .map(|_| next(&mut pos))
                .collect::<Result<Vec<_>, _>>()?;
            Some((t, l))
        } else {
            None
        };
        self.core.h = h;
        self.order = order;
        self.steps_at_order = sao;
        self.since_start = since;
        self.lam_last = (hist.front().map_or(0.0, |p| p.t), lam.clone());
        self.lam_prev = lam_prev;
        self.hist = hist;
        self.lam = lam;
        self.core.jac_valid = false;
        self.jac_point = None;
        Ok(())
    }

    pub(super) fn write_monitors(&self) -> Vec<f64> {
        let point =
            JacobianPoint::restore_point(&self.jac_point, self.core.jac_valid, &self.pending);
        crate::integrator::write_monitors(&[&self.rank, &self.rows], &self.lin, point)
    }

    pub(super) fn read_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        crate::integrator::read_monitors(
            m,
            &mut [&mut self.rank, &mut self.rows],
            &mut self.lin,
            self.pending.as_mut(),
        )
    }
}
