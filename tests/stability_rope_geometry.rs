//! Stability suite, RopeBlock: the hook dragged 9 m along the block, so that the sling contact
//! nodes slide along the deck edges (with friction, and frictionless), and a 2000-node sling,
//! run as the FMU runs them. Every case must complete with finite outputs, a mechanical energy
//! that never exceeds its start plus the work put in (the scene is passive) and a hook load near
//! the block's weight; a stop fails the suite. The geometric corners (chamfer, 32 edges
//! within one segment, a rope sliding off its edge's end) are in tests/rope/hard_cases.rs.
//! `cargo test --release --test stability_rope_geometry -- --nocapture` prints the figures.

use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};

/// What a run showed: largest mechanical energy gain beyond the work put in (kinetic +
/// potential - input - rebuild events, from its start), and the largest growth and largest loss
/// of the full balance (dissipation included), all relative to the block's weight times 1 m;
/// largest total hook load [N], most contact nodes at once, final block height [m].
#[derive(Debug)]
struct Run {
    gain: f64,
    balance_growth: f64,
    balance_loss: f64,
    peak_load: f64,
    max_contacts: usize,
    block_z: f64,
}

/// Runs `p` for `t_end` [s] in 0.05 s communication steps, the hooks driven by `drive(t)`
/// (hook, velocity [m/s]); every output must stay finite.
fn run(
    p: RopeBlockParams,
    t_end: f64,
    drive: impl Fn(f64) -> Vec<(usize, Vec3)>,
) -> Result<Run, String> {
    let weight = p.block_mass * p.gravity;
    let mut scene = RopeBlockScene::new(p)?;
    let names = scene.output_names().to_vec();
    let col = |n: &str| names.iter().position(|x| x == n).unwrap();
    let energy: Vec<usize> = ["kinetic", "potential", "dissipated", "input", "events"]
        .iter()
        .map(|c| col(&format!("energy.{c}")))
        .collect();
    let loads: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].starts_with("hook") && names[i].ends_with(".load"))
        .collect();
    let z = col("block.z");
    let mechanical = |o: &[f64]| o[energy[0]] + o[energy[1]] - o[energy[3]] - o[energy[4]];
    let first = scene.outputs();
    let (m0, d0) = (mechanical(&first), first[energy[2]]);
    let mut r = Run {
        gain: 0.0,
        balance_growth: 0.0,
        balance_loss: 0.0,
        peak_load: 0.0,
        max_contacts: 0,
        block_z: f64::NAN,
    };
    let h = 0.05;
    let n = (t_end / h).round() as usize;
    for k in 0..n {
        let t = k as f64 * h;
        for (hook, v) in drive(t) {
            scene.set_hook(hook, v, 0.0)?;
        }
        scene.step(h)?;
        let o = scene.outputs();
        if let Some(i) = o.iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "non-finite output {} at t = {t} s without an error (defect)",
                names[i]
            ));
        }
        let gain = mechanical(&o) - m0;
        r.gain = r.gain.max(gain / weight);
        let balance = gain + o[energy[2]] - d0;
        r.balance_growth = r.balance_growth.max(balance / weight);
        r.balance_loss = r.balance_loss.max(-balance / weight);
        r.peak_load = r.peak_load.max(loads.iter().map(|&i| o[i]).sum());
        r.max_contacts = r.max_contacts.max(scene.sim.contact_reports().len());
        r.block_z = o[z];
    }
    Ok(r)
}

/// Passes when the run completed passively with a plausible load; a stop fails the case (no case
/// of this suite is expected to stop).
fn check(case: &str, r: Result<Run, String>, weight: f64, rtol: f64) -> Run {
    match r {
        Ok(run) => {
            println!("{case}: {run:?}");
            // a passive scene: the mechanical energy may exceed its start plus the work put in
            // by the integration error, never by more
            assert!(
                run.gain <= 100.0 * rtol.max(1e-4),
                "{case}: energy grew by {} x weight x 1 m",
                run.gain
            );
            // every joule is booked: damping and drag by the integrator, the friction slides
            // of the contact nodes by the contact manager (this was 4.7e-2 before they were);
            // the one unbooked flow is generalized-alpha's numerical damping (rho_inf 0), a loss
            assert!(
                run.balance_growth <= 1e-4,
                "{case}: energy balance grew by {} x weight x 1 m",
                run.balance_growth
            );
            assert!(
                run.balance_loss <= 5e-3,
                "{case}: energy balance lost {} x weight x 1 m",
                run.balance_loss
            );
            assert!(
                run.peak_load > 0.9 * weight && run.peak_load < 3.0 * weight,
                "{case}: peak hook load {} N for a {weight} N block",
                run.peak_load
            );
            run
        }
        Err(msg) => panic!("{case}: stopped: {msg} (every case of this suite must complete)"),
    }
}

/// The hook driven along the block's length at 1.5 m/s for 6 s (9 m) while rising at 0.1 m/s.
fn drag_along(t: f64) -> Vec<(usize, Vec3)> {
    let v = if (0.5..6.5).contains(&t) { 1.5 } else { 0.0 };
    vec![(0, Vec3::new(v, 0.0, 0.1))]
}

#[test]
fn slings_dragged_along_their_edges() {
    // the default lift (40 segments per sling) with its hook driven along the block's length:
    // the sling contact nodes slide along the deck edges, with friction and on frictionless edges
    for (case, mu) in [
        ("hook dragged 9 m along the block", None),
        (
            "hook dragged 9 m along the block, frictionless edges",
            Some(0.0),
        ),
    ] {
        let mut p = RopeBlockParams {
            segments: 40,
            ..RopeBlockParams::default()
        };
        if let Some(mu) = mu {
            p.rope.friction = mu;
        }
        let weight = p.block_mass * p.gravity;
        let rtol = p.rtol;
        check(case, run(p, 8.0, drag_along), weight, rtol);
    }
}

#[test]
fn two_thousand_rope_nodes() {
    // the block below the hook on one sling of 2000 segments (1999 rope nodes, 9.5 mm each,
    // node-to-block mass ratio 1.4e6), settled hanging at rest and hoisted at 0.3 m/s
    let p = RopeBlockParams::single_sling(2000);
    let weight = p.block_mass * p.gravity;
    let rtol = p.rtol;
    let hoist = |t: f64| {
        let v = if t < 0.5 { 0.0 } else { 0.3 };
        vec![(0, Vec3::new(0.0, 0.0, v))]
    };
    let start = std::time::Instant::now();
    let r = check("2000 rope nodes", run(p, 2.0, hoist), weight, rtol);
    println!(
        "2000 rope nodes: 2 s in {:.2} s",
        start.elapsed().as_secs_f64()
    );
    assert!(r.block_z > 0.0, "block height {}", r.block_z);
}

#[test]
fn energy_guard_stops_an_unstable_run() {
    // No setting of the default scene is known to go unstable any more (the last one, slings
    // with 5e6 N s axial damping under gen-alpha at rho_inf 0.8, stopped once the damping no
    // longer switched on the speeds: src/rope/segment.rs), so the energy an unstable step would
    // leave is put in by hand: after 1 s of hoisting, the block is given 3 m/s upwards between
    // two communication steps (0.9 MJ, 46 % of the weight times 1 m, booked nowhere). The next
    // step must stop with the cause and the parameters to change instead of returning the
    // state; a step without the injection must go on (the guard does not fire on its own).
    let p = RopeBlockParams {
        segments: 20,
        ..RopeBlockParams::default()
    };
    let mut scene = RopeBlockScene::new(p).unwrap();
    let hoist = Vec3::new(0.0, 0.0, 0.3);
    for _ in 0..20 {
        scene.set_hook(0, hoist, 0.0).unwrap();
        scene.step(0.05).expect("the undisturbed hoist");
    }
    let body = scene.sim.map.blocks[0].index().unwrap();
    let vo = scene.sim.sim.system.model.bodies[body].v_offset;
    scene.sim.sim.state.v[vo + 2] += 3.0;
    match scene.step(0.05) {
        Ok(()) => panic!("the run went on after a 0.9 MJ gain"),
        Err(msg) => {
            println!("{msg}");
            assert!(
                msg.contains("numerical instability")
                    && msg.contains("energy balance grew")
                    && msg.contains("rope_damping")
                    && msg.contains("bdf"),
                "{msg}"
            );
        }
    }
}
