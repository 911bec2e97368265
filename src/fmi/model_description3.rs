//! Writes the FMI 3.0 Co-Simulation `modelDescription.xml` from the same variable table as the
//! FMI 2.0 one ([`super::model_description`]), with the same rules, deterministic output and
//! checked-in copies (`modelDescription/fmi3/<Model>.xml`). What differs from FMI 2.0:
//!
//! - `instantiationToken` is the FMI 2.0 GUID (one binary serves both, `fmi3InstantiateCoSimulation`
//!   finds the model by it); `fmiVersion="3.0"`.
//! - Variables are typed elements: Real -> `Float64`, Integer -> `Int32`, Enumeration ->
//!   `Enumeration` (accessed with `fmi3Get/SetInt64`), Boolean, String (start as a `<Start>`
//!   child); enumeration types are `EnumerationType` definitions.
//! - Value references are unique over the model ([`super::variables3`]), and the independent
//!   variable `time` comes first.
//! - `ModelStructure` names variables by value reference: `Output` (with `dependencies=""`) and
//!   `InitialUnknown` (dependencies as value references).

use std::collections::BTreeMap;
use std::io;

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, Event};

use super::logger::CATEGORIES;
use super::model_description::{
    Attrs, GENERATION_TOOL, Xml, default_initial, fmt_bool, fmt_real, initial_attr,
};
use super::units::{self, BASE_NAMES};
use super::variables3::{self, TIME_NAME, TIME_VR, Type3, vr3};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType};

/// The element and attributes of a variable (besides name, value reference, description,
/// causality, variability, initial), and a String start value (a `<Start>` child in FMI 3.0).
fn type_attrs(p: &PortSpec) -> (&'static str, Attrs, Option<&'static str>) {
    let mut a: Attrs = Vec::new();
    let mut string_start = None;
    match &p.ty {
        PortType::Real {
            start, min, max, ..
        } => {
            if let Some(u) = p.unit {
                a.push(("unit", u.to_string()));
            }
            for (k, v) in [("min", min), ("max", max), ("start", start)] {
                if let Some(v) = v {
                    a.push((k, fmt_real(*v)));
                }
            }
        }
        PortType::Integer { start, min, max } => {
            for (k, v) in [("min", min), ("max", max), ("start", start)] {
                if let Some(v) = v {
                    a.push((k, v.to_string()));
                }
            }
        }
        PortType::Boolean { start } => {
            if let Some(v) = start {
                a.push(("start", fmt_bool(*v).to_string()));
            }
        }
        PortType::String { start } => string_start = *start,
        PortType::Enumeration {
            type_name, start, ..
        } => {
            a.push(("declaredType", type_name.to_string()));
            if let Some(v) = start {
                a.push(("start", v.to_string()));
            }
        }
    }
    (Type3::of(&p.ty).element(), a, string_start)
}

/// Writes the FMI 3.0 model description of `info` as a UTF-8 XML document.
///
/// Fails when the table is invalid, uses an unknown unit, or does not map to FMI 3.0 value
/// references ([`variables3::check`]).
pub fn write(info: &ModelInfo) -> Result<String, String> {
    let (mut units, enums) = super::model_description::declared(info)?;
    variables3::check(info)?;
    // the independent variable is in seconds
    units.insert("s", units::parse("s")?);
    let mut x = Xml {
        w: Writer::new_with_indent(Vec::new(), b' ', 2),
    };
    write_document(&mut x, info, &units, &enums).map_err(|e| e.to_string())?;
    let mut text = String::from_utf8(x.w.into_inner()).map_err(|e| e.to_string())?;
    text.push('\n');
    Ok(text)
}

fn write_document(
    x: &mut Xml,
    info: &ModelInfo,
    units: &BTreeMap<&str, units::SiUnit>,
    enums: &BTreeMap<&str, &[(&str, &str)]>,
) -> io::Result<()> {
    let s = |v: &str| v.to_string();
    let vr = |p: &PortSpec| vr3(p).map_err(io::Error::other);
    x.w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    x.start(
        "fmiModelDescription",
        &[
            ("fmiVersion", s("3.0")),
            ("modelName", s(info.identifier)),
            ("instantiationToken", s(info.guid)),
            ("description", s(info.description)),
            ("generationTool", s(GENERATION_TOOL)),
            ("variableNamingConvention", s("structured")),
        ],
    )?;
    x.empty(
        "CoSimulation",
        &[
            ("modelIdentifier", s(info.identifier)),
            ("needsExecutionTool", s("false")),
            ("canBeInstantiatedOnlyOncePerProcess", s("false")),
            ("canGetAndSetFMUState", s("true")),
            ("canSerializeFMUState", s("true")),
            ("providesDirectionalDerivatives", s("false")),
            ("providesAdjointDerivatives", s("false")),
            ("providesPerElementDependencies", s("false")),
            ("canHandleVariableCommunicationStepSize", s("true")),
            ("maxOutputDerivativeOrder", s("0")),
            ("providesIntermediateUpdate", s("true")),
            ("mightReturnEarlyFromDoStep", s("true")),
            ("canReturnEarlyAfterIntermediateUpdate", s("true")),
            ("hasEventMode", s("false")),
            ("providesEvaluateDiscreteStates", s("false")),
        ],
    )?;
    x.start("UnitDefinitions", &[])?;
    for (name, u) in units {
        x.start("Unit", &[("name", s(name))])?;
        let mut a: Attrs = BASE_NAMES
            .iter()
            .zip(u.exponents)
            .filter(|(_, e)| *e != 0)
            .map(|(n, e)| (*n, e.to_string()))
            .collect();
        if u.factor != 1.0 {
            a.push(("factor", fmt_real(u.factor)));
        }
        x.empty("BaseUnit", &a)?;
        x.end("Unit")?;
    }
    x.end("UnitDefinitions")?;
    if !enums.is_empty() {
        x.start("TypeDefinitions", &[])?;
        for (name, items) in enums {
            x.start("EnumerationType", &[("name", s(name))])?;
            for (k, (item, desc)) in items.iter().enumerate() {
                x.empty(
                    "Item",
                    &[
                        ("name", s(item)),
                        ("value", (k + 1).to_string()),
                        ("description", s(desc)),
                    ],
                )?;
            }
            x.end("EnumerationType")?;
        }
        x.end("TypeDefinitions")?;
    }
    x.start("LogCategories", &[])?;
    for (_, name, desc) in CATEGORIES {
        x.empty(
            "Category",
            &[
                ("name", name.to_string_lossy().into_owned()),
                // the same categories; their texts name the FMI 3.0 statuses and functions
                ("description", desc.replace("fmi2", "fmi3")),
            ],
        )?;
    }
    x.end("LogCategories")?;
    x.empty(
        "DefaultExperiment",
        &[
            ("startTime", s("0")),
            ("stopTime", fmt_real(info.default_stop_time)),
            ("stepSize", fmt_real(info.default_step)),
        ],
    )?;
    x.start("ModelVariables", &[])?;
    x.empty(
        "Float64",
        &[
            ("name", s(TIME_NAME)),
            ("valueReference", TIME_VR.to_string()),
            ("description", s("Simulation time.")),
            ("causality", s("independent")),
            ("variability", s("continuous")),
            ("unit", s("s")),
        ],
    )?;
    for p in &info.ports {
        let mut a: Attrs = vec![
            ("name", p.name.clone()),
            ("valueReference", vr(p)?.to_string()),
            ("description", p.description.clone()),
            ("causality", s(p.causality.name())),
            ("variability", s(p.variability.name())),
        ];
        if let Some(init) = initial_attr(p) {
            a.push(("initial", s(init)));
        }
        let (element, ta, string_start) = type_attrs(p);
        a.extend(ta);
        match string_start {
            Some(v) => {
                x.start(element, &a)?;
                x.empty("Start", &[("value", s(v))])?;
                x.end(element)?;
            }
            None => x.empty(element, &a)?,
        }
    }
    x.end("ModelVariables")?;
    x.start("ModelStructure", &[])?;
    for p in info
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Output)
    {
        x.empty(
            "Output",
            &[
                ("valueReference", vr(p)?.to_string()),
                ("dependencies", String::new()),
            ],
        )?;
    }
    for p in info.ports.iter().filter(|p| {
        matches!(
            p.causality,
            Causality::Output | Causality::CalculatedParameter
        ) && matches!(
            initial_attr(p).or(default_initial(p)),
            Some("calculated" | "approx")
        )
    }) {
        let mut attrs = vec![("valueReference", vr(p)?.to_string())];
        if let Some(names) = (info.initial_dependencies)(info, p) {
            attrs.push(("dependencies", known_refs(info, &names)?));
        }
        x.empty("InitialUnknown", &attrs)?;
    }
    x.end("ModelStructure")?;
    x.end("fmiModelDescription")
}

/// The FMI 3.0 value references of the knowns `names`, ascending, space-separated.
fn known_refs(info: &ModelInfo, names: &[String]) -> io::Result<String> {
    let mut refs = names
        .iter()
        .map(|n| {
            let p = info
                .ports
                .iter()
                .find(|p| {
                    p.name == *n && matches!(p.causality, Causality::Parameter | Causality::Input)
                })
                .ok_or_else(|| {
                    io::Error::other(format!(
                        "`{}` declares an initial dependency on `{n}`, which is not one of its parameters or inputs",
                        info.identifier
                    ))
                })?;
            vr3(p).map_err(io::Error::other)
        })
        .collect::<io::Result<Vec<_>>>()?;
    refs.sort_unstable();
    refs.dedup();
    Ok(refs
        .iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(" "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::registry;

    #[test]
    fn fmi3_descriptions_have_the_required_parts() {
        for e in registry() {
            let info = (e.info)();
            let xml = write(info).unwrap();
            for needle in [
                r#"fmiVersion="3.0""#,
                &format!(r#"instantiationToken="{}""#, info.guid),
                &format!(r#"<CoSimulation modelIdentifier="{}""#, info.identifier),
                r#"canGetAndSetFMUState="true""#,
                r#"canSerializeFMUState="true""#,
                r#"<Float64 name="time" valueReference="4000000""#,
                r#"causality="independent""#,
                r#"<Output valueReference="#,
            ] {
                assert!(
                    xml.contains(needle),
                    "{}: missing {needle}",
                    info.identifier
                );
            }
            assert!(!xml.contains("ScalarVariable"));
            assert_eq!(xml, write(info).unwrap(), "deterministic");
        }
    }
}
