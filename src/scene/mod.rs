//! Scenes: models assembled from bodies, joints, forces and contacts, each exposing named ports.
//!
//! [`CoSimModel`] is the interface the FMI wrapper (`crate::fmi`) drives; it knows nothing of FMI
//! itself. A model receives parameter and input values by value reference, is initialized, and
//! then advanced in communication steps. Its whole state can be cloned (FMU state get/set) and
//! serialized to a versioned, pointer-free byte format.
//!
//! Helpers every model reuses: [`store::PortStore`] (port values with the importer-facing
//! rules), [`bytes::ByteWriter`] / [`bytes::ByteReader`] (state serialization) and
//! [`check_step`] (communication-point checks).
//!
//! # Adding a model
//! 1. Write `src/scene/<name>.rs` with `info()` (the variable table, a [`ModelInfo`] in a
//!    `OnceLock`), `create()` and a type implementing [`CoSimModel`]; [`pid`] is a small example.
//! 2. Add `ModelEntry::new(<name>::info, <name>::create)` to [`registry()`].
//! 3. Regenerate the checked-in descriptions (`cargo run --release --bin mbcosim --
//!    model-descriptions`) and pack (`... -- pack`).

pub mod bytes;
pub mod choice;
pub mod clock;
pub mod native;
pub mod panel_lock;
pub mod param_spec;
pub mod pid;
pub mod port;
pub mod power_port;
pub mod rope_block;
pub mod scene_file;
pub mod sim_state;
pub mod spring_mass_damper;
pub mod store;
pub mod view;
pub mod watch;

use port::{ModelInfo, ValueRef};

/// Severity of a message a model wants logged.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogLevel {
    /// Events such as a lock-up or a contact node being inserted.
    Event,
    /// Solver statistics and step-size decisions.
    Solver,
    /// Something the user should look at, the run continues.
    Warning,
    /// The run cannot continue.
    Error,
}

/// A message a model emits for the importer's logger.
#[derive(Debug, Clone, PartialEq)]
pub struct LogRecord {
    /// How severe the message is (selects the log category).
    pub level: LogLevel,
    /// The text, naming the cause and the value to change where it helps.
    pub message: String,
}

/// Why a model call failed. The text names the cause and, where it helps, the value to change.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelError {
    /// A value reference the model does not have, or of another type.
    UnknownValueRef(ValueRef),
    /// A value outside what the model accepts (NaN, negative mass, ...).
    InvalidValue(String),
    /// A call that is not allowed now (e.g. setting a fixed parameter after initialization).
    NotAllowed(String),
    /// The solver could not continue; the message says why and which parameter to change.
    SolverFailure(String),
    /// A corrupt or foreign serialized state.
    BadState(String),
}

impl std::fmt::Display for ModelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelError::UnknownValueRef(vr) => write!(f, "unknown value reference {vr}"),
            ModelError::InvalidValue(m)
            | ModelError::NotAllowed(m)
            | ModelError::SolverFailure(m)
            | ModelError::BadState(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ModelError {}

/// A co-simulation model: ports in, ports out, advanced in communication steps.
///
/// Call order: `set_*` (parameters, inputs) -> [`CoSimModel::initialize`] -> repeated
/// (`set_*` inputs, [`CoSimModel::do_step`], `get_*`). Fixed parameters may only be set before
/// `initialize`; the model refuses them afterwards.
///
/// Outputs are computed in `initialize` and `do_step` only: an input set at a communication
/// point acts during the next step and does not change the outputs read at that point (no direct
/// feedthrough; the model description declares outputs as depending on no input).
pub trait CoSimModel: Send {
    /// The port values (parameters, inputs, outputs) with their rules; the getters and setters
    /// below forward to it unless a model needs more (e.g. an input that acts at once).
    fn ports(&self) -> &store::PortStore;
    /// Mutable access to [`CoSimModel::ports`].
    fn ports_mut(&mut self) -> &mut store::PortStore;

    /// The model's static description and variable table.
    fn info(&self) -> &'static ModelInfo {
        self.ports().info()
    }

    /// Sets a real parameter or input (SI unit of the port); [`store::PortStore::set_real`]
    /// implements the rules.
    fn set_real(&mut self, vr: ValueRef, value: f64) -> Result<(), ModelError> {
        self.ports_mut().set_real(vr, value)
    }
    /// Current value of any real port (SI unit of the port).
    fn get_real(&self, vr: ValueRef) -> Result<f64, ModelError> {
        self.ports().get_real(vr)
    }
    /// Sets an integer or enumeration parameter or input.
    fn set_integer(&mut self, vr: ValueRef, value: i32) -> Result<(), ModelError> {
        self.ports_mut().set_integer(vr, value)
    }
    /// Current value of any integer or enumeration port.
    fn get_integer(&self, vr: ValueRef) -> Result<i32, ModelError> {
        self.ports().get_integer(vr)
    }
    /// Sets a boolean parameter or input.
    fn set_boolean(&mut self, vr: ValueRef, value: bool) -> Result<(), ModelError> {
        self.ports_mut().set_boolean(vr, value)
    }
    /// Current value of any boolean port.
    fn get_boolean(&self, vr: ValueRef) -> Result<bool, ModelError> {
        self.ports().get_boolean(vr)
    }
    /// Sets a string parameter or input.
    fn set_string(&mut self, vr: ValueRef, value: &str) -> Result<(), ModelError> {
        self.ports_mut().set_string(vr, value)
    }
    /// Current value of any string port.
    fn get_string(&self, vr: ValueRef) -> Result<String, ModelError> {
        self.ports().get_string(vr)
    }

    /// Builds the system from the parameters and finds consistent initial conditions at
    /// `t_start` [s]; once only (the lifecycle guard of every model): refused when the ports are
    /// already initialized, and on success the fixed parameters are frozen
    /// ([`PortStore::mark_initialized`]). The model's own part is [`CoSimModel::set_up`].
    fn initialize(&mut self, t_start: f64) -> Result<(), ModelError> {
        if self.ports().is_initialized() {
            return Err(ModelError::NotAllowed(
                "the model is already initialized (reset it to initialize again)".into(),
            ));
        }
        self.set_up(t_start)?;
        self.ports_mut().mark_initialized();
        Ok(())
    }

    /// The model's part of [`CoSimModel::initialize`]: builds the system from the parameters
    /// and finds consistent initial conditions at `t_start` [s]. Called once, on ports not yet
    /// initialized; the caller marks them initialized after it succeeds.
    fn set_up(&mut self, t_start: f64) -> Result<(), ModelError>;

    /// The checked request to step from `t` over `h` [s]: refused before
    /// [`CoSimModel::initialize`] (the lifecycle guard of every model), then [`check_step`]
    /// against the model's time. The only caller of [`check_step`]; called once per step, by
    /// the FMI wrapper's step and by [`CoSimModel::do_step`].
    fn step_request(&self, t: f64, h: f64) -> Result<StepRequest, ModelError> {
        if !self.ports().is_initialized() {
            return Err(ModelError::NotAllowed("do_step before initialize".into()));
        }
        check_step(self.time(), t, h)
    }

    /// Advances from `t` to `t + h` [s]; `t` must equal the model's current time (within
    /// rounding). The one check of the request ([`CoSimModel::step_request`]) is made here, then the step is
    /// [`CoSimModel::do_step_watched`] without a watcher.
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), ModelError> {
        let request = self.step_request(t, h)?;
        self.do_step_watched(request, &mut watch::NoWatch)
            .map(|_| ())
    }

    /// The step `request` (checked once by its caller, [`check_step`]) under `watch`
    /// ([`watch`]): the step may end early, at an event of the model (when the watcher stops at
    /// events) or where the watcher asks; the model's time then tells where. A model without
    /// events or internal steps ignores `watch` and completes the step.
    fn do_step_watched(
        &mut self,
        request: StepRequest,
        watch: &mut dyn watch::StepWatch,
    ) -> Result<watch::StepEnd, ModelError>;

    /// Current simulation time [s].
    fn time(&self) -> f64;

    /// An exact copy of the whole model (parameters, inputs, solver state).
    fn clone_box(&self) -> Box<dyn CoSimModel>;

    /// Versioned, pointer-free bytes of the whole model; restorable in another process.
    fn serialize(&self) -> Vec<u8>;

    /// Restores what [`CoSimModel::serialize`] wrote (from this model kind only).
    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), ModelError>;

    /// Back to the freshly instantiated state (default parameters, not initialized).
    fn reset(&mut self);

    /// Takes the messages emitted since the last call.
    fn take_log(&mut self) -> Vec<LogRecord>;

    /// The integrator's work counters since the start, for the `logSolver` statistics the FMI
    /// wrapper logs at `fmi2Terminate` and after a failed step; `None` for models without an
    /// integrator (the default) or before initialization.
    fn solver_stats(&self) -> Option<crate::integrator::Stats> {
        None
    }

    /// What the model looks like now, for visualization ([`view::Snapshot`]: shapes with SI
    /// sizes and world-frame poses); `None` for a model that draws nothing or before
    /// [`CoSimModel::initialize`]. Reads the state only (it may refresh cached kinematics, hence
    /// `&mut`); the default draws nothing.
    fn snapshot(&mut self) -> Option<view::Snapshot> {
        None
    }

    /// Tells the model where its data files (see [`ModelEntry::resources`]) were unpacked.
    /// Called once after creation when the importer provides the folder; the default ignores it.
    fn set_resource_dir(&mut self, _dir: &std::path::Path) -> Result<(), ModelError> {
        Ok(())
    }

    /// Takes the tables of a scene file other than `[parameters]` (RopeBlock's rig: `[block]`,
    /// `[[lug]]`, `[[sling]]`, `[[hook]]`), before initialization; `origin` (the file) prefixes
    /// messages, which name the line. The default refuses any table.
    fn set_tables(
        &mut self,
        tables: &[scene_file::SceneTable],
        origin: &str,
    ) -> Result<(), String> {
        match tables.first() {
            None => Ok(()),
            Some(t) => Err(format!(
                "{origin}:{}: unknown table `[{}]`: a scene file of `{}` has only `[parameters]`",
                t.line,
                t.name,
                self.info().identifier
            )),
        }
    }
}

/// Relative tolerance for matching a communication point with the model time: importers send
/// points with rounding jitter (e.g. `0.009999999999999998` for `0.01`).
pub const TIME_RTOL: f64 = 1e-9;

/// A communication step request that passed [`check_step`]: the only way to build one, so a
/// model handed a `StepRequest` need not check it again (the check runs once per step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepRequest {
    t: f64,
    h: f64,
}

impl StepRequest {
    /// The communication point the step starts from [s] (the importer's value).
    pub fn t(&self) -> f64 {
        self.t
    }

    /// The communication step size [s] (the importer's value, positive and finite).
    pub fn h(&self) -> f64 {
        self.h
    }
}

/// Checks a step request: `h` [s] positive and finite, `t` [s] finite and equal to `model_time`
/// [s] within [`TIME_RTOL`] relative to `max(1 s, |t|, |model_time|)`.
pub fn check_step(model_time: f64, t: f64, h: f64) -> Result<StepRequest, ModelError> {
    #[cfg(test)]
    check_counter::note();
    if !(h.is_finite() && h > 0.0) {
        return Err(ModelError::InvalidValue(format!(
            "communication step size {h} s refused: it must be positive and finite"
        )));
    }
    if !t.is_finite() {
        return Err(ModelError::InvalidValue(format!(
            "communication point {t} s must be finite"
        )));
    }
    let tol = TIME_RTOL * 1f64.max(t.abs()).max(model_time.abs());
    if (t - model_time).abs() > tol {
        return Err(ModelError::NotAllowed(format!(
            "communication point t = {t} s does not match the model time {model_time} s (tolerance {tol:e} s)"
        )));
    }
    Ok(StepRequest { t, h })
}

/// Counts [`check_step`] calls on this thread, for the unit tests that hold the check to once
/// per step.
#[cfg(test)]
pub mod check_counter {
    use std::cell::Cell;

    thread_local! {
        static CALLS: Cell<usize> = const { Cell::new(0) };
    }

    /// One more call.
    pub fn note() {
        CALLS.with(|c| c.set(c.get() + 1));
    }

    /// Calls so far on this thread; resets the count.
    pub fn take() -> usize {
        CALLS.with(|c| c.replace(0))
    }
}

/// A data file shipped with a model (packed into the FMU's `resources/` folder).
#[derive(Debug, Clone, Copy)]
pub struct Resource {
    /// Path relative to the resources folder, `/`-separated.
    pub path: &'static str,
    /// File contents.
    pub bytes: &'static [u8],
}

/// One entry of the model registry: how the FMI layer finds and creates a model.
pub struct ModelEntry {
    /// The model's variable table.
    pub info: fn() -> &'static ModelInfo,
    /// A new instance at default parameters, not initialized.
    pub create: fn() -> Box<dyn CoSimModel>,
    /// Data files the model needs at run time (empty for most models).
    pub resources: &'static [Resource],
    /// The model's power ports (effort beside flow), for masters that join models port to port.
    pub power_ports: fn() -> Vec<power_port::PowerPort>,
}

impl ModelEntry {
    /// An entry without data files.
    pub const fn new(
        info: fn() -> &'static ModelInfo,
        create: fn() -> Box<dyn CoSimModel>,
    ) -> Self {
        Self {
            info,
            create,
            resources: &[],
            power_ports: power_port::none,
        }
    }

    /// The same entry with data files.
    pub const fn with_resources(self, resources: &'static [Resource]) -> Self {
        Self { resources, ..self }
    }

    /// The same entry with power ports.
    pub const fn with_power_ports(self, power_ports: fn() -> Vec<power_port::PowerPort>) -> Self {
        Self {
            power_ports,
            ..self
        }
    }
}

/// All models this library serves, looked up by GUID or identifier.
pub fn registry() -> Vec<ModelEntry> {
    vec![
        ModelEntry::new(panel_lock::info, panel_lock::create)
            .with_power_ports(panel_lock::power_ports::power_ports),
        ModelEntry::new(pid::info, pid::create),
        ModelEntry::new(rope_block::info, rope_block::create)
            .with_power_ports(rope_block::power_ports::power_ports),
        ModelEntry::new(spring_mass_damper::info, spring_mass_damper::create)
            .with_power_ports(spring_mass_damper::power_ports),
    ]
}

/// The registered model with this GUID.
pub fn find_by_guid(guid: &str) -> Option<ModelEntry> {
    registry().into_iter().find(|e| (e.info)().guid == guid)
}

/// The registered model with this identifier.
pub fn find_by_identifier(identifier: &str) -> Option<ModelEntry> {
    registry()
        .into_iter()
        .find(|e| (e.info)().identifier == identifier)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_tables_are_valid_and_unique() {
        let entries = registry();
        assert!(!entries.is_empty());
        let mut ids = std::collections::HashSet::new();
        let mut guids = std::collections::HashSet::new();
        for e in &entries {
            let info = (e.info)();
            if let Err(errs) = info.validate() {
                panic!("{}: {}", info.identifier, errs.join("; "));
            }
            assert!(
                ids.insert(info.identifier),
                "duplicate identifier {}",
                info.identifier
            );
            assert!(guids.insert(info.guid), "duplicate GUID {}", info.guid);
            let m = (e.create)();
            assert_eq!(m.info().identifier, info.identifier);
            assert!(find_by_guid(info.guid).is_some());
            assert!(find_by_identifier(info.identifier).is_some());
        }
        assert!(find_by_guid("{nope}").is_none());
    }

    #[test]
    fn step_checks_tolerate_jitter_only() {
        check_step(0.01, 0.009999999999999998, 0.01).unwrap();
        check_step(1000.0, 1000.0 + 1e-7, 0.01).unwrap();
        assert!(check_step(0.0, 1e-6, 0.01).is_err());
        assert!(check_step(0.0, 0.0, 0.0).is_err());
        assert!(check_step(0.0, 0.0, -1.0).is_err());
        assert!(check_step(0.0, 0.0, f64::INFINITY).is_err());
        assert!(check_step(0.0, f64::NAN, 0.1).is_err());
    }
}
