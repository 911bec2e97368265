//! The checked-in `modelDescription/<Model>.xml` files are the source of truth: each must equal
//! what the Rust variable table produces, and a second parser (`fmi-schema`) must accept it.
//!
//! Regenerate after changing a table: `cargo run --release --bin mbcosim -- model-descriptions`.

use std::path::PathBuf;

use mbcosim::fmi::{model_description, package};
use mbcosim::scene::registry;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("modelDescription")
}

/// The FMI 2.0 descriptions under `modelDescription/` and the FMI 3.0 ones under
/// `modelDescription/fmi3/` (docs/fmi3.md) must equal what the same tables produce.
#[test]
fn checked_in_descriptions_match_the_tables() {
    type Checker = fn(&mbcosim::scene::ModelEntry, &std::path::Path) -> Result<String, String>;
    let checkers: [(&str, Checker); 2] = [
        ("FMI 2.0", package::checked_description),
        ("FMI 3.0", package::checked_description3),
    ];
    let mut problems = Vec::new();
    for (version, check) in checkers {
        for e in registry() {
            if let Err(msg) = check(&e, &dir()) {
                problems.push(format!("{version}: {msg}"));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "{}\n(regenerate with `{}`)",
        problems.join("\n"),
        package::REGENERATE
    );
}

#[test]
fn no_description_without_a_registered_model() {
    let known: Vec<String> = registry()
        .iter()
        .map(|e| format!("{}.xml", (e.info)().identifier))
        .collect();
    for (folder, sub) in [(dir(), ""), (dir().join("fmi3"), "fmi3/")] {
        for f in std::fs::read_dir(folder).unwrap() {
            let f = f.unwrap();
            let name = f.file_name().to_string_lossy().into_owned();
            if sub.is_empty() && name == "fmi3" && f.path().is_dir() {
                continue;
            }
            assert!(
                known.contains(&name),
                "modelDescription/{sub}{name} belongs to no registered model"
            );
        }
    }
}

#[test]
fn a_second_parser_accepts_every_description() {
    use fmi::schema::fmi2::Fmi2ModelDescription;
    for e in registry() {
        let info = (e.info)();
        let xml = model_description::write(info).unwrap();
        let md: Fmi2ModelDescription = fmi::schema::deserialize(&xml).unwrap_or_else(|err| {
            panic!("{}: fmi-schema refused the XML: {err:?}", info.identifier)
        });
        assert_eq!(md.guid, info.guid);
        assert_eq!(md.model_variables.variables.len(), info.ports.len());
    }
}

#[test]
fn checked_in_default_scenes_match_the_tables() {
    use mbcosim::scene::scene_file;
    let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("resources/scenes");
    for e in registry() {
        let info = (e.info)();
        let path = scenes.join(format!("{}.toml", info.identifier));
        let text = std::fs::read_to_string(&path)
            .unwrap_or_else(|err| panic!("{}: {err}", path.display()));
        assert_eq!(
            text,
            scene_file::render(info),
            "{} is out of date (regenerate with `{}`)",
            path.display(),
            package::REGENERATE
        );
    }
}

/// FNV-1a (64 bit) of the interface an importer binds to: every variable's name, value
/// reference, causality, variability and base type, in table order (descriptions, units and
/// start values left out).
fn interface_fingerprint(info: &mbcosim::scene::port::ModelInfo) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in &info.ports {
        let ty = format!("{:?}", p.ty);
        let kind = ty.split(['(', '{', ' ']).next().unwrap_or("");
        let line = format!(
            "{}|{}|{:?}|{:?}|{kind}\n",
            p.name, p.vr, p.causality, p.variability
        );
        for b in line.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// The GUID must change whenever the variables an importer binds to change (a saved FMU state or
/// an importer's stored value references would otherwise be taken for the new interface): each
/// model's interface fingerprint is recorded here with its GUID. A change of the variables fails
/// this test until the model gets a new GUID and both are recorded anew.
#[test]
fn the_guid_changes_with_the_interface() {
    let recorded: [(&str, &str, u64); 4] = [
        (
            "PanelLock",
            "{0d731b86-81f5-4830-8d8c-4a13aed89c98}",
            0xc728_b9e9_7dd0_7a71,
        ),
        (
            "RopeBlock",
            "{72837ef2-af5d-4268-b848-abbcd5919726}",
            0x0c49_7f3b_347a_da4c,
        ),
        (
            "PidController",
            "{d3273808-9b6c-429a-8343-c6d18db11dab}",
            0x8c75_b021_d43a_1c76,
        ),
        (
            "SpringMassDamper",
            "{2cf7553d-8235-494e-a966-408337f98079}",
            0x40e5_63bc_3b75_f3e2,
        ),
    ];
    let mut problems = Vec::new();
    for e in registry() {
        let info = (e.info)();
        let fp = interface_fingerprint(info);
        match recorded.iter().find(|(id, _, _)| *id == info.identifier) {
            None => problems.push(format!(
                "{}: not recorded (add (\"{}\", \"{}\", {fp:#x}))",
                info.identifier, info.identifier, info.guid
            )),
            Some((_, guid, recorded_fp)) if *recorded_fp != fp => problems.push(format!(
                "{}: the variables changed (fingerprint {fp:#x}, recorded {recorded_fp:#x}); give the model a new GUID{} and record (\"{}\", \"<new guid>\", {fp:#x})",
                info.identifier,
                if *guid == info.guid { "" } else { " (it has one)" },
                info.identifier
            )),
            Some((_, guid, _)) if *guid != info.guid => problems.push(format!(
                "{}: the GUID changed to {} with the same variables; record it",
                info.identifier, info.guid
            )),
            Some(_) => {}
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// `rtol`, `atol` and `h_max` are declared once for every model (issue #43 item 3): both
/// mechanisms show the same range, the one docs/parameter_spec.md decides (written out here,
/// not read from the declaration). The tolerances' 0 is the integrator's own default
/// (docs/auto_integrator.md); the values between 0 and the floors are refused where they are
/// set (`a_tolerance_below_its_floor_is_refused_where_it_is_set_naming_it`).
#[test]
fn the_solver_knobs_have_one_range_in_every_model() {
    use mbcosim::scene::port::PortType;
    let decided = [("rtol", 0.0, 0.1), ("atol", 0.0, 1.0), ("h_max", 1e-4, 1.0)];
    for info in [
        mbcosim::scene::panel_lock::info(),
        mbcosim::scene::rope_block::info(),
    ] {
        for (name, lo, hi) in decided {
            let port = info.port_by_name(name).unwrap();
            let PortType::Real { min, max, open, .. } = port.ty else {
                panic!("{}: {name} is not Real", info.identifier);
            };
            assert_eq!(
                (min, max, open),
                (Some(lo), Some(hi), [false; 2]),
                "{}: {name}",
                info.identifier
            );
        }
    }
}

/// The finding: `--set rtol=50` on PanelLock ran. Through the model's port table (what
/// the FMU's set functions, the CLI and scene files call) it is now refused, naming rtol.
#[test]
fn a_tolerance_above_its_range_is_refused_naming_it() {
    use mbcosim::scene::native;
    for (name, mut model) in [
        (
            "PanelLock",
            Box::new(mbcosim::scene::panel_lock::PanelLockModel::new())
                as Box<dyn mbcosim::scene::CoSimModel>,
        ),
        (
            "RopeBlock",
            Box::new(mbcosim::scene::rope_block::RopeBlockModel::new()),
        ),
    ] {
        let err = native::set_by_name(model.as_mut(), "rtol", 50.0).unwrap_err();
        assert!(err.to_string().contains("rtol"), "{name}: {err}");
        native::set_by_name(model.as_mut(), "rtol", 0.1).unwrap();
    }
}

/// 0 means the integrator's own tolerance; a positive value below the floor (1e3 machine
/// epsilons for `rtol`, 1e-15 for `atol`) is refused where it is set, naming it and the floor,
/// and 0 itself runs.
#[test]
fn a_tolerance_below_its_floor_is_refused_where_it_is_set_naming_it() {
    use mbcosim::scene::native;
    let models = || -> [(&str, Box<dyn mbcosim::scene::CoSimModel>); 2] {
        [
            (
                "PanelLock",
                Box::new(mbcosim::scene::panel_lock::PanelLockModel::new()),
            ),
            (
                "RopeBlock",
                Box::new(mbcosim::scene::rope_block::RopeBlockModel::new()),
            ),
        ]
    };
    for (knob, below, floor) in [
        ("rtol", 1e-14, "2.220446049250313e-13"),
        ("atol", 1e-16, "1e-15"),
    ] {
        for (name, mut model) in models() {
            let err = native::set_by_name(model.as_mut(), knob, below)
                .unwrap_err()
                .to_string();
            assert!(err.contains(knob) && err.contains(floor), "{name}: {err}");
        }
        for (name, mut model) in models() {
            native::set_by_name(model.as_mut(), knob, 0.0).unwrap();
            model
                .initialize(0.0)
                .unwrap_or_else(|e| panic!("{name}: {knob} = 0: {e}"));
        }
    }
}
