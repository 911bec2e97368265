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
//! - Families of outputs `<prefix><k>_<field>` are one array each ([`super::arrays3`]), with
//!   `<Dimension start="n"/>`; `ModelStructure` names the array.
//! - A Float64 variable's unit comes from a `Float64Type` named after the unit (`declaredType="m"`
//!   with `<Float64Type name="m" unit="m"/>`), not from a `unit` attribute of its own: both are
//!   FMI 3.0, and the type form is what the `fmi` crate's schema (0.8) reads (it refused the
//!   attribute form: "UnknownField FmiFloat64 unit").
//! - `ModelStructure` names variables by value reference: `Output` (with `dependencies=""`) and
//!   `InitialUnknown` (dependencies as value references).

use std::collections::BTreeMap;
use std::io;

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, Event};

use super::arrays3::{self, Var3, View3};
use super::logger::CATEGORIES;
use super::model_description::{
    Attrs, GENERATION_TOOL, Xml, default_initial, fmt_bool, fmt_real, initial_attr, write_items,
};
use super::units::{self, BASE_NAMES};
use super::variables3::{self, TIME_NAME, TIME_VR, Type3};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType};

/// The element and attributes of a variable (besides name, value reference, description,
/// causality, variability, initial, and its start value: see [`start_text`]).
fn type_attrs(p: &PortSpec) -> (&'static str, Attrs) {
    let mut a: Attrs = Vec::new();
    match &p.ty {
        PortType::Real { min, max, .. } => {
            if let Some(u) = p.unit {
                a.push(("declaredType", u.to_string()));
            }
            for (k, v) in [("min", min), ("max", max)] {
                if let Some(v) = v {
                    a.push((k, fmt_real(*v)));
                }
            }
        }
        PortType::Integer { min, max, .. } => {
            for (k, v) in [("min", min), ("max", max)] {
                if let Some(v) = v {
                    a.push((k, v.to_string()));
                }
            }
        }
        PortType::Boolean { .. } | PortType::String { .. } => {}
        PortType::Enumeration { type_name, .. } => {
            a.push(("declaredType", type_name.to_string()));
        }
    }
    (Type3::of(&p.ty).element(), a)
}

/// The start value of a port as XML text (a `start` attribute, or for a String the value of a
/// `<Start>` child); `None` without one.
fn start_text(p: &PortSpec) -> Option<String> {
    match &p.ty {
        PortType::Real { start, .. } => start.map(fmt_real),
        PortType::Integer { start, .. } | PortType::Enumeration { start, .. } => {
            start.map(|v| v.to_string())
        }
        PortType::Boolean { start } => start.map(|v| fmt_bool(v).to_string()),
        PortType::String { start } => start.map(str::to_string),
    }
}

/// Writes one FMI 3.0 variable: a scalar, or an array with `<Dimension start="n"/>` and its start
/// values (if any) in element order, space-separated (one `<Start>` per element for strings).
fn write_variable(x: &mut Xml, info: &ModelInfo, v: &Var3) -> io::Result<()> {
    let p = v.head(info);
    let mut a: Attrs = vec![
        ("name", v.name.clone()),
        ("valueReference", v.vr.to_string()),
        ("description", arrays3::description(info, v)),
        ("causality", p.causality.name().to_string()),
        ("variability", p.variability.name().to_string()),
    ];
    if let Some(init) = initial_attr(p) {
        a.push(("initial", init.to_string()));
    }
    let (element, ta) = type_attrs(p);
    a.extend(ta);
    let starts: Option<Vec<String>> = v
        .ports
        .iter()
        .map(|&i| start_text(&info.ports[i]))
        .collect();
    let is_string = matches!(p.ty, PortType::String { .. });
    if let (Some(st), false) = (&starts, is_string) {
        a.push(("start", st.join(" ")));
    }
    let string_starts = starts.filter(|_| is_string).unwrap_or_default();
    if !v.is_array() && string_starts.is_empty() {
        return x.empty(element, &a);
    }
    x.start(element, &a)?;
    if v.is_array() {
        x.empty("Dimension", &[("start", v.ports.len().to_string())])?;
    }
    for st in string_starts {
        x.empty("Start", &[("value", st)])?;
    }
    x.end(element)
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
    let view = &View3::new(info).map_err(io::Error::other)?;
    x.w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let mut root = vec![
        ("fmiVersion", s("3.0")),
        ("modelName", s(info.identifier)),
        ("instantiationToken", s(info.guid)),
        ("description", s(info.description)),
    ];
    root.extend(super::metadata::attributes());
    root.extend([
        ("generationTool", s(GENERATION_TOOL)),
        ("variableNamingConvention", s("structured")),
    ]);
    x.start("fmiModelDescription", &root)?;
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
    x.start("TypeDefinitions", &[])?;
    // a variable's unit through a type named after it (see the module documentation)
    for name in units.keys() {
        x.empty("Float64Type", &[("name", s(name)), ("unit", s(name))])?;
    }
    for (name, items) in enums {
        x.start("EnumerationType", &[("name", s(name))])?;
        write_items(x, items)?;
        x.end("EnumerationType")?;
    }
    x.end("TypeDefinitions")?;
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
            ("declaredType", s("s")),
        ],
    )?;
    for v in &view.vars {
        write_variable(x, info, v)?;
    }
    x.end("ModelVariables")?;
    x.start("ModelStructure", &[])?;
    for v in view
        .vars
        .iter()
        .filter(|v| v.head(info).causality == Causality::Output)
    {
        x.empty(
            "Output",
            &[
                ("valueReference", v.vr.to_string()),
                ("dependencies", String::new()),
            ],
        )?;
    }
    for v in view.vars.iter().filter(|v| {
        let p = v.head(info);
        matches!(
            p.causality,
            Causality::Output | Causality::CalculatedParameter
        ) && matches!(
            initial_attr(p).or(default_initial(p)),
            Some("calculated" | "approx")
        )
    }) {
        let mut attrs = vec![("valueReference", v.vr.to_string())];
        if let Some(refs) = initial_knowns(info, view, v)? {
            attrs.push(("dependencies", refs));
        }
        x.empty("InitialUnknown", &attrs)?;
    }
    x.end("ModelStructure")?;
    x.end("fmiModelDescription")
}

/// The FMI 3.0 value references (ascending, space-separated) of the knowns that the initial
/// value of `v` depends on: the union over its elements; `None` when an element depends on all
/// knowns.
fn initial_knowns(info: &ModelInfo, view: &View3, v: &Var3) -> io::Result<Option<String>> {
    let mut refs = Vec::new();
    for &i in &v.ports {
        let Some(names) = (info.initial_dependencies)(info, &info.ports[i]) else {
            return Ok(None);
        };
        for n in &names {
            let k = info
                .ports
                .iter()
                .position(|p| {
                    p.name == *n && matches!(p.causality, Causality::Parameter | Causality::Input)
                })
                .ok_or_else(|| {
                    io::Error::other(format!(
                        "`{}` declares an initial dependency on `{n}`, which is not one of its parameters or inputs",
                        info.identifier
                    ))
                })?;
            refs.push(view.var_of_port(k).vr);
        }
    }
    refs.sort_unstable();
    refs.dedup();
    Ok(Some(
        refs.iter()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(" "),
    ))
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

    #[test]
    fn an_array_has_one_reference_a_dimension_and_its_start_values_in_element_order() {
        let xml = write((crate::fmi::test_probe::probe_entry().info)()).unwrap();
        assert!(
            xml.contains(r#"<Float64 name="arm_x" valueReference="4" description="Array over k = 0..2, element k = `arm&lt;k&gt;_x`: Arm k: position"#),
            "{xml}"
        );
        assert!(xml.contains("<Dimension start=\"3\"/>"), "{xml}");
        assert!(!xml.contains("arm1_x") && !xml.contains(r#"valueReference="5""#));
        assert!(xml.contains(r#"<Output valueReference="4" dependencies=""/>"#));
        // start values (outputs of the models have none; an exact output here)
        let with_start = |name: &str, vr, start| {
            let mut p = PortSpec::real_output(name, vr, None, "Out.");
            p.ty = PortType::Real {
                start: Some(start),
                min: None,
                max: None,
                open: [false; 2],
                unit_note: None,
                floor: None,
            };
            p
        };
        let info = ModelInfo {
            identifier: "T",
            guid: "{t}",
            description: "T.",
            ports: vec![with_start("q1_v", 0, 0.5), with_start("q0_v", 1, 2.0)],
            default_stop_time: 1.0,
            default_step: 0.1,
            initial_dependencies: crate::scene::port::on_all_knowns,
        };
        let view = View3::new(&info).unwrap();
        let mut x = Xml {
            w: Writer::new_with_indent(Vec::new(), b' ', 2),
        };
        write_variable(&mut x, &info, &view.vars[0]).unwrap();
        let text = String::from_utf8(x.w.into_inner()).unwrap();
        assert!(
            text.contains(r#"valueReference="1""#)
                && text.contains(r#"initial="exact" start="2 0.5">"#),
            "{text}"
        );
    }
}
