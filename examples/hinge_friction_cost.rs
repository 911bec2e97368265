//! Cost of PanelLock runs with hinge friction (docs/hinge_friction_cost.md): accepted and
//! rejected steps, Newton iterations and failures, thread CPU time of one run. Reported, never
//! asserted (the step counts are asserted in `tests/panel_lock_flex/hinge_friction.rs`).
//!
//! `cargo run --release --example hinge_friction_cost -- FLEX FRICTION KIND RTOL T_END`
//! (FLEX: rigid or flex; FRICTION [N m]; KIND: gen-alpha, bdf, ...; T_END [s]).

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{DEFAULT_ATOL, DEFAULT_RTOL, PanelLock, PanelLockParams};

/// CPU time of the calling thread [s], from `/proc/thread-self/schedstat` (its first field is
/// the time spent on the CPU [ns]); NaN where that file is not there. The machine is shared, so
/// wall time would count the other processes.
fn thread_cpu() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let flex = args.get(1).is_some_and(|s| s == "flex");
    let friction: f64 = args.get(2).map_or(0.05, |s| s.parse().expect("friction"));
    let name = args.get(3).map_or("gen-alpha", |s| s.as_str());
    let kind = IntegratorKind::ALL
        .into_iter()
        .find(|k| k.name() == name)
        .expect("integrator name");
    let rtol: f64 = args.get(4).map_or(1e-4, |s| s.parse().expect("rtol"));
    let t_end: f64 = args.get(5).map_or(0.3, |s| s.parse().expect("t_end"));
    let defaults = PanelLockParams::default();
    let p = PanelLockParams {
        flexible_panels: flex,
        // the FMU's and the CLI's modes for `n_modes = 0` with flexible panels
        n_modes: if flex { 10 } else { 0 },
        hinge_friction_torque: friction,
        integrator: Some(kind),
        settings: Settings {
            rtol,
            atol: DEFAULT_ATOL * rtol / DEFAULT_RTOL,
            ..defaults.settings
        },
        ..defaults
    };
    let t0 = thread_cpu();
    let mut s = PanelLock::new(p).expect("scene");
    s.advance_to(t_end).expect("run");
    let cpu = thread_cpu() - t0;
    let st = s.sim.stats();
    let angles: Vec<f64> = (0..s.lock_times().len())
        .map(|k| s.hinge_angle(k).0)
        .collect();
    println!(
        "{} friction {friction} {} rtol {rtol:e} to {t_end} s: steps {} rejected {} newton {} failures {} jacobians {} last step {:.3e} s; cpu {cpu:.3} s; angles {:?}",
        if flex { "flex" } else { "rigid" },
        kind.name(),
        st.steps,
        st.rejected,
        st.newton_iterations,
        st.newton_failures,
        st.jacobians,
        st.last_step,
        angles
    );
}
