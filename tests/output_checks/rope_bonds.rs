//! RopeBlock's power bonds (issue #46, item 1) against other paths: the hooks' forces at rest
//! against the weight of everything hanging, against the slings' pull read from the tensions
//! (`hook#_fz`, `hook#_load`), the ports' powers against the rope effect's own input power, the
//! ports' work against the energy books (the balance), and the work against the communication
//! step.

use mbcosim::math::Vec3;
use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::{RopeBlockModel, RopeBlockParams, RopeBlockScene};

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

/// A model with these integer and real parameters, initialized at 0 s.
fn started(ints: &[(&str, i32)], reals: &[(&str, f64)]) -> RopeBlockModel {
    let mut m = RopeBlockModel::new();
    for (n, v) in ints {
        let r = vr(&m, n);
        m.set_integer(r, *v).unwrap();
    }
    for (n, v) in reals {
        set(&mut m, n, *v);
    }
    m.initialize(0.0).unwrap();
    m
}

/// Hook `k`'s force on the crane [N] as the outputs give it.
fn hook_force(m: &RopeBlockModel, k: usize) -> Vec3 {
    Vec3::new(
        get(m, &format!("hook{k}_fx")),
        get(m, &format!("hook{k}_fy")),
        get(m, &format!("hook{k}_fz")),
    )
}

#[test]
fn hook_forces_at_rest_carry_the_weight_of_block_and_slings() {
    // the lift (one hook) and the turn-over (two hooks) hanging at rest: the only external
    // forces are gravity and the hooks, so the hooks' forces on the crane add up to
    // (0, 0, -(block + slings) g), the masses summed over the model's bodies (statics solved to
    // 1e-9 of the weight); the bond force's z is `hook#_fz` and its length `hook#_load`, read
    // from the first segments' tensions and directions, to 1e-9
    for params in [RopeBlockParams::default(), RopeBlockParams::turnover()] {
        let mut scene = RopeBlockScene::new(RopeBlockParams {
            segments: 20,
            ..params
        })
        .unwrap();
        let weight = scene.sim.total_mass() * scene.params.gravity;
        let bonds = scene.sim.hook_bonds();
        let total: Vec3 = bonds.iter().map(|b| b.force).sum();
        println!(
            "hooks {}: total force {total:?} N, weight {weight} N",
            bonds.len()
        );
        assert!((total + Vec3::new(0.0, 0.0, weight)).norm() < 1e-8 * weight);
        for (k, b) in bonds.iter().enumerate() {
            let fz = scene.output(&format!("hook{k}.fz")).unwrap();
            let load = scene.output(&format!("hook{k}.load")).unwrap();
            assert!((b.force.z - fz).abs() < 1e-9 * weight, "{k}: {b:?} {fz}");
            assert!((b.force.norm() - load).abs() < 1e-9 * weight, "{k}: {load}");
            assert_eq!(b.power(), 0.0);
        }
    }
}

#[test]
fn port_powers_add_up_to_the_rope_effect_s_input_power() {
    // the lift swinging under a hook moving sideways and up while the winch pays out: at every
    // communication point the hooks' and winches' powers add up to the input power the rope
    // effect books for the integrator (its own sum), to 1e-9 of the largest port power; the bond
    // force keeps matching the tension path (`hook#_fz`, `hook#_load`) while the load swings
    let mut scene = RopeBlockScene::new(RopeBlockParams {
        segments: 20,
        ..RopeBlockParams::default()
    })
    .unwrap();
    scene.set_hook(0, Vec3::new(0.4, 0.0, 0.2), 0.1).unwrap();
    let (mut worst, mut largest, mut worst_force) = (0.0f64, 0.0f64, 0.0f64);
    let mut horizontal = 0.0f64;
    for _ in 0..40 {
        scene.step(0.05).unwrap();
        let bonds = scene.sim.hook_bonds();
        let ports: f64 = bonds.iter().map(|b| b.power() + b.winch_power()).sum();
        let sim = &mut scene.sim.sim;
        let st = sim.state.clone();
        let (_, input) = sim.system.powers(st.t, &st.q, &st.v);
        worst = worst.max((ports - input).abs());
        largest = largest.max(bonds[0].power().abs().max(bonds[0].winch_power().abs()));
        let fz = scene.output("hook0.fz").unwrap();
        let load = scene.output("hook0.load").unwrap();
        worst_force = worst_force
            .max((bonds[0].force.z - fz).abs())
            .max((bonds[0].force.norm() - load).abs());
        horizontal = horizontal.max(bonds[0].force.x.abs());
    }
    println!(
        "ports vs effect: {worst:.3e} W of {largest:.3e} W; force {worst_force:.3e} N; |fx| up to {horizontal:.1} N"
    );
    assert!(largest > 1e4 && worst < 1e-9 * largest);
    assert!(horizontal > 1e2, "the hook moved sideways: fx {horizontal}");
    assert!(worst_force < 1e-9 * scene.sim.total_mass() * 9.81);
}

#[test]
fn hook_power_is_the_force_outputs_against_the_commanded_velocity() {
    // through the FMU variables: once the commanded hook velocity (0.3, 0, 0.2) m/s and pay-out
    // rate 0.1 m/s are reached (after the 0.5 s ramp), hook0_power = -(hook0_fx, fy, fz) . v with
    // fz from the segment tensions (the older output), to 1e-9 of the power, and
    // hook0_winch_power = -hook0_winch_force x 0.1, to 1e-12
    let mut m = started(&[("segments", 20)], &[("rope_damping", 2e6)]);
    let v = Vec3::new(0.3, 0.0, 0.2);
    set(&mut m, "hook0_vx", v.x);
    set(&mut m, "hook0_vz", v.z);
    set(&mut m, "hook0_payout_rate", 0.1);
    let (mut worst, mut worst_winch, mut largest) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..24 {
        m.do_step(i as f64 * 0.05, 0.05).unwrap();
        if i < 12 {
            continue;
        }
        let p = get(&m, "hook0_power");
        worst = worst.max((p + hook_force(&m, 0).dot(&v)).abs());
        largest = largest.max(p.abs());
        let pw = get(&m, "hook0_winch_power");
        worst_winch = worst_winch.max((pw + 0.1 * get(&m, "hook0_winch_force")).abs() / pw.abs());
    }
    println!("hook power off by {worst:.2e} W of {largest:.3e} W; winch {worst_winch:.1e}");
    assert!(largest > 1e5 && worst < 1e-9 * largest);
    assert!(worst_winch < 1e-12);
}

/// The lift (20 segments, slings damped) driven through the FMU variables with communication
/// step `h` [s] for `stop` [s]: hook 0 moved sideways and up while the winch pays out, then
/// held. Returns the model at the end, the energy books at the start and the hook's and winch's
/// work as the powers sampled at the communication points integrate (trapezoidal), for
/// comparison.
fn driven_lift(h: f64, stop: f64, reals: &[(&str, f64)]) -> (RopeBlockModel, [f64; 5], [f64; 2]) {
    let mut all = vec![("rope_damping", 2e6), ("hook_ramp_time", 0.5)];
    all.extend_from_slice(reals);
    let mut m = started(&[("segments", 20)], &all);
    let e0 = energy(&m);
    let powers = |m: &RopeBlockModel| [get(m, "hook0_power"), get(m, "hook0_winch_power")];
    let mut sampled = [0.0; 2];
    let n = (stop / h).round() as usize;
    for i in 0..n {
        let t = i as f64 * h;
        if i == 0 {
            set(&mut m, "hook0_vx", 0.3);
            set(&mut m, "hook0_vz", 0.2);
            set(&mut m, "hook0_payout_rate", 0.1);
        }
        if (t - 1.5).abs() < 0.5 * h {
            set(&mut m, "hook0_vx", 0.0);
            set(&mut m, "hook0_vz", 0.0);
            set(&mut m, "hook0_payout_rate", 0.0);
        }
        let p0 = powers(&m);
        m.do_step(t, h).unwrap();
        let p1 = powers(&m);
        for j in 0..2 {
            sampled[j] += 0.5 * h * (p0[j] + p1[j]);
        }
    }
    (m, e0, sampled)
}

/// kinetic, potential, dissipated, input, events [J].
fn energy(m: &RopeBlockModel) -> [f64; 5] {
    ["kinetic", "potential", "dissipated", "input", "events"]
        .map(|n| get(m, &format!("energy_{n}")))
}

#[test]
fn port_work_closes_the_energy_balance() {
    // the driven lift over 3 s: the hook's and the winch's work together equal the change of
    // kinetic + potential energy plus the energy dissipated, less the event changes (contact
    // nodes inserted or moved), to 1e-6 of the work done (|hook work| + |winch work|); their sum
    // also equals the integrator's own input books (`energy_input`) to 1e-9 of it. Steps of at
    // most 1 ms: at the default 12.5 ms the balance stayed 2.6e-6 off whatever the rtol (the
    // numerical damping of generalized-alpha at rho_inf 0 and BDF2, which no book holds; without
    // contact and pay-out 2.0e-6 at 12.5 ms, 4.2e-9 at 1 ms, 2.5e-10 at 0.25 ms); here 1.6e-7
    let (m, e0, _) = driven_lift(0.05, 3.0, &[("rtol", 1e-8), ("h_max", 1e-3)]);
    let e = energy(&m);
    let (hook, winch) = (get(&m, "hook0_work"), get(&m, "hook0_winch_work"));
    let done = hook.abs() + winch.abs();
    let stored = (e[0] + e[1]) - (e0[0] + e0[1]) + (e[2] - e0[2]) - (e[4] - e0[4]);
    println!(
        "hook work {hook:.6e} J, winch work {winch:.6e} J; stored + dissipated - events {stored:.6e} J; input books {:.6e} J; balance off by {:.3e} of the work done",
        e[3] - e0[3],
        (hook + winch - stored).abs() / done
    );
    assert!(hook > 1e4 && winch < -1e3, "{hook} {winch}");
    assert!(((hook + winch) - (e[3] - e0[3])).abs() < 1e-9 * done);
    assert!((hook + winch - stored).abs() < 1e-6 * done);
}

#[test]
fn port_work_does_not_move_with_the_communication_step() {
    // the driven lift over 2 s at communication steps of 1 ms and of 0.1 s: the work is
    // integrated inside the solver's steps, so both give the same hook and winch work to the
    // solver's tolerance (1e-4)
    let (fine, _, _) = driven_lift(1e-3, 2.0, &[]);
    let (coarse, _, sampled) = driven_lift(0.1, 2.0, &[]);
    for (j, name) in ["hook0_work", "hook0_winch_work"].into_iter().enumerate() {
        let (a, b) = (get(&fine, name), get(&coarse, name));
        println!(
            "{name}: {a:.6e} J at 1 ms, {b:.6e} J at 0.1 s; sampled at the 0.1 s points {:.6e} J ({:.2e} off)",
            sampled[j],
            (sampled[j] - a).abs() / a.abs()
        );
        assert!((a - b).abs() < 1e-4 * a.abs(), "{name}: {a} vs {b}");
    }
}

#[test]
fn dissipated_energy_never_falls_while_the_winch_pays_out_and_in() {
    // a 1000 kg block on soft slings (EA 1e6 N, damped) at gravity 1 m/s^2, the winch paying out
    // and in at 0.8 sin(8 t) m/s with no ramp, 1 ms communication steps over 1.5 s (the block
    // drops, the slings go slack and snatch at about 1.39 s): `energy_dissipated` is the damper's
    // and friction's work, c L (strain rate)^2 >= 0, so it never falls (second law). Before the
    // dashpot's power was taken on its own rate `l_dot - l L_dot / L` (it took `l_dot`, which also
    // carries the paid-out length) it fell to -30.8 J, by up to 13.5 J in one step. The books
    // still close: the damper's share of the pay-out went into the winch's input power
    // (`winch_pull`), and the ports' work still equals `energy_input` to 1e-9.
    let mut m = started(
        &[("segments", 20)],
        &[
            ("block_mass", 1000.0),
            ("rope_ea", 1e6),
            ("gravity", 1.0),
            ("hook_ramp_time", 0.0),
        ],
    );
    let h = 1e-3;
    let mut last = get(&m, "energy_dissipated");
    let (mut worst_fall, mut worst_books, mut peak_winch) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..1500 {
        let t = i as f64 * h;
        set(&mut m, "hook0_payout_rate", 0.8 * (8.0 * t).sin());
        m.do_step(t, h).unwrap();
        let d = get(&m, "energy_dissipated");
        worst_fall = worst_fall.max(last - d);
        last = d;
        let (work, input) = (
            get(&m, "hook0_work") + get(&m, "hook0_winch_work"),
            get(&m, "energy_input"),
        );
        worst_books = worst_books.max((work - input).abs() / input.abs().max(1.0));
        peak_winch = peak_winch.max(get(&m, "hook0_winch_force").abs());
    }
    println!(
        "largest fall of energy_dissipated {worst_fall:.2e} J (end {last:.1} J); ports' work against energy_input {worst_books:.1e}; winch force peak {peak_winch:.3e} N"
    );
    assert!(last > 1.0, "nothing was dissipated: the case tests nothing");
    assert!(
        peak_winch > 1e4,
        "no snatch: the case tests less than it says"
    );
    assert!(
        worst_fall <= 1e-9 * last,
        "energy_dissipated fell by {worst_fall} J"
    );
    assert!(
        worst_books < 1e-9,
        "ports' work off energy_input by {worst_books:.1e}"
    );
}
