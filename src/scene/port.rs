//! Named ports of a co-simulation model: the variable table.
//!
//! Every model describes its parameters, inputs and outputs once, here, as a table of
//! [`PortSpec`]. The FMI layer turns the table into `modelDescription.xml`, and a test checks that
//! the checked-in XML under `modelDescription/` matches it, so the two cannot drift apart.
//! Nothing in this file knows about FMI: the causality and variability words are the generic
//! ones (parameter, input, output; fixed before initialization, tunable, continuous).

/// Value reference: the stable numeric id of a port inside one model.
pub type ValueRef = u32;

/// Who sets or reads a port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    /// Set by the user before (fixed) or during (tunable) the simulation.
    Parameter,
    /// Computed from parameters at initialization (read-only).
    CalculatedParameter,
    /// Set by the importer at every communication point (controller coupling).
    Input,
    /// Computed by the model, read by the importer.
    Output,
    /// Internal value exposed for inspection.
    Local,
}

/// When a port's value may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    /// Never changes.
    Constant,
    /// Set before initialization only (structure, effect switches).
    Fixed,
    /// May change between communication steps (parameters that physics allows to change).
    Tunable,
    /// Changes only at events (counters, latch states).
    Discrete,
    /// Changes continuously in time.
    Continuous,
}

/// The value type of a port, with its start value where it has one.
#[derive(Debug, Clone, PartialEq)]
pub enum PortType {
    /// Floating point value; `start` is required for parameters and inputs.
    Real {
        start: Option<f64>,
        min: Option<f64>,
        max: Option<f64>,
    },
    /// Integer value.
    Integer {
        start: Option<i32>,
        min: Option<i32>,
        max: Option<i32>,
    },
    /// Boolean value.
    Boolean { start: Option<bool> },
    /// String value.
    String { start: Option<&'static str> },
    /// Enumeration stored as an integer: `items` are the names of values 1, 2, 3, ...
    Enumeration {
        type_name: &'static str,
        items: &'static [(&'static str, &'static str)],
        start: Option<i32>,
    },
}

/// One row of a model's variable table.
#[derive(Debug, Clone, PartialEq)]
pub struct PortSpec {
    /// Unique name, e.g. `hinge[1].angle`.
    pub name: String,
    /// Value reference, unique per base type within one model.
    pub vr: ValueRef,
    pub causality: Causality,
    pub variability: Variability,
    pub ty: PortType,
    /// SI unit symbol (`"N"`, `"rad/s"`), or `None` for dimensionless values.
    pub unit: Option<&'static str>,
    /// One sentence that says what the value is, with its frame where it has one.
    pub description: String,
}

/// Everything that describes a model independently of its state.
#[derive(Debug, Clone)]
pub struct ModelInfo {
    /// `modelIdentifier` and model name, e.g. `PanelLock`.
    pub identifier: &'static str,
    /// Globally unique id (changes whenever the variable table changes).
    pub guid: &'static str,
    /// One paragraph describing the model.
    pub description: &'static str,
    /// The variable table, in the order it appears in `modelDescription.xml`.
    pub ports: Vec<PortSpec>,
    /// Default communication/stop times offered to importers [s].
    pub default_stop_time: f64,
    pub default_step: f64,
}
