//! OSP-IS port files (`<Model>_OspModelDescription.xml`, OSP interface specification, model
//! description version 1.0): a model's power ports ([`crate::scene::power_port`]) as variable
//! groups, so that libcosim and other OSP tools can join two FMUs port to port
//! (`VariableGroupConnection` in `OspSystemStructure.xml`) and check that a force meets a
//! velocity. libcosim looks for the file beside the FMU (or beside the system structure file),
//! named after the FMU's `modelName`; `mbcosim pack` writes it beside each FMU
//! (docs/osp_ports.md).
//!
//! Layout, as the specification's schema fixes it: root `OspModelDescription` (namespace
//! [`NAMESPACE`], `version="1.0"`) with one `VariableGroups`; in it every
//! `LinearMechanicalPort` before every `AngularMechanicalPort` (the schema's sequence), each
//! holding its effort group (`Force` / `Torque`) and then its flow group (`LinearVelocity` /
//! `AngularVelocity`) with 1 to 3 `Variable ref=".." unit=".."` each. Group names are unique in
//! the file (libcosim finds nested groups by name alone): `<port>`, `<port> effort`,
//! `<port> flow`. Units refer to the model description's unit definitions.

use crate::scene::ModelEntry;
use crate::scene::power_port::{PortDomain, PowerPort};
use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};

/// The OSP-IS model description namespace, version 1.0.0.
pub const NAMESPACE: &str = "https://open-simulation-platform.com/OspModelDescription/1.0.0";

/// File name libcosim looks for beside the FMU of `model_name`.
pub fn file_name(model_name: &str) -> String {
    format!("{model_name}_OspModelDescription.xml")
}

/// Element names of a port and of its effort and flow groups.
fn elements(domain: PortDomain) -> [&'static str; 3] {
    match domain {
        PortDomain::LinearMechanical => ["LinearMechanicalPort", "Force", "LinearVelocity"],
        PortDomain::AngularMechanical => ["AngularMechanicalPort", "Torque", "AngularVelocity"],
    }
}

/// The OSP-IS file of `entry`, or `None` for a model without power ports. Every port is checked
/// against the variable table first ([`PowerPort::check`]); port names must be unique.
pub fn write(entry: &ModelEntry) -> Result<Option<String>, String> {
    let info = (entry.info)();
    let mut ports = (entry.power_ports)();
    if ports.is_empty() {
        return Ok(None);
    }
    for (k, p) in ports.iter().enumerate() {
        p.check(info)?;
        if ports[..k].iter().any(|q| q.name == p.name) {
            return Err(format!(
                "{}: two power ports named `{}`",
                info.identifier, p.name
            ));
        }
    }
    // the schema's sequence: linear ports first (stable: the model's order within a domain)
    ports.sort_by_key(|p| p.domain == PortDomain::AngularMechanical);
    let err = |e: std::io::Error| format!("{}: writing the OSP-IS file: {e}", info.identifier);
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))
        .map_err(err)?;
    let mut root = BytesStart::new("OspModelDescription");
    root.push_attribute(("xmlns", NAMESPACE));
    root.push_attribute(("version", "1.0"));
    w.write_event(Event::Start(root)).map_err(err)?;
    w.write_event(Event::Start(BytesStart::new("VariableGroups")))
        .map_err(err)?;
    for p in &ports {
        write_port(&mut w, p).map_err(err)?;
    }
    w.write_event(Event::End(BytesEnd::new("VariableGroups")))
        .map_err(err)?;
    w.write_event(Event::End(BytesEnd::new("OspModelDescription")))
        .map_err(err)?;
    let mut xml = String::from_utf8(w.into_inner()).map_err(|e| e.to_string())?;
    xml.push('\n');
    Ok(Some(xml))
}

fn write_port(w: &mut Writer<Vec<u8>>, p: &PowerPort) -> std::io::Result<()> {
    let [port, effort, flow] = elements(p.domain);
    let (effort_unit, flow_unit) = p.domain.units();
    let mut start = BytesStart::new(port);
    start.push_attribute(("name", p.name.as_str()));
    w.write_event(Event::Start(start))?;
    for (element, suffix, names, unit) in [
        (effort, "effort", &p.effort, effort_unit),
        (flow, "flow", &p.flow, flow_unit),
    ] {
        let mut group = BytesStart::new(element);
        let name = format!("{} {suffix}", p.name);
        group.push_attribute(("name", name.as_str()));
        w.write_event(Event::Start(group))?;
        for n in names {
            let mut v = BytesStart::new("Variable");
            v.push_attribute(("ref", n.as_str()));
            v.push_attribute(("unit", unit));
            w.write_event(Event::Empty(v))?;
        }
        w.write_event(Event::End(BytesEnd::new(element)))?;
    }
    w.write_event(Event::End(BytesEnd::new(port)))
}
