//! Hook position commands and hooks 2-3 through the FMU's variables (issue #21).
//!
//! With `hook_command = position` the `hookN_dx/dy/dz` inputs are a target displacement from the
//! hook's start position; the hook moves there along the cubic that keeps its position and
//! velocity continuous and arrives at rest after `hook_ramp_time` (or longer for a long move,
//! its own peak speed 1.5 d / T staying within 2 m/s). The tests compare the hook's position
//! with that cubic computed here by hand, also for a target changed in the middle of a move, and
//! check that the block follows a hoisted hook to its static equilibrium. A four-hook rig is
//! driven and observed through `hook2_*` and `hook3_*`.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::RopeBlockModel;
use mbcosim::scene::scene_file::{apply, apply_file, parse};

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info()
        .port_by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

fn get(m: &RopeBlockModel, name: &str) -> f64 {
    m.get_real(vr(m, name)).unwrap()
}

fn set(m: &mut RopeBlockModel, name: &str, v: f64) {
    let r = vr(m, name);
    m.set_real(r, v).unwrap();
}

/// A model in position mode with 20 segments per sling and these real parameters, from scene
/// text `scene` if given, initialized at 0 s.
fn started(values: &[(&str, f64)], scene: Option<&str>) -> RopeBlockModel {
    let mut m = RopeBlockModel::new();
    let (seg, cmd) = (vr(&m, "segments"), vr(&m, "hook_command"));
    m.set_integer(seg, 20).unwrap();
    m.set_integer(cmd, 2).unwrap();
    for (n, v) in values {
        set(&mut m, n, *v);
    }
    if let Some(text) = scene {
        let origin = std::env::temp_dir().join("hook_position.toml");
        let origin = origin.display().to_string();
        let file = parse(text, &origin).unwrap();
        apply(&mut m, &file, &origin).unwrap();
    }
    m.initialize(0.0).unwrap();
    m
}

/// The move by hand: from `x0` at speed `v0` to `x1` at rest over `dur` [s], at `tau` [s]
/// after the command: position and velocity of the cubic Hermite with those end conditions.
fn cubic(x0: f64, v0: f64, x1: f64, dur: f64, tau: f64) -> (f64, f64) {
    if tau >= dur {
        return (x1, 0.0);
    }
    let s = tau / dur;
    let (h00, h10, h01) = (
        2.0 * s.powi(3) - 3.0 * s * s + 1.0,
        s.powi(3) - 2.0 * s * s + s,
        -2.0 * s.powi(3) + 3.0 * s * s,
    );
    let (d00, d10, d01) = (
        (6.0 * s * s - 6.0 * s) / dur,
        3.0 * s * s - 4.0 * s + 1.0,
        (-6.0 * s * s + 6.0 * s) / dur,
    );
    (
        h00 * x0 + h10 * dur * v0 + h01 * x1,
        d00 * x0 + d10 * v0 + d01 * x1,
    )
}

#[test]
fn the_hook_follows_the_cubic_move_by_hand() {
    let ramp = 1.2;
    let mut m = started(&[("hook_ramp_time", ramp)], None);
    let (x0, z0) = (get(&m, "hook0_x"), get(&m, "hook0_z"));
    let h = 0.05;
    // at 0.5 s: to (+0.4, 0, +1.5) m (1.55 m: 1.5 x 1.55 / 2 m/s = 1.16 s < 1.2 s, the ramp
    // sets the duration); at 1.0 s, mid-move, to (+0.4, 0, +0.5) m; at 3.0 s to +4.5 m up
    // (the move lasts 1.5 x 4 / 2 = 3.0 s, longer than the ramp)
    let mut worst: f64 = 0.0;
    let (mut ax, mut az) = ((x0, 0.0, x0, 0.0, 0.0), (z0, 0.0, z0, 0.0, 0.0));
    for k in 0..140 {
        let t = k as f64 * h;
        let retarget = |a: (f64, f64, f64, f64, f64), x1: f64, dur: f64| {
            let (x, v) = cubic(a.0, a.1, a.2, a.3, t - a.4);
            (x, v, x1, dur, t)
        };
        match k {
            10 => {
                set(&mut m, "hook0_dx", 0.4);
                set(&mut m, "hook0_dz", 1.5);
                ax = retarget(ax, x0 + 0.4, ramp);
                az = retarget(az, z0 + 1.5, ramp);
            }
            20 => {
                set(&mut m, "hook0_dz", 0.5);
                // from where the hook is now: distance (0.4 - x(1.0) ... , 0.5 - z) < 1.6 m
                let (x, _) = cubic(ax.0, ax.1, ax.2, ax.3, t - ax.4);
                let (z, _) = cubic(az.0, az.1, az.2, az.3, t - az.4);
                let d = ((x0 + 0.4 - x).powi(2) + (z0 + 0.5 - z).powi(2)).sqrt();
                let dur = ramp.max(1.5 * d / 2.0);
                ax = retarget(ax, x0 + 0.4, dur);
                az = retarget(az, z0 + 0.5, dur);
            }
            60 => {
                set(&mut m, "hook0_dz", 4.5);
                let dur = 1.5 * 4.0 / 2.0;
                ax = retarget(ax, x0 + 0.4, dur);
                az = retarget(az, z0 + 4.5, dur);
            }
            _ => {}
        }
        m.do_step(t, h).unwrap();
        let te = t + h;
        let (x, _) = cubic(ax.0, ax.1, ax.2, ax.3, te - ax.4);
        let (z, _) = cubic(az.0, az.1, az.2, az.3, te - az.4);
        let (ex, ez) = (get(&m, "hook0_x") - x, get(&m, "hook0_z") - z);
        assert!(get(&m, "hook0_y").abs() < 1e-12);
        worst = worst.max(ex.abs()).max(ez.abs());
        if k % 10 == 9 {
            println!(
                "t {te:.2} s: hook at x {:.9}, z {:.9} m; by hand {x:.9}, {z:.9} m",
                get(&m, "hook0_x"),
                get(&m, "hook0_z")
            );
        }
    }
    println!("largest difference from the cubic by hand: {worst:.2e} m");
    assert!(worst < 1e-9, "{worst}");
    assert!((get(&m, "hook0_z") - (z0 + 4.5)).abs() < 1e-12);
}

#[test]
fn the_block_follows_a_hoisted_hook_to_its_static_equilibrium() {
    // hoist 2 m over 5 s, then hang; the slings' damping raised from 0.6 % to about 20 % of
    // critical on the block's 1.6 Hz bounce so that the bounce the move leaves (the cubic's
    // acceleration steps by 6 d / T^2 = 0.48 m/s2 on arrival: some 5 mm) dies out within the run
    let mut m = started(&[("hook_ramp_time", 5.0), ("rope_damping", 5e6)], None);
    let (bz0, hz0, bx0) = (get(&m, "block_z"), get(&m, "hook0_z"), get(&m, "block_x"));
    let load0 = get(&m, "hook0_load");
    set(&mut m, "hook0_dz", 2.0);
    let h = 0.05;
    for k in 0..240 {
        m.do_step(k as f64 * h, h).unwrap();
    }
    let (bz, hz, bx) = (get(&m, "block_z"), get(&m, "hook0_z"), get(&m, "block_x"));
    let (vz, daf, load) = (get(&m, "block_vz"), get(&m, "daf"), get(&m, "hook0_load"));
    println!(
        "after 12 s: hook +{:.9} m, block +{:.6} m (x {:.2e} m), block vz {vz:.2e} m/s, daf {daf:.6}, hook load {load:.1} N (at rest {load0:.1} N)",
        hz - hz0,
        bz - bz0,
        bx - bx0
    );
    assert!((hz - hz0 - 2.0).abs() < 1e-12);
    // at rest the block hangs from the same slings 2 m higher
    assert!((bz - bz0 - 2.0).abs() < 1e-5, "{}", bz - bz0);
    assert!((bx - bx0).abs() < 1e-6);
    assert!(vz.abs() < 1e-5 && (daf - 1.0).abs() < 1e-5, "{vz} {daf}");
    assert!((load - load0).abs() < 1e-5 * load0);
}

/// Four hooks, each straight above one lug of the built-in lift, one sling each (vertical, clear
/// of the block's side shell, which lies 0.3 m inboard of the lugs).
const FOUR_HOOKS: &str = "
[[lug]]
position = [6.5, 6.3, 6.0]
[[lug]]
position = [-6.5, 6.3, 6.0]
[[lug]]
position = [-6.5, -6.3, 6.0]
[[lug]]
position = [6.5, -6.3, 6.0]
[[sling]]
lug = 0
hook = 0
route = \"straight\"
[[sling]]
lug = 1
hook = 1
route = \"straight\"
[[sling]]
lug = 2
hook = 2
route = \"straight\"
[[sling]]
lug = 3
hook = 3
route = \"straight\"
[[hook]]
position = [6.5, 6.3, 26.0]
crane = 0
[[hook]]
position = [-6.5, 6.3, 26.0]
crane = 1
[[hook]]
position = [-6.5, -6.3, 26.0]
crane = 2
[[hook]]
position = [6.5, -6.3, 26.0]
crane = 3
";

#[test]
fn a_four_hook_rig_is_driven_and_observed_through_its_variables() {
    // a plain box: its centre of gravity in the middle, each hook carries a quarter
    let scene = format!("[block]\nbox = [18.0, 12.0, 7.0]\nmass = 200e3\n{FOUR_HOOKS}");
    let mut m = started(&[], Some(&scene));
    let hooks = [(6.5, 6.3), (-6.5, 6.3), (-6.5, -6.3), (6.5, -6.3)];
    // each hook: a quarter of the block and its vertical sling's own weight (20 m of 15 kg/m)
    let quarter = 200e3 * 9.81 / 4.0;
    let sling = 15.0 * 20.0 * 9.81;
    for (k, (x, y)) in hooks.iter().enumerate() {
        let at = [
            get(&m, &format!("hook{k}_x")),
            get(&m, &format!("hook{k}_y")),
            get(&m, &format!("hook{k}_z")),
        ];
        let (load, fz) = (
            get(&m, &format!("hook{k}_load")),
            get(&m, &format!("hook{k}_fz")),
        );
        println!(
            "hook {k}: at {at:?}, load {load:.1} N, fz {fz:.1} N (quarter {quarter:.1} N + sling {sling:.1} N)"
        );
        assert_eq!(at, [*x, *y, 26.0]);
        assert!((load - (quarter + sling)).abs() < 1e-6 * load, "{load}");
        assert!(
            (fz + load).abs() < 1e-6 * load,
            "vertical sling: fz = -load"
        );
    }
    let daf = get(&m, "daf");
    assert!((daf - 1.0).abs() < 1e-6, "{daf}");
    // hooks 2 and 3 (the -y side) up by 0.3 m through their position commands
    set(&mut m, "hook2_dz", 0.3);
    set(&mut m, "hook3_dz", 0.3);
    let h = 0.05;
    for k in 0..40 {
        m.do_step(k as f64 * h, h).unwrap();
    }
    for k in 0..4 {
        let z = get(&m, &format!("hook{k}_z"));
        let want = if k >= 2 { 26.3 } else { 26.0 };
        assert!((z - want).abs() < 1e-12, "hook {k} at {z}");
    }
    // the -y side (hooks 2 and 3) raised: the block rolls negative about x, by about the angle
    // of 0.3 m over the 12.6 m between the lugs (it still swings a little)
    let (qw, qx) = (get(&m, "block_qw"), get(&m, "block_qx"));
    let roll = 2.0 * qx.atan2(qw);
    let hand = -(0.3f64 / 12.6).atan();
    println!(
        "after raising hooks 2 and 3 by 0.3 m: roll {roll:.6} rad (0.3 m over 12.6 m: {hand:.6})"
    );
    assert!((roll - hand).abs() < 0.05 * hand.abs(), "{roll}");
}

#[test]
fn a_sling_swung_over_the_deck_edge_and_back_wraps_the_edge_and_leaves_it() {
    // one sling from a lug on the side shell straight up to its hook, block on the ground,
    // sling in water; 20 segments, position commands (the scene's [parameters])
    let mut m = RopeBlockModel::new();
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes/sling_over_deck_edge.toml");
    apply_file(&mut m, &file).unwrap();
    m.initialize(0.0).unwrap();
    let count = |m: &RopeBlockModel| m.get_integer(vr(m, "contact_count")).unwrap();
    let t0 = get(&m, "sling0_tension_lug");
    assert_eq!(count(&m), 0);
    let h = 0.05;
    let mut t = 0.0;
    let mut run_to = |m: &mut RopeBlockModel, end: f64| {
        while t < end - 1e-9 {
            m.do_step(t, h).unwrap();
            t += h;
        }
    };
    // the hook swings 10 m inboard over the deck at about the sling's length from the lug: the
    // straight line from the lug to the hook then cuts the deck edge (y 6 m, z 7 m)
    run_to(&mut m, 0.5);
    set(&mut m, "hook0_dy", -10.0);
    set(
        &mut m,
        "hook0_dz",
        (20.0f64.powi(2) - 10.0f64.powi(2)).sqrt() - 20.0,
    );
    run_to(&mut m, 12.0);
    let (n, y, z) = (
        get(&m, "contact0_normal"),
        get(&m, "contact0_y"),
        get(&m, "contact0_z"),
    );
    let wrapped = get(&m, "sling0_tension_lug");
    println!(
        "hook inboard: {} node(s), at y {y} z {z} m, N {n:.1} N, lug tension {wrapped:.1} N",
        count(&m)
    );
    assert_eq!(count(&m), 1);
    assert!((y - 6.0).abs() < 1e-9 && (z - 7.0).abs() < 1e-9, "{y} {z}");
    assert!(n > 0.0);
    // back over the lug: the rope bends away from the edge, which could hold it only by pulling
    set(&mut m, "hook0_dy", 0.0);
    set(&mut m, "hook0_dz", 0.0);
    run_to(&mut m, 20.0);
    assert_eq!(
        count(&m),
        0,
        "the node stays on the edge after the hook came back"
    );
    // at rest the sling hangs as at the start (one static state), not stretched over the edge
    run_to(&mut m, 140.0);
    let t1 = get(&m, "sling0_tension_lug");
    println!("lug tension at rest: {t1:.1} N at 140 s, {t0:.1} N at the start");
    assert!((t1 - t0).abs() < 0.02 * t0, "{t1} against {t0}");
}
