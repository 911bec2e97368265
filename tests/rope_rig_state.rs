//! The rig in serialized FMU states (issue #21): a state restores into an instance with the same
//! effective rig (also when one instance has the built-in lift and the other the same rig written
//! out in a scene file: values count, not files) and continues bit for bit; into an instance with
//! another rig it is refused, naming the parts that differ. The block's start pose in `[block]`
//! is read, checked and used.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::RopeBlockModel;
use mbcosim::scene::scene_file::{apply, parse};

const LIFT: &str = include_str!("../examples/scenes/lift.toml");

/// `LIFT` without its top-level `model` key, to follow a `[block]` table.
fn lift_tables() -> String {
    LIFT.replace("model = \"RopeBlock\"\n", "")
}

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info().port_by_name(name).unwrap().vr
}

/// A model with 20 segments per sling from scene text `text` (none: the built-in lift).
fn model(text: Option<&str>) -> Result<RopeBlockModel, String> {
    let mut m = RopeBlockModel::new();
    let seg = vr(&m, "segments");
    m.set_integer(seg, 20).unwrap();
    if let Some(text) = text {
        let origin = std::env::temp_dir().join("rig_state.toml");
        let origin = origin.display().to_string();
        let file = parse(text, &origin)?;
        apply(&mut m, &file, &origin)?;
    }
    Ok(m)
}

/// Every real output.
fn outputs(m: &RopeBlockModel) -> Vec<f64> {
    let info = m.info();
    info.ports
        .iter()
        .filter(|p| p.causality == mbcosim::scene::port::Causality::Output)
        .filter_map(|p| m.get_real(p.vr).ok())
        .collect()
}

/// A state taken after 0.2 s of hoisting at 0.2 m/s, and the model it was taken from.
fn state_after_hoisting(text: Option<&str>) -> (Vec<u8>, RopeBlockModel) {
    let mut m = model(text).unwrap();
    m.initialize(0.0).unwrap();
    let vz = vr(&m, "hook0_vz");
    m.set_real(vz, 0.2).unwrap();
    for k in 0..4 {
        m.do_step(k as f64 * 0.05, 0.05).unwrap();
    }
    (m.serialize(), m)
}

#[test]
fn a_state_restores_into_the_same_rig_and_continues_bit_for_bit() {
    let (bytes, mut original) = state_after_hoisting(None);
    // the built-in lift, and the same rig written out in a scene file
    for text in [None, Some(LIFT)] {
        let mut copy = model(text).unwrap();
        copy.deserialize(&bytes).expect("same rig");
        let mut a = original.clone();
        for k in 4..8 {
            a.do_step(k as f64 * 0.05, 0.05).unwrap();
            copy.do_step(k as f64 * 0.05, 0.05).unwrap();
        }
        assert_eq!(
            outputs(&a),
            outputs(&copy),
            "scene file: {}",
            text.is_some()
        );
    }
    original.do_step(0.2, 0.05).unwrap();
}

#[test]
fn a_state_is_refused_by_another_rig_naming_what_differs() {
    let (bytes, _) = state_after_hoisting(Some(LIFT));
    let want = |parts: &str| {
        format!(
            "RopeBlock state refused: it was taken with another rig ({parts} differ from this instance's, made from its scenario and scene file); a state restores only into an instance with the same rig"
        )
    };
    let cases = [
        // one lug 1 cm further out
        (
            LIFT.replacen(
                "position = [6.5, 6.3, 6.0]",
                "position = [6.5, 6.31, 6.0]",
                1,
            ),
            "[[lug]]",
        ),
        // a sling of its own stiffness, and the hook 1 m higher
        (
            LIFT.replacen("lug = 0\nhook = 0\n", "lug = 0\nhook = 0\nea = 1.7e8\n", 1)
                .replace("position = [0.0, 0.0, 26.0]", "position = [0.0, 0.0, 27.0]"),
            "[[sling]], [[hook]]",
        ),
        // a block of its own
        (
            format!(
                "[block]\nbox = [18.0, 12.0, 7.0]\nmass = 200e3\n{}",
                lift_tables()
            ),
            "[block]",
        ),
    ];
    for (text, parts) in cases {
        assert!(text != LIFT);
        let mut other = model(Some(&text)).unwrap();
        let e = other.deserialize(&bytes).unwrap_err().to_string();
        println!("{e}");
        assert_eq!(e, want(parts));
        // the refused state left the instance as it was: it still initializes
        other.initialize(0.0).unwrap();
    }
}

#[test]
fn the_block_start_pose_is_read_and_checked() {
    let base = "[block]\nbox = [18.0, 12.0, 7.0]\nmass = 200e3\n";
    let bad = [
        (
            "orientation = [1.0, 0.0, 0.0, 0.1]\n",
            ":4: [block] `orientation` must be a unit quaternion [w, x, y, z], its norm is 1.004987562112089",
        ),
        (
            "orientation = [1.0, 0.0, 0.0, 0.0]\nroll_pitch_yaw = [0.0, 0.0, 0.1]\n",
            ":5: [block] give either `orientation` or `roll_pitch_yaw`, not both",
        ),
        (
            "position = [0.0, 1.0]\n",
            ":4: [block] `position` must be an array of 3 numbers",
        ),
    ];
    for (extra, want) in bad {
        let e = model(Some(&format!("{base}{extra}{}", lift_tables()))).unwrap_err();
        println!("{e}");
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
    // a block started 1 m lower and turned 90 degrees about z (quaternion and roll/pitch/yaw
    // alike) settles 1 m lower than the block started on the world frame (each sling is just
    // taut on its start route, the box and its lugs are symmetric, so only the stretch and the
    // slightly different sling angles differ), its centre of gravity under the hook, turned by
    // 90 degrees
    let quarter = std::f64::consts::FRAC_PI_4;
    let (c, s) = (quarter.cos(), quarter.sin());
    let poses = [
        String::new(),
        format!("position = [0.0, 0.0, -1.0]\norientation = [{c:.17}, 0.0, 0.0, {s:.17}]\n"),
        format!(
            "position = [0.0, 0.0, -1.0]\nroll_pitch_yaw = [0.0, 0.0, {:.17}]\n",
            2.0 * quarter
        ),
    ];
    let mut settled = Vec::new();
    for pose in &poses {
        let mut m = model(Some(&format!("{base}{pose}{}", lift_tables()))).unwrap();
        m.initialize(0.0).unwrap();
        let get = |n: &str| m.get_real(vr(&m, n)).unwrap();
        let p = [get("block_x"), get("block_y"), get("block_z")];
        let q = [
            get("block_qw"),
            get("block_qx"),
            get("block_qy"),
            get("block_qz"),
        ];
        println!("pose {pose:?}: block at {p:?}, q {q:?}");
        settled.push((p, q));
    }
    let (p0, q0) = settled[0];
    assert!((q0[0] - 1.0).abs() < 1e-9, "{q0:?}");
    for (p, q) in &settled[1..] {
        assert!(p[0].abs() < 1e-6 && p[1].abs() < 1e-6, "{p:?}");
        assert!((p[2] - (p0[2] - 1.0)).abs() < 0.01, "{p:?} against {p0:?}");
        assert!(
            (q[0] - c).abs() < 1e-6 && (q[3] - s).abs() < 1e-6,
            "{q:?}: 90 degrees about z"
        );
    }
}
