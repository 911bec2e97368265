//! `SpringMassDamper`'s binding: variable table, parameters, the co-simulation calls and the
//! state bytes. Everything here is what a model on the solver needs besides its physics
//! ([`super`]); the framework supplies the rest (port rules: [`PortStore`]; the step check:
//! [`crate::scene::check_step`]; the step clock: [`Clock`]; the solver knobs:
//! [`solver`]; the simulation's bytes: [`sim_state`]).

use std::sync::OnceLock;

use super::{Oscillator, Params};
use crate::scene::bytes::{ByteReader, ByteWriter};
use crate::scene::clock::Clock;
use crate::scene::param_spec::{Bounds, Range, RealSpec, SolverKnobs, solver};
use crate::scene::port::{ModelInfo, PortSpec, ValueRef};
use crate::scene::store::PortStore;
use crate::scene::watch::{StepEnd, StepWatch};
use crate::scene::{CoSimModel, LogRecord, ModelError, StepRequest, sim_state};

/// Model identifier (also the state tag).
pub const IDENTIFIER: &str = "SpringMassDamper";
/// Version of the serialized state.
const STATE_FORMAT: u32 = 1;

/// Value references: the parameters take `0..PARAMS.len()` in [`PARAMS`]' order.
const FORCE: ValueRef = 8;
/// `x`, `v`, `a`, `spring_force`.
const OUTPUTS: [ValueRef; 4] = [9, 10, 11, 12];

impl SolverKnobs for Params {
    fn knobs(&self) -> [f64; 3] {
        [self.rtol, self.atol, self.h_max]
    }
    fn knobs_mut(&mut self) -> [&mut f64; 3] {
        [&mut self.rtol, &mut self.atol, &mut self.h_max]
    }
}

/// `[lo, hi]`.
const fn within(lo: f64, hi: f64) -> Bounds {
    Bounds::Fixed(Range::closed(Some(lo), Some(hi)))
}

macro_rules! param {
    ($name:literal, $unit:literal, $bounds:expr, $desc:literal, $field:ident) => {
        RealSpec::new(
            $name,
            Some($unit),
            $bounds,
            $desc,
            |p: &Params| p.$field,
            |p: &mut Params, v| p.$field = v,
        )
    };
}

/// Real parameters, value references 0.. in this order. The ranges keep DOPRI5 out of
/// stiffness (`c/m <= 500 1/s`, `sqrt(k/m) <= 316 rad/s`) and the spring longer than zero.
static PARAMS: [RealSpec<Params>; 8] = [
    param!("m", "kg", within(0.1, 100.0), "Mass.", m),
    param!("k", "N/m", within(1.0, 1.0e4), "Spring stiffness.", k),
    param!("c", "N.s/m", within(0.0, 50.0), "Damping coefficient.", c),
    param!("x0", "m", within(-1.0, 1.0), "Initial displacement.", x0),
    param!("v0", "m/s", within(-10.0, 10.0), "Initial velocity.", v0),
    solver::rtol(),
    solver::atol(),
    solver::h_max(),
];

const _: () = assert!(PARAMS.len() == FORCE as usize);

/// The variable table.
pub fn info() -> &'static ModelInfo {
    static INFO: OnceLock<ModelInfo> = OnceLock::new();
    INFO.get_or_init(|| {
        let d = Params::default();
        let params = PARAMS.iter().zip(0..).map(|(p, vr)| p.port(vr, &d));
        let outputs = [
            ("x", "m", "Displacement from the spring's free length."),
            ("v", "m/s", "Velocity."),
            ("a", "m/s2", "Acceleration (F - c v - k x) / m."),
            ("spring_force", "N", "Force of the spring and damper on the mass, -k x - c v."),
        ];
        let outputs = outputs
            .iter()
            .zip(OUTPUTS)
            .map(|((n, u, s), vr)| PortSpec::real_output(n, vr, Some(u), s));
        let force = PortSpec::real_input("F", FORCE, 0.0, Some("N"), "Force on the mass, held over each communication step.");
        ModelInfo {
            identifier: IDENTIFIER,
            guid: "{2cf7553d-8235-494e-a966-408337f98079}",
            description: "Mass on a linear spring and damper, pushed by an input force, integrated by the multibody solver (DOPRI5): m x'' + c x' + k x = F.",
            ports: params.chain([force]).chain(outputs).collect(),
            default_stop_time: 5.0,
            default_step: 0.01,
            initial_dependencies,
        }
    })
}

/// What the outputs depend on in initialization mode: `x = x0`, `v = v0`, the spring force
/// `-k x0 - c v0` and the acceleration `(F - k x0 - c v0) / m`.
fn initial_dependencies(_: &ModelInfo, unknown: &PortSpec) -> Option<Vec<String>> {
    let names: &[&str] = match unknown.name.as_str() {
        "x" => &["x0"],
        "v" => &["v0"],
        "spring_force" => &["k", "c", "x0", "v0"],
        _ => &["m", "k", "c", "x0", "v0", "F"],
    };
    Some(names.iter().map(|n| n.to_string()).collect())
}

/// A new oscillator at its default parameters.
pub fn create() -> Box<dyn CoSimModel> {
    Box::new(Model::new())
}

/// The co-simulation model.
#[derive(Debug, Clone)]
pub struct Model {
    ports: PortStore,
    clock: Clock,
    /// `None` before initialization.
    run: Option<Oscillator>,
}

impl Model {
    fn new() -> Self {
        Model {
            ports: PortStore::new(info()),
            clock: Clock::default(),
            run: None,
        }
    }

    fn params(&self) -> Result<Params, ModelError> {
        let mut p = Params::default();
        for (spec, vr) in PARAMS.iter().zip(0..) {
            (spec.set)(&mut p, self.ports.get_real(vr)?);
        }
        Ok(p)
    }

    fn run(&mut self) -> Result<&mut Oscillator, ModelError> {
        self.run
            .as_mut()
            .ok_or_else(|| ModelError::NotAllowed("SpringMassDamper is not initialized".into()))
    }

    fn publish(&mut self) -> Result<(), ModelError> {
        let out = self.run()?.outputs();
        for (vr, v) in OUTPUTS.into_iter().zip(out) {
            self.ports.put_real(vr, v)?;
        }
        Ok(())
    }
}

impl CoSimModel for Model {
    fn ports(&self) -> &PortStore {
        &self.ports
    }
    fn ports_mut(&mut self) -> &mut PortStore {
        &mut self.ports
    }

    fn set_up(&mut self, t_start: f64) -> Result<(), ModelError> {
        let force = self.ports.get_real(FORCE)?;
        self.clock = Clock::new(t_start)?;
        let run = Oscillator::new(&self.params()?, force).map_err(ModelError::InvalidValue)?;
        self.run = Some(run);
        self.publish()?;
        Ok(())
    }

    fn do_step_watched(
        &mut self,
        request: StepRequest,
        _watch: &mut dyn StepWatch,
    ) -> Result<StepEnd, ModelError> {
        let step = self.clock.step(request)?;
        let force = self.ports.get_real(FORCE)?;
        let run = self.run()?;
        run.set_force(force).map_err(ModelError::InvalidValue)?;
        run.advance_to(step.end)
            .map_err(|e| ModelError::SolverFailure(format!("SpringMassDamper: {e}")))?;
        self.clock.advance(&step);
        self.publish()?;
        Ok(StepEnd::Complete)
    }

    fn time(&self) -> f64 {
        self.clock.time()
    }

    fn clone_box(&self) -> Box<dyn CoSimModel> {
        Box::new(self.clone())
    }

    fn serialize(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.header(IDENTIFIER, STATE_FORMAT);
        self.ports.write(&mut w);
        self.clock.write(&mut w);
        w.bool(self.run.is_some());
        if let Some(run) = &self.run {
            sim_state::write(&mut w, &run.sim);
        }
        w.into_bytes()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let mut r = ByteReader::new(bytes);
        r.header(IDENTIFIER, STATE_FORMAT)?;
        let mut restored = Model {
            ports: self.ports.read(&mut r)?,
            clock: Clock::read(&mut r)?,
            run: None,
        };
        if r.bool("initialized")? {
            let p = restored.params()?;
            let mut run = Oscillator::new(&p, 0.0).map_err(ModelError::BadState)?;
            sim_state::read(&mut r, &mut run.sim, restored.clock.elapsed())?;
            restored.run = Some(run);
        }
        r.finish()?;
        *self = restored;
        Ok(())
    }

    fn reset(&mut self) {
        *self = Model::new();
    }

    fn take_log(&mut self) -> Vec<LogRecord> {
        Vec::new()
    }

    fn solver_stats(&self) -> Option<crate::integrator::Stats> {
        self.run.as_ref().map(|r| r.sim.stats())
    }
}
