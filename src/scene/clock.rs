//! A model's clock: the importer's start time plus whole nanoseconds since the start.
//!
//! Importers compute communication points differently: fmpy multiplies (`t0 + k h`), Ecos adds
//! the nominal step, libcosim keeps integer nanoseconds and passes the differences. The points
//! then differ by a few units in the last place, and a solver that integrated to exactly
//! `t + h` would end each step at a slightly different time and give results that differ
//! between importers (after impacts, far beyond round-off). The clock therefore ends each step at
//! the clock time plus the step size rounded to whole nanoseconds, so every importer asking for
//! the same steps (within half a nanosecond each) gets the same step ends, bit for bit, and a
//! run started at `t0` takes the same steps as one started at 0 (outputs shifted by `t0`).
//! Where the importer's points drift from the clock by more than half the matching tolerance
//! (steps that are not whole nanoseconds, e.g. 1/3 s), the end is taken from the importer's
//! point `t + h` instead, so the clock follows the importer.

use super::{ModelError, TIME_RTOL, check_step};

/// Time resolution of the clock [s].
pub const RESOLUTION: f64 = 1e-9;

/// Start time and elapsed nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Clock {
    /// The importer's start time [s].
    start: f64,
    /// Whole nanoseconds since the start.
    ticks: i64,
}

impl Clock {
    /// A clock at `start` [s] (any finite value).
    pub fn new(start: f64) -> Result<Self, ModelError> {
        if !start.is_finite() {
            return Err(ModelError::InvalidValue(format!(
                "start time {start} s must be finite"
            )));
        }
        Ok(Clock { start, ticks: 0 })
    }

    /// Restores a clock from [`Clock::start`] and [`Clock::ticks`] (serialized states).
    pub fn restore(start: f64, ticks: i64) -> Result<Self, ModelError> {
        if !start.is_finite() || ticks < 0 {
            return Err(ModelError::BadState(format!(
                "clock start {start} s / {ticks} ns is not a valid time"
            )));
        }
        Ok(Clock { start, ticks })
    }

    /// The importer's start time [s].
    pub fn start(&self) -> f64 {
        self.start
    }

    /// Whole nanoseconds since the start.
    pub fn ticks(&self) -> i64 {
        self.ticks
    }

    /// Time since the start [s]: the scene's own time axis, which begins at 0.
    pub fn elapsed(&self) -> f64 {
        self.ticks as f64 / 1e9
    }

    /// The model time the importer sees [s].
    pub fn time(&self) -> f64 {
        self.start + self.elapsed()
    }

    /// Checks a step request from `t` over `h` [s] (see [`check_step`]) and returns the step's
    /// end in nanoseconds since the start (see the module documentation).
    pub fn step_end(&self, t: f64, h: f64) -> Result<i64, ModelError> {
        check_step(self.time(), t, h)?;
        let from_step = self.ticks as f64 + (h / RESOLUTION).round();
        let from_point = ((t - self.start + h) / RESOLUTION).round();
        let drift_limit = 0.5 * TIME_RTOL * 1f64.max(t.abs()) / RESOLUTION;
        let end = if (from_step - from_point).abs() <= drift_limit {
            from_step
        } else {
            from_point
        };
        if !(end.is_finite() && end < 9.0e18) {
            return Err(ModelError::InvalidValue(format!(
                "the step from t = {t} s with h = {h} s ends beyond the model's time range"
            )));
        }
        let end = end as i64;
        if end <= self.ticks {
            return Err(ModelError::InvalidValue(format!(
                "communication step size {h} s is below the model's time resolution of 1 ns"
            )));
        }
        Ok(end)
    }

    /// Moves the clock to `ticks` nanoseconds since the start (after a completed step).
    pub fn advance_to(&mut self, ticks: i64) {
        self.ticks = ticks;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn importer_rounding_lands_on_the_same_step_ends() {
        let h = 0.01;
        let (mut multiplied, mut added, mut nanos) = (
            Clock::new(0.0).unwrap(),
            Clock::new(0.0).unwrap(),
            Clock::new(0.0).unwrap(),
        );
        let mut t_added = 0.0;
        for k in 0..100_000i64 {
            let t_mul = k as f64 * h;
            let (t_ns, h_ns) = (k * 10_000_000, 10_000_000i64);
            let a = multiplied.step_end(t_mul, h).unwrap();
            let b = added.step_end(t_added, h).unwrap();
            let c = nanos
                .step_end(
                    t_ns as f64 / 1e9,
                    ((t_ns + h_ns) as f64 - t_ns as f64) / 1e9,
                )
                .unwrap();
            assert_eq!((a, b), (c, c), "step {k}");
            multiplied.advance_to(a);
            added.advance_to(b);
            nanos.advance_to(c);
            t_added += h;
        }
        assert_eq!(multiplied.elapsed(), 1000.0);
        assert!(
            (t_added - 1000.0f64).abs() > 5e-10,
            "the added points drifted"
        );
    }

    #[test]
    fn steps_of_no_whole_nanoseconds_follow_the_importer() {
        let (mut c, h) = (Clock::new(1000.0).unwrap(), 1.0 / 3.0);
        for k in 0..300_000 {
            let t = 1000.0 + k as f64 * h;
            let end = c.step_end(t, h).unwrap();
            c.advance_to(end);
        }
        let limit = 0.5 * TIME_RTOL * c.time() + 2.0 * RESOLUTION;
        assert!((c.time() - 101_000.0).abs() < limit, "{}", c.time());
    }

    #[test]
    fn a_shifted_start_takes_the_same_steps() {
        let (mut zero, mut late, mut early) = (
            Clock::new(0.0).unwrap(),
            Clock::new(1000.0).unwrap(),
            Clock::new(-1.0).unwrap(),
        );
        for k in 0..5000 {
            let t = k as f64 * 0.05;
            let a = zero.step_end(t, 0.05).unwrap();
            let b = late.step_end(1000.0 + t, 0.05).unwrap();
            let c = early.step_end(-1.0 + t, 0.05).unwrap();
            assert_eq!((a, b), (c, c));
            zero.advance_to(a);
            late.advance_to(b);
            early.advance_to(c);
        }
        assert_eq!(late.time(), 1250.0);
    }

    #[test]
    fn refusals_name_the_cause() {
        let c = Clock::new(0.0).unwrap();
        assert!(Clock::new(f64::NAN).is_err());
        let e = c.step_end(0.0, 1e-10).unwrap_err().to_string();
        assert!(e.contains("resolution of 1 ns"), "{e}");
        let e = c.step_end(0.5, 0.1).unwrap_err().to_string();
        assert!(e.contains("does not match"), "{e}");
        let e = c.step_end(0.0, 1e300).unwrap_err().to_string();
        assert!(e.contains("time range"), "{e}");
        assert!(Clock::restore(0.0, -1).is_err());
    }
}
