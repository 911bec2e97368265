//! The tilted sharp edge pulled by a hook at quasi-static speeds (issue #42): T2/T1 across the
//! contact node must not depend on the pull speed, and the run must not cost more steps than
//! the rope's own motion asks (rigs of `pulled.rs`, figures in docs/rope_friction.md, "Pulled at
//! a speed").

use super::pulled::{
    PullOptions, TiltedRun, run_tilted, run_tilted_by_length, strand_critical_damping,
    swing_critical_damping, tilted_rig,
};

/// Runs the tilted edge at 0.05 and 0.2 m/s; returns both runs and the relative difference of
/// their mean T2/T1 over 1-2 s.
fn at_two_speeds(t1: f64, tilt: f64) -> (TiltedRun, TiltedRun, f64) {
    let slow = run_tilted(t1, tilt, 0.05);
    let fast = run_tilted(t1, tilt, 0.2);
    let spread = (fast.mean / slow.mean - 1.0).abs();
    println!(
        "T1 {t1:.3e} N, tilt {tilt} deg: 0.05 m/s {slow:?}; 0.2 m/s {fast:?}; T2/T1 apart by {spread:.2e}"
    );
    (slow, fast, spread)
}

/// 10 degrees: the node holds along its edge (edge load below `mu N`, no edge slide) and the
/// rope slides through it steadily: T2/T1 1.3286 at both speeds (samples within 1.3281-1.3292),
/// 4,010-4,016 steps for 2 s (2,000 of them the 1 ms samples'), 11-17 rejected, no Newton
/// failure. A guard for the change of item 2 (20 degrees), which must leave this rig alone.
#[test]
fn tilted_edge_at_10_degrees_slides_at_one_ratio_whatever_the_pull_speed() {
    let (slow, fast, spread) = at_two_speeds(9.81e5, 10.0);
    assert!(spread < 5e-3, "T2/T1 {} against {}", slow.mean, fast.mean);
    for r in [slow, fast] {
        assert!((r.mean - 1.3286).abs() < 1e-3, "{r:?}");
        assert!(r.largest - r.least < 2e-3, "{r:?}");
        assert!(r.steps <= 4_100 && r.rejected <= 50, "{r:?}");
        assert!(
            r.edge_slides == 0 && r.newton_failed == 0 && r.newton < 3 * r.steps,
            "{r:?}"
        );
    }
}

/// 20 degrees on the quasi-static version of the rig (docs/rope_friction.md, "The tilted edge
/// made quasi-static"): the end load's swing, the strands' transverse vibration and the contact
/// node's slide along its edge critically damped (rig dampers, the rope model unchanged). Then
/// T2/T1 is a function of the pulled length, not of the speed: its mean over 0.2-0.4 m pulled
/// at 0.05, 0.1 and 0.2 m/s (1.00814 / 1.00911 / 1.01044 measured) agrees within 0.5 % and lies
/// within 1.5 % of the edge-first quasi-static value 1 (the node held at its cone's tip leaves
/// the rope no friction). Pulled 0.4 m at 0.2 m/s and sampled every 10 mm the run takes 3,760
/// steps (bound 4,000; the undamped rig takes 15,049 for 2 s). Fails with the end load alone
/// damped (means 1.030-1.034) or with the dampers three times critical (1.031-1.048).
#[test]
fn tilted_edge_at_20_degrees_damped_gives_one_ratio_at_equal_pulled_length() {
    let (t1, tilt) = (9.81e5, 20.0);
    let rig = tilted_rig(t1, tilt);
    let cs = strand_critical_damping(&rig, t1);
    let opt = PullOptions {
        damping: swing_critical_damping(&rig, t1),
        strand_damping: cs,
        contact_damping: cs,
        ..PullOptions::default()
    };
    let means: Vec<f64> = [0.05, 0.1, 0.2]
        .iter()
        .map(|&v| {
            let r = run_tilted_by_length(t1, tilt, v, opt, 2e-4, 0.4);
            let (mean, least, largest) = r.stats_from(0.2);
            println!(
                "v {v} m/s to {} s: steps {}, rejected {}, Newton {} (failed {}), edge slides {}; T2/T1 over 0.2-0.4 m pulled: mean {mean:.5}, {least:.5}-{largest:.5}",
                r.t_end, r.steps, r.rejected, r.newton, r.newton_failed, r.edge_slides
            );
            mean
        })
        .collect();
    let hi = means.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lo = means.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(hi / lo - 1.0 < 5e-3, "T2/T1 means {means:?}");
    assert!(means.iter().all(|m| (m - 1.0).abs() < 1.5e-2), "{means:?}");
    let coarse = run_tilted_by_length(t1, tilt, 0.2, opt, 1e-2, 0.4);
    println!("0.2 m/s, samples every 10 mm: {} steps", coarse.steps);
    assert!(coarse.steps <= 4_000, "{} steps", coarse.steps);
}
