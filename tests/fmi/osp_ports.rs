//! OSP-IS port files (issue #46 item 4, docs/osp_ports.md): every model's power ports, written
//! as `<Model>_OspModelDescription.xml`, read back and held to the OSP-IS model description
//! schema's rules (written out here from the specification, not from the writer) and to the
//! model's variable table: namespace and version, `VariableGroups` with linear ports before
//! angular ones, each port an effort group then a flow group of 1-3 variables, names unique,
//! every `ref` a variable with the group's unit, effort and flow of opposite causalities.

use mbcosim::fmi::osp;
use mbcosim::scene::port::{Causality, ModelInfo};
use mbcosim::scene::power_port::{PortDomain, PowerPort};
use mbcosim::scene::registry;
use quick_xml::Reader;
use quick_xml::XmlVersion;
use quick_xml::events::Event;

/// A port as read: name, effort variables, flow variables.
type Port = (String, Vec<String>, Vec<String>);

/// The ports each model declares, written out: (model, ports).
fn expected() -> Vec<(&'static str, Vec<Port>)> {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let mut rope = Vec::new();
    for k in 0..4 {
        let h = |x: &str| format!("hook{k}_{x}");
        rope.push((
            format!("hook{k}"),
            vec![h("fx"), h("fy"), h("fz")],
            vec![h("vx"), h("vy"), h("vz")],
        ));
        rope.push((
            format!("hook{k}_winch"),
            vec![h("winch_force")],
            vec![h("payout_rate")],
        ));
    }
    vec![
        (
            "PanelLock",
            vec![(
                "root_motor".into(),
                s(&["root_motor_torque"]),
                s(&["hinge0_rate"]),
            )],
        ),
        ("PidController", vec![]),
        ("RopeBlock", rope),
        (
            "SpringMassDamper",
            vec![("mass".into(), s(&["F"]), s(&["v"]))],
        ),
    ]
}

/// One element of the file: name, attributes, children (variables have none).
#[derive(Debug)]
struct Element {
    name: String,
    attrs: Vec<(String, String)>,
    children: Vec<Element>,
}

impl Element {
    fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

fn parse(xml: &str) -> Element {
    let mut reader = Reader::from_str(xml);
    let mut stack: Vec<Element> = Vec::new();
    let open = |e: &quick_xml::events::BytesStart| Element {
        name: e.name().as_ref().to_string(),
        attrs: e
            .attributes()
            .map(|a| {
                let a = a.unwrap();
                (
                    a.key.as_ref().to_string(),
                    a.normalized_value(XmlVersion::Implicit1_0)
                        .unwrap()
                        .into_owned(),
                )
            })
            .collect(),
        children: Vec::new(),
    };
    loop {
        match reader.read_event().unwrap() {
            Event::Start(e) => stack.push(open(&e)),
            Event::Empty(e) => {
                let el = open(&e);
                stack.last_mut().expect("an empty root").children.push(el);
            }
            Event::End(_) => {
                let done = stack.pop().unwrap();
                match stack.last_mut() {
                    Some(parent) => parent.children.push(done),
                    None => return done,
                }
            }
            Event::Eof => panic!("unclosed document"),
            Event::Text(t) => assert!(t.as_ref().trim_ascii().is_empty(), "text in the file"),
            _ => {}
        }
    }
}

/// The schema's and the specification's rules, and the variable table's: returns the ports read.
fn check_file(xml: &str, info: &ModelInfo) -> Vec<Port> {
    let id = info.identifier;
    let root = parse(xml);
    assert_eq!(root.name, "OspModelDescription", "{id}");
    assert_eq!(root.attr("xmlns"), Some(osp::NAMESPACE), "{id}");
    assert_eq!(
        root.attr("version"),
        Some("1.0"),
        "{id}: the schema fixes 1.0"
    );
    assert_eq!(root.children.len(), 1, "{id}: one VariableGroups");
    let groups = &root.children[0];
    assert_eq!(groups.name, "VariableGroups", "{id}");
    let mut names = std::collections::HashSet::new();
    let mut seen_angular = false;
    let mut ports = Vec::new();
    for port in &groups.children {
        let (effort, flow, effort_unit, flow_unit) = match port.name.as_str() {
            "LinearMechanicalPort" => {
                assert!(
                    !seen_angular,
                    "{id}: the schema's sequence puts linear ports first"
                );
                ("Force", "LinearVelocity", "N", "m/s")
            }
            "AngularMechanicalPort" => {
                seen_angular = true;
                ("Torque", "AngularVelocity", "N.m", "rad/s")
            }
            other => panic!("{id}: unexpected group {other}"),
        };
        let name = port.attr("name").expect("a port has a name").to_string();
        assert!(names.insert(name.clone()), "{id}: group name {name} twice");
        assert_eq!(port.children.len(), 2, "{id}: {name}: effort and flow");
        let mut causality = Vec::new();
        let mut refs = Vec::new();
        for (group, element, unit) in [
            (&port.children[0], effort, effort_unit),
            (&port.children[1], flow, flow_unit),
        ] {
            assert_eq!(group.name, element, "{id}: {name}");
            let gname = group.attr("name").expect("a group has a name").to_string();
            assert!(
                names.insert(gname.clone()),
                "{id}: group name {gname} twice"
            );
            assert!(
                (1..=3).contains(&group.children.len()),
                "{id}: {gname}: 1 to 3 variables"
            );
            let mut these = Vec::new();
            for v in &group.children {
                assert_eq!(v.name, "Variable", "{id}: {gname}");
                let r = v.attr("ref").expect("a variable has a ref");
                assert_eq!(v.attr("unit"), Some(unit), "{id}: {gname}: {r}");
                let p = info
                    .port_by_name(r)
                    .unwrap_or_else(|| panic!("{id}: {gname}: no variable {r}"));
                assert_eq!(p.unit, Some(unit), "{id}: {r} in the model description");
                causality.push((group.name.clone(), p.causality));
                these.push(r.to_string());
            }
            refs.push(these);
        }
        assert_eq!(
            refs[0].len(),
            refs[1].len(),
            "{id}: {name}: as many efforts as flows"
        );
        let of = |g: &str| -> Vec<Causality> {
            causality
                .iter()
                .filter(|(n, _)| n == g)
                .map(|(_, c)| *c)
                .collect()
        };
        let (e, f) = (of(effort), of(flow));
        assert!(
            e.iter().all(|c| *c == e[0]) && f.iter().all(|c| *c == f[0]),
            "{id}: {name}: one causality per group"
        );
        assert!(
            matches!(
                (e[0], f[0]),
                (Causality::Input, Causality::Output) | (Causality::Output, Causality::Input)
            ),
            "{id}: {name}: effort {:?} and flow {:?} must be input against output",
            e[0],
            f[0]
        );
        let flow_refs = refs.pop().unwrap();
        let effort_refs = refs.pop().unwrap();
        ports.push((name, effort_refs, flow_refs));
    }
    ports
}

#[test]
fn every_model_writes_its_power_ports_as_the_osp_is_schema_and_its_variables_require() {
    let expected = expected();
    assert_eq!(
        registry().len(),
        expected.len(),
        "a model without an entry here"
    );
    for e in registry() {
        let info = (e.info)();
        let (_, want) = expected
            .iter()
            .find(|(id, _)| *id == info.identifier)
            .unwrap_or_else(|| panic!("{}: no expected ports", info.identifier));
        match osp::write(&e).unwrap() {
            None => assert!(want.is_empty(), "{}: no file", info.identifier),
            Some(xml) => assert_eq!(&check_file(&xml, info), want, "{}", info.identifier),
        }
    }
}

/// The checks the writer runs refuse what the schema or the specification would: a unit that is
/// not the domain's, effort and flow of one causality, unequal component counts, more than three
/// components, an unknown variable.
#[test]
fn ill_formed_ports_are_refused_naming_the_port() {
    let info = mbcosim::scene::rope_block::info();
    let lin = PortDomain::LinearMechanical;
    let bad = [
        (
            PowerPort::new(
                "p",
                PortDomain::AngularMechanical,
                &["hook0_fx"],
                &["hook0_vx"],
            ),
            "unit",
        ),
        (
            PowerPort::new("p", lin, &["hook0_fx"], &["hook0_fy"]),
            "unit",
        ),
        (
            PowerPort::new("p", lin, &["hook0_fx", "hook0_fy"], &["hook0_vx"]),
            "as many",
        ),
        (
            PowerPort::new(
                "p",
                lin,
                &["hook0_fx", "hook0_fy", "hook0_fz", "hook1_fx"],
                &["hook0_vx", "hook0_vy", "hook0_vz", "hook1_vx"],
            ),
            "1 to 3",
        ),
        (
            PowerPort::new("p", lin, &["hook0_fx"], &["hook9_vx"]),
            "no variable",
        ),
        (
            PowerPort::new("p", lin, &["hook0_fx"], &["hook0_x"]),
            "unit",
        ),
        (
            PowerPort::new("p", lin, &["hook0_winch_force"], &["hook1_load"]),
            "unit",
        ),
    ];
    for (port, says) in bad {
        let err = port.check(info).unwrap_err();
        assert!(err.contains("`p`") && err.contains(says), "{port:?}: {err}");
    }
    // effort and flow both outputs: the hook's force against the hook's position rate is not
    // a variable, so take two outputs with the right units from SpringMassDamper
    let smd = mbcosim::scene::spring_mass_damper::info();
    let err = PowerPort::new("p", lin, &["spring_force"], &["v"])
        .check(smd)
        .unwrap_err();
    assert!(err.contains("one must be an input"), "{err}");
    PowerPort::new("p", lin, &["F"], &["v"]).check(smd).unwrap();
}
