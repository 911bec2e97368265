//! RopeBlock's events for early return ([`crate::scene::watch`]): a contact node created or
//! released, a sling going slack (its segment at the block's lug without tension: the sling no
//! longer holds the block; the segments near the hook still carry the hanging rope's weight).

use super::runner::RopeBlockSim;
use crate::scene::watch::Watchable;

/// What RopeBlock's events change.
#[derive(Debug, Clone, PartialEq)]
pub struct RopeMarks {
    /// Contact nodes inserted and removed so far.
    inserted: u64,
    removed: u64,
    /// Per sling: slack (no tension in its segment at the lug).
    slack: Vec<bool>,
}

impl Watchable for RopeBlockSim {
    type Marks = RopeMarks;

    fn now(&self) -> f64 {
        self.time()
    }

    fn advance(&mut self, end: f64, one_step: bool) -> Result<(), String> {
        RopeBlockSim::advance(self, end, one_step)
    }

    fn marks(&mut self) -> RopeMarks {
        let slack = (0..self.structure.ropes.len())
            .map(|r| self.rope_tensions(r).last().is_none_or(|&(t, _)| t <= 0.0))
            .collect();
        RopeMarks {
            inserted: self.counters.inserted,
            removed: self.counters.removed,
            slack,
        }
    }

    fn happened(&self, before: &RopeMarks, after: &RopeMarks) -> Option<String> {
        let mut what = Vec::new();
        if after.inserted > before.inserted {
            what.push("a contact node was created".to_string());
        }
        if after.removed > before.removed {
            what.push("a contact node was released".to_string());
        }
        for (r, (b, a)) in before.slack.iter().zip(&after.slack).enumerate() {
            if *a && !*b {
                what.push(format!("sling {r} went slack"));
            }
        }
        (!what.is_empty()).then(|| what.join(", "))
    }

    /// The energy balance, which single-step advances do not check.
    fn check_at_end(&mut self) -> Result<(), String> {
        self.check_energy()
    }
}
