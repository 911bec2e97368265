//! The rope effect's memory records (`src/rope/memory.rs`, issue #43 item 4): every named field
//! sits at the index the serialized RopeBlock state has always stored it at, and a state saved
//! mid-run restores and continues bit for bit.

use mbcosim::rope::{CONTACT_MEM, HOOK_MEM, HookInit, HookMode, RopeMemory, SlipMode};
use mbcosim::scene::CoSimModel;
use mbcosim::scene::port::Causality;
use mbcosim::scene::rope_block::RopeBlockModel;
use nalgebra::Vector3;

/// A raw memory of two hooks and three contact nodes holding `i + 0.25` at index `i`.
fn raw() -> Vec<f64> {
    (0..2 * HOOK_MEM + 3 * CONTACT_MEM)
        .map(|i| i as f64 + 0.25)
        .collect()
}

/// The indices of the values that differ between `a` and `b`.
fn changed(a: &[f64], b: &[f64]) -> Vec<usize> {
    (0..a.len()).filter(|&i| a[i] != b[i]).collect()
}

#[test]
fn the_record_sizes_are_those_of_the_state_format() {
    assert_eq!((HOOK_MEM, CONTACT_MEM), (18, 7));
    assert_eq!(RopeMemory::<&[f64]>::len(2, 3), 57);
}

#[test]
fn each_contact_field_reads_and_writes_its_documented_index_only() {
    let m = raw();
    let mem = RopeMemory::new(&m[..], 2);
    // contact slot 1 starts after two hooks and one contact: 2 * 18 + 7 = 43
    let o = 43;
    let rec = mem.contact(1);
    let v = |k: usize| (o + k) as f64 + 0.25;
    assert_eq!(rec.sigma(), v(0));
    assert_eq!(rec.mode_code(), v(1));
    assert_eq!(rec.share(), v(2));
    assert_eq!(rec.anchor(), v(3));
    assert_eq!(rec.cap(), v(4));
    assert_eq!(rec.edge_slide(), v(5));
    assert_eq!(rec.mu(), v(6));
    // 44.25 decodes as sliding forward (the code's sign, anything beyond 0.5)
    assert_eq!(rec.mode(), SlipMode::SlipForward);

    type Set = fn(&mut mbcosim::rope::ContactRecord<&mut [f64]>);
    let setters: [(usize, Set); 7] = [
        (0, |r| r.set_sigma(-1.0)),
        (1, |r| r.set_mode(SlipMode::SlipBackward)),
        (2, |r| r.set_share(-1.0)),
        (3, |r| r.set_anchor(-1.0)),
        (4, |r| r.set_cap(-1.0)),
        (5, |r| r.set_edge_slide(-1.0)),
        (6, |r| r.set_mu(-1.0)),
    ];
    for (k, set) in setters {
        let mut w = raw();
        set(&mut RopeMemory::new(&mut w[..], 2).contact_mut(1));
        assert_eq!(changed(&m, &w), vec![o + k], "field {k}");
        assert_eq!(w[o + k], -1.0, "field {k}");
    }
}

#[test]
fn each_hook_field_reads_and_writes_its_documented_index_only() {
    let m = raw();
    let mem = RopeMemory::new(&m[..], 2);
    let o = HOOK_MEM; // hook 1
    let v = |k: usize| (o + k) as f64 + 0.25;
    let v3 = |k: usize| Vector3::new(v(k), v(k + 1), v(k + 2));
    let h = mem.hook(1).get();
    assert_eq!(h.position, v3(0));
    assert_eq!(h.velocity, v3(3));
    assert_eq!(h.target_velocity, v3(6));
    assert_eq!(h.t0, v(9));
    assert_eq!(h.payout, v(10));
    assert_eq!(h.payout_rate, v(11));
    assert_eq!(h.target_payout_rate, v(12));
    assert_eq!(h.ramp, v(13));
    assert_eq!(h.target_position, v3(14));
    // 35.25 is not the position code 1
    assert_eq!(h.mode, HookMode::Velocity);

    // written: every field at its index, nothing outside hook 1's record
    let w3 = |k: usize| Vector3::new(-(k as f64), -(k as f64) - 1.0, -(k as f64) - 2.0);
    let new = HookInit {
        position: w3(0),
        velocity: w3(3),
        target_velocity: w3(6),
        t0: -9.0,
        payout: -10.0,
        payout_rate: -11.0,
        target_payout_rate: -12.0,
        ramp: -13.0,
        mode: HookMode::Position,
        target_position: w3(14),
    };
    let mut w = raw();
    RopeMemory::new(&mut w[..], 2).hook_mut(1).set(&new);
    assert_eq!(changed(&m, &w), (o..o + HOOK_MEM).collect::<Vec<_>>());
    let expect: Vec<f64> = (0..17).map(|k| -(k as f64)).chain([1.0]).collect();
    assert_eq!(&w[o..o + HOOK_MEM], &expect[..]);
    assert_eq!(RopeMemory::new(&w[..], 2).hook(1).get(), new);
}

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info().port_by_name(name).unwrap().vr
}

/// Every real output.
fn outputs(m: &RopeBlockModel) -> Vec<f64> {
    m.info()
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Output)
        .filter_map(|p| m.get_real(p.vr).ok())
        .collect()
}

/// Steps of 0.05 s at which the fixture's state was taken and after which its outputs end.
const SAVED_AT: usize = 40;
const END: usize = 60;

/// The lift with 8 segments per sling: hoisted at 0.3 m/s from 0.5 s, pay-out 0.05 m/s on hook
/// 0 from 1 s, hook 0 moved sideways at 0.4 m/s from 1.5 s (the slings slide along the deck
/// edges, so every contact field is in use), before step `k`.
fn drive(m: &mut RopeBlockModel, k: usize) {
    let t = k as f64 * 0.05;
    if k == 10 {
        m.set_real(vr(m, "hook0_vz"), 0.3).unwrap();
    }
    if k == 20 {
        m.set_real(vr(m, "hook0_payout_rate"), 0.05).unwrap();
    }
    if k == 30 {
        m.set_real(vr(m, "hook0_vx"), 0.4).unwrap();
    }
    m.do_step(t, 0.05).unwrap();
}

fn fresh() -> RopeBlockModel {
    let mut m = RopeBlockModel::new();
    m.set_integer(vr(&m, "segments"), 8).unwrap();
    m
}

/// A state saved mid-run (the lift above, after step [`SAVED_AT`]) restores into a fresh model to
/// the same bytes and continues with every output bit-identical to the run that was not
/// interrupted. (A state written before the records, at 6271529, did the same on branch `mem`;
/// a stored state holds the port values of one interface, so it is not kept as a fixture: the
/// index tests above pin the layout.)
#[test]
fn a_saved_state_restores_to_the_same_bytes_and_continues_bit_for_bit() {
    let mut live = fresh();
    live.initialize(0.0).unwrap();
    for k in 0..SAVED_AT {
        drive(&mut live, k);
    }
    let bytes = live.serialize();
    let mut restored = fresh();
    restored.deserialize(&bytes).unwrap();
    assert!(
        restored.serialize() == bytes,
        "serialized again, the bytes differ"
    );
    for k in SAVED_AT..END {
        drive(&mut live, k);
        drive(&mut restored, k);
        let (a, b): (Vec<u64>, Vec<u64>) = (
            outputs(&live).iter().map(|x| x.to_bits()).collect(),
            outputs(&restored).iter().map(|x| x.to_bits()).collect(),
        );
        assert_eq!(a, b, "outputs after step {k}");
    }
}
