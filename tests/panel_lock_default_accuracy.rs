//! PanelLock's default integrator settings hold what docs/panel_lock_defaults.md chose them for:
//! the rigid default scene's lock force and root lock time within 1 % and 1 ms of a much tighter
//! BDF run, and the flexible paper configuration's first lock force within 1 % of one.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{ErrorControl, PanelLock, PanelLockParams};

/// Largest lock force over all hinges [N] and the root lock time [s] after `t_end` [s].
fn run(p: PanelLockParams, t_end: f64) -> (f64, f64) {
    let mut s = PanelLock::new(p).unwrap();
    s.advance_to(t_end).unwrap();
    let o = s.outputs();
    let peak = o.hinges.iter().map(|h| h.peak_force).fold(0.0, f64::max);
    (peak, o.hinges[0].lock_time)
}

/// `p` with BDF at `rtol` (atol rtol / 100) and the error control `control`.
fn tight(p: PanelLockParams, rtol: f64, control: ErrorControl) -> PanelLockParams {
    PanelLockParams {
        integrator: Some(IntegratorKind::Bdf),
        settings: Settings {
            rtol,
            atol: rtol * 1e-2,
            ..p.settings
        },
        error_control: control,
        ..p
    }
}

/// `p` with its default solver against `p` on BDF at `rtol_ref` with `control`, both over
/// `t_end` [s]: the largest lock force within 1 % and the root lock time within 1 ms.
fn assert_default_within_one_percent(
    p: PanelLockParams,
    t_end: f64,
    rtol_ref: f64,
    control: ErrorControl,
) {
    let (peak, lock) = run(p.clone(), t_end);
    let (peak_ref, lock_ref) = run(tight(p, rtol_ref, control), t_end);
    let e = (peak - peak_ref).abs() / peak_ref;
    println!("peak {peak} N vs {peak_ref} N ({e:.1e}); root lock {lock} s vs {lock_ref} s");
    assert!(e < 0.01, "peak lock force off by {e:.2e}");
    assert!(
        (lock - lock_ref).abs() < 1e-3,
        "root lock time {lock} s vs {lock_ref} s"
    );
}

#[test]
fn rigid_default_scene_within_one_percent_of_a_tight_bdf_run() {
    // 12 s: the root, third and second hinges lock (4.9, 7.1, 10.9 s); the largest force is
    // among them
    assert_default_within_one_percent(
        PanelLockParams::default(),
        12.0,
        1e-9,
        ErrorControl::PerUnitStep,
    );
}

#[test]
fn flexible_paper_configuration_first_lock_within_one_percent_of_a_tight_bdf_run() {
    // the root lock (5.02 s) of the paper configuration, 10 modes per panel, per step (as the
    // default runs flexible panels)
    assert_default_within_one_percent(
        PanelLockParams::flexible(10),
        6.0,
        1e-8,
        ErrorControl::PerStep,
    );
}
