//! PanelLock's events for early return ([`crate::scene::watch`]): a hinge's latch engaging.

use super::PanelLock;
use crate::scene::watch::Watchable;

impl Watchable for PanelLock {
    /// Per hinge: locked (its latch has a lock time).
    type Marks = Vec<bool>;

    fn now(&self) -> f64 {
        self.sim.state.t
    }

    fn advance(&mut self, end: f64, one_step: bool) -> Result<(), String> {
        PanelLock::advance(self, end, one_step).map_err(|e| e.to_string())
    }

    fn marks(&mut self) -> Vec<bool> {
        self.lock_times().iter().map(|t| t.is_finite()).collect()
    }

    fn happened(&self, before: &Vec<bool>, after: &Vec<bool>) -> Option<String> {
        let locked: Vec<String> = before
            .iter()
            .zip(after)
            .enumerate()
            .filter(|(_, (b, a))| **a && !**b)
            .map(|(k, _)| k.to_string())
            .collect();
        match locked.len() {
            0 => None,
            1 => Some(format!("hinge {} locked", locked[0])),
            _ => Some(format!("hinges {} locked", locked.join(", "))),
        }
    }
}
