//! Scenes: models assembled from bodies, joints, forces and contacts, each exposing named ports.
//!
//! [`CoSimModel`] is the interface the FMI wrapper (`crate::fmi`) drives; it knows nothing of FMI
//! itself. A model receives parameter and input values by value reference, is initialized, and
//! then advanced in communication steps. Its whole state can be cloned (FMU state get/set) and
//! serialized to a versioned, pointer-free byte format.

pub mod port;
pub mod rope_block;

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
    pub level: LogLevel,
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
pub trait CoSimModel: Send {
    /// The model's static description and variable table.
    fn info(&self) -> &'static ModelInfo;

    fn set_real(&mut self, vr: ValueRef, value: f64) -> Result<(), ModelError>;
    fn get_real(&self, vr: ValueRef) -> Result<f64, ModelError>;
    fn set_integer(&mut self, vr: ValueRef, value: i32) -> Result<(), ModelError>;
    fn get_integer(&self, vr: ValueRef) -> Result<i32, ModelError>;
    fn set_boolean(&mut self, vr: ValueRef, value: bool) -> Result<(), ModelError>;
    fn get_boolean(&self, vr: ValueRef) -> Result<bool, ModelError>;
    fn set_string(&mut self, vr: ValueRef, value: &str) -> Result<(), ModelError>;
    fn get_string(&self, vr: ValueRef) -> Result<String, ModelError>;

    /// Builds the system from the parameters and finds consistent initial conditions at `t_start` [s].
    fn initialize(&mut self, t_start: f64) -> Result<(), ModelError>;

    /// Advances from `t` to `t + h` [s]; `t` must equal the model's current time (within rounding).
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), ModelError>;

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
}

/// One entry of the model registry: how the FMI layer finds and creates a model.
pub struct ModelEntry {
    pub info: fn() -> &'static ModelInfo,
    pub create: fn() -> Box<dyn CoSimModel>,
}

/// All models this library serves, looked up by GUID or identifier.
pub fn registry() -> Vec<ModelEntry> {
    Vec::new()
}
