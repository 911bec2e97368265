//! The `dependencies` of every initial unknown, checked against the model itself.
//!
//! In initialization mode an output may depend on the knowns: inputs and parameters (FMI 2.0:
//! "inputs, variables with initial=exact, independent variable"). The model description declares
//! these from the variable tables ([`ModelInfo::initial_dependencies`]). This test perturbs each
//! known, one at a time, in several base configurations of each model, initializes, and records
//! which initial unknowns change (bit for bit). Then:
//! - every observed dependency must be declared (an undeclared one would let an importer break
//!   a loop that exists);
//! - every declared dependency on an input must be observed in some configuration (an input
//!   dependency that does not exist makes importers such as OMSimulator iterate an algebraic
//!   loop that is not there);
//! - a declared dependency on a parameter need not show: some act only in configurations not
//!   perturbed here (a user mesh, a number of panels), so parameter declarations are supersets
//!   by physical group; the test prints how many did not show.

use std::collections::{BTreeMap, BTreeSet};

use mbcosim::scene::port::{BaseType, Causality, ModelInfo, PortSpec, PortType};
use mbcosim::scene::{self, CoSimModel, ModelEntry};

/// A port value of any type.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Real(f64),
    Int(i32),
    Bool(bool),
    Str(String),
}

fn get(m: &dyn CoSimModel, p: &PortSpec) -> Value {
    match p.ty.base() {
        BaseType::Real => Value::Real(m.get_real(p.vr).unwrap()),
        BaseType::Integer => Value::Int(m.get_integer(p.vr).unwrap()),
        BaseType::Boolean => Value::Bool(m.get_boolean(p.vr).unwrap()),
        BaseType::String => Value::Str(m.get_string(p.vr).unwrap()),
    }
}

fn set(m: &mut dyn CoSimModel, p: &PortSpec, v: &Value) -> Result<(), String> {
    match v {
        Value::Real(x) => m.set_real(p.vr, *x),
        Value::Int(x) => m.set_integer(p.vr, *x),
        Value::Bool(x) => m.set_boolean(p.vr, *x),
        Value::Str(x) => m.set_string(p.vr, x),
    }
    .map_err(|e| e.to_string())
}

/// Nearby valid values of a known, one on each side where there is room (for inputs also two
/// far ones); none where no
/// meaningful nearby value exists (strings: file names).
fn perturbed(p: &PortSpec, v: &Value) -> Vec<Value> {
    match (&p.ty, v) {
        (PortType::Real { min, max, .. }, Value::Real(x)) => {
            let inside = |y: &f64| min.is_none_or(|m| *y >= m) && max.is_none_or(|m| *y <= m);
            let mut candidates = if *x == 0.0 {
                vec![1e-3, -1e-3]
            } else {
                vec![x * 1.01, x * 0.99]
            };
            if p.causality == Causality::Input {
                // also far away: a flag such as `saturated` moves only with a large change
                candidates.extend(if *x == 0.0 {
                    [10.0, -10.0]
                } else {
                    [x * 10.0, -x]
                });
            }
            candidates
                .into_iter()
                .filter(inside)
                .map(Value::Real)
                .collect()
        }
        (PortType::Integer { min, max, .. }, Value::Int(x)) => [x + 1, x - 1]
            .into_iter()
            .filter(|y| min.is_none_or(|m| *y >= m) && max.is_none_or(|m| *y <= m))
            .map(Value::Int)
            .collect(),
        (PortType::Enumeration { items, .. }, Value::Int(x)) => (1..=items.len() as i32)
            .filter(|y| y != x)
            .map(Value::Int)
            .collect(),
        (PortType::Boolean { .. }, Value::Bool(b)) => vec![Value::Bool(!b)],
        _ => Vec::new(),
    }
}

fn knowns(info: &ModelInfo) -> Vec<&PortSpec> {
    info.ports
        .iter()
        .filter(|p| matches!(p.causality, Causality::Parameter | Causality::Input))
        .collect()
}

fn unknowns(info: &ModelInfo) -> Vec<&PortSpec> {
    info.ports
        .iter()
        .filter(|p| {
            matches!(
                p.causality,
                Causality::Output | Causality::CalculatedParameter
            )
        })
        .collect()
}

/// A fresh model with its data files in a temporary folder and `values` set by name.
fn model(entry: &ModelEntry, values: &[(&str, Value)]) -> Box<dyn CoSimModel> {
    let mut m = (entry.create)();
    if !entry.resources.is_empty() {
        let dir = std::env::temp_dir().join(format!(
            "mbcosim-deps-{}-{}",
            (entry.info)().identifier,
            std::process::id()
        ));
        for r in entry.resources {
            let path = dir.join(r.path);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, r.bytes).unwrap();
        }
        m.set_resource_dir(&dir).unwrap();
    }
    let info = (entry.info)();
    for (name, v) in values {
        let p = info.ports.iter().find(|p| p.name == *name).unwrap();
        set(m.as_mut(), p, v).unwrap();
    }
    m
}

/// The initial unknowns after initialization, or why it failed.
fn initial_values(mut m: Box<dyn CoSimModel>) -> Result<Vec<Value>, String> {
    m.initialize(0.0).map_err(|e| e.to_string())?;
    Ok(unknowns(m.info())
        .iter()
        .map(|p| get(m.as_ref(), p))
        .collect())
}

/// Observed dependencies (unknown -> knowns) in one base configuration, and the knowns whose
/// perturbation could not be initialized or has no meaningful nearby value.
fn observe(
    entry: &ModelEntry,
    base: &[(&str, Value)],
) -> (BTreeMap<String, BTreeSet<String>>, Vec<String>) {
    let info = (entry.info)();
    let reference = initial_values(model(entry, base)).unwrap();
    let outs = unknowns(info);
    let mut seen: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut unobservable = Vec::new();
    for k in knowns(info) {
        let values = perturbed(k, &get(model(entry, base).as_ref(), k));
        if values.is_empty() {
            unobservable.push(format!("{} (no nearby value)", k.name));
        }
        for v in values {
            let mut probe = model(entry, base);
            if set(probe.as_mut(), k, &v).is_err() {
                unobservable.push(format!("{} (refused {v:?})", k.name));
                continue;
            }
            match initial_values(probe) {
                Ok(vals) => {
                    for (o, (a, b)) in outs.iter().zip(reference.iter().zip(&vals)) {
                        let same = match (a, b) {
                            // last-bit noise is no dependency: the pure-Rust libm's sin/cos/atan2
                            // round trips are not exact where glibc's happened to be (docs/platforms.md)
                            (Value::Real(x), Value::Real(y)) => {
                                x.to_bits() == y.to_bits()
                                    || (x - y).abs() <= 1e-14 * x.abs().max(y.abs()).max(1.0)
                            }
                            _ => a == b,
                        };
                        if !same {
                            seen.entry(o.name.clone())
                                .or_default()
                                .insert(k.name.clone());
                        }
                    }
                }
                Err(e) => unobservable.push(format!("{} = {v:?} (not initialized: {e})", k.name)),
            }
        }
    }
    (seen, unobservable)
}

/// Base configurations per model: defaults plus settings that switch on more dependencies.
fn configurations(id: &str) -> Vec<Vec<(&'static str, Value)>> {
    use Value::*;
    match id {
        "PanelLock" => vec![
            vec![("root_motor_torque", Real(0.05))],
            vec![
                ("gravity_on", Bool(true)),
                ("free_satellite", Bool(true)),
                ("cable_loop", Bool(true)),
                ("root_motor_torque", Real(0.05)),
            ],
            vec![
                ("n_panels", Int(6)),
                ("gravity_on", Bool(true)),
                ("free_satellite", Bool(true)),
            ],
            vec![("n_panels", Int(1)), ("cable_loop", Bool(true))],
            // a centre of mass off the array's plane couples the in-plane satellite loads
            // (force x, y, torque z) with the out-of-plane reactions and back
            vec![
                ("free_satellite", Bool(true)),
                ("satellite_cg_y", Real(0.3)),
                ("satellite_cg_z", Real(0.5)),
            ],
            vec![("n_panels", Int(2)), ("gravity_on", Bool(true))],
            vec![
                ("flexible_panels", Bool(true)),
                ("n_modes", Int(2)),
                ("n_panels", Int(2)),
                ("gravity_on", Bool(true)),
            ],
        ],
        "RopeBlock" => vec![
            vec![("segments", Int(8))],
            vec![("segments", Int(8)), ("contact_outputs", Int(2))],
            vec![
                ("segments", Int(8)),
                ("scenario", Int(1)),
                ("bending", Bool(true)),
                ("drag", Bool(true)),
                ("ground_contact", Bool(true)),
                ("hook0_vz", Real(0.1)),
            ],
        ],
        "PidController" => vec![
            vec![("setpoint", Real(1.0)), ("measurement", Real(0.3))],
            vec![
                ("setpoint", Real(1.0)),
                ("measurement", Real(0.3)),
                ("u_max", Real(0.5)),
                ("kp", Real(2.0)),
            ],
            vec![
                ("setpoint", Real(-1.0)),
                ("measurement", Real(0.3)),
                ("u_min", Real(-0.5)),
                ("kp", Real(2.0)),
            ],
            vec![
                ("setpoint", Real(1.0)),
                ("measurement", Real(0.3)),
                ("kp", Real(100.0)),
            ],
        ],
        _ => vec![vec![]],
    }
}

#[test]
fn declared_initial_dependencies_match_perturbations() {
    for entry in scene::registry() {
        let info = (entry.info)();
        let mut observed: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        let mut unobservable = BTreeSet::new();
        for base in configurations(info.identifier) {
            let (seen, skipped) = observe(&entry, &base);
            for (o, ks) in seen {
                observed.entry(o).or_default().extend(ks);
            }
            unobservable.extend(skipped);
        }
        let inputs: BTreeSet<String> = info
            .ports
            .iter()
            .filter(|p| p.causality == Causality::Input)
            .map(|p| p.name.clone())
            .collect();
        let (mut declared_total, mut unseen, mut problems) = (0, 0, Vec::new());
        for u in unknowns(info) {
            let declared: BTreeSet<String> = (info.initial_dependencies)(info, u)
                .unwrap_or_else(|| {
                    panic!("{} {}: no dependencies declared", info.identifier, u.name)
                })
                .into_iter()
                .collect();
            declared_total += declared.len();
            let seen = observed.remove(&u.name).unwrap_or_default();
            for k in seen.difference(&declared) {
                problems.push(format!("{}: depends on `{k}`, not declared", u.name));
            }
            for k in declared.difference(&seen) {
                if inputs.contains(k) {
                    problems.push(format!("{}: declared on input `{k}`, not observed", u.name));
                } else {
                    unseen += 1;
                }
            }
        }
        eprintln!(
            "{}: {declared_total} declared dependencies, {unseen} on parameters not shown by a perturbation here; knowns not perturbed in some configuration: {unobservable:?}",
            info.identifier
        );
        assert!(
            problems.is_empty(),
            "{}: declared initial dependencies differ from the perturbations:\n{}",
            info.identifier,
            problems.join("\n")
        );
    }
}
