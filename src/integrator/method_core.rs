//! What the implicit step loop ([`super::implicit::advance`]) reads and writes of a method, the
//! same for generalized-alpha and BDF: one struct each method owns, so the loop reaches it
//! through one accessor ([`super::implicit::ImplicitMethod::core`]) instead of one per field.

use super::events::EventLocator;
use super::{Settings, Stats};

/// The shared part of an implicit integrator's state.
#[derive(Debug, Clone)]
pub(super) struct MethodCore {
    /// The settings.
    pub(super) s: Settings,
    /// The controller's next step [s].
    pub(super) h: f64,
    /// The step counters.
    pub(super) stats: Stats,
    /// Contact-event location (adaptive mode, models with contact events).
    pub(super) events: EventLocator,
    /// Whether the current Newton matrix is valid (a failed step is first retried with a fresh
    /// one).
    pub(super) jac_valid: bool,
}

impl MethodCore {
    /// The core of a method with settings `s`, before its start: no step size, no counts, no
    /// matrix.
    pub(super) fn new(s: Settings) -> Self {
        MethodCore {
            s,
            h: 0.0,
            stats: Stats::default(),
            events: EventLocator::default(),
            jac_valid: false,
        }
    }
}
