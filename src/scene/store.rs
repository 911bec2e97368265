//! The port value store: current values of a model's ports, with the validation rules.
//!
//! A model keeps one [`PortStore`] built from its [`ModelInfo`]. The store starts with every
//! port at its start value (0, `false` or `""` where none is given), gives typed access by value
//! reference, and enforces the rules an importer must follow:
//!
//! - only parameters and inputs are writable ([`check_writable`]);
//! - fixed parameters only before initialization, tunable parameters and inputs at any time;
//! - reals must be finite and within `[min, max]`, integers within `[min, max]`, enumerations
//!   one of their item numbers ([`check_real`], [`check_integer`]).
//!
//! The same free functions are used by the FMI layer, so an importer gets the same messages
//! whether the wrapper or the model refuses a value. Model code writes outputs with the `put_*`
//! methods, which skip the causality rules but still check the value reference and type.

use std::collections::HashMap;
use std::sync::Arc;

use super::ModelError;
use super::bytes::{ByteReader, ByteWriter};
use super::port::{BaseType, Causality, ModelInfo, PortSpec, PortType, ValueRef, Variability};

/// The current value of one port.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A real value (SI unit of the port).
    Real(f64),
    /// An integer or enumeration item number.
    Integer(i32),
    /// A boolean.
    Boolean(bool),
    /// A string.
    String(String),
}

impl Value {
    /// The start value of a port, or the type's zero when it has none.
    pub fn start_of(ty: &PortType) -> Value {
        match ty {
            PortType::Real { start, .. } => Value::Real(start.unwrap_or(0.0)),
            PortType::Integer { start, .. } => Value::Integer(start.unwrap_or(0)),
            PortType::Enumeration { start, .. } => Value::Integer(start.unwrap_or(1)),
            PortType::Boolean { start } => Value::Boolean(start.unwrap_or(false)),
            PortType::String { start } => Value::String(start.unwrap_or("").to_string()),
        }
    }

    fn base(&self) -> BaseType {
        match self {
            Value::Real(_) => BaseType::Real,
            Value::Integer(_) => BaseType::Integer,
            Value::Boolean(_) => BaseType::Boolean,
            Value::String(_) => BaseType::String,
        }
    }
}

/// Fails unless an importer may write `port` now; `initialized` is true once the model has been
/// initialized (fixed parameters are then frozen).
pub fn check_writable(port: &PortSpec, initialized: bool) -> Result<(), ModelError> {
    let name = &port.name;
    match (port.causality, port.variability) {
        (_, Variability::Constant) => Err(ModelError::NotAllowed(format!(
            "`{name}` is a constant and cannot be set"
        ))),
        (Causality::Parameter, Variability::Fixed) if initialized => {
            Err(ModelError::NotAllowed(format!(
                "`{name}` is a fixed parameter: it can only be set before initialization (reset the model to change it)"
            )))
        }
        (Causality::Parameter | Causality::Input, _) => Ok(()),
        (c, _) => Err(ModelError::NotAllowed(format!(
            "`{name}` is {} {}: it is computed by the model and cannot be set",
            if c == Causality::Input || c == Causality::Output {
                "an"
            } else {
                "a"
            },
            c.name()
        ))),
    }
}

/// Fails unless `v` is finite and inside the port's `[min, max]`.
pub fn check_real(port: &PortSpec, v: f64) -> Result<(), ModelError> {
    let name = &port.name;
    if !v.is_finite() {
        return Err(ModelError::InvalidValue(format!(
            "`{name}` = {v} refused: the value must be finite"
        )));
    }
    if let PortType::Real {
        min, max, floor, ..
    } = &port.ty
    {
        if let Some(f) = floor
            && v != 0.0
            && v < *f
        {
            return Err(ModelError::InvalidValue(format!(
                "`{name}` = {v:?} is below its minimum {f:?} (0 takes the default)"
            )));
        }
        if let Some(lo) = min
            && v < *lo
        {
            return Err(ModelError::InvalidValue(format!(
                "`{name}` = {v:?} is below its minimum {lo:?}"
            )));
        }
        if let Some(hi) = max
            && v > *hi
        {
            return Err(ModelError::InvalidValue(format!(
                "`{name}` = {v:?} is above its maximum {hi:?}"
            )));
        }
    }
    Ok(())
}

/// Fails unless `v` is inside an integer port's `[min, max]` or is an item of an enumeration.
pub fn check_integer(port: &PortSpec, v: i32) -> Result<(), ModelError> {
    let name = &port.name;
    match &port.ty {
        PortType::Integer { min, max, .. } => {
            if let Some(lo) = min
                && v < *lo
            {
                return Err(ModelError::InvalidValue(format!(
                    "`{name}` = {v} is below its minimum {lo}"
                )));
            }
            if let Some(hi) = max
                && v > *hi
            {
                return Err(ModelError::InvalidValue(format!(
                    "`{name}` = {v} is above its maximum {hi}"
                )));
            }
            Ok(())
        }
        PortType::Enumeration {
            type_name, items, ..
        } => {
            if v >= 1 && (v as usize) <= items.len() {
                Ok(())
            } else {
                Err(ModelError::InvalidValue(format!(
                    "`{name}` = {v} is not an item of enumeration {type_name} (1..={})",
                    items.len()
                )))
            }
        }
        _ => Ok(()),
    }
}

/// Map from (storage type, value reference) to the row index in a [`ModelInfo`].
///
/// Value references below [`PortIndex::DENSE_LIMIT`] are looked up in a plain table per storage
/// type (a few nanoseconds, models read their ports every step); larger ones in a hash map.
#[derive(Debug)]
pub struct PortIndex {
    /// Per storage type: row index + 1 at position `vr` (0 = no such port).
    dense: [Vec<u32>; 4],
    sparse: HashMap<(BaseType, ValueRef), usize>,
}

impl PortIndex {
    /// Value references from here on go to the hash map.
    pub const DENSE_LIMIT: ValueRef = 1 << 16;

    fn slot(base: BaseType) -> usize {
        match base {
            BaseType::Real => 0,
            BaseType::Integer => 1,
            BaseType::Boolean => 2,
            BaseType::String => 3,
        }
    }

    /// Indexes every row of `info` (the first row wins on a duplicate, which
    /// [`ModelInfo::validate`] reports).
    pub fn new(info: &ModelInfo) -> Self {
        let mut index = Self {
            dense: Default::default(),
            sparse: HashMap::new(),
        };
        for (i, p) in info.ports.iter().enumerate() {
            let base = p.ty.base();
            if index.get(base, p.vr).is_some() {
                continue;
            }
            if p.vr < Self::DENSE_LIMIT {
                let table = &mut index.dense[Self::slot(base)];
                let at = p.vr as usize;
                if table.len() <= at {
                    table.resize(at + 1, 0);
                }
                table[at] = i as u32 + 1;
            } else {
                index.sparse.insert((base, p.vr), i);
            }
        }
        index
    }

    /// Row index of the port with this storage type and value reference.
    pub fn get(&self, base: BaseType, vr: ValueRef) -> Option<usize> {
        if vr < Self::DENSE_LIMIT {
            match self.dense[Self::slot(base)].get(vr as usize) {
                Some(&k) if k > 0 => Some(k as usize - 1),
                _ => None,
            }
        } else {
            self.sparse.get(&(base, vr)).copied()
        }
    }
}

/// Current values of all ports of one model instance.
#[derive(Debug, Clone)]
pub struct PortStore {
    info: &'static ModelInfo,
    index: Arc<PortIndex>,
    values: Vec<Value>,
    initialized: bool,
}

impl PortStore {
    /// Every port at its start value, not initialized.
    pub fn new(info: &'static ModelInfo) -> Self {
        Self {
            info,
            index: Arc::new(PortIndex::new(info)),
            values: info.ports.iter().map(|p| Value::start_of(&p.ty)).collect(),
            initialized: false,
        }
    }

    /// The variable table this store holds values for.
    pub fn info(&self) -> &'static ModelInfo {
        self.info
    }

    /// True after [`PortStore::mark_initialized`]: fixed parameters are then frozen.
    pub fn is_initialized(&self) -> bool {
        self.initialized
    }

    /// Freezes fixed parameters (call when the model is initialized).
    pub fn mark_initialized(&mut self) {
        self.initialized = true;
    }

    /// Back to start values, not initialized.
    pub fn reset(&mut self) {
        for (v, p) in self.values.iter_mut().zip(&self.info.ports) {
            *v = Value::start_of(&p.ty);
        }
        self.initialized = false;
    }

    fn lookup(&self, base: BaseType, vr: ValueRef) -> Result<usize, ModelError> {
        self.index
            .get(base, vr)
            .ok_or(ModelError::UnknownValueRef(vr))
    }

    fn writable(&self, base: BaseType, vr: ValueRef) -> Result<usize, ModelError> {
        let i = self.lookup(base, vr)?;
        check_writable(&self.info.ports[i], self.initialized)?;
        Ok(i)
    }

    /// Importer-side write of a real parameter or input, with every rule checked.
    pub fn set_real(&mut self, vr: ValueRef, v: f64) -> Result<(), ModelError> {
        let i = self.writable(BaseType::Real, vr)?;
        check_real(&self.info.ports[i], v)?;
        self.values[i] = Value::Real(v);
        Ok(())
    }

    /// Importer-side write of an integer or enumeration parameter or input.
    pub fn set_integer(&mut self, vr: ValueRef, v: i32) -> Result<(), ModelError> {
        let i = self.writable(BaseType::Integer, vr)?;
        check_integer(&self.info.ports[i], v)?;
        self.values[i] = Value::Integer(v);
        Ok(())
    }

    /// Importer-side write of a boolean parameter or input.
    pub fn set_boolean(&mut self, vr: ValueRef, v: bool) -> Result<(), ModelError> {
        let i = self.writable(BaseType::Boolean, vr)?;
        self.values[i] = Value::Boolean(v);
        Ok(())
    }

    /// Importer-side write of a string parameter or input.
    pub fn set_string(&mut self, vr: ValueRef, v: &str) -> Result<(), ModelError> {
        let i = self.writable(BaseType::String, vr)?;
        self.values[i] = Value::String(v.to_string());
        Ok(())
    }

    /// Model-side write of any real port (outputs included); the value is not range-checked.
    pub fn put_real(&mut self, vr: ValueRef, v: f64) -> Result<(), ModelError> {
        let i = self.lookup(BaseType::Real, vr)?;
        self.values[i] = Value::Real(v);
        Ok(())
    }

    /// Model-side write of any integer port.
    pub fn put_integer(&mut self, vr: ValueRef, v: i32) -> Result<(), ModelError> {
        let i = self.lookup(BaseType::Integer, vr)?;
        self.values[i] = Value::Integer(v);
        Ok(())
    }

    /// Model-side write of any boolean port.
    pub fn put_boolean(&mut self, vr: ValueRef, v: bool) -> Result<(), ModelError> {
        let i = self.lookup(BaseType::Boolean, vr)?;
        self.values[i] = Value::Boolean(v);
        Ok(())
    }

    /// Model-side write of any string port.
    pub fn put_string(&mut self, vr: ValueRef, v: &str) -> Result<(), ModelError> {
        let i = self.lookup(BaseType::String, vr)?;
        self.values[i] = Value::String(v.to_string());
        Ok(())
    }

    /// Current value of a real port.
    pub fn get_real(&self, vr: ValueRef) -> Result<f64, ModelError> {
        match &self.values[self.lookup(BaseType::Real, vr)?] {
            Value::Real(v) => Ok(*v),
            _ => Err(ModelError::UnknownValueRef(vr)),
        }
    }

    /// Current value of an integer or enumeration port.
    pub fn get_integer(&self, vr: ValueRef) -> Result<i32, ModelError> {
        match &self.values[self.lookup(BaseType::Integer, vr)?] {
            Value::Integer(v) => Ok(*v),
            _ => Err(ModelError::UnknownValueRef(vr)),
        }
    }

    /// Current value of a boolean port.
    pub fn get_boolean(&self, vr: ValueRef) -> Result<bool, ModelError> {
        match &self.values[self.lookup(BaseType::Boolean, vr)?] {
            Value::Boolean(v) => Ok(*v),
            _ => Err(ModelError::UnknownValueRef(vr)),
        }
    }

    /// Current value of a string port.
    pub fn get_string(&self, vr: ValueRef) -> Result<String, ModelError> {
        match &self.values[self.lookup(BaseType::String, vr)?] {
            Value::String(v) => Ok(v.clone()),
            _ => Err(ModelError::UnknownValueRef(vr)),
        }
    }

    /// Writes the initialized flag and every value (tagged by type) to `w`.
    pub fn write(&self, w: &mut ByteWriter) {
        w.bool(self.initialized);
        w.u64(self.values.len() as u64);
        for v in &self.values {
            match v {
                Value::Real(x) => {
                    w.u8(0);
                    w.f64(*x);
                }
                Value::Integer(x) => {
                    w.u8(1);
                    w.i32(*x);
                }
                Value::Boolean(x) => {
                    w.u8(2);
                    w.bool(*x);
                }
                Value::String(x) => {
                    w.u8(3);
                    w.str(x);
                }
            }
        }
    }

    /// Reads what [`PortStore::write`] wrote into a copy of this store; `self` is left
    /// unchanged on error.
    pub fn read(&self, r: &mut ByteReader<'_>) -> Result<PortStore, ModelError> {
        let initialized = r.bool("port store: initialized flag")?;
        let n = r.u64("port store: port count")?;
        if n != self.values.len() as u64 {
            return Err(ModelError::BadState(format!(
                "state holds {n} port values, model `{}` has {} ports",
                self.info.identifier,
                self.values.len()
            )));
        }
        let mut values = Vec::with_capacity(self.values.len());
        for p in &self.info.ports {
            let what = format!("value of `{}`", p.name);
            let v = match r.u8(&what)? {
                0 => Value::Real(r.f64(&what)?),
                1 => Value::Integer(r.i32(&what)?),
                2 => Value::Boolean(r.bool(&what)?),
                3 => Value::String(r.str(&what)?.to_string()),
                t => {
                    return Err(ModelError::BadState(format!(
                        "corrupt state: {what} has unknown type tag {t}"
                    )));
                }
            };
            if v.base() != p.ty.base() {
                return Err(ModelError::BadState(format!(
                    "corrupt state: {what} is a {}, the port is a {}",
                    v.base().name(),
                    p.ty.base().name()
                )));
            }
            // parameters and inputs obey the rules of their setters (a forged NaN limit used to
            // reach the model and panic in a clamp: issue #25)
            if matches!(p.causality, Causality::Parameter | Causality::Input) {
                let checked = match &v {
                    Value::Real(x) => check_real(p, *x),
                    Value::Integer(x) => check_integer(p, *x),
                    _ => Ok(()),
                };
                checked.map_err(|e| ModelError::BadState(format!("corrupt state: {what}: {e}")))?;
            }
            values.push(v);
        }
        Ok(PortStore {
            info: self.info,
            index: Arc::clone(&self.index),
            values,
            initialized,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::port::PortSpec;
    use std::sync::OnceLock;

    const ITEMS: &[(&str, &str)] = &[("a", "first"), ("b", "second")];

    fn info() -> &'static ModelInfo {
        static INFO: OnceLock<ModelInfo> = OnceLock::new();
        INFO.get_or_init(|| ModelInfo {
            identifier: "StoreTest",
            guid: "{00000000-0000-0000-0000-000000000001}",
            description: "test table",
            ports: vec![
                PortSpec::real_parameter("mass", 0, Variability::Fixed, 1.0, Some("kg"), "Mass.")
                    .with_min(0.0),
                PortSpec::real_parameter("gain", 1, Variability::Tunable, 2.0, None, "Gain.")
                    .with_max(10.0),
                PortSpec::real_input("force", 2, 0.0, Some("N"), "Force."),
                PortSpec::real_output("x", 3, Some("m"), "Position."),
                PortSpec {
                    name: "mode".into(),
                    vr: 0,
                    causality: Causality::Parameter,
                    variability: Variability::Fixed,
                    ty: PortType::Enumeration {
                        type_name: "Mode",
                        items: ITEMS,
                        start: Some(1),
                    },
                    unit: None,
                    description: "Mode.".into(),
                },
                PortSpec {
                    name: "label".into(),
                    vr: 0,
                    causality: Causality::Parameter,
                    variability: Variability::Tunable,
                    ty: PortType::String { start: Some("hi") },
                    unit: None,
                    description: "Label.".into(),
                },
                PortSpec::boolean_output("on", 0, "Switch."),
            ],
            default_stop_time: 1.0,
            default_step: 0.1,
            initial_dependencies: crate::scene::port::on_all_knowns,
        })
    }

    #[test]
    fn table_is_valid_and_starts_apply() {
        info().validate().unwrap();
        let s = PortStore::new(info());
        assert_eq!(s.get_real(0).unwrap(), 1.0);
        assert_eq!(s.get_real(3).unwrap(), 0.0);
        assert_eq!(s.get_integer(0).unwrap(), 1);
        assert_eq!(s.get_string(0).unwrap(), "hi");
        assert!(!s.get_boolean(0).unwrap());
    }

    #[test]
    fn rules_are_enforced_with_precise_messages() {
        let mut s = PortStore::new(info());
        s.set_real(0, 3.0).unwrap();
        let e = s.set_real(0, -1.0).unwrap_err().to_string();
        assert!(e.contains("`mass` = -1.0 is below its minimum 0.0"), "{e}");
        let e = s.set_real(1, f64::NAN).unwrap_err().to_string();
        assert!(e.contains("must be finite"), "{e}");
        let e = s.set_real(3, 1.0).unwrap_err().to_string();
        assert!(e.contains("`x` is an output"), "{e}");
        assert_eq!(s.set_real(99, 1.0), Err(ModelError::UnknownValueRef(99)));
        assert!(
            s.set_integer(0, 3)
                .unwrap_err()
                .to_string()
                .contains("enumeration Mode")
        );
        s.set_integer(0, 2).unwrap();
        s.mark_initialized();
        let e = s.set_real(0, 2.0).unwrap_err().to_string();
        assert!(e.contains("`mass` is a fixed parameter"), "{e}");
        s.set_real(1, 5.0).unwrap();
        s.set_real(2, -7.0).unwrap();
        s.set_string(0, "new").unwrap();
        s.put_real(3, 0.5).unwrap();
        s.put_boolean(0, true).unwrap();
        assert_eq!(s.get_real(3).unwrap(), 0.5);
        s.reset();
        assert!(!s.is_initialized());
        assert_eq!(s.get_real(1).unwrap(), 2.0);
    }

    #[test]
    fn index_finds_dense_and_sparse_references() {
        let mut info = info().clone();
        info.ports[2].vr = 4_000_000_000;
        let index = PortIndex::new(&info);
        assert_eq!(index.get(BaseType::Real, 4_000_000_000), Some(2));
        assert_eq!(index.get(BaseType::Real, 3), Some(3));
        assert_eq!(index.get(BaseType::Integer, 0), Some(4));
        assert_eq!(index.get(BaseType::Real, 2), None);
        assert_eq!(index.get(BaseType::Boolean, 1), None);
        assert_eq!(index.get(BaseType::String, u32::MAX), None);
    }

    #[test]
    fn serialization_round_trips_and_refuses_foreign_bytes() {
        let mut s = PortStore::new(info());
        s.set_real(2, 4.5).unwrap();
        s.set_string(0, "xyz").unwrap();
        s.mark_initialized();
        let mut w = ByteWriter::new();
        s.write(&mut w);
        let bytes = w.into_bytes();
        let mut r = ByteReader::new(&bytes);
        let back = PortStore::new(info()).read(&mut r).unwrap();
        r.finish().unwrap();
        assert_eq!(back.values, s.values);
        assert!(back.is_initialized());
        for cut in 0..bytes.len() {
            assert!(
                PortStore::new(info())
                    .read(&mut ByteReader::new(&bytes[..cut]))
                    .is_err()
            );
        }
        let mut bad = bytes.clone();
        bad[9] = 1; // first value's type tag: Real -> Integer
        assert!(
            PortStore::new(info())
                .read(&mut ByteReader::new(&bad))
                .is_err()
        );
    }
}
