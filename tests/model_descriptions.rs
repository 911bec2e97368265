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

#[test]
fn checked_in_descriptions_match_the_tables() {
    let mut problems = Vec::new();
    for e in registry() {
        if let Err(msg) = package::checked_description(&e, &dir()) {
            problems.push(msg);
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
    for f in std::fs::read_dir(dir()).unwrap() {
        let name = f.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            known.contains(&name),
            "modelDescription/{name} belongs to no registered model"
        );
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
