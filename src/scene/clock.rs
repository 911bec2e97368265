//! A model's clock: the importer's start time plus the time elapsed since the start.
//!
//! Importers compute communication steps differently: fmpy and Ecos pass the nominal step, while
//! libcosim keeps integer nanoseconds and passes differences of rounded points, which differ from
//! the nominal step by a few units in the last place. A solver that integrated exactly `h` would
//! end each step at a slightly different time and give results that differ between importers
//! (after impacts, far beyond round-off). The clock therefore snaps a step that is a whole number
//! of nanoseconds up to rounding (within 1e-3 ns) to exactly that number of nanoseconds, so every
//! importer asking for the same steps gets the same step ends, bit for bit. Other steps (1/3 s,
//! random step sequences) are taken as given. The scene's own time axis begins at 0, so a run
//! started at `t0` takes the same steps as one started at 0 (outputs shifted by `t0`).

use super::bytes::{ByteReader, ByteWriter};
use super::{ModelError, StepRequest};

/// Time resolution of the snapping [s]: a step within 1e-3 of a whole number of these is taken as
/// that whole number; steps below one are refused.
pub const RESOLUTION: f64 = 1e-9;

/// Start time and elapsed time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Clock {
    /// The importer's start time [s].
    start: f64,
    /// Time since the start [s]: the sum of the (snapped) steps taken.
    elapsed: f64,
    /// The model time the importer sees [s]: the start, then the end `t + h` of its last step
    /// as it computed it (so `fmi2GetRealStatus(lastSuccessfulTime)` equals its own point).
    now: f64,
}

/// One step as the clock takes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Elapsed time at the end [s].
    pub end: f64,
    /// The step taken [s] (snapped to whole nanoseconds where it is one up to rounding).
    pub h: f64,
    /// The importer's end point `t + h` [s].
    pub time: f64,
}

impl Clock {
    /// A clock at `start` [s] (any finite value).
    pub fn new(start: f64) -> Result<Self, ModelError> {
        if !start.is_finite() {
            return Err(ModelError::InvalidValue(format!(
                "start time {start} s must be finite"
            )));
        }
        Ok(Clock {
            start,
            elapsed: 0.0,
            now: start,
        })
    }

    /// Restores a clock from [`Clock::start`], [`Clock::elapsed`] and [`Clock::time`]
    /// (serialized states).
    pub fn restore(start: f64, elapsed: f64, now: f64) -> Result<Self, ModelError> {
        if !(start.is_finite() && elapsed.is_finite() && elapsed >= 0.0 && now.is_finite()) {
            return Err(ModelError::BadState(format!(
                "clock start {start} s / elapsed {elapsed} s / time {now} s is not a valid time"
            )));
        }
        // the importer's time and the scene's own axis differ by rounding only (a forged
        // elapsed time of 20000 s at t = 0.02 s made the next step integrate for 16 s CPU)
        if !same_time(start + elapsed, now) {
            return Err(ModelError::BadState(format!(
                "clock start {start} s + elapsed {elapsed} s does not match the time {now} s"
            )));
        }
        Ok(Clock {
            start,
            elapsed,
            now,
        })
    }

    /// The importer's start time [s].
    pub fn start(&self) -> f64 {
        self.start
    }

    /// Time since the start [s]: the scene's own time axis, which begins at 0.
    pub fn elapsed(&self) -> f64 {
        self.elapsed
    }

    /// The model time the importer sees [s].
    pub fn time(&self) -> f64 {
        self.now
    }

    /// The step the model takes for `request` (checked by [`super::check_step`] against this
    /// clock's time; see the module documentation).
    pub fn step(&self, request: StepRequest) -> Result<Step, ModelError> {
        let (t, h) = (request.t(), request.h());
        if h < RESOLUTION {
            return Err(ModelError::InvalidValue(format!(
                "communication step size {h} s is below the model's time resolution of 1 ns"
            )));
        }
        let ns = (h / RESOLUTION).round();
        let taken = if (h / RESOLUTION - ns).abs() <= 1e-3 && ns < 9.0e15 {
            ns / 1e9
        } else {
            h
        };
        let (end, time) = (self.elapsed + taken, t + h);
        if !(end.is_finite() && time.is_finite()) {
            return Err(ModelError::InvalidValue(format!(
                "the step from t = {t} s with h = {h} s ends beyond the model's time range"
            )));
        }
        Ok(Step {
            end,
            h: taken,
            time,
        })
    }

    /// Writes the clock into a serialized state (start, elapsed, time).
    pub fn write(&self, w: &mut ByteWriter) {
        w.f64(self.start);
        w.f64(self.elapsed);
        w.f64(self.now);
    }

    /// Reads what [`Clock::write`] wrote.
    pub fn read(r: &mut ByteReader) -> Result<Self, ModelError> {
        let start = r.finite_f64("start time")?;
        let elapsed = r.finite_f64("elapsed time")?;
        Clock::restore(start, elapsed, r.finite_f64("time")?)
    }

    /// Moves the clock to the end of `step` (after it completed).
    pub fn advance(&mut self, step: &Step) {
        self.elapsed = step.end;
        self.now = step.time;
    }

    /// Moves the clock to `elapsed` [s] inside a step that ended early (at an event): the
    /// importer's time is then `start + elapsed`, which it passes back as the next step's start.
    pub fn advance_early(&mut self, elapsed: f64) {
        self.elapsed = elapsed;
        self.now = self.start + elapsed;
    }
}

/// Relative tolerance of [`same_time`]: far above the rounding of importer time grids against
/// the accumulated elapsed time, far below any meaningful difference.
pub const TIME_CONSISTENCY_RTOL: f64 = 1e-6;

/// Two times [s] that agree within [`TIME_CONSISTENCY_RTOL`] relative to `max(1 s, |a|, |b|)`.
pub fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= TIME_CONSISTENCY_RTOL * 1f64.max(a.abs()).max(b.abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::check_step;

    /// The clock's step for a request checked as the FMI layer checks it.
    fn at(c: &Clock, t: f64, h: f64) -> Result<Step, ModelError> {
        c.step(check_step(c.time(), t, h)?)
    }

    #[test]
    fn importer_rounding_lands_on_the_same_step_ends() {
        let h = 0.01;
        let (mut multiplied, mut added, mut nanos) = (
            Clock::new(0.0).unwrap(),
            Clock::new(0.0).unwrap(),
            Clock::new(0.0).unwrap(),
        );
        let mut t_added = 0.0;
        let mut differed = 0;
        for k in 0..100_000i64 {
            // fmpy: t0 + k h; Ecos: accumulated t, nominal h; libcosim: nanosecond points
            let t_mul = k as f64 * h;
            let (t_ns, h_ns) = (k * 10_000_000, 10_000_000i64);
            let (t_lc, h_lc) = (
                t_ns as f64 / 1e9,
                (t_ns + h_ns) as f64 / 1e9 - t_ns as f64 / 1e9,
            );
            differed += usize::from(h_lc != h);
            let a = at(&multiplied, t_mul, h).unwrap();
            let b = at(&added, t_added, h).unwrap();
            let c = at(&nanos, t_lc, h_lc).unwrap();
            assert_eq!(
                (a.end.to_bits(), b.end.to_bits()),
                (c.end.to_bits(), c.end.to_bits()),
                "step {k}"
            );
            assert_eq!((a.h, b.h, c.h), (h, h, h), "step {k}");
            multiplied.advance(&a);
            added.advance(&b);
            nanos.advance(&c);
            t_added += h;
        }
        assert!(
            differed > 1000,
            "libcosim's steps differ from the nominal one: {differed}"
        );
        assert!((multiplied.elapsed() - 1000.0).abs() < 1e-9);
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
            let a = at(&zero, t, 0.05).unwrap();
            let b = at(&late, 1000.0 + t, 0.05).unwrap();
            let c = at(&early, -1.0 + t, 0.05).unwrap();
            assert_eq!(
                (a.end.to_bits(), b.end.to_bits()),
                (c.end.to_bits(), c.end.to_bits())
            );
            zero.advance(&a);
            late.advance(&b);
            early.advance(&c);
        }
        assert!((late.time() - 1250.0).abs() < 1e-9);
    }

    #[test]
    fn steps_of_no_whole_nanoseconds_are_taken_as_given() {
        let (mut c, mut t) = (Clock::new(0.0).unwrap(), 0.0);
        for h in [1.0 / 3.0, 0.123_456_789_012_3, 2e-4 / 3.0] {
            let step = at(&c, t, h).unwrap();
            assert_eq!((step.end, step.h, step.time), (t + h, h, t + h));
            c.advance(&step);
            t += h;
        }
    }

    #[test]
    fn refusals_name_the_cause() {
        let c = Clock::new(0.0).unwrap();
        assert!(Clock::new(f64::NAN).is_err());
        let e = at(&c, 0.0, 1e-10).unwrap_err().to_string();
        assert!(e.contains("resolution of 1 ns"), "{e}");
        let e = at(&c, 0.5, 0.1).unwrap_err().to_string();
        assert!(e.contains("does not match"), "{e}");
        assert!(Clock::restore(0.0, -1.0, 0.0).is_err());
    }
}
