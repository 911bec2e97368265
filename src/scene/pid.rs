//! `PidController`: a discrete-time PID controller with a filtered derivative and anti-windup.
//!
//! The controller is sampled once per communication step. At `do_step(t, h)` it reads the inputs
//! set at `t` (held constant over the step, zero-order hold) and returns, at `t + h`, the control
//! of the continuous-time law
//!
//! ```text
//! u = sat( kp*e + I + D ),   dI/dt = ki*e + (u - v)/Tt,   Tf*dD/dt + D = kd*dx/dt
//! ```
//!
//! with `e = setpoint - measurement`, `x = e` (or `x = -measurement` when
//! `d_on_measurement`), `v` the unsaturated output and `sat` the clamp to `[u_min, u_max]`.
//! Discretization over one step `h` [s] (Åström & Hägglund, *Advanced PID Control*, ch. 13):
//!
//! ```text
//! D    <- (Tf*D + kd*(x_k - x_{k-1})) / (Tf + h)     backward Euler: stable for every Tf >= 0,
//!                                                   a plain difference quotient when Tf = 0
//! I'   =  I + ki*h*e_k                               exact integral of the held error
//! v    =  kp*e_k + I' + D,   u = clamp(v, u_min, u_max)
//! I    <- I' + (1 - exp(-h/Tt))*(u - v)               back-calculation, exact first-order
//!                                                   tracking; Tt = 0 resets I at once
//! ```
//!
//! For a constant error the output is exactly `kp*e + ki*e*(t - t0)` at every communication
//! point, whatever the step sizes (no derivative kick at start: `x_{-1} = x_0`). Outputs change
//! only in `do_step` (no direct feedthrough): an input set at `t` acts in the step from `t`.

use std::sync::OnceLock;

use super::bytes::{ByteReader, ByteWriter};
use super::clock::Clock;
use super::param_spec::{Bounds, Range, RealSpec};
use super::port::{ModelInfo, PortSpec, ValueRef, Variability};
use super::store::PortStore;
use super::watch::{StepEnd, StepWatch};
use super::{CoSimModel, LogLevel, LogRecord, ModelError, StepRequest};

/// Version of the serialized state (2: the clock, start time and elapsed time; version 1
/// states stored the time, read as a start time).
const STATE_FORMAT: u32 = 2;

/// Model identifier (also the state tag).
pub const IDENTIFIER: &str = "PidController";

/// Real value references (the parameters take 0..=6, [`REAL_PARAMS`] in order; the tests set
/// them by these names).
mod vr {
    use super::ValueRef;
    #[cfg(test)]
    pub const KP: ValueRef = 0;
    #[cfg(test)]
    pub const KI: ValueRef = 1;
    #[cfg(test)]
    pub const KD: ValueRef = 2;
    #[cfg(test)]
    pub const TF: ValueRef = 3;
    #[cfg(test)]
    pub const TT: ValueRef = 4;
    #[cfg(test)]
    pub const U_MIN: ValueRef = 5;
    #[cfg(test)]
    pub const U_MAX: ValueRef = 6;
    pub const SETPOINT: ValueRef = 7;
    pub const MEASUREMENT: ValueRef = 8;
    pub const U: ValueRef = 9;
    pub const ERROR: ValueRef = 10;
    /// Boolean value references.
    pub const D_ON_MEASUREMENT: ValueRef = 0;
    pub const SATURATED: ValueRef = 1;
}

/// The PID variable table.
pub fn info() -> &'static ModelInfo {
    static INFO: OnceLock<ModelInfo> = OnceLock::new();
    INFO.get_or_init(|| {
        use Variability::Fixed;
        ModelInfo {
            identifier: IDENTIFIER,
            guid: "{d3273808-9b6c-429a-8343-c6d18db11dab}",
            description: "Discrete-time PID controller sampled at the communication step: filtered derivative (backward Euler), exact integral of the held error, output limits with back-calculation anti-windup.",
            ports: REAL_PARAMS.iter().enumerate().map(|(i, p)| p.port(i as ValueRef, &Params::default())).chain([
                PortSpec::boolean_parameter("d_on_measurement", vr::D_ON_MEASUREMENT, Fixed, false, "Derivative acts on minus the measurement instead of the error (no kick on setpoint steps)."),
                PortSpec::real_input("setpoint", vr::SETPOINT, 0.0, None, "Reference value the measurement should follow."),
                PortSpec::real_input("measurement", vr::MEASUREMENT, 0.0, None, "Measured value of the controlled quantity."),
                PortSpec::real_output("u", vr::U, None, "Control output, clamped to [u_min, u_max]."),
                PortSpec::real_output("error", vr::ERROR, None, "Control error setpoint - measurement at the last sample."),
                PortSpec::boolean_output("saturated", vr::SATURATED, "True while the output is clamped to one of its limits."),
            ]).collect(),
            default_stop_time: 10.0,
            default_step: 0.01,
            initial_dependencies,
        }
    })
}

/// What the outputs depend on in initialization mode: the first sample `u = kp e` clamped to
/// the limits, with `e = setpoint - measurement` (integral and derivative start at zero).
fn initial_dependencies(_: &ModelInfo, unknown: &PortSpec) -> Option<Vec<String>> {
    let names: &[&str] = match unknown.name.as_str() {
        "error" => &["setpoint", "measurement"],
        _ => &["kp", "u_min", "u_max", "setpoint", "measurement"],
    };
    Some(names.iter().map(|n| n.to_string()).collect())
}

/// A new PID controller at its default parameters.
pub fn create() -> Box<dyn CoSimModel> {
    Box::new(Pid::new())
}

/// Controller state between samples.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct PidState {
    /// Integral term `I` (output units).
    integral: f64,
    /// Filtered derivative term `D` (output units).
    derivative: f64,
    /// Derivative source `x` at the previous sample.
    x_prev: f64,
    /// Simulation time (start time and elapsed time; the sample interval `h` used in the update
    /// is the clock's step, snapped to whole nanoseconds, so importers that round the
    /// communication step differently in the last bits get the same controller output).
    clock: Clock,
}

/// The PID controller model.
#[derive(Debug, Clone)]
pub struct Pid {
    ports: PortStore,
    state: PidState,
    log: Vec<LogRecord>,
}

impl Default for Pid {
    fn default() -> Self {
        Self::new()
    }
}

/// Parameters read from the port store for one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Params {
    /// Proportional gain [output units per error unit].
    kp: f64,
    /// Integral gain [1/s].
    ki: f64,
    /// Derivative gain [s].
    kd: f64,
    /// Derivative filter time constant [s].
    tf: f64,
    /// Anti-windup tracking time constant [s].
    tt: f64,
    /// Output limits [output units].
    u_min: f64,
    u_max: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            kp: 1.0,
            ki: 0.5,
            kd: 0.0,
            tf: 0.01,
            tt: 0.1,
            u_min: -1.0e9,
            u_max: 1.0e9,
        }
    }
}

/// Any finite value.
const ANY: Bounds = Bounds::Fixed(Range::closed(None, None));
/// Finite and >= 0.
const NON_NEGATIVE: Bounds = Bounds::Fixed(Range::closed(Some(0.0), None));

macro_rules! pid_param {
    ($name:literal, $unit:expr, $bounds:expr, $desc:literal, $field:ident) => {
        RealSpec::new(
            $name,
            $unit,
            $bounds,
            $desc,
            |p: &Params| p.$field,
            |p: &mut Params, v| p.$field = v,
        )
        .tunable()
    };
}

const _: () = assert!(REAL_PARAMS.len() == vr::SETPOINT as usize);

/// Real parameters, value references 0.. in this order ([`vr`]).
static REAL_PARAMS: [RealSpec<Params>; 7] = [
    pid_param!(
        "kp",
        None,
        ANY,
        "Proportional gain (output units per error unit).",
        kp
    ),
    pid_param!(
        "ki",
        Some("1/s"),
        ANY,
        "Integral gain (output units per error unit and second).",
        ki
    ),
    pid_param!(
        "kd",
        Some("s"),
        ANY,
        "Derivative gain (output units per error unit per second of rate).",
        kd
    ),
    pid_param!(
        "Tf",
        Some("s"),
        NON_NEGATIVE,
        "Time constant of the first-order filter on the derivative; 0 gives a plain difference quotient.",
        tf
    ),
    pid_param!(
        "Tt",
        Some("s"),
        NON_NEGATIVE,
        "Anti-windup tracking time constant: how fast the integral follows the saturated output; 0 resets it at once.",
        tt
    ),
    pid_param!(
        "u_min",
        None,
        ANY,
        "Lower output limit (must not exceed u_max).",
        u_min
    ),
    pid_param!(
        "u_max",
        None,
        ANY,
        "Upper output limit (must not be below u_min).",
        u_max
    ),
];

impl Pid {
    /// A controller at its default parameters, not initialized.
    pub fn new() -> Self {
        Self {
            ports: PortStore::new(info()),
            state: PidState::default(),
            log: Vec::new(),
        }
    }

    fn params(&self) -> Result<Params, ModelError> {
        let mut p = Params::default();
        for (i, spec) in REAL_PARAMS.iter().enumerate() {
            (spec.set)(&mut p, self.ports.get_real(i as ValueRef)?);
        }
        if p.u_min > p.u_max {
            return Err(ModelError::InvalidValue(format!(
                "u_min = {} exceeds u_max = {}: set u_min <= u_max",
                p.u_min, p.u_max
            )));
        }
        Ok(p)
    }

    /// Error `e` and derivative source `x` from the current inputs.
    fn sample(&self) -> Result<(f64, f64), ModelError> {
        let sp = self.ports.get_real(vr::SETPOINT)?;
        let y = self.ports.get_real(vr::MEASUREMENT)?;
        let x = if self.ports.get_boolean(vr::D_ON_MEASUREMENT)? {
            -y
        } else {
            sp - y
        };
        let e = sp - y;
        if !e.is_finite() {
            return Err(ModelError::InvalidValue(format!(
                "the control error setpoint - measurement = {sp} - ({y}) overflows; scale the signals"
            )));
        }
        Ok((e, x))
    }

    /// Clamps `v`, publishes the outputs and logs saturation changes; returns the clamped output.
    fn publish(&mut self, p: &Params, v: f64, e: f64) -> Result<f64, ModelError> {
        if !v.is_finite() {
            return Err(ModelError::SolverFailure(format!(
                "t = {} s: the controller output is not finite ({v}, error {e}); reduce the gains or scale the signals",
                self.state.clock.time()
            )));
        }
        let u = v.clamp(p.u_min, p.u_max);
        let saturated = u != v;
        if saturated != self.ports.get_boolean(vr::SATURATED)? {
            let message = if saturated {
                format!(
                    "t = {} s: output saturated at {u} (unsaturated {v})",
                    self.state.clock.time()
                )
            } else {
                format!(
                    "t = {} s: output left saturation ({u})",
                    self.state.clock.time()
                )
            };
            self.log.push(LogRecord {
                level: LogLevel::Event,
                message,
            });
        }
        self.ports.put_real(vr::U, u)?;
        self.ports.put_real(vr::ERROR, e)?;
        self.ports.put_boolean(vr::SATURATED, saturated)?;
        Ok(u)
    }

    fn read_state(&self, bytes: &[u8]) -> Result<Pid, ModelError> {
        let mut r = ByteReader::new(bytes);
        let version = r.header(IDENTIFIER, STATE_FORMAT)?;
        let ports = self.ports.read(&mut r)?;
        let (integral, derivative, x_prev) = (
            r.f64("integral term")?,
            r.f64("derivative term")?,
            r.f64("previous derivative source")?,
        );
        let clock = if version >= 2 {
            Clock::read(&mut r)?
        } else {
            let time = r.finite_f64("time")?;
            Clock::restore(time, 0.0, time)?
        };
        let state = PidState {
            integral,
            derivative,
            x_prev,
            clock,
        };
        r.finish()?;
        Ok(Pid {
            ports,
            state,
            log: Vec::new(),
        })
    }
}

impl CoSimModel for Pid {
    fn ports(&self) -> &PortStore {
        &self.ports
    }
    fn ports_mut(&mut self) -> &mut PortStore {
        &mut self.ports
    }

    fn set_up(&mut self, t_start: f64) -> Result<(), ModelError> {
        if !t_start.is_finite() {
            return Err(ModelError::InvalidValue(format!(
                "start time {t_start} must be finite"
            )));
        }
        let p = self.params()?;
        let (e, x) = self.sample()?;
        self.state = PidState {
            integral: 0.0,
            derivative: 0.0,
            x_prev: x,
            clock: Clock::new(t_start)?,
        };
        self.publish(&p, p.kp * e, e)?;
        Ok(())
    }

    fn do_step_watched(
        &mut self,
        request: StepRequest,
        _watch: &mut dyn StepWatch,
    ) -> Result<StepEnd, ModelError> {
        let step = self.state.clock.step(request)?;
        let h = step.h;
        let p = self.params()?;
        let (e, x) = self.sample()?;
        let s = &mut self.state;
        s.derivative = (p.tf * s.derivative + p.kd * (x - s.x_prev)) / (p.tf + h);
        s.x_prev = x;
        let integral = s.integral + p.ki * h * e;
        let v = p.kp * e + integral + s.derivative;
        s.clock.advance(&step);
        let u = self.publish(&p, v, e)?;
        let tracking = if p.tt > 0.0 {
            -(-h / p.tt).exp_m1()
        } else {
            1.0
        };
        self.state.integral = integral + tracking * (u - v);
        if !(u.is_finite() && self.state.integral.is_finite() && self.state.derivative.is_finite())
        {
            return Err(ModelError::SolverFailure(format!(
                "t = {} s: the controller state overflowed (u = {u}); reduce the gains",
                self.state.clock.time()
            )));
        }
        Ok(StepEnd::Complete)
    }

    fn time(&self) -> f64 {
        self.state.clock.time()
    }

    fn clone_box(&self) -> Box<dyn CoSimModel> {
        Box::new(self.clone())
    }

    fn serialize(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.header(IDENTIFIER, STATE_FORMAT);
        self.ports.write(&mut w);
        let s = &self.state;
        for v in [s.integral, s.derivative, s.x_prev] {
            w.f64(v);
        }
        s.clock.write(&mut w);
        w.into_bytes()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        *self = self.read_state(bytes)?;
        Ok(())
    }

    fn reset(&mut self) {
        *self = Pid::new();
    }

    fn take_log(&mut self) -> Vec<LogRecord> {
        std::mem::take(&mut self.log)
    }
}

#[cfg(test)]
#[path = "pid_tests.rs"]
mod tests;
