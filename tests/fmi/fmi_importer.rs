//! The packed PID FMU driven by a second, independent importer: the `fmi` crate (Rust).
//!
//! The FMU is packed into a temporary folder around the cdylib that `cargo test` has just built
//! next to this test executable (`target/<profile>/deps/libmbcosim.so`), so the test always
//! checks the current sources; `tests/run_all.sh` additionally checks `dist/` with fmpy.

use crate::common;

use std::path::PathBuf;

use common::packed::{Fmi, packed};

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::traits::{FmiImport, FmiInstance, FmiStatus};
use mbcosim::scene::{self, native};

/// The PID FMU, packed once per test process.
fn packed_pid() -> PathBuf {
    static FMU: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    FMU.get_or_init(|| packed("PidController", Fmi::V2, "fmi-importer"))
        .clone()
}

// PID value references (see modelDescription/PidController.xml).
const KP: u32 = 0;
const KI: u32 = 1;
const SETPOINT: u32 = 7;
const MEASUREMENT: u32 = 8;
const U: u32 = 9;

fn instance(import: &Fmi2Import, name: &str) -> InstanceCS {
    import
        .instantiate_cs(name, false, true)
        .expect("fmi2Instantiate")
}

fn start(inst: &mut InstanceCS, kp: f64) {
    inst.setup_experiment(None, 0.0, Some(5.0)).unwrap();
    inst.set_real(&[KP, KI, SETPOINT], &[kp, 0.5, 1.0]).unwrap();
    Common::enter_initialization_mode(inst).unwrap();
    Common::exit_initialization_mode(inst).unwrap();
}

fn u(inst: &mut InstanceCS) -> f64 {
    let mut v = [0.0];
    inst.get_real(&[U], &mut v).unwrap();
    v[0]
}

/// Steps `n` times with `h`, feeding back a first-order plant; returns the output bits.
fn run(inst: &mut InstanceCS, t0: f64, n: usize, h: f64) -> Vec<u64> {
    let mut y = 0.2;
    let mut out = Vec::new();
    for k in 0..n {
        inst.set_real(&[MEASUREMENT], &[y]).unwrap();
        inst.do_step(t0 + k as f64 * h, h, true).unwrap();
        let uk = u(inst);
        y += h * (uk - y);
        out.push(uk.to_bits());
    }
    out
}

#[test]
fn fmi_crate_runs_the_packed_fmu_like_the_native_model() {
    let import: Fmi2Import = fmi::import::from_path(packed_pid()).unwrap();
    assert_eq!(import.model_description().guid, scene::pid::info().guid);
    let mut inst = instance(&import, "pid");
    assert_eq!(Common::get_version(&inst), "2.0");
    inst.setup_experiment(None, 0.0, Some(1.0)).unwrap();
    inst.set_real(&[SETPOINT], &[2.0]).unwrap();
    Common::enter_initialization_mode(&mut inst).unwrap();
    Common::exit_initialization_mode(&mut inst).unwrap();
    let native = native::simulate(
        scene::pid::create().as_mut(),
        &[("setpoint".into(), 2.0)],
        1.0,
        0.1,
    )
    .unwrap();
    let expected = native.column("u").unwrap();
    let mut got = vec![u(&mut inst)];
    for k in 0..10 {
        inst.do_step(k as f64 * 0.1, (k + 1) as f64 * 0.1 - k as f64 * 0.1, true)
            .unwrap();
        got.push(u(&mut inst));
    }
    assert_eq!(got, expected, "same code path: bit-identical");
    assert_eq!(inst.last_successful_time().unwrap(), 1.0);
    assert!(!inst.terminated().unwrap());
    assert!(inst.do_step(1.0, 0.5, true).is_err(), "past the stop time");
    Common::reset(&mut inst).unwrap();
}

#[test]
fn fmu_state_rollback_serialization_and_reset_through_the_fmi_crate() {
    let import: Fmi2Import = fmi::import::from_path(packed_pid()).unwrap();
    let mut a = instance(&import, "a");
    start(&mut a, 2.0);
    run(&mut a, 0.0, 10, 0.01);
    let state = a.get_fmu_state().unwrap();
    let first = run(&mut a, 0.1, 50, 0.01);
    a.set_fmu_state(&state).ok().unwrap();
    assert_eq!(
        run(&mut a, 0.1, 50, 0.01),
        first,
        "rollback replays bit-identically"
    );

    let bytes = a.serialize_fmu_state(&state).unwrap();
    let mut b = instance(&import, "b");
    let restored = b.deserialize_fmu_state(&bytes).unwrap();
    b.set_fmu_state(&restored).ok().unwrap();
    assert_eq!(
        run(&mut b, 0.1, 50, 0.01),
        first,
        "restored in a second instance"
    );

    let mut corrupt = bytes.clone();
    corrupt[bytes.len() / 2] ^= 0x40;
    let mut c = instance(&import, "c");
    assert!(c.deserialize_fmu_state(&corrupt).is_err());
    assert!(c.deserialize_fmu_state(&bytes[..bytes.len() - 1]).is_err());

    Common::reset(&mut a).unwrap();
    start(&mut a, 2.0);
    let again = run(&mut a, 0.0, 10, 0.01);
    Common::reset(&mut b).unwrap();
    start(&mut b, 2.0);
    assert_eq!(
        run(&mut b, 0.0, 10, 0.01),
        again,
        "reset + re-initialization reproduces the run"
    );
}

#[test]
fn instances_are_independent_and_thread_safe() {
    let import: Fmi2Import = fmi::import::from_path(packed_pid()).unwrap();
    let serial: Vec<Vec<u64>> = [1.0, 3.0]
        .iter()
        .map(|kp| {
            let mut i = instance(&import, "serial");
            start(&mut i, *kp);
            run(&mut i, 0.0, 200, 0.01)
        })
        .collect();
    // alternating steps of two instances with different gains
    let (mut a, mut b) = (instance(&import, "a"), instance(&import, "b"));
    start(&mut a, 1.0);
    start(&mut b, 3.0);
    let (mut ra, mut rb) = (Vec::new(), Vec::new());
    for k in 0..200 {
        ra.extend(run_one(&mut a, k, &serial[0]));
        rb.extend(run_one(&mut b, k, &serial[1]));
    }
    assert_eq!(ra, serial[0]);
    assert_eq!(rb, serial[1]);
    // on threads
    let threads: Vec<_> = [1.0, 3.0]
        .into_iter()
        .map(|kp| {
            let path = packed_pid();
            std::thread::spawn(move || {
                let import: Fmi2Import = fmi::import::from_path(path).unwrap();
                let mut i = instance(&import, "thread");
                start(&mut i, kp);
                run(&mut i, 0.0, 200, 0.01)
            })
        })
        .collect();
    for (t, expected) in threads.into_iter().zip(&serial) {
        assert_eq!(&t.join().unwrap(), expected);
    }
}

/// One step of the same closed loop as [`run`], replaying the plant from the serial outputs.
fn run_one(inst: &mut InstanceCS, k: usize, serial: &[u64]) -> Option<u64> {
    let h = 0.01;
    let mut y = 0.2;
    for uk in &serial[..k] {
        y += h * (f64::from_bits(*uk) - y);
    }
    inst.set_real(&[MEASUREMENT], &[y]).unwrap();
    inst.do_step(k as f64 * h, h, true).unwrap();
    Some(u(inst).to_bits())
}

#[test]
fn misuse_is_refused_without_crashing() {
    let import: Fmi2Import = fmi::import::from_path(packed_pid()).unwrap();
    let mut i = instance(&import, "misuse");
    assert!(
        i.do_step(0.0, 0.1, true).is_err(),
        "doStep before initialization"
    );
    Common::reset(&mut i).unwrap();
    assert!(
        i.set_real(&[U], &[1.0]).is_err(),
        "outputs are not settable"
    );
    Common::reset(&mut i).unwrap();
    assert!(i.set_real(&[KP], &[f64::NAN]).is_err(), "NaN");
    Common::reset(&mut i).unwrap();
    start(&mut i, 1.0);
    assert!(i.do_step(0.0, -0.1, true).is_err(), "negative step");
    let name = FmiInstance::name(&i).to_string();
    assert_eq!(name, "misuse");
}
