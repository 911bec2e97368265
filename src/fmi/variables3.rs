//! The FMI 3.0 view of a variable table: each port's FMI 3.0 type and value reference.
//!
//! FMI 2.0 value references are unique per base type only (a model has a Real 0 and an Integer
//! 0); FMI 3.0 requires them unique over all variables. The FMI 3.0 value reference is therefore
//! the FMI 2.0 one plus a block offset per base type, so a Float64 keeps its FMI 2.0 number:
//!
//! | FMI 2.0 base type               | FMI 3.0 type            | FMI 3.0 value reference |
//! |---------------------------------|-------------------------|-------------------------|
//! | Real                            | `Float64`               | vr                      |
//! | Integer                         | `Int32`                 | 1 000 000 + vr          |
//! | Integer holding an enumeration  | `Enumeration` (`Int64`) | 1 000 000 + vr          |
//! | Boolean                         | `Boolean`               | 2 000 000 + vr          |
//! | String                          | `String`                | 3 000 000 + vr          |
//! | (none: FMI 3.0 only)            | `Float64` `time`        | 4 000 000               |
//!
//! `time` is the independent variable that FMI 3.0 requires in every model description.
//!
//! An array variable ([`super::arrays3`]) takes the FMI 3.0 reference of its element 0; its other
//! elements' references are not used in FMI 3.0.

use super::arrays3::View3;
use crate::scene::port::{BaseType, ModelInfo, PortSpec, PortType, ValueRef};

/// Size of one value-reference block; every FMI 2.0 value reference must be below it.
pub const VR_BLOCK: u32 = 1_000_000;
/// Value reference of the independent variable `time`.
pub const TIME_VR: u32 = 4 * VR_BLOCK;
/// Name of the independent variable.
pub const TIME_NAME: &str = "time";

/// FMI 3.0 variable type of a port (the getter and setter family that serves it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type3 {
    /// `fmi3GetFloat64` / `fmi3SetFloat64`.
    Float64,
    /// `fmi3GetInt32` / `fmi3SetInt32`.
    Int32,
    /// Enumerations: `fmi3GetInt64` / `fmi3SetInt64`.
    Enumeration,
    /// `fmi3GetBoolean` / `fmi3SetBoolean`.
    Boolean,
    /// `fmi3GetString` / `fmi3SetString`.
    String,
}

impl Type3 {
    /// The FMI 3.0 type of a port type.
    pub fn of(ty: &PortType) -> Type3 {
        match ty {
            PortType::Real { .. } => Type3::Float64,
            PortType::Integer { .. } => Type3::Int32,
            PortType::Enumeration { .. } => Type3::Enumeration,
            PortType::Boolean { .. } => Type3::Boolean,
            PortType::String { .. } => Type3::String,
        }
    }

    /// XML element name (`Float64`, `Int32`, `Enumeration`, `Boolean`, `String`).
    pub fn element(self) -> &'static str {
        match self {
            Type3::Float64 => "Float64",
            Type3::Int32 => "Int32",
            Type3::Enumeration => "Enumeration",
            Type3::Boolean => "Boolean",
            Type3::String => "String",
        }
    }

    /// The C functions that access a variable of this type, for messages.
    pub fn accessor(self) -> &'static str {
        match self {
            Type3::Float64 => "Float64 (fmi3Get/SetFloat64)",
            Type3::Int32 => "Int32 (fmi3Get/SetInt32)",
            Type3::Enumeration => "Enumeration (fmi3Get/SetInt64)",
            Type3::Boolean => "Boolean (fmi3Get/SetBoolean)",
            Type3::String => "String (fmi3Get/SetString)",
        }
    }
}

fn block(base: BaseType) -> u32 {
    match base {
        BaseType::Real => 0,
        BaseType::Integer => 1,
        BaseType::Boolean => 2,
        BaseType::String => 3,
    }
}

/// The FMI 3.0 value reference of a port; `Err` when its FMI 2.0 one does not fit in a block.
pub fn vr3(p: &PortSpec) -> Result<u32, String> {
    if p.vr >= VR_BLOCK {
        return Err(format!(
            "`{}` has value reference {}, too large for the FMI 3.0 mapping (at most {})",
            p.name,
            p.vr,
            VR_BLOCK - 1
        ));
    }
    Ok(block(p.ty.base()) * VR_BLOCK + p.vr)
}

/// The FMI 2.0 base type and value reference behind an FMI 3.0 value reference (`None` for
/// `time` and numbers outside every block).
pub fn split(vr3: u32) -> Option<(BaseType, ValueRef)> {
    let base = match vr3 / VR_BLOCK {
        0 => BaseType::Real,
        1 => BaseType::Integer,
        2 => BaseType::Boolean,
        3 => BaseType::String,
        _ => return None,
    };
    Some((base, vr3 % VR_BLOCK))
}

/// Checks that the FMI 3.0 variables of `info` ([`View3`]) have distinct value references and
/// names, none named like the independent variable.
pub fn check(info: &ModelInfo) -> Result<(), String> {
    let view = View3::new(info)?;
    let mut refs = std::collections::HashSet::new();
    let mut names = std::collections::HashSet::new();
    for v in &view.vars {
        if v.name == TIME_NAME {
            return Err(format!(
                "{}: a variable is named `{TIME_NAME}`, the FMI 3.0 independent variable",
                info.identifier
            ));
        }
        if !refs.insert(v.vr) || v.vr == TIME_VR {
            return Err(format!(
                "{}: FMI 3.0 value reference {} of `{}` is used twice",
                info.identifier, v.vr, v.name
            ));
        }
        if !names.insert(v.name.as_str()) {
            return Err(format!(
                "{}: two FMI 3.0 variables are named `{}`",
                info.identifier, v.name
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::registry;

    #[test]
    fn every_model_maps_to_unique_fmi3_references_that_split_back() {
        for e in registry() {
            let info = (e.info)();
            check(info).unwrap();
            for p in &info.ports {
                assert_eq!(split(vr3(p).unwrap()), Some((p.ty.base(), p.vr)));
            }
        }
        assert_eq!(split(TIME_VR), None);
    }
}
