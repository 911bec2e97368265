//! Snapshots replay bit for bit: a clone of a running simulation, and a fresh simulation restored
//! from the plain-number state and integrator memory (the serialized form), continue exactly
//! like the original, with Newton matrices kept across communication steps.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};

fn scene(kind: IntegratorKind) -> PanelLock {
    let p = PanelLockParams {
        integrator: Some(kind),
        settings: Settings {
            rtol: 1e-5,
            atol: 1e-7,
            h_max: 0.02,
            ..PanelLockParams::default().settings
        },
        ..PanelLockParams::default()
    };
    PanelLock::new(p).unwrap()
}

fn run(s: &mut PanelLock, from: usize, to: usize) {
    for k in from..to {
        // a motor torque that changes at every communication point (as from a controller)
        s.set_motor_torque(0.05 * ((k as f64) * 0.7).sin()).unwrap();
        s.advance_to(0.05 * (k + 1) as f64).unwrap();
    }
}

#[test]
fn clones_and_restored_states_continue_bit_for_bit() {
    for kind in IntegratorKind::ALL {
        let mut a = scene(kind);
        run(&mut a, 0, 120); // through the root-hinge lock-up at 4.9 s
        let mut b = a.clone();
        let (state, memory) = (a.sim.state.clone(), a.sim.integrator_memory());
        let mut c = scene(kind);
        c.sim.restore(state, &memory).unwrap();
        // the motor input is part of the model inputs; restore it as an importer would
        c.sim.system.inputs.clone_from(&a.sim.system.inputs);
        run(&mut a, 120, 200);
        run(&mut b, 120, 200);
        run(&mut c, 120, 200);
        let bits = |s: &PanelLock| {
            s.sim
                .state
                .q
                .iter()
                .chain(&s.sim.state.v)
                .chain(&s.sim.state.memory)
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&a), bits(&b), "{}: clone diverged", kind.name());
        assert_eq!(
            bits(&a),
            bits(&c),
            "{}: restored state diverged",
            kind.name()
        );
        assert!(
            a.outputs().hinges[0].engaged,
            "the window must include a lock-up"
        );
    }
}

#[test]
fn corrupt_integrator_memory_is_refused() {
    let mut a = scene(IntegratorKind::Bdf);
    run(&mut a, 0, 10);
    let (state, memory) = (a.sim.state.clone(), a.sim.integrator_memory());
    let mut c = scene(IntegratorKind::Bdf);
    for cut in [0, 1, 5, memory.len() / 2, memory.len() - 1] {
        let e = c.sim.restore(state.clone(), &memory[..cut]).unwrap_err();
        assert!(
            e.contains("truncated or corrupt") || e.contains("truncated"),
            "{e}"
        );
    }
    let mut wrong = state.clone();
    wrong.q.pop();
    assert!(
        c.sim
            .restore(wrong, &memory)
            .unwrap_err()
            .contains("does not belong")
    );
}
