//! The example rigs shipped in `examples/scenes/` (issue #21) hang at rest: each is accepted at
//! instantiation and settles with the hooks carrying the weight (`daf` = 1), and the two that
//! write out a built-in scenario give that scenario's outputs exactly.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::RopeBlockModel;
use mbcosim::scene::scene_file::apply_file;
use std::path::PathBuf;

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes")
        .join(name)
}

/// Every real output after initialization, with `segments` per sling, from the scene file (or
/// the scenario number without one).
fn outputs(file: Option<&str>, scenario: i32) -> (RopeBlockModel, Vec<(String, f64)>) {
    let mut m = RopeBlockModel::new();
    if let Some(f) = file {
        apply_file(&mut m, &scene(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    }
    let info = m.info();
    m.set_integer(info.port_by_name("scenario").unwrap().vr, scenario)
        .unwrap();
    m.set_integer(info.port_by_name("segments").unwrap().vr, 16)
        .unwrap();
    m.initialize(0.0)
        .unwrap_or_else(|e| panic!("{file:?}: {e}"));
    let out = info
        .ports
        .iter()
        .filter(|p| p.causality == mbcosim::scene::port::Causality::Output)
        .filter_map(|p| m.get_real(p.vr).ok().map(|v| (p.name.clone(), v)))
        .collect();
    (m, out)
}

fn get(out: &[(String, f64)], name: &str) -> f64 {
    out.iter().find(|(n, _)| n == name).unwrap().1
}

#[test]
fn every_example_scene_hangs_at_rest() {
    for f in [
        "lift.toml",
        "four_point_mesh.toml",
        "two_crane_turnover.toml",
        "spreader_bar.toml",
    ] {
        let (_, out) = outputs(Some(f), 0);
        let daf = get(&out, "daf");
        println!(
            "{f}: daf {daf:.9}, hook loads {:.0} / {:.0} N, utilisation of sling 0 {:.3}, angle {:.2} deg",
            get(&out, "hook0_load"),
            get(&out, "hook1_load"),
            get(&out, "sling0_utilisation"),
            get(&out, "sling0_angle").to_degrees()
        );
        assert!((daf - 1.0).abs() < 1e-6, "{f}: daf {daf}");
    }
}

#[test]
fn examples_of_the_built_in_scenarios_give_their_numbers() {
    for (f, scenario) in [("lift.toml", 0), ("two_crane_turnover.toml", 1)] {
        let (_, a) = outputs(Some(f), 0);
        let (_, b) = outputs(None, scenario);
        assert_eq!(a, b, "{f} against scenario {scenario}");
    }
}
