//! PanelLock rigid default scene, 60 s in one `advance_to` call (as `bench_core panel`): largest
//! lock force and thread CPU time (best of N) of one setting. Reported, never asserted.
//!
//! `cargo run --release --example panel_speed -- KIND RTOL [step|unit|default] [REPEATS]`
//! (KIND: gen-alpha, bdf, dopri5, dopri5-tree, verner65-tree, verner87-tree; atol = rtol / 100, h_max 0.02 s as in `bench_core`; the
//! environment variables `T_END` [s] and `H_MAX` [s] change the run's length and h_max).

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{ErrorControl, PanelLock, PanelLockParams};

/// CPU time of the calling thread [s] (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`): the machine
/// is shared, so wall time would count the other processes.
fn thread_cpu() -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: a valid pointer to a timespec; clock 3 is CLOCK_THREAD_CPUTIME_ID on Linux.
    unsafe { clock_gettime(3, &mut ts) };
    ts.sec as f64 + ts.nsec as f64 * 1e-9
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("gen-alpha", |s| s.as_str());
    let kind = IntegratorKind::ALL
        .into_iter()
        .chain(IntegratorKind::LIBRARY_ONLY)
        .find(|k| k.name() == name)
        .expect("integrator name");
    let rtol: f64 = args.get(2).map_or(1e-4, |s| s.parse().expect("rtol"));
    let control = match args.get(3).map_or("default", |s| s.as_str()) {
        "step" => ErrorControl::PerStep,
        "unit" => ErrorControl::PerUnitStep,
        _ => ErrorControl::ByPanels,
    };
    let repeats: usize = args.get(4).map_or(3, |s| s.parse().expect("repeats"));
    let t_end: f64 = std::env::var("T_END")
        .ok()
        .map_or(60.0, |s| s.parse().expect("T_END"));
    let h_max: f64 = std::env::var("H_MAX")
        .ok()
        .map_or(0.02, |s| s.parse().expect("H_MAX"));
    let p = PanelLockParams {
        integrator: Some(kind),
        settings: Settings {
            rtol,
            atol: rtol * 1e-2,
            h_max,
            ..Settings::default()
        },
        error_control: control,
        ..PanelLockParams::default()
    };
    let mut best = f64::INFINITY;
    for _ in 0..repeats {
        let t0 = thread_cpu();
        let mut s = PanelLock::new(p.clone()).expect("scene");
        s.advance_to(t_end).expect("run");
        let cpu = thread_cpu() - t0;
        best = best.min(cpu);
        let o = s.outputs();
        let peaks: Vec<f64> = o.hinges.iter().map(|h| h.peak_force).collect();
        let st = s.sim.stats();
        println!(
            "{} rtol {rtol:e} {control:?}: peaks {:?} max {:.9e} N; steps {} rejected {} newton {} jac {} fact {} rhs {}; cpu {cpu:.4} s",
            kind.name(),
            peaks,
            peaks.iter().copied().fold(0.0, f64::max),
            st.steps,
            st.rejected,
            st.newton_iterations,
            st.jacobians,
            st.factorizations,
            st.rhs_evaluations
        );
    }
    println!(
        "best thread CPU {best:.4} s, real-time factor {:.0}",
        t_end / best
    );
}
