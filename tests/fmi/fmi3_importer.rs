//! The packed FMI 3.0 PanelLock FMU driven by a second, independent importer: the `fmi` crate
//! (Rust, `fmi3` feature). Value references come from the imported modelDescription.xml (parsed
//! by `fmi-schema`), not from this crate's tables.
//!
//! The FMU is packed into a temporary folder around the cdylib that `cargo test` has just built
//! next to this test executable, so the test checks the current sources.

use crate::common;

use std::path::PathBuf;

use common::packed::{Fmi, packed};

use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{CoSimulation, Common, Fmi3Model, GetSet};
use fmi::traits::FmiImport;
use mbcosim::scene::{self, native};

/// The FMI 3.0 PanelLock FMU, packed once per test process.
fn packed_panel_lock() -> PathBuf {
    static FMU: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    FMU.get_or_init(|| packed("PanelLock", Fmi::V3, "fmi3-importer"))
        .clone()
}

/// Value reference of variable `name` in the imported description.
fn vr(import: &Fmi3Import, name: &str) -> u32 {
    import
        .model_description()
        .model_variables
        .iter_abstract()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable `{name}` in the FMI 3.0 description"))
        .value_reference()
}

#[test]
fn fmi_crate_runs_the_fmi3_fmu_like_the_native_model_and_returns_early_at_lock_up() {
    let import: Fmi3Import = fmi::import::from_path(packed_panel_lock()).unwrap();
    assert_eq!(import.model_description().fmi_version, "3.0");
    let (rtol, angle, lock) = (
        vr(&import, "rtol"),
        vr(&import, "hinge_angle"),
        vr(&import, "hinge_lock_time"),
    );

    // without early return: the native runner's numbers, bit for bit, through the FMI 3.0 API
    let mut inst = import
        .instantiate_cs("plain", false, false, false, false, &[])
        .unwrap();
    inst.set_float64(&[rtol], &[1e-6]).unwrap();
    inst.enter_initialization_mode(None, 0.0, None).unwrap();
    inst.exit_initialization_mode().unwrap();
    let native = native::simulate(
        scene::panel_lock::create().as_mut(),
        &[("rtol".into(), 1e-6)],
        1.0,
        0.25,
    )
    .unwrap();
    let expected: Vec<u64> = native
        .column("hinge0_angle")
        .unwrap()
        .iter()
        .map(|x| x.to_bits())
        .collect();
    let mut got = Vec::new();
    let mut angles = [0.0; 7];
    inst.get_float64(&[angle], &mut angles).unwrap();
    got.push(angles[0].to_bits());
    for k in 0..4 {
        let (mut ev, mut term, mut early, mut last) = (false, false, false, 0.0);
        let t = k as f64 * 0.25;
        inst.do_step(t, 0.25, true, &mut ev, &mut term, &mut early, &mut last)
            .unwrap();
        assert!(!ev && !term && !early && (last - (t + 0.25)).abs() < 1e-12);
        inst.get_float64(&[angle], &mut angles).unwrap();
        got.push(angles[0].to_bits());
    }
    assert_eq!(got, expected);

    // with early return: the step that contains the root lock-up ends there
    let mut inst = import
        .instantiate_cs("early", false, false, false, true, &[])
        .unwrap();
    inst.set_float64(&[rtol], &[1e-6]).unwrap();
    inst.enter_initialization_mode(None, 0.0, None).unwrap();
    inst.exit_initialization_mode().unwrap();
    let mut t = 0.0;
    let mut stops = Vec::new();
    while t < 6.0 - 1e-9 {
        let (mut ev, mut term, mut early, mut last) = (false, false, false, 0.0);
        inst.do_step(t, 0.5, true, &mut ev, &mut term, &mut early, &mut last)
            .unwrap();
        if early {
            assert!(t < last && last < t + 0.5);
            let mut locks = [0.0; 7];
            inst.get_float64(&[lock], &mut locks).unwrap();
            stops.push((last, locks[0]));
        }
        t = last;
    }
    assert_eq!(stops.len(), 1, "{stops:?}");
    let (at, lock_time) = stops[0];
    // docs/details.md: the root hinge locks at about 4.92 s; the step ends at the located time
    assert!((at - 4.9194).abs() < 1e-3, "{at}");
    assert!((at - lock_time).abs() < 2e-8, "{at} vs {lock_time}");
}
