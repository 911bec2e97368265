//! The approach speed `delta_dot_minus` [m/s] of a contact: state that the caller keeps per contact
//! pair, because the damped laws scale their damping by the speed at which the contact closed.
//!
//! How a caller records it:
//! - Call [`ApproachMemory::update`] once per **accepted** step (never inside Newton iterations,
//!   where the trial states must see a fixed approach speed) with the penetration and its rate at
//!   the end of the step. On the first accepted state with `delta > 0` after a separated one, the
//!   current `delta_dot` is stored. This slightly underestimates the true onset speed (the contact
//!   has already braked the bodies during the part of the step spent in contact, an `O(F h / m)`
//!   error), so:
//! - an integrator that locates the onset event (`delta = 0`) calls
//!   [`ApproachMemory::record_onset`] with the rate at the event instead, which is exact.
//! - When `delta <= 0` again the memory forgets the speed; the next contact records a new one.
//!
//! A contact that is closed from the start (initial penetration) or closes while opening
//! (`delta_dot <= 0` at onset) has no meaningful approach speed: the memory holds 0, and the law
//! then uses its floor [`super::ContactLaw::min_approach_speed`].

/// Per-contact memory of the approach speed at onset. Plain data: clone it with the model state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ApproachMemory {
    in_contact: bool,
    approach_speed: f64,
}

impl ApproachMemory {
    /// A separated contact with no recorded approach speed.
    pub fn new() -> Self {
        Self::default()
    }

    /// Updates the memory from an accepted state: penetration `delta` [m], rate `delta_dot` [m/s].
    /// Records `max(delta_dot, 0)` when the contact has just closed; forgets it when it opens.
    /// Non-finite inputs are ignored (the memory is left as it was).
    pub fn update(&mut self, delta: f64, delta_dot: f64) {
        if !(delta.is_finite() && delta_dot.is_finite()) {
            return;
        }
        if delta > 0.0 {
            if !self.in_contact {
                self.in_contact = true;
                self.approach_speed = delta_dot.max(0.0);
            }
        } else {
            self.in_contact = false;
            self.approach_speed = 0.0;
        }
    }

    /// Records the onset exactly: the caller located `delta = 0` with rate `delta_dot` [m/s]
    /// (closing: `> 0`). Marks the contact closed. A non-finite rate records 0 (unknown).
    pub fn record_onset(&mut self, delta_dot: f64) {
        self.in_contact = true;
        self.approach_speed = if delta_dot.is_finite() {
            delta_dot.max(0.0)
        } else {
            0.0
        };
    }

    /// Whether the last accepted state was in contact (`delta > 0`).
    pub fn in_contact(&self) -> bool {
        self.in_contact
    }

    /// Recorded approach speed [m/s]; 0 when unknown or separated (the law then uses its floor).
    pub fn approach_speed(&self) -> f64 {
        self.approach_speed
    }
}

#[cfg(test)]
mod tests {
    use super::ApproachMemory;

    #[test]
    fn records_on_closing_keeps_while_closed_forgets_on_opening() {
        let mut m = ApproachMemory::new();
        m.update(-1e-6, 0.5);
        assert!(!m.in_contact());
        assert_eq!(m.approach_speed(), 0.0);
        m.update(1e-6, 0.4);
        assert!(m.in_contact());
        assert_eq!(m.approach_speed(), 0.4);
        m.update(2e-6, 0.1);
        m.update(1e-6, -0.3);
        assert_eq!(m.approach_speed(), 0.4);
        m.update(f64::NAN, 1.0);
        assert_eq!(m.approach_speed(), 0.4);
        m.update(0.0, -0.35);
        assert!(!m.in_contact());
        assert_eq!(m.approach_speed(), 0.0);
        m.update(1e-7, -0.2);
        assert_eq!(m.approach_speed(), 0.0);
        m.record_onset(0.7);
        assert!(m.in_contact());
        assert_eq!(m.approach_speed(), 0.7);
        m.record_onset(f64::INFINITY);
        assert_eq!(m.approach_speed(), 0.0);
    }
}
