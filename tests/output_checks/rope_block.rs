//! RopeBlock outputs against other paths to the same quantity: the block's position and
//! attitude against its velocities and angular velocities integrated, the hook work
//! against the integral of the hook force over the hook's travel, the potential energy against
//! the weight lifted, and the kinetic energy against the block's mass and velocity.

use mbcosim::math::Vec3;
use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::RopeBlockModel;

use super::panel_lock::qmul;

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info()
        .port_by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

fn get(m: &RopeBlockModel, name: &str) -> f64 {
    m.get_real(vr(m, name)).unwrap()
}

/// A model with these integer and real parameters, initialized at 0 s.
fn started(ints: &[(&str, i32)], reals: &[(&str, f64)]) -> RopeBlockModel {
    let mut m = RopeBlockModel::new();
    for (n, v) in ints {
        let r = vr(&m, n);
        m.set_integer(r, *v).unwrap();
    }
    for (n, v) in reals {
        let r = vr(&m, n);
        m.set_real(r, *v).unwrap();
    }
    m.initialize(0.0).unwrap();
    m
}

/// The block's outputs: position, quaternion (w, x, y, z), velocity, angular velocity.
struct Block {
    r: Vec3,
    q: [f64; 4],
    v: Vec3,
    w: Vec3,
}

fn block(m: &RopeBlockModel) -> Block {
    let g = |s: &str| get(m, &format!("block_{s}"));
    Block {
        r: Vec3::new(g("x"), g("y"), g("z")),
        q: [g("qw"), g("qx"), g("qy"), g("qz")],
        v: Vec3::new(g("vx"), g("vy"), g("vz")),
        w: Vec3::new(g("wx"), g("wy"), g("wz")),
    }
}

/// Unit quaternion of the rotation by vector `phi` [rad].
fn rotation(phi: Vec3) -> [f64; 4] {
    let angle = phi.norm();
    if angle == 0.0 {
        return [1.0, 0.0, 0.0, 0.0];
    }
    let (s, c) = (0.5 * angle).sin_cos();
    let u = phi / angle;
    [c, s * u.x, s * u.y, s * u.z]
}

/// Angle [rad] of the rotation between unit quaternions `a` and `b`.
fn angle_between(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d = qmul([a[0], -a[1], -a[2], -a[3]], b);
    2.0 * Vec3::new(d[1], d[2], d[3]).norm().min(1.0).asin()
}

#[test]
fn block_position_and_attitude_are_the_integrals_of_its_velocities() {
    // the turn-over with crane B lowering at 0.3 m/s: the block swings and turns. Over 2 ms
    // samples for 1.5 s the reported velocity (world) is integrated by the trapezoidal rule and
    // the reported angular velocity (block frame) by q <- q exp(w dt / 2) with the interval's
    // mean w, from the start pose; both must stay on the reported position and attitude. (The
    // rope's stick/slip and slack switching make the acceleration jump: a central difference of
    // the position at 2 ms misses the velocity by 3e-3 of its largest, halving only as dt^1.5;
    // the integrals are not hurt by that.) The quaternion stays a unit one.
    let dt = 2e-3;
    let mut m = started(
        &[("scenario", 1), ("segments", 12)],
        &[("hook1_vz", -0.3), ("rtol", 1e-8), ("atol", 1e-10)],
    );
    let first = block(&m);
    let (mut r, mut q, mut last) = (first.r, first.q, first);
    let (mut worst_r, mut worst_q, mut worst_norm) = (0.0f64, 0.0f64, 0.0f64);
    let (mut path, mut turn) = (0.0, 0.0);
    for i in 0..750 {
        m.do_step(i as f64 * dt, dt).unwrap();
        let b = block(&m);
        r += 0.5 * dt * (last.v + b.v);
        q = qmul(q, rotation(0.5 * dt * (last.w + b.w)));
        path += (b.r - last.r).norm();
        turn += 0.5 * dt * (last.w + b.w).norm();
        worst_r = worst_r.max((r - b.r).norm());
        worst_q = worst_q.max(angle_between(q, b.q));
        let n: f64 = b.q.iter().map(|x| x * x).sum();
        worst_norm = worst_norm.max((n.sqrt() - 1.0).abs());
        last = b;
    }
    println!(
        "block position: integrated velocity off by {worst_r:.2e} m over a {path:.4} m path; attitude: integrated angular velocity off by {worst_q:.2e} rad over {turn:.4} rad turned; |q| - 1 up to {worst_norm:.1e}"
    );
    assert!(path > 0.05 && turn > 0.01, "the block moves and turns");
    assert!(worst_r < 1e-5 * path, "{worst_r}");
    assert!(worst_q < 1e-5 * turn, "{worst_q}");
    assert!(worst_norm < 1e-12, "{worst_norm}");
}

#[test]
fn hook_work_lifted_weight_and_kinetic_energy_by_hand() {
    // the default lift (20 segments) hoisted 1 m by a position command over 3 s, the slings
    // damped (5e6 N s) so that it comes to rest by 10 s. Hook work: the integral of the slings'
    // pull on the hook against the hook's travel, -fz dz (trapezoidal over 5 ms samples);
    // potential energy: up by the hook load at rest (block and slings) times 1 m; kinetic
    // energy while moving: the block's m v^2 / 2 (the slings, 0.6 % of the mass, and the
    // block's slow turn carry the rest); the balance closes
    let h = 5e-3;
    let mut m = started(
        &[("segments", 20), ("hook_command", 2)],
        &[("hook_ramp_time", 3.0), ("rope_damping", 5e6)],
    );
    let mass = get(&m, "block_mass");
    let names = ["kinetic", "potential", "dissipated", "input", "events"];
    let energy = |m: &RopeBlockModel| names.map(|n| get(m, &format!("energy_{n}")));
    let balance = |e: [f64; 5]| e[0] + e[1] + e[2] - e[3] - e[4];
    let (w0, e0) = (get(&m, "hook0_load"), energy(&m));
    let z0 = get(&m, "hook0_z");
    let (mut z, mut fz) = (z0, get(&m, "hook0_fz"));
    let dz = vr(&m, "hook0_dz");
    m.set_real(dz, 1.0).unwrap();
    let (mut work, mut worst_k, mut k_max, mut worst_balance) = (0.0, 0.0f64, 0.0f64, 0.0f64);
    let mut worst_daf = 0.0f64;
    for i in 0..2000 {
        m.do_step(i as f64 * h, h).unwrap();
        let (z1, fz1) = (get(&m, "hook0_z"), get(&m, "hook0_fz"));
        work -= 0.5 * (fz + fz1) * (z1 - z);
        (z, fz) = (z1, fz1);
        let e = energy(&m);
        let b = block(&m);
        worst_k = worst_k.max((e[0] - 0.5 * mass * b.v.norm_squared()).abs());
        k_max = k_max.max(e[0]);
        worst_balance = worst_balance.max((balance(e) - balance(e0)).abs());
        // the dynamic amplification: the hook's vertical load over the weight it holds at rest
        worst_daf = worst_daf.max((get(&m, "daf") + fz / w0).abs());
    }
    let e = energy(&m);
    let lifted = w0 * 1.0;
    println!(
        "hook work {:.1} J, integral of -fz dz {work:.1} J; potential energy up {:.1} J, weight {w0:.1} N x 1 m {lifted:.1} J; kinetic: worst {worst_k:.1} J off m v^2 / 2 of {k_max:.1} J, {:.2e} J at the end; balance within {worst_balance:.2e} J; daf within {worst_daf:.1e} of -fz / load at rest",
        e[3],
        e[1] - e0[1],
        e[0]
    );
    assert!((z - z0 - 1.0).abs() < 1e-12, "hook rose {}", z - z0);
    assert!(worst_daf < 1e-5, "daf {worst_daf}");
    assert!(
        (e[3] - work).abs() < 1e-4 * lifted,
        "hook work {} vs {work}",
        e[3]
    );
    assert!(
        (e[1] - e0[1] - lifted).abs() < 1e-4 * lifted,
        "potential energy up by {} vs {lifted}",
        e[1] - e0[1]
    );
    assert!(
        k_max > 1e3 && worst_k < 0.02 * k_max,
        "{worst_k} of {k_max}"
    );
    assert!(e[0] < 1e-6 * lifted, "at rest: kinetic {}", e[0]);
    assert!(worst_balance < 1e-4 * lifted, "{worst_balance}");
}

/// The point `(x, y, z)` of the edge line through `(., y, z)` along x where the path
/// `hook -> point -> lug` is shortest (golden-section search over x between the two).
fn shortest_over_edge(hook: Vec3, lug: Vec3, y: f64, z: f64) -> Vec3 {
    let length = |x: f64| {
        let p = Vec3::new(x, y, z);
        (p - hook).norm() + (lug - p).norm()
    };
    let (mut a, mut b) = (hook.x.min(lug.x), hook.x.max(lug.x));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    while b - a > 1e-12 {
        let (c, d) = (b - r * (b - a), a + r * (b - a));
        if length(c) < length(d) {
            b = d;
        } else {
            a = c;
        }
    }
    Vec3::new(0.5 * (a + b), y, z)
}

#[test]
fn each_contact_slot_reports_its_sling_s_node_on_the_shortest_path_over_the_edge() {
    // the default lift at rest: four slings, each over the deck edge (y +-6 m, z 7 m, the
    // 18 m x 12 m x 7 m block in its design frame) on its lug's side. Slot i names sling s and
    // reports its node where the straight legs hook -> edge -> lug are shortest, found here by
    // hand from the rig's hook and lug; the slings appear once each; empty slots read -1
    let m = started(&[("segments", 20)], &[]);
    let rig = mbcosim::scene::rope_block::RopeBlockParams::default().rig;
    let count = m.get_integer(vr(&m, "contact_count")).unwrap();
    assert_eq!(count, 4);
    let mut seen = Vec::new();
    for i in 0..8 {
        let s = m.get_integer(vr(&m, &format!("contact{i}_sling"))).unwrap();
        if i >= count as usize {
            assert_eq!(s, -1, "slot {i}");
            continue;
        }
        let p = Vec3::new(
            get(&m, &format!("contact{i}_x")),
            get(&m, &format!("contact{i}_y")),
            get(&m, &format!("contact{i}_z")),
        );
        let sling = &rig.slings[s as usize];
        let (lug, hook) = (rig.lugs[sling.lug].position, rig.hooks[sling.hook].position);
        let want = shortest_over_edge(hook, lug, 6f64.copysign(lug.y), 7.0);
        println!("slot {i}: sling {s}, node at {p:?}, shortest path over the edge at {want:?}");
        assert!((p - want).norm() < 1e-6, "slot {i}: {p:?} vs {want:?}");
        seen.push(s);
    }
    seen.sort();
    assert_eq!(seen, [0, 1, 2, 3]);
}

#[test]
fn contact_rebuilds_and_event_energy_follow_the_contact_node_changes() {
    // one sling swung over the deck edge and back (examples/scenes/sling_over_deck_edge.toml):
    // a node is created at the edge, moved, and released again.
    // Rebuilds: 0 at the start and while the sling hangs clear, never falling, growing in every
    // step in which the number of contact nodes changes (each such change is a rebuild; nodes
    // moved along the edge may add more), so that they end at least at the number of changes.
    // Event energy: changes only in steps with a rebuild, and there by what the other four
    // energies jump: kinetic + potential + dissipated - input changes in that step by the
    // change of `energy_events` (measured: -1.152 J, 44.6 J, 243 J, each within 0.1 J; allowed
    // 0.5 J + 2e-3 of it: elsewhere that sum creeps by up to about 2 J per step)
    let mut m = RopeBlockModel::new();
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes/sling_over_deck_edge.toml");
    mbcosim::scene::scene_file::apply_file(&mut m, &file).unwrap();
    m.initialize(0.0).unwrap();
    let int = |m: &RopeBlockModel, n: &str| m.get_integer(vr(m, n)).unwrap();
    // kinetic + potential + dissipated - input, and events
    let energy = |m: &RopeBlockModel| {
        let e = ["kinetic", "potential", "dissipated", "input", "events"]
            .map(|n| get(m, &format!("energy_{n}")));
        (e[0] + e[1] + e[2] - e[3], e[4])
    };
    let (mut count, mut rebuilds) = (int(&m, "contact_count"), int(&m, "contact_rebuilds"));
    let (mut sum, mut events) = energy(&m);
    assert_eq!((count, rebuilds, events), (0, 0, 0.0));
    let (dy, dz) = (vr(&m, "hook0_dy"), vr(&m, "hook0_dz"));
    let (h, mut changes, mut counts, mut jumps) = (0.05, 0, vec![count], Vec::new());
    for i in 0..400 {
        let t = i as f64 * h;
        if i == 10 {
            // 10 m inboard at about the sling's 20 m from the lug: over the deck edge
            m.set_real(dy, -10.0).unwrap();
            m.set_real(dz, (20.0f64.powi(2) - 10.0f64.powi(2)).sqrt() - 20.0)
                .unwrap();
        }
        if i == 240 {
            m.set_real(dy, 0.0).unwrap();
            m.set_real(dz, 0.0).unwrap();
        }
        m.do_step(t, h).unwrap();
        let (c, r) = (int(&m, "contact_count"), int(&m, "contact_rebuilds"));
        let (s, e) = energy(&m);
        assert!(
            r >= rebuilds,
            "t {}: rebuilds fell from {rebuilds} to {r}",
            t + h
        );
        if i < 10 {
            assert_eq!(r, 0, "nothing changes while the sling hangs clear");
        }
        if c != count {
            changes += 1;
            counts.push(c);
            assert!(
                r > rebuilds,
                "t {}: nodes {count} -> {c} without a rebuild",
                t + h
            );
        }
        if r == rebuilds {
            assert_eq!(e, events, "t {}: event energy without a rebuild", t + h);
        } else {
            jumps.push((t + h, s - sum, e - events));
        }
        (count, rebuilds, sum, events) = (c, r, s, e);
    }
    println!("contact nodes {counts:?}; {changes} changes, {rebuilds} rebuilds");
    for (t, ds, de) in &jumps {
        println!("t {t:.2} s: energies jump by {ds:.3} J, events by {de:.3} J");
    }
    assert_eq!(counts, [0, 1, 0], "the node is created and released");
    assert!(rebuilds >= changes);
    assert!(jumps.iter().any(|j| j.2.abs() > 100.0), "{jumps:?}");
    for (t, ds, de) in jumps {
        assert!(
            (ds - de).abs() < 0.5 + 2e-3 * de.abs(),
            "t {t}: {ds} J vs events {de} J"
        );
    }
}

#[test]
fn ground_friction_dissipates_its_force_times_the_sliding_speed() {
    // the default lift partly set down on a ground 5 cm below the block (20 segments): the hook
    // lowered 2 cm, then moved 2 m along x by a position command over 10 s, dragging the block
    // (half its weight on the ground) along. The energy dissipated over the drag is the integral
    // of the ground's friction times the block's horizontal speed (trapezoidal over 10 ms), the
    // rope's damping and the block's small turn adding little: measured 0.16 % apart
    let h = 0.01;
    let mut m = RopeBlockModel::new();
    m.set_boolean(vr(&m, "ground_contact"), true).unwrap();
    for (n, v) in [("segments", 20), ("hook_command", 2)] {
        m.set_integer(vr(&m, n), v).unwrap();
    }
    for (n, v) in [("ground_height", -0.05), ("hook_ramp_time", 10.0)] {
        m.set_real(vr(&m, n), v).unwrap();
    }
    m.initialize(0.0).unwrap();
    let (dx, dz) = (vr(&m, "hook0_dx"), vr(&m, "hook0_dz"));
    m.set_real(dz, -0.02).unwrap();
    let mut t = 0.0;
    while t < 2.0 - 1e-9 {
        m.do_step(t, h).unwrap();
        t += h;
    }
    m.set_real(dx, 2.0).unwrap();
    let power = |m: &RopeBlockModel| {
        let b = block(m);
        get(m, "ground_friction") * b.v.xy().norm()
    };
    let (d0, mut p0) = (get(&m, "energy_dissipated"), power(&m));
    let mut work = 0.0;
    while t < 14.0 - 1e-9 {
        m.do_step(t, h).unwrap();
        t += h;
        let p = power(&m);
        work += 0.5 * h * (p + p0);
        p0 = p;
    }
    let d = get(&m, "energy_dissipated") - d0;
    println!(
        "dissipated {d:.1} J, integral of ground friction x speed {work:.1} J, normal {:.1} N",
        get(&m, "ground_normal")
    );
    assert!(work > 1e5, "the block slides: {work} J");
    assert!(
        (d - work).abs() < 5e-3 * work,
        "dissipated {d} J vs {work} J"
    );
}
