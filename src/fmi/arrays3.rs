//! The FMI 3.0 variables of a model: the table's ports, with indexed families of outputs folded
//! into FMI 3.0 arrays (docs/fmi3.md, "Arrays"). FMI 2.0 keeps every port a scalar.
//!
//! A family is the set of ports named `<prefix><k>_<field>` with the same `prefix` (ASCII
//! letters) and `field`, `k` a decimal index without leading zeros (`contact3_normal`,
//! `sling0_tension_hook`, `panel2_mode1`). A family becomes one array `<prefix>_<field>` when
//!
//! - every member is an output (inputs and parameters stay scalars: an input is a coupling port
//!   that one connection drives, see docs/fmi3.md),
//! - it has at least two members whose indices are contiguous, `k0, k0 + 1, ..., k0 + n - 1`,
//! - the members agree on type (with bounds and enumeration type), causality, variability, unit
//!   and `initial`, and either all or none have a start value,
//! - and no port is already named `<prefix>_<field>`.
//!
//! Otherwise its members stay scalars. Element `j` of the array is member `k0 + j`; the array
//! takes the place of its first member in the table order and the FMI 3.0 value reference of the
//! member with index `k0`; the other members' references are not used in FMI 3.0.

use std::collections::{BTreeMap, HashMap, HashSet};

use super::model_description::initial_attr;
use super::variables3::{Type3, vr3};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType};

/// Where an array's elements come from: the table's family `<prefix><k>_<field>`,
/// `k = first, ..., first + n - 1`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Family {
    /// Letters before the index (`contact`).
    pub prefix: String,
    /// Text after the index and its underscore (`normal`).
    pub field: String,
    /// Index of element 0.
    pub first: u32,
}

/// One FMI 3.0 variable: a scalar port, or an array over a family of ports.
#[derive(Debug, Clone)]
pub struct Var3 {
    /// FMI 3.0 name (`contact_normal` for an array, the port's name for a scalar).
    pub name: String,
    /// FMI 3.0 value reference (unique over the model).
    pub vr: u32,
    /// Getter and setter family.
    pub ty: Type3,
    /// Positions in the table of the elements, in element order (one for a scalar).
    pub ports: Vec<usize>,
    /// The family of an array; `None` for a scalar.
    pub family: Option<Family>,
}

impl Var3 {
    /// True for an array variable.
    pub fn is_array(&self) -> bool {
        self.family.is_some()
    }

    /// The port of element 0 (the scalar's own port), which carries the shared attributes.
    pub fn head<'a>(&self, info: &'a ModelInfo) -> &'a PortSpec {
        &info.ports[self.ports[0]]
    }
}

/// The FMI 3.0 variables of one model, in `modelDescription.xml` order (without `time`).
#[derive(Debug, Clone)]
pub struct View3 {
    /// The variables.
    pub vars: Vec<Var3>,
    by_vr: HashMap<u32, usize>,
    /// FMI 3.0 reference a folded member would have as a scalar -> (array, element).
    folded: HashMap<u32, (usize, usize)>,
    /// For each port: its variable and element.
    of_port: Vec<(usize, usize)>,
}

impl View3 {
    /// The FMI 3.0 view of `info`; fails when a port's value reference does not fit the FMI 3.0
    /// mapping ([`vr3`]).
    pub fn new(info: &ModelInfo) -> Result<View3, String> {
        let refs = info
            .ports
            .iter()
            .map(vr3)
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| format!("{}: {e}", info.identifier))?;
        let arrays = families(info);
        // the array of each folded port: (family number, element)
        let mut member: HashMap<usize, (usize, usize)> = HashMap::new();
        for (a, (_, ports)) in arrays.iter().enumerate() {
            for (j, &i) in ports.iter().enumerate() {
                member.insert(i, (a, j));
            }
        }
        let mut view = View3 {
            vars: Vec::new(),
            by_vr: HashMap::new(),
            folded: HashMap::new(),
            of_port: vec![(0, 0); info.ports.len()],
        };
        let mut placed = HashSet::new();
        for (i, p) in info.ports.iter().enumerate() {
            let Some(&(a, _)) = member.get(&i) else {
                view.of_port[i] = (view.vars.len(), 0);
                view.vars.push(Var3 {
                    name: p.name.clone(),
                    vr: refs[i],
                    ty: Type3::of(&p.ty),
                    ports: vec![i],
                    family: None,
                });
                continue;
            };
            if !placed.insert(a) {
                continue;
            }
            let (family, ports) = &arrays[a];
            for (j, &e) in ports.iter().enumerate() {
                view.of_port[e] = (view.vars.len(), j);
                if j > 0 {
                    view.folded.insert(refs[e], (view.vars.len(), j));
                }
            }
            view.vars.push(Var3 {
                name: format!("{}_{}", family.prefix, family.field),
                vr: refs[ports[0]],
                ty: Type3::of(&p.ty),
                ports: ports.clone(),
                family: Some(family.clone()),
            });
        }
        view.by_vr = view
            .vars
            .iter()
            .enumerate()
            .map(|(n, v)| (v.vr, n))
            .collect();
        Ok(view)
    }

    /// The variable with FMI 3.0 value reference `vr`.
    pub fn get(&self, vr: u32) -> Option<&Var3> {
        self.by_vr.get(&vr).map(|&n| &self.vars[n])
    }

    /// The array and element that took over the port whose scalar FMI 3.0 reference would be
    /// `vr` (element 1 or later: element 0 keeps the reference), for messages.
    pub fn folded(&self, vr: u32) -> Option<(&Var3, usize)> {
        self.folded.get(&vr).map(|&(n, j)| (&self.vars[n], j))
    }

    /// The variable that holds port `i` of the table.
    pub fn var_of_port(&self, i: usize) -> &Var3 {
        &self.vars[self.of_port[i].0]
    }
}

/// The description of an array: which table ports its elements are, then their common
/// description with the index written `k` (the text most members share when they differ, e.g.
/// when member 0 lacks a note that the others carry).
pub fn description(info: &ModelInfo, var: &Var3) -> String {
    let Some(f) = &var.family else {
        return var.head(info).description.clone();
    };
    let texts: Vec<String> = var
        .ports
        .iter()
        .enumerate()
        .map(|(j, &i)| generic(&info.ports[i].description, &f.prefix, f.first as usize + j))
        .collect();
    let mut best = &texts[0];
    let mut best_count = 0;
    for t in &texts {
        let count = texts.iter().filter(|u| *u == t).count();
        if count > best_count {
            (best, best_count) = (t, count);
        }
    }
    let element = match f.first {
        0 => "k".to_string(),
        k0 => format!("k - {k0}"),
    };
    format!(
        "Array over k = {}..{}, element {element} = `{}<k>_{}`: {best}",
        f.first,
        f.first as usize + var.ports.len() - 1,
        f.prefix,
        f.field,
    )
}

/// `text` with each standalone number `k` that follows the word `prefix` (`Sling 3`), or
/// `prefix` and one more word (`Contact slot 3`), written `k`.
fn generic(text: &str, prefix: &str, k: usize) -> String {
    let key = k.to_string();
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut last = 0;
    let mut i = 0;
    while i < bytes.len() {
        if !bytes[i].is_ascii_digit() || (i > 0 && bytes[i - 1].is_ascii_alphanumeric()) {
            i += 1;
            continue;
        }
        let end = i + text[i..]
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(text.len() - i);
        let standalone = !text[end..].starts_with(|c: char| c.is_ascii_alphanumeric());
        if standalone && text[i..end] == key && follows_prefix(&text[..i], prefix) {
            out.push_str(&text[last..i]);
            out.push('k');
            last = end;
        }
        i = end;
    }
    out.push_str(&text[last..]);
    out
}

/// True when `before` ends with `<prefix> ` or `<prefix> <word> ` (case-insensitive prefix).
fn follows_prefix(before: &str, prefix: &str) -> bool {
    let trailing_word = |s: &str| {
        let start = s
            .char_indices()
            .rev()
            .find(|(_, c)| !c.is_ascii_alphabetic())
            .map_or(0, |(n, c)| n + c.len_utf8());
        (s[start..].to_string(), start)
    };
    let Some(before) = before.strip_suffix(' ') else {
        return false;
    };
    let (w1, start) = trailing_word(before);
    if w1.eq_ignore_ascii_case(prefix) {
        return true;
    }
    if w1.is_empty() {
        return false;
    }
    before[..start]
        .strip_suffix(' ')
        .is_some_and(|s| trailing_word(s).0.eq_ignore_ascii_case(prefix))
}

/// `(prefix, k, field)` of a name `<prefix><k>_<field>`.
pub fn indexed_name(name: &str) -> Option<(&str, u32, &str)> {
    let letters = name
        .find(|c: char| !c.is_ascii_alphabetic())
        .filter(|&n| n > 0)?;
    let rest = &name[letters..];
    let digits = rest.find(|c: char| !c.is_ascii_digit())?;
    let (index, tail) = rest.split_at(digits);
    let field = tail.strip_prefix('_').filter(|f| !f.is_empty())?;
    if index.is_empty() || (index.len() > 1 && index.starts_with('0')) {
        return None;
    }
    Some((&name[..letters], index.parse().ok()?, field))
}

/// The port type without its start value (what the elements of an array must share).
fn without_start(ty: &PortType) -> PortType {
    let mut t = ty.clone();
    match &mut t {
        PortType::Real { start, .. } => *start = None,
        PortType::Integer { start, .. } | PortType::Enumeration { start, .. } => *start = None,
        PortType::Boolean { start } => *start = None,
        PortType::String { start } => *start = None,
    }
    t
}

/// True when ports `a` and `b` may be elements of one array.
fn alike(a: &PortSpec, b: &PortSpec) -> bool {
    a.causality == b.causality
        && a.variability == b.variability
        && a.unit == b.unit
        && initial_attr(a) == initial_attr(b)
        && without_start(&a.ty) == without_start(&b.ty)
        && a.ty.has_start() == b.ty.has_start()
}

/// The families of `info` that become arrays, each with its ports in element order, in the
/// order of their first port in the table.
fn families(info: &ModelInfo) -> Vec<(Family, Vec<usize>)> {
    let mut groups: BTreeMap<(&str, &str), Vec<(u32, usize)>> = BTreeMap::new();
    for (i, p) in info.ports.iter().enumerate() {
        if p.causality != Causality::Output {
            continue;
        }
        if let Some((prefix, k, field)) = indexed_name(&p.name) {
            groups.entry((prefix, field)).or_default().push((k, i));
        }
    }
    let mut out = Vec::new();
    for ((prefix, field), mut members) in groups {
        members.sort_unstable();
        let first = members[0].0;
        let contiguous = members
            .iter()
            .enumerate()
            .all(|(j, &(k, _))| u64::from(k) == u64::from(first) + j as u64);
        let head = &info.ports[members[0].1];
        let name = format!("{prefix}_{field}");
        if members.len() < 2
            || !contiguous
            || !members.iter().all(|&(_, i)| alike(head, &info.ports[i]))
            || info.ports.iter().any(|p| p.name == name)
        {
            continue;
        }
        let ports: Vec<usize> = members.iter().map(|&(_, i)| i).collect();
        let family = Family {
            prefix: prefix.to_string(),
            field: field.to_string(),
            first,
        };
        out.push((family, ports));
    }
    out.sort_by_key(|(_, ports)| ports.iter().min().copied());
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::port::on_all_knowns;
    use crate::scene::registry;

    fn model(id: &str) -> &'static ModelInfo {
        registry()
            .iter()
            .map(|e| (e.info)())
            .find(|i| i.identifier == id)
            .unwrap()
    }

    fn element_names(info: &ModelInfo, v: &Var3) -> Vec<String> {
        v.ports
            .iter()
            .map(|&i| info.ports[i].name.clone())
            .collect()
    }

    #[test]
    fn families_of_outputs_become_arrays_and_inputs_stay_scalars() {
        let rope = model("RopeBlock");
        let view = View3::new(rope).unwrap();
        let var = |n: &str| view.vars.iter().find(|v| v.name == n);
        let normal = var("contact_normal").unwrap();
        assert_eq!(
            element_names(rope, normal),
            (0..8)
                .map(|k| format!("contact{k}_normal"))
                .collect::<Vec<_>>()
        );
        assert_eq!(
            normal.vr,
            vr3(rope.port_by_name("contact0_normal").unwrap()).unwrap()
        );
        assert_eq!(var("contact_slip").unwrap().ty, Type3::Int32);
        assert_eq!(var("sling_tension_hook").unwrap().ports.len(), 4);
        assert_eq!(var("hook_load").unwrap().ports.len(), 4);
        assert!(var("hook0_vz").is_some() && var("hook_vz").is_none());
        assert!(var("contact_outputs").is_some());
        let panel = model("PanelLock");
        let view = View3::new(panel).unwrap();
        let var = |n: &str| view.vars.iter().find(|v| v.name == n).unwrap();
        assert_eq!(var("panel_mode1").family.as_ref().unwrap().first, 1);
        assert_eq!(var("panel_mode1").ports.len(), 6);
        assert_eq!(var("hinge_latched").ty, Type3::Boolean);
        assert_eq!(var("hinge_latched").ports.len(), 7);
        // every port in exactly one variable, where var_of_port says
        for info in [rope, panel, model("PidController")] {
            let view = View3::new(info).unwrap();
            let mut seen = vec![0; info.ports.len()];
            for v in &view.vars {
                for &i in &v.ports {
                    seen[i] += 1;
                    assert_eq!(view.var_of_port(i).name, v.name);
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{}", info.identifier);
        }
    }

    #[test]
    fn families_that_break_a_condition_stay_scalars() {
        let out = |name: &str, vr, unit| PortSpec::real_output(name, vr, unit, "Out.");
        let info = ModelInfo {
            identifier: "T",
            guid: "{t}",
            description: "T.",
            ports: vec![
                out("a0_x", 0, Some("m")),
                out("a2_x", 1, Some("m")),
                out("b0_x", 2, Some("m")),
                out("b1_x", 3, Some("N")),
                out("c1_x", 4, None),
                out("d0_x", 5, None),
                out("d1_x", 6, None),
                out("d_x", 7, None),
                PortSpec::real_input("e0_u", 8, 0.0, None, "In."),
                PortSpec::real_input("e1_u", 9, 0.0, None, "In."),
                out("f1_y", 10, None),
                out("f0_y", 11, None),
            ],
            default_stop_time: 1.0,
            default_step: 0.1,
            initial_dependencies: on_all_knowns,
        };
        let view = View3::new(&info).unwrap();
        let arrays: Vec<_> = view.vars.iter().filter(|v| v.is_array()).collect();
        assert_eq!(arrays.len(), 1, "{arrays:?}");
        assert_eq!(arrays[0].name, "f_y");
        assert_eq!(element_names(&info, arrays[0]), ["f0_y", "f1_y"]);
        assert_eq!(arrays[0].vr, 11, "the reference of element 0");
        assert_eq!(view.folded(10).unwrap().1, 1);
        assert_eq!(view.vars.len(), info.ports.len() - 1);
    }

    #[test]
    fn indexed_names_split_into_prefix_index_and_field() {
        assert_eq!(
            indexed_name("contact3_normal"),
            Some(("contact", 3, "normal"))
        );
        assert_eq!(
            indexed_name("sling0_tension_hook"),
            Some(("sling", 0, "tension_hook"))
        );
        assert_eq!(indexed_name("panel12_mode1"), Some(("panel", 12, "mode1")));
        for plain in [
            "contact_outputs",
            "block_x",
            "n_panels",
            "hinge0",
            "hinge0_",
            "0_x",
            "hinge01_angle",
            "time",
        ] {
            assert_eq!(indexed_name(plain), None, "{plain}");
        }
    }

    #[test]
    fn the_index_after_the_family_word_becomes_k() {
        assert_eq!(
            generic("Sling 2: angle; 0 when the rig has no sling 2.", "sling", 2),
            "Sling k: angle; 0 when the rig has no sling k."
        );
        assert_eq!(
            generic("Contact slot 0: force; 0 for an empty slot.", "contact", 0),
            "Contact slot k: force; 0 for an empty slot."
        );
        assert_eq!(
            generic("Hinge 0 (0 = root): angle of hinge0_x, 10 N.", "hinge", 0),
            "Hinge k (0 = root): angle of hinge0_x, 10 N."
        );
        assert_eq!(generic("Hinge 12: x.", "hinge", 1), "Hinge 12: x.");
    }
}
