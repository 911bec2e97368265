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
        /// Start value (SI unit of the port).
        start: Option<f64>,
        /// Inclusive lower bound.
        min: Option<f64>,
        /// Inclusive upper bound.
        max: Option<f64>,
        /// The validation's set is open at `min` (`open[0]`) or `max` (`open[1]`): the bound it
        /// refuses is the next float past the declared one (see [`PortSpec::with_open_min`]),
        /// and the documentation shows it as `(b, ...` or `..., b)`.
        open: [bool; 2],
        /// Unit shown in the documentation where none can be declared (`N/m^n`, with an
        /// exponent that is itself a parameter); `None`: the declared unit.
        unit_note: Option<&'static str>,
        /// With `min` 0 meaning "a default" (the solver tolerances' 0), the smallest positive
        /// value accepted: values in (0, floor) are refused where they are set.
        floor: Option<f64>,
    },
    /// Integer value.
    Integer {
        /// Start value.
        start: Option<i32>,
        /// Inclusive lower bound.
        min: Option<i32>,
        /// Inclusive upper bound.
        max: Option<i32>,
    },
    /// Boolean value.
    Boolean {
        /// Start value.
        start: Option<bool>,
    },
    /// String value.
    String {
        /// Start value.
        start: Option<&'static str>,
    },
    /// Enumeration stored as an integer: `items` are the names of values 1, 2, 3, ...
    Enumeration {
        /// Name of the enumeration type (one `SimpleType` per name).
        type_name: &'static str,
        /// `(name, description)` of items 1, 2, 3, ...
        items: &'static [(&'static str, &'static str)],
        /// Start item number (1-based).
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
    /// Who sets or reads the port.
    pub causality: Causality,
    /// When its value may change.
    pub variability: Variability,
    /// Value type, start value and bounds.
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
    /// Default stop time offered to importers [s].
    pub default_stop_time: f64,
    /// Default communication step offered to importers [s].
    pub default_step: f64,
    /// The knowns each initial unknown depends on in initialization mode (see
    /// [`InitialDependencies`]).
    pub initial_dependencies: InitialDependencies,
}

/// The knowns (inputs and parameters, by name) that an initial unknown (an output or calculated
/// parameter) depends on in initialization mode; `None` means all of them (FMI 2.0 writes no
/// `dependencies` attribute then). FMI 2.0's knowns there are the inputs, the variables with
/// `initial="exact"` (every parameter here) and time.
pub type InitialDependencies = fn(&ModelInfo, &PortSpec) -> Option<Vec<String>>;

/// [`InitialDependencies`] of a model that declares none: every unknown depends on every known.
pub fn on_all_knowns(_: &ModelInfo, _: &PortSpec) -> Option<Vec<String>> {
    None
}

/// The storage type behind a port, as an importer sees it (enumerations are integers).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BaseType {
    /// 64-bit float.
    Real,
    /// 32-bit signed integer (also enumerations).
    Integer,
    /// Boolean.
    Boolean,
    /// UTF-8 string.
    String,
}

impl BaseType {
    /// Human-readable name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            BaseType::Real => "Real",
            BaseType::Integer => "Integer",
            BaseType::Boolean => "Boolean",
            BaseType::String => "String",
        }
    }
}

impl PortType {
    /// The storage type of this port type.
    pub fn base(&self) -> BaseType {
        match self {
            PortType::Real { .. } => BaseType::Real,
            PortType::Integer { .. } | PortType::Enumeration { .. } => BaseType::Integer,
            PortType::Boolean { .. } => BaseType::Boolean,
            PortType::String { .. } => BaseType::String,
        }
    }

    /// True when a start value is given.
    pub fn has_start(&self) -> bool {
        match self {
            PortType::Real { start, .. } => start.is_some(),
            PortType::Integer { start, .. } | PortType::Enumeration { start, .. } => {
                start.is_some()
            }
            PortType::Boolean { start } => start.is_some(),
            PortType::String { start } => start.is_some(),
        }
    }
}

impl Causality {
    /// Lower-case name (`parameter`, `calculatedParameter`, `input`, `output`, `local`).
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
        }
    }
}

impl Variability {
    /// Lower-case name (`constant`, `fixed`, `tunable`, `discrete`, `continuous`).
    pub fn name(self) -> &'static str {
        match self {
            Variability::Constant => "constant",
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

impl PortSpec {
    /// A real parameter with a start value; `variability` is `Fixed` or `Tunable`.
    pub fn real_parameter(
        name: &str,
        vr: ValueRef,
        variability: Variability,
        start: f64,
        unit: Option<&'static str>,
        description: &str,
    ) -> Self {
        Self {
            name: name.to_string(),
            vr,
            causality: Causality::Parameter,
            variability,
            ty: PortType::Real {
                start: Some(start),
                min: None,
                max: None,
                open: [false; 2],
                unit_note: None,
                floor: None,
            },
            unit,
            description: description.to_string(),
        }
    }

    /// A boolean parameter with a start value; `variability` is `Fixed` or `Tunable`.
    pub fn boolean_parameter(
        name: &str,
        vr: ValueRef,
        variability: Variability,
        start: bool,
        description: &str,
    ) -> Self {
        Self {
            name: name.to_string(),
            vr,
            causality: Causality::Parameter,
            variability,
            ty: PortType::Boolean { start: Some(start) },
            unit: None,
            description: description.to_string(),
        }
    }

    /// A continuous real input with the value it holds until the importer sets it.
    pub fn real_input(
        name: &str,
        vr: ValueRef,
        start: f64,
        unit: Option<&'static str>,
        description: &str,
    ) -> Self {
        Self {
            name: name.to_string(),
            vr,
            causality: Causality::Input,
            variability: Variability::Continuous,
            ty: PortType::Real {
                start: Some(start),
                min: None,
                max: None,
                open: [false; 2],
                unit_note: None,
                floor: None,
            },
            unit,
            description: description.to_string(),
        }
    }

    /// A continuous real output (computed by the model, no start value).
    pub fn real_output(
        name: &str,
        vr: ValueRef,
        unit: Option<&'static str>,
        description: &str,
    ) -> Self {
        Self {
            name: name.to_string(),
            vr,
            causality: Causality::Output,
            variability: Variability::Continuous,
            ty: PortType::Real {
                start: None,
                min: None,
                max: None,
                open: [false; 2],
                unit_note: None,
                floor: None,
            },
            unit,
            description: description.to_string(),
        }
    }

    /// A discrete boolean output (computed by the model, no start value).
    pub fn boolean_output(name: &str, vr: ValueRef, description: &str) -> Self {
        Self {
            name: name.to_string(),
            vr,
            causality: Causality::Output,
            variability: Variability::Discrete,
            ty: PortType::Boolean { start: None },
            unit: None,
            description: description.to_string(),
        }
    }

    /// Sets the inclusive lower bound of a real or integer port.
    pub fn with_min(mut self, lo: f64) -> Self {
        match &mut self.ty {
            PortType::Real { min, .. } => *min = Some(lo),
            PortType::Integer { min, .. } => *min = Some(lo as i32),
            _ => {}
        }
        self
    }

    /// Sets a real port's smallest positive value where its minimum 0 means a default
    /// (`PortType::Real::floor`).
    pub fn with_floor(mut self, f: f64) -> Self {
        if let PortType::Real { floor, .. } = &mut self.ty {
            *floor = Some(f);
        }
        self
    }

    /// Declares a real port's set open at `lo`: the declared (inclusive) minimum is the smallest
    /// float above `lo`, and the documentation shows `(lo, ...`.
    pub fn with_open_min(mut self, lo: f64) -> Self {
        if let PortType::Real { min, open, .. } = &mut self.ty {
            *min = Some(lo.next_up());
            open[0] = true;
        }
        self
    }

    /// Declares a real port's set open at `hi`: the declared (inclusive) maximum is the largest
    /// float below `hi`, and the documentation shows `..., hi)`.
    pub fn with_open_max(mut self, hi: f64) -> Self {
        if let PortType::Real { max, open, .. } = &mut self.ty {
            *max = Some(hi.next_down());
            open[1] = true;
        }
        self
    }

    /// The unit the documentation shows for a real port declared without one (see
    /// `PortType::Real::unit_note`).
    pub fn with_unit_note(mut self, note: &'static str) -> Self {
        if let PortType::Real { unit_note, .. } = &mut self.ty {
            *unit_note = Some(note);
        }
        self
    }

    /// Sets the inclusive upper bound of a real or integer port.
    pub fn with_max(mut self, hi: f64) -> Self {
        match &mut self.ty {
            PortType::Real { max, .. } => *max = Some(hi),
            PortType::Integer { max, .. } => *max = Some(hi as i32),
            _ => {}
        }
        self
    }

    /// True when an importer may write this port at all (parameters and inputs).
    pub fn is_writable(&self) -> bool {
        matches!(self.causality, Causality::Parameter | Causality::Input)
            && self.variability != Variability::Constant
    }
}

impl ModelInfo {
    /// The position and row of the port with this storage type and value reference.
    pub fn find(&self, base: BaseType, vr: ValueRef) -> Option<(usize, &PortSpec)> {
        self.ports
            .iter()
            .enumerate()
            .find(|(_, p)| p.vr == vr && p.ty.base() == base)
    }

    /// Names of the knowns (parameters and inputs) other than `excluded`, in table order.
    pub fn knowns_except(&self, excluded: &[&str]) -> Vec<String> {
        self.ports
            .iter()
            .filter(|p| matches!(p.causality, Causality::Parameter | Causality::Input))
            .filter(|p| !excluded.contains(&p.name.as_str()))
            .map(|p| p.name.clone())
            .collect()
    }

    /// The row named `name`.
    pub fn port_by_name(&self, name: &str) -> Option<&PortSpec> {
        self.ports.iter().find(|p| p.name == name)
    }

    /// Checks the table for what every importer relies on; returns every problem found.
    ///
    /// Rules: unique names; value references unique per [`BaseType`]; parameters are `Fixed` or
    /// `Tunable` and, like inputs and constants, have a start value; outputs, locals and
    /// calculated parameters have none; only reals are `Continuous`; `min <= start <= max`;
    /// enumeration starts lie in `1..=items`; default times are positive and finite.
    pub fn validate(&self) -> Result<(), Vec<String>> {
        let mut errs = Vec::new();
        let mut seen_names = std::collections::HashSet::new();
        let mut seen_vrs = std::collections::HashSet::new();
        for p in &self.ports {
            let n = &p.name;
            if p.name.is_empty() {
                errs.push("a port has an empty name".to_string());
            }
            if !seen_names.insert(p.name.as_str()) {
                errs.push(format!("duplicate port name `{n}`"));
            }
            if !seen_vrs.insert((p.ty.base(), p.vr)) {
                errs.push(format!(
                    "`{n}`: value reference {} is used twice for {}",
                    p.vr,
                    p.ty.base().name()
                ));
            }
            if p.description.trim().is_empty() {
                errs.push(format!("`{n}` has no description"));
            }
            let needs_start = matches!(p.causality, Causality::Parameter | Causality::Input)
                || p.variability == Variability::Constant;
            if needs_start && !p.ty.has_start() {
                errs.push(format!(
                    "`{n}` ({}) needs a start value",
                    p.causality.name()
                ));
            }
            if !needs_start && p.ty.has_start() {
                errs.push(format!(
                    "`{n}` ({}) is computed by the model and must not have a start value",
                    p.causality.name()
                ));
            }
            let param_like = matches!(
                p.causality,
                Causality::Parameter | Causality::CalculatedParameter
            );
            if param_like && !matches!(p.variability, Variability::Fixed | Variability::Tunable) {
                errs.push(format!("`{n}`: a parameter must be fixed or tunable"));
            }
            if !param_like
                && matches!(p.variability, Variability::Fixed | Variability::Tunable)
                && p.causality != Causality::Local
            {
                errs.push(format!(
                    "`{n}`: only parameters and locals can be fixed or tunable"
                ));
            }
            if p.variability == Variability::Continuous && p.ty.base() != BaseType::Real {
                errs.push(format!("`{n}`: only Real ports can be continuous"));
            }
            if p.causality == Causality::Input && p.variability == Variability::Constant {
                errs.push(format!("`{n}`: an input cannot be constant"));
            }
            match &p.ty {
                PortType::Real {
                    start, min, max, ..
                } => {
                    for (what, v) in [("start", start), ("min", min), ("max", max)] {
                        if v.is_some_and(|v| !v.is_finite()) {
                            errs.push(format!("`{n}`: {what} must be finite"));
                        }
                    }
                    if let (Some(lo), Some(hi)) = (min, max)
                        && lo > hi
                    {
                        errs.push(format!("`{n}`: min {lo} > max {hi}"));
                    }
                    if let Some(s) = start
                        && (min.is_some_and(|lo| *s < lo) || max.is_some_and(|hi| *s > hi))
                    {
                        errs.push(format!("`{n}`: start {s} is outside [min, max]"));
                    }
                }
                PortType::Integer { start, min, max } => {
                    if let (Some(lo), Some(hi)) = (min, max)
                        && lo > hi
                    {
                        errs.push(format!("`{n}`: min {lo} > max {hi}"));
                    }
                    if let Some(s) = start
                        && (min.is_some_and(|lo| *s < lo) || max.is_some_and(|hi| *s > hi))
                    {
                        errs.push(format!("`{n}`: start {s} is outside [min, max]"));
                    }
                }
                PortType::Enumeration {
                    type_name,
                    items,
                    start,
                } => {
                    if type_name.is_empty() || items.is_empty() {
                        errs.push(format!("`{n}`: an enumeration needs a type name and items"));
                    }
                    if let Some(s) = start
                        && (*s < 1 || *s as usize > items.len())
                    {
                        errs.push(format!(
                            "`{n}`: start {s} is not an item number 1..={}",
                            items.len()
                        ));
                    }
                }
                PortType::Boolean { .. } | PortType::String { .. } => {}
            }
        }
        if !(self.default_stop_time.is_finite() && self.default_stop_time > 0.0) {
            errs.push("default_stop_time must be positive and finite".to_string());
        }
        if !(self.default_step.is_finite() && self.default_step > 0.0) {
            errs.push("default_step must be positive and finite".to_string());
        }
        if errs.is_empty() { Ok(()) } else { Err(errs) }
    }
}
