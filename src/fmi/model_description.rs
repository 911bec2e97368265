//! Writes `modelDescription.xml` (FMI 2.0 Co-Simulation) from a model's variable table.
//!
//! The output is deterministic (no date, variables in table order), so the files checked in
//! under `modelDescription/` can be compared byte for byte with what the table produces
//! (`tests/fmi/model_descriptions.rs`). Rules applied:
//!
//! - `UnitDefinitions`: every unit used, with its SI `BaseUnit` exponents ([`super::units`]).
//! - `TypeDefinitions`: one `SimpleType` per enumeration type.
//! - `LogCategories`: the categories of [`super::logger::CATEGORIES`].
//! - `ModelVariables`: start values only for parameters, inputs and constants (the others are
//!   `initial="calculated"`, the default, and get none); `initial` is written only where it
//!   differs from the default for its causality and variability.
//! - `ModelStructure`: every output under `Outputs` with `dependencies=""` (outputs change only in
//!   `fmi2DoStep`: no direct feedthrough), and every output and calculated parameter under
//!   `InitialUnknowns` with the `dependencies` the model declares
//!   ([`ModelInfo::initial_dependencies`]; none written where it declares "all knowns").
//!   Indices are 1-based positions in `ModelVariables`.

use std::collections::BTreeMap;
use std::io;

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};

use super::logger::CATEGORIES;
use super::metadata;
use super::units::{self, BASE_NAMES};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType, Variability};

pub use super::metadata::GENERATION_TOOL;

/// A real number as `xs:double` text: shortest round-trip form, no trailing `.0`.
pub fn fmt_real(v: f64) -> String {
    let s = format!("{v:?}");
    s.strip_suffix(".0").map(str::to_string).unwrap_or(s)
}

pub(crate) fn fmt_bool(b: bool) -> &'static str {
    if b { "true" } else { "false" }
}

pub(crate) type Attrs = Vec<(&'static str, String)>;

pub(crate) struct Xml {
    pub(crate) w: Writer<Vec<u8>>,
}

impl Xml {
    pub(crate) fn start(&mut self, name: &str, attrs: &[(&str, String)]) -> io::Result<()> {
        let mut e = BytesStart::new(name);
        for (k, v) in attrs {
            e.push_attribute((*k, v.as_str()));
        }
        self.w.write_event(Event::Start(e))
    }
    pub(crate) fn empty(&mut self, name: &str, attrs: &[(&str, String)]) -> io::Result<()> {
        let mut e = BytesStart::new(name);
        for (k, v) in attrs {
            e.push_attribute((*k, v.as_str()));
        }
        self.w.write_event(Event::Empty(e))
    }
    pub(crate) fn end(&mut self, name: &str) -> io::Result<()> {
        self.w.write_event(Event::End(BytesEnd::new(name)))
    }
    pub(crate) fn comment(&mut self, text: &str) -> io::Result<()> {
        self.w.write_event(Event::Comment(BytesText::new(text)))
    }
}

/// The `initial` attribute the standard assumes when none is written.
pub(crate) fn default_initial(p: &PortSpec) -> Option<&'static str> {
    match (p.causality, p.variability) {
        (_, Variability::Constant) => Some("exact"),
        (Causality::Parameter, _) => Some("exact"),
        (Causality::Input, _) => None,
        _ => Some("calculated"),
    }
}

/// The `<Item>`s of an enumeration type (values 1, 2, ... in order), the same in FMI 2.0's
/// `SimpleType` and FMI 3.0's `EnumerationType`.
pub(crate) fn write_items(x: &mut Xml, items: &[(&str, &str)]) -> io::Result<()> {
    for (k, (item, desc)) in items.iter().enumerate() {
        x.empty(
            "Item",
            &[
                ("name", item.to_string()),
                ("value", (k + 1).to_string()),
                ("description", desc.to_string()),
            ],
        )?;
    }
    Ok(())
}

/// The `initial` attribute this port needs written (`None` when the default applies).
pub(crate) fn initial_attr(p: &PortSpec) -> Option<&'static str> {
    let wanted = match (p.causality, p.variability, p.ty.has_start()) {
        (Causality::Input, _, _) => None,
        (Causality::Parameter, _, _) | (_, Variability::Constant, _) => Some("exact"),
        (Causality::CalculatedParameter, _, true) => Some("approx"),
        (_, _, true) => Some("exact"),
        (_, _, false) => Some("calculated"),
    };
    if wanted == default_initial(p) {
        None
    } else {
        wanted
    }
}

fn type_element(p: &PortSpec) -> (&'static str, Attrs) {
    let mut a: Attrs = Vec::new();
    let name = match &p.ty {
        PortType::Real {
            start, min, max, ..
        } => {
            if let Some(u) = p.unit {
                a.push(("unit", u.to_string()));
            }
            if let Some(v) = min {
                a.push(("min", fmt_real(*v)));
            }
            if let Some(v) = max {
                a.push(("max", fmt_real(*v)));
            }
            if let Some(v) = start {
                a.push(("start", fmt_real(*v)));
            }
            "Real"
        }
        PortType::Integer { start, min, max } => {
            for (k, v) in [("min", min), ("max", max), ("start", start)] {
                if let Some(v) = v {
                    a.push((k, v.to_string()));
                }
            }
            "Integer"
        }
        PortType::Boolean { start } => {
            if let Some(v) = start {
                a.push(("start", fmt_bool(*v).to_string()));
            }
            "Boolean"
        }
        PortType::String { start } => {
            if let Some(v) = start {
                a.push(("start", v.to_string()));
            }
            "String"
        }
        PortType::Enumeration {
            type_name, start, ..
        } => {
            a.push(("declaredType", type_name.to_string()));
            if let Some(v) = start {
                a.push(("start", v.to_string()));
            }
            "Enumeration"
        }
    };
    (name, a)
}

/// The units and enumeration types a valid table declares (by name), shared by the FMI 2.0 and
/// FMI 3.0 writers. Fails when the table is invalid ([`ModelInfo::validate`]), uses an unknown
/// unit, or declares one enumeration type with different items.
pub(crate) type Declared<'a> = (
    BTreeMap<&'a str, units::SiUnit>,
    BTreeMap<&'a str, &'a [(&'a str, &'a str)]>,
);

pub(crate) fn declared(info: &ModelInfo) -> Result<Declared<'_>, String> {
    info.validate().map_err(|errs| {
        format!(
            "{}: invalid variable table: {}",
            info.identifier,
            errs.join("; ")
        )
    })?;
    let mut units = BTreeMap::new();
    for p in &info.ports {
        if let Some(u) = p.unit {
            units.insert(
                u,
                units::parse(u).map_err(|e| format!("{}: `{}`: {e}", info.identifier, p.name))?,
            );
        }
    }
    let mut enums = BTreeMap::new();
    for p in &info.ports {
        if let PortType::Enumeration {
            type_name, items, ..
        } = &p.ty
            && enums
                .insert(*type_name, *items)
                .is_some_and(|old| old != *items)
        {
            return Err(format!(
                "{}: enumeration type {type_name} is declared with different items",
                info.identifier
            ));
        }
    }
    Ok((units, enums))
}

/// Writes the model description of `info` as a UTF-8 XML document.
///
/// Fails when the table is invalid ([`ModelInfo::validate`]) or uses an unknown unit.
pub fn write(info: &ModelInfo) -> Result<String, String> {
    let (units, enums) = declared(info)?;
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
    x.w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let s = |v: &str| v.to_string();
    let mut root = vec![
        ("fmiVersion", s("2.0")),
        ("modelName", s(info.identifier)),
        ("guid", s(info.guid)),
        ("description", s(info.description)),
    ];
    root.extend(metadata::attributes());
    root.extend([
        ("generationTool", s(GENERATION_TOOL)),
        ("variableNamingConvention", s("structured")),
        ("numberOfEventIndicators", s("0")),
    ]);
    x.start("fmiModelDescription", &root)?;
    x.empty(
        "CoSimulation",
        &[
            ("modelIdentifier", s(info.identifier)),
            ("needsExecutionTool", s("false")),
            ("canHandleVariableCommunicationStepSize", s("true")),
            ("canInterpolateInputs", s("false")),
            ("maxOutputDerivativeOrder", s("0")),
            ("canRunAsynchronuously", s("false")),
            ("canBeInstantiatedOnlyOncePerProcess", s("false")),
            ("canNotUseMemoryManagementFunctions", s("true")),
            ("canGetAndSetFMUstate", s("true")),
            ("canSerializeFMUstate", s("true")),
            ("providesDirectionalDerivative", s("false")),
        ],
    )?;
    if !units.is_empty() {
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
    }
    if !enums.is_empty() {
        x.start("TypeDefinitions", &[])?;
        for (name, items) in enums {
            x.start("SimpleType", &[("name", s(name))])?;
            x.start("Enumeration", &[])?;
            write_items(x, items)?;
            x.end("Enumeration")?;
            x.end("SimpleType")?;
        }
        x.end("TypeDefinitions")?;
    }
    x.start("LogCategories", &[])?;
    for (_, name, desc) in CATEGORIES {
        x.empty(
            "Category",
            &[
                ("name", name.to_string_lossy().into_owned()),
                ("description", s(desc)),
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
    for (k, p) in info.ports.iter().enumerate() {
        x.comment(&format!(" index {} ", k + 1))?;
        let mut a: Attrs = vec![
            ("name", p.name.clone()),
            ("valueReference", p.vr.to_string()),
            ("description", p.description.clone()),
            ("causality", s(p.causality.name())),
            ("variability", s(p.variability.name())),
        ];
        if let Some(init) = initial_attr(p) {
            a.push(("initial", s(init)));
        }
        x.start("ScalarVariable", &a)?;
        let (ty, ta) = type_element(p);
        x.empty(ty, &ta)?;
        x.end("ScalarVariable")?;
    }
    x.end("ModelVariables")?;
    x.start("ModelStructure", &[])?;
    let index_of = |c: Causality| {
        info.ports
            .iter()
            .enumerate()
            .filter(move |(_, p)| p.causality == c)
            .map(|(k, _)| k + 1)
    };
    let outputs: Vec<usize> = index_of(Causality::Output).collect();
    if !outputs.is_empty() {
        x.start("Outputs", &[])?;
        for k in &outputs {
            x.empty(
                "Unknown",
                &[("index", k.to_string()), ("dependencies", String::new())],
            )?;
        }
        x.end("Outputs")?;
    }
    let mut initial: Vec<usize> = index_of(Causality::Output)
        .chain(index_of(Causality::CalculatedParameter))
        .filter(|k| {
            matches!(
                initial_attr(&info.ports[k - 1]).or(default_initial(&info.ports[k - 1])),
                Some("calculated" | "approx")
            )
        })
        .collect();
    initial.sort_unstable();
    if !initial.is_empty() {
        x.start("InitialUnknowns", &[])?;
        for k in initial {
            let mut attrs = vec![("index", k.to_string())];
            if let Some(names) = (info.initial_dependencies)(info, &info.ports[k - 1]) {
                attrs.push(("dependencies", known_indices(info, &names)?));
            }
            x.empty("Unknown", &attrs)?;
        }
        x.end("InitialUnknowns")?;
    }
    x.end("ModelStructure")?;
    x.end("fmiModelDescription")
}

/// The 1-based `ModelVariables` indices of the knowns `names`, ascending, space-separated.
fn known_indices(info: &ModelInfo, names: &[String]) -> io::Result<String> {
    let mut indices = names
        .iter()
        .map(|n| {
            info.ports
                .iter()
                .position(|p| {
                    p.name == *n && matches!(p.causality, Causality::Parameter | Causality::Input)
                })
                .map(|i| i + 1)
                .ok_or_else(|| {
                    io::Error::other(format!(
                        "`{}` declares an initial dependency on `{n}`, which is not one of its parameters or inputs",
                        info.identifier
                    ))
                })
        })
        .collect::<io::Result<Vec<_>>>()?;
    indices.sort_unstable();
    indices.dedup();
    Ok(indices
        .iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(" "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::pid;

    #[test]
    fn pid_description_has_the_required_parts() {
        let xml = write(pid::info()).unwrap();
        for needle in [
            r#"fmiVersion="2.0""#,
            r#"canGetAndSetFMUstate="true""#,
            r#"canSerializeFMUstate="true""#,
            r#"canHandleVariableCommunicationStepSize="true""#,
            r#"canNotUseMemoryManagementFunctions="true""#,
            r#"needsExecutionTool="false""#,
            r#"<Unit name="1/s">"#,
            r#"<BaseUnit s="-1"/>"#,
            r#"<Category name="logSolver""#,
            r#"<Unknown index="11" dependencies=""/>"#,
            r#"<Real unit="s" min="0" start="0.01"/>"#,
            r#"<Real start="-1000000000"/>"#,
        ] {
            assert!(xml.contains(needle), "missing {needle}\n{xml}");
        }
        assert!(
            !xml.contains("initial="),
            "PID needs no explicit initial attributes"
        );
        assert_eq!(xml, write(pid::info()).unwrap(), "deterministic");
    }

    #[test]
    fn every_variable_kind_is_written_and_parsed_back() {
        use crate::scene::port::{PortSpec, PortType, Variability};
        const ITEMS: &[(&str, &str)] = &[
            ("bdf", "BDF order 1-5."),
            ("gen_alpha", "Generalized alpha."),
        ];
        let info = ModelInfo {
            identifier: "Kinds",
            guid: "{kinds}",
            description: "All kinds <&> of variables.",
            ports: vec![
                PortSpec {
                    name: "integrator".into(),
                    vr: 0,
                    causality: Causality::Parameter,
                    variability: Variability::Fixed,
                    ty: PortType::Enumeration {
                        type_name: "Integrator",
                        items: ITEMS,
                        start: Some(2),
                    },
                    unit: None,
                    description: "Time integrator.".into(),
                },
                PortSpec {
                    name: "n_nodes".into(),
                    vr: 1,
                    causality: Causality::Parameter,
                    variability: Variability::Fixed,
                    ty: PortType::Integer {
                        start: Some(10),
                        min: Some(2),
                        max: Some(2000),
                    },
                    unit: None,
                    description: "Rope nodes.".into(),
                },
                PortSpec {
                    name: "label".into(),
                    vr: 0,
                    causality: Causality::Parameter,
                    variability: Variability::Tunable,
                    ty: PortType::String { start: Some("a&b") },
                    unit: None,
                    description: "Label.".into(),
                },
                PortSpec::real_parameter(
                    "stiffness",
                    0,
                    Variability::Fixed,
                    1e9,
                    Some("N/m"),
                    "Contact stiffness.",
                )
                .with_min(0.0),
                PortSpec::real_input("torque", 1, 0.0, Some("N.m"), "Motor torque."),
                PortSpec {
                    name: "mass_total".into(),
                    vr: 2,
                    causality: Causality::CalculatedParameter,
                    variability: Variability::Fixed,
                    ty: PortType::Real {
                        start: None,
                        min: None,
                        max: None,
                        open: [false; 2],
                        unit_note: None,
                        floor: None,
                    },
                    unit: Some("kg"),
                    description: "Total mass.".into(),
                },
                PortSpec::real_output("hinge[1].angle", 3, Some("rad"), "Hinge angle."),
                PortSpec {
                    name: "energy".into(),
                    vr: 4,
                    causality: Causality::Local,
                    variability: Variability::Continuous,
                    ty: PortType::Real {
                        start: None,
                        min: None,
                        max: None,
                        open: [false; 2],
                        unit_note: None,
                        floor: None,
                    },
                    unit: Some("J"),
                    description: "Energy.".into(),
                },
                PortSpec {
                    name: "n_steps".into(),
                    vr: 2,
                    causality: Causality::Output,
                    variability: Variability::Discrete,
                    ty: PortType::Integer {
                        start: None,
                        min: None,
                        max: None,
                    },
                    unit: None,
                    description: "Internal steps taken.".into(),
                },
            ],
            default_stop_time: 2.0,
            default_step: 1e-3,
            initial_dependencies: crate::scene::port::on_all_knowns,
        };
        let xml = write(&info).unwrap();
        for needle in [
            r#"<SimpleType name="Integrator">"#,
            r#"<Item name="gen_alpha" value="2" description="Generalized alpha."/>"#,
            r#"<Enumeration declaredType="Integrator" start="2"/>"#,
            r#"<Integer min="2" max="2000" start="10"/>"#,
            r#"<String start="a&amp;b"/>"#,
            r#"description="All kinds &lt;&amp;&gt; of variables.""#,
            r#"<Unit name="N.m">"#,
            r#"<BaseUnit kg="1" m="2" s="-2"/>"#,
            r#"<BaseUnit kg="1" s="-2"/>"#,
            r#"<Unknown index="7" dependencies=""/>"#,
            r#"<Unknown index="9" dependencies=""/>"#,
            r#"<InitialUnknowns>"#,
            r#"<Unknown index="6"/>"#,
            r#"stepSize="0.001""#,
        ] {
            assert!(xml.contains(needle), "missing {needle}\n{xml}");
        }
        assert!(!xml.contains("initial="));
        let md: fmi::schema::fmi2::Fmi2ModelDescription = fmi::schema::deserialize(&xml).unwrap();
        assert_eq!(md.model_variables.variables.len(), 9);
        let mut bad = info.clone();
        bad.ports[4].unit = Some("furlong");
        assert!(write(&bad).unwrap_err().contains("furlong"));
        bad.ports[4].unit = None;
        bad.ports[3].ty = PortType::Real {
            start: None,
            min: None,
            max: None,
            open: [false; 2],
            unit_note: None,
            floor: None,
        };
        assert!(write(&bad).unwrap_err().contains("needs a start value"));
    }

    #[test]
    fn numbers_are_valid_xs_double() {
        assert_eq!(fmt_real(1.0), "1");
        assert_eq!(fmt_real(-1e9), "-1000000000");
        assert_eq!(fmt_real(0.01), "0.01");
        assert_eq!(fmt_real(1e300), "1e300");
        assert_eq!(fmt_real(2.5e-7), "2.5e-7");
    }
}
