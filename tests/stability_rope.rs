//! Stability suite, RopeBlock: rope resolution, integrator, friction from zero to high, block
//! masses up to 10,000 t (block-to-node mass ratio above 1e7), steel-to-stiffer EA, slack-to-taut
//! snaps, through the co-simulation model the FMU runs. Every case completes with finite outputs
//! and an energy balance that never gains more than the tolerance allows, except the cases
//! listed in `EXPECTED_STOPS`, which must stop with exactly the message listed there. `cargo test --release --test stability_rope -- --nocapture` prints
//! the envelope.

use mbcosim::scene::rope_block::cosim::RopeBlockModel;
use mbcosim::scene::{CoSimModel, native};

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info()
        .port_by_name(name)
        .unwrap_or_else(|| panic!("no port {name}"))
        .vr
}

/// Runs a lift: hook still until 0.5 s, then `profile(t)` as hook vertical speed [m/s], to
/// `t_end` [s] with communication step 0.05 s. Returns the largest energy gain (balance drift
/// above its start) relative to the block's weight times one metre, and the peak hook load [N].
fn lift(
    values: &[(&str, f64)],
    t_end: f64,
    profile: impl Fn(f64) -> f64,
) -> Result<(f64, f64), String> {
    let mut m = RopeBlockModel::new();
    for (k, v) in values {
        native::set_by_name(&mut m, k, *v).map_err(|e| e.to_string())?;
    }
    let weight = 9.81 * m.get_real(vr(&m, "block_mass")).unwrap();
    m.initialize(0.0).map_err(|e| e.to_string())?;
    let names = [
        "energy_kinetic",
        "energy_potential",
        "energy_dissipated",
        "energy_input",
        "energy_events",
    ];
    let refs: Vec<u32> = names.iter().map(|n| vr(&m, n)).collect();
    let balance = |m: &RopeBlockModel| {
        let e: Vec<f64> = refs.iter().map(|r| m.get_real(*r).unwrap()).collect();
        e[0] + e[1] + e[2] - e[3] - e[4]
    };
    let b0 = balance(&m);
    let (vz, load) = (vr(&m, "hook0_vz"), vr(&m, "hook0_load"));
    let mut gain: f64 = 0.0;
    let mut peak: f64 = 0.0;
    let h = 0.05;
    let n = (t_end / h).round() as usize;
    for k in 0..n {
        let t = k as f64 * h;
        m.set_real(vz, profile(t)).map_err(|e| e.to_string())?;
        m.do_step(t, h).map_err(|e| e.to_string())?;
        let b = balance(&m);
        let l = m.get_real(load).unwrap();
        if !(b.is_finite() && l.is_finite()) {
            return Err("non-finite outputs without an error (defect)".into());
        }
        gain = gain.max((b - b0) / weight);
        peak = peak.max(l);
    }
    Ok((gain, peak))
}

fn hoist(t: f64) -> f64 {
    if t < 0.5 { 0.0 } else { 0.3 }
}

/// The cases that stop instead of completing, with their exact messages: every other case must
/// complete, and each of these must stop with exactly this message (a case that starts to
/// complete, or stops for another reason, fails the sweep until this list is updated).
const EXPECTED_STOPS: &[(&str, &str)] = &[
    (
        "block 2000000 kg, 400 segments",
        "RopeBlock could not be set up: no static equilibrium within the slings' strength: sling 0 carries 5.2569e6 N at rest, above its breaking load 2.5000e6 N (the block is too heavy for this sling: lower block_mass, or use stronger slings: rope_breaking_load, or breaking_load in the scene file's [[sling]]; more slings or a better share between them also help; with ground_contact on, a ground_height above the hanging block pushes it into the slings)",
    ),
    (
        "block 10000000 kg, 400 segments",
        "RopeBlock could not be set up: no static equilibrium found in 300 iterations: largest force imbalance 3.181e9 N (is the scene statically stable? free bodies need supports; a load far beyond the slings' strength, e.g. block_mass against rope_ea, or too few segments, also ends here; with ground_contact on, so does a ground_stiffness or ground_height the slings cannot balance)",
    ),
];

fn check(case: &str, r: Result<(f64, f64), String>, allowed_gain: f64, stopped: &mut Vec<String>) {
    let expected = EXPECTED_STOPS.iter().find(|(c, _)| *c == case).map(|e| e.1);
    match r {
        Ok((gain, peak)) => {
            println!("{case}: energy gain {gain:.2e} W*m, peak hook load {peak:.4e} N");
            assert!(
                expected.is_none(),
                "{case}: completed, but is listed in EXPECTED_STOPS (update the list)"
            );
            assert!(
                gain <= allowed_gain,
                "{case}: energy grew by {gain} W*m (allowed {allowed_gain})"
            );
        }
        Err(msg) => {
            match expected {
                Some(want) => assert_eq!(msg, want, "{case}: stopped with another message"),
                None => panic!("{case}: stopped, and is not listed as expected to: {msg}"),
            }
            stopped.push(format!("{case}: {msg}"));
        }
    }
}

#[test]
fn resolution_and_integrators() {
    let mut stopped = Vec::new();
    // DOPRI5 is explicit: the axial wave of a steel rope bounds its step by the segment length
    // over the wave speed (5.2 km/s), so it runs only on the coarsest ropes here (docs/details.md, tested envelope)
    for (segments, integrators) in [
        (2.0, &[1.0, 2.0, 3.0][..]),
        (10.0, &[1.0, 2.0, 3.0][..]),
        (50.0, &[1.0, 2.0][..]),
        (200.0, &[1.0, 2.0][..]),
    ] {
        for &integrator in integrators {
            let case = format!("segments {segments} integrator {integrator}");
            let r = lift(
                &[("segments", segments), ("integrator", integrator)],
                2.0,
                hoist,
            );
            check(&case, r, 1e-3, &mut stopped);
        }
    }
    println!("stopped with a message: {stopped:#?}");
}

#[test]
fn friction_from_zero_to_one_and_heavy_blocks() {
    let mut stopped = Vec::new();
    for mu in [0.0, 0.15, 1.0] {
        let case = format!("mu {mu}");
        check(
            &case,
            lift(&[("segments", 20.0), ("mu", mu)], 3.0, hoist),
            1e-3,
            &mut stopped,
        );
    }
    // 2,000 t on 400-segment slings (block-to-node mass ratio 2e6 / 0.82 kg ~ 2.4e6) loads the
    // 60 mm slings to twice their breaking load and 10,000 t (ratio 1.2e7) about tenfold: a
    // clear stop at set-up is the right answer for both (EXPECTED_STOPS)
    for (mass, segments) in [(1e3, 20.0), (2e5, 100.0), (2e6, 400.0), (1e7, 400.0)] {
        let case = format!("block {mass} kg, {segments} segments");
        check(
            &case,
            lift(&[("segments", segments), ("block_mass", mass)], 1.5, hoist),
            1e-3,
            &mut stopped,
        );
    }
    println!("stopped with a message: {stopped:#?}");
}

#[test]
fn slack_to_taut_snap_and_stiff_rope() {
    let mut stopped = Vec::new();
    // lower the hook 0.3 m (slings go slack), then snap them taut at 1 m/s
    let snap = |t: f64| {
        if t < 0.5 {
            0.0
        } else if t < 1.1 {
            -0.5
        } else {
            1.0
        }
    };
    for integrator in [1.0, 2.0] {
        let case = format!("snap, integrator {integrator}");
        check(
            &case,
            lift(&[("segments", 20.0), ("integrator", integrator)], 2.5, snap),
            1e-2,
            &mut stopped,
        );
    }
    for ea in [1.6e8, 1e9] {
        let case = format!("EA {ea:e} N");
        check(
            &case,
            lift(&[("segments", 20.0), ("rope_ea", ea)], 2.0, hoist),
            1e-3,
            &mut stopped,
        );
    }
    println!("stopped with a message: {stopped:#?}");
}

#[test]
fn axial_damping_from_default_to_extreme() {
    // Kelvin-Voigt damping of the slings from the default (retardation time 1 ms) to 5e6 N s
    // (31 ms, node-scale axial modes overdamped about 400-fold), gen-alpha and BDF: all run
    // passively. History: while the law clamped the total tension at zero, BDF's Newton
    // iteration diverged at 5e6 N s (0.83 s) and gen-alpha at rho_inf 0.8 went unstable in
    // longer hoists (kinetic energy 9 kJ -> 700 kJ in 6 s)
    let mut stopped = Vec::new();
    for damping in [1.6e5, 1e6, 5e6] {
        for integrator in [1.0, 2.0] {
            let case = format!("rope_damping {damping:e} N s, integrator {integrator}");
            let r = lift(
                &[
                    ("segments", 20.0),
                    ("rope_damping", damping),
                    ("integrator", integrator),
                ],
                3.0,
                hoist,
            );
            if let Err(msg) = &r {
                panic!("{case}: {msg}");
            }
            check(&case, r, 1e-3, &mut stopped);
        }
    }
    println!("stopped with a message: {stopped:#?}");
}

/// Peak sling tension of the default lift [N]: gen-alpha, rtol 1e-7, atol 1e-9, h_max 2 ms
/// (docs/rope_speed_bench.md, recomputed by `examples/bench_rope`).
const LIFT_PEAK_TENSION: f64 = 595.67e3;

/// Runs the default lift (demo schedule, 12 s) with gen-alpha at `rtol`: (peak sling tension
/// [N], steps).
fn default_lift(rtol: f64) -> (f64, u64) {
    use mbcosim::integrator::IntegratorKind;
    use mbcosim::math::Vec3;
    use mbcosim::scene::rope_block::demo::lift_hook_speed;
    use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
    let p = RopeBlockParams {
        integrator: IntegratorKind::GenAlpha,
        rtol,
        ..RopeBlockParams::default()
    };
    let mut scene = RopeBlockScene::new(p).unwrap();
    let slings: Vec<usize> = (0..scene.output_names().len())
        .filter(|&i| scene.output_names()[i].starts_with("sling"))
        .collect();
    let (mut peak, mut v_last): (f64, f64) = (0.0, f64::NAN);
    for k in 0..240 {
        let t = scene.sim.time();
        let v = lift_hook_speed(t);
        if v != v_last {
            scene.set_hook(0, Vec3::new(0.0, 0.0, v), 0.0).unwrap();
            v_last = v;
        }
        scene
            .step(0.05)
            .unwrap_or_else(|e| panic!("rtol {rtol}: stopped at t = {t} s: {e}"));
        let row = scene.outputs();
        peak = slings.iter().map(|&i| row[i]).fold(peak, f64::max);
        assert!(
            scene.sim.sim.stats().steps < 2000,
            "rtol {rtol}: more than 2000 steps by t = {t} s, step {k} (stick/slip chatter)"
        );
    }
    (peak, scene.sim.sim.stats().steps)
}

/// Issue #5: with error weights on absolute positions (nodes 7-26 m from the origin) gen-alpha at
/// rtol 1e-3 and 1e-4 fell into stick/slip chatter on the lift (1e-3: 11,900 steps for the first
/// 1.85 s). With the rope nodes weighted on their segment length the lift completes in a few
/// hundred steps, the peak tension within 3 % at 1e-3 and 0.1 % from 3e-4 on.
#[test]
fn gen_alpha_lift_completes_at_loose_tolerances() {
    for (rtol, allowed) in [(1e-3, 0.03), (3e-4, 1e-3), (1e-4, 1e-3)] {
        let (peak, steps) = default_lift(rtol);
        let err = (peak / LIFT_PEAK_TENSION - 1.0).abs();
        println!("rtol {rtol:e}: {steps} steps, peak tension {peak:.6e} N, error {err:.2e}");
        assert!(
            err <= allowed,
            "rtol {rtol}: peak tension {peak} N, {err:.3e} off the reference (allowed {allowed})"
        );
    }
}

/// Tight tolerances at the rope's slip reversals (t ~ 1.3 s and ~4.6 s of the lift): with the
/// slip modes re-decided at every Newton iterate, successive iterates switched modes and Newton
/// cycled (rate ~1), so steps failed and shrank: rtol 1e-4 took 1226 steps, 3e-5 2948 (h_max
/// 0.025 s, at least 480 steps). With the modes frozen after the first iterate (gen-alpha) they
/// took 472 and 652 steps, at the same peak tension; at today's h_max of 0.0125 s (at least
/// 960 steps) they take about 1130 and 1180.
#[test]
fn gen_alpha_lift_tight_tolerances_without_newton_cycling() {
    for rtol in [1e-4, 3e-5] {
        let (peak, steps) = default_lift(rtol);
        let err = (peak / LIFT_PEAK_TENSION - 1.0).abs();
        println!("rtol {rtol:e}: {steps} steps, peak tension {peak:.6e} N, error {err:.2e}");
        assert!(
            err <= 1e-3,
            "rtol {rtol}: peak tension {peak} N, {err:.3e} off the reference (allowed 1e-3)"
        );
        let fewest = 12.0 / mbcosim::scene::rope_block::RopeBlockParams::default().h_max;
        assert!(
            (steps as f64) < 1.5 * fewest,
            "rtol {rtol}: {steps} steps, the step limit allows {fewest} (Newton cycling at slip reversals?)"
        );
    }
}
