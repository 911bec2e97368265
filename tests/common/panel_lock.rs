//! PanelLock parameters shared by the integration tests.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{ErrorControl, PanelLockParams};

/// The default scene on `kind` at `rtol`, `atol = rtol * 1e-2`, h_max 0.02 s, the error held
/// per step: the tolerances of the tests that use it were chosen for that (BDF per step was the
/// default before docs/panel_lock_defaults.md; generalized-alpha per unit step stops with a
/// message at rtol 1e-7 and 1e-8 on this scene: docs/integrator_error_control.md).
pub fn per_step(kind: IntegratorKind, rtol: f64) -> PanelLockParams {
    PanelLockParams {
        integrator: Some(kind),
        error_control: ErrorControl::PerStep,
        settings: Settings {
            rtol,
            atol: rtol * 1e-2,
            h_max: 0.02,
            ..PanelLockParams::default().settings
        },
        ..PanelLockParams::default()
    }
}
