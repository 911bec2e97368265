//! Rank of the active constraint Jacobian, watched through the pivots of the Newton (or
//! `[M G^T; G 0]`) matrix the integrator factorizes anyway: no extra factorization.
//!
//! When the active rows `G` lose rank (a closed loop at a singular configuration: a
//! parallelogram four-bar with its links collinear, a four-bar at its change point) the matrix
//! becomes singular, and the dense LU shows it in the pivot of a constraint column: that column
//! is then nearly a combination of the columns before it. The pivot of each watched column is
//! compared with its value at the first factorization (a regular configuration: the redundancy
//! check at the start keeps only independent rows), both relative to the largest pivot of the
//! watched columns of the same block, so a uniform scaling of the constraint block (BDF's
//! leading coefficient) does not count. A ratio below [`RANK_DROP`] is a rank drop; the
//! passage ends when every ratio is back above [`RANK_BACK`]. Each passage is counted in
//! [`Stats::singular_configurations`]; the first passage of a set of joints is reported once
//! through the system's log queue, with the joints named.
//!
//! Only rows in components of the joint graph with a closed loop are watched (a tree of
//! standard joints never loses rank), so models without loops pay nothing. The sparse LU
//! (systems above [`crate::dae::linear::DENSE_LIMIT`] unknowns) reorders columns for fill and
//! is not watched.

use super::Stats;
use crate::dae::System;
use crate::dae::linear::LinearSolver;

/// Relative pivot below which the constraint Jacobian counts as rank-deficient. Measured on a
/// parallelogram four-bar: the ratio falls linearly with the distance to the change point
/// (about 11 per radian of crank angle there) and stays above 0.18 elsewhere on its turn.
pub const RANK_DROP: f64 = 1e-2;
/// Relative pivot above which (for every watched row) a passage has ended.
pub const RANK_BACK: f64 = 1e-1;

/// What an observation found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Passage {
    /// Nothing new.
    None,
    /// A passage through a singular configuration begins here.
    Entered,
    /// The passage has ended here.
    Left,
}

/// The watcher of one integrator's factorizations.
#[derive(Debug, Clone, Default)]
pub struct RankMonitor {
    /// Normalized pivot of each watched column at the first observation.
    baseline: Vec<f64>,
    /// Scratch: normalized pivots of the current observation.
    now: Vec<f64>,
    /// Inside a passage (a ratio fell below [`RANK_DROP`] and not all are back).
    inside: bool,
    /// Joint sets (indices into `model.joints`, sorted) already reported.
    reported: Vec<Vec<usize>>,
    /// Joints and time of the last passage (for messages).
    last: Option<(Vec<usize>, f64)>,
    /// Smallest pivot ratio of the last observation (1 before the first).
    smallest: f64,
    /// Largest watched pivot magnitude of the last observation's first block (0 before the
    /// first): the scale of the constraint block's Schur complement `G M^-1 G^T`.
    scale: f64,
    /// Loop rows grouped by component, for observations without pivots (computed once).
    groups: Option<Vec<Vec<usize>>>,
    /// Active row with the smallest pivot ratio in the last observation.
    weakest: Option<usize>,
}

impl RankMonitor {
    /// Appends what steers the integrator's numbers to a flat vector (for serialized states):
    /// the baseline's length and values, the smallest ratio and the pivot scale of the last
    /// observation, whether inside a passage, and the weakest row (-1: none). The joints already
    /// reported and the last passage only shape messages and are not written (a restored run
    /// may report a passage again).
    pub fn write(&self, m: &mut Vec<f64>) {
        m.push(self.baseline.len() as f64);
        m.extend_from_slice(&self.baseline);
        m.extend([
            self.smallest,
            self.scale,
            if self.inside { 1.0 } else { 0.0 },
            self.weakest.map_or(-1.0, |w| w as f64),
        ]);
    }

    /// Reads what [`RankMonitor::write`] appended, from `m[0]`; returns the count used.
    pub fn read(&mut self, m: &[f64]) -> Result<usize, String> {
        let bad = || "integrator monitor: truncated or corrupt rank monitor".to_string();
        let n = *m.first().ok_or_else(bad)?;
        if !(n.is_finite() && n >= 0.0 && n.fract() == 0.0 && n <= m.len() as f64) {
            return Err(bad());
        }
        let n = n as usize;
        let rest = m.get(1 + n..5 + n).ok_or_else(bad)?;
        let (smallest, scale, inside, weakest) = (rest[0], rest[1], rest[2], rest[3]);
        let whole = |x: f64| x.is_finite() && x.fract() == 0.0;
        if smallest.is_nan()
            || !(scale.is_finite() && scale >= 0.0)
            || !(inside == 0.0 || inside == 1.0)
            || !(whole(weakest) && (-1.0..=1e9).contains(&weakest))
            || m[1..1 + n].iter().any(|b| !b.is_finite())
        {
            return Err(bad());
        }
        self.baseline = m[1..1 + n].to_vec();
        self.smallest = smallest;
        self.scale = scale;
        self.inside = inside == 1.0;
        self.weakest = (weakest >= 0.0).then_some(weakest as usize);
        Ok(5 + n)
    }

    /// Forgets the baseline (a new system or a restart with another structure).
    pub fn reset(&mut self) {
        self.baseline.clear();
        self.inside = false;
        self.groups = None;
    }

    /// Whether the last observation was inside a passage through a singular configuration.
    pub fn inside(&self) -> bool {
        self.inside
    }

    /// How much the last factorization amplifies round-off beyond the first one's: the inverse
    /// of the smallest pivot ratio inside a passage (capped at 1e8), 1 outside.
    pub fn round_off_amplification(&self) -> f64 {
        if self.inside && self.smallest > 0.0 {
            (1.0 / self.smallest).min(1e8)
        } else {
            1.0
        }
    }

    /// As [`RankMonitor::round_off_amplification`], but from the first observation on, inside
    /// a passage or not: the inverse of the smallest pivot ratio (at least 1, capped at 1e8).
    pub fn conditioning_amplification(&self) -> f64 {
        if self.observed() && self.smallest > 0.0 {
            (1.0 / self.smallest).clamp(1.0, 1e8)
        } else {
            1.0
        }
    }

    /// Whether a first observation (the baseline) has been made.
    pub fn observed(&self) -> bool {
        !self.baseline.is_empty()
    }

    /// Smallest pivot ratio against the baseline in the last observation (0 before a second).
    pub fn smallest_ratio(&self) -> f64 {
        self.smallest
    }

    /// The joint (name, quoted) of the row with the smallest pivot ratio in the last observation.
    pub fn weakest_joints(&self, sys: &System) -> Option<String> {
        let j = sys.joint_of_active_row(self.weakest?)?;
        Some(joint_names(sys, &[j]))
    }

    /// Largest watched pivot magnitude of the last observation (the scale of `G M^-1 G^T` in
    /// the first block; 0 before the first observation).
    pub fn pivot_scale(&self) -> f64 {
        self.scale
    }

    /// Joints (names) and time of the last singular configuration seen, for messages.
    pub fn last_passage(&self, sys: &System) -> Option<(String, f64)> {
        let (joints, t) = self.last.as_ref()?;
        Some((joint_names(sys, joints), *t))
    }

    /// Looks at the pivots of the factorization just made of a matrix whose constraint columns
    /// are `col0 + b * n_c + r` for blocks `b < blocks` and active rows `r`, formed at time `t`.
    pub fn observe(
        &mut self,
        sys: &mut System,
        lin: &LinearSolver,
        col0: usize,
        blocks: usize,
        t: f64,
        stats: &mut Stats,
    ) -> Passage {
        self.observe_pivots(sys, &|c| lin.dense_pivot(c), (col0, blocks), t, stats)
    }

    /// As [`RankMonitor::observe`] with the pivot of column `c` from `pivot` (`None`: not shown).
    pub fn observe_pivots(
        &mut self,
        sys: &mut System,
        pivot: &dyn Fn(usize) -> Option<f64>,
        (col0, blocks): (usize, usize),
        t: f64,
        stats: &mut Stats,
    ) -> Passage {
        if !sys.has_loops() {
            return Passage::None;
        }
        let nc = sys.n_c();
        self.now.clear();
        for b in 0..blocks {
            let at = self.now.len();
            for r in 0..nc {
                let p = if sys.active_row_in_loop(r) {
                    match pivot(col0 + b * nc + r) {
                        Some(p) => p,
                        None => return Passage::None,
                    }
                } else {
                    0.0
                };
                self.now.push(p);
            }
            let big = self.now[at..].iter().fold(0.0_f64, |m, p| m.max(*p));
            if !(big > 0.0 && big.is_finite()) {
                return Passage::None;
            }
            if b == 0 {
                self.scale = big;
            }
            self.now[at..].iter_mut().for_each(|p| *p /= big);
        }
        self.decide(sys, nc, t, stats)
    }

    /// [`RankMonitor::observe`] when the factorization shows its pivots (dense LU), otherwise
    /// [`RankMonitor::observe_rows`] on the constraint rows evaluated last.
    pub fn observe_factorization(
        &mut self,
        sys: &mut System,
        lin: &LinearSolver,
        (col0, blocks): (usize, usize),
        t: f64,
        stats: &mut Stats,
    ) -> Passage {
        self.observe_pivots_or_rows(sys, &|c| lin.dense_pivot(c), (col0, blocks), t, stats)
    }

    /// [`RankMonitor::observe_pivots`] when `pivot` shows the constraint columns' pivots,
    /// otherwise [`RankMonitor::observe_rows`] on the constraint rows evaluated last.
    pub fn observe_pivots_or_rows(
        &mut self,
        sys: &mut System,
        pivot: &dyn Fn(usize) -> Option<f64>,
        (col0, blocks): (usize, usize),
        t: f64,
        stats: &mut Stats,
    ) -> Passage {
        if pivot(col0).is_some() {
            self.observe_pivots(sys, pivot, (col0, blocks), t, stats)
        } else {
            self.observe_rows(sys, t, stats)
        }
    }

    /// As [`RankMonitor::observe`] for a factorization that does not show its pivots (sparse
    /// LU): observes the constraint rows evaluated last directly, by the pivots of `G G^T` of
    /// each closed loop's rows ([`System::loop_row_pivots`], a small dense Cholesky per loop).
    /// The scale for [`RankMonitor::pivot_scale`] is then the largest `|G_r|^2` over the mass of
    /// the heaviest body (an estimate of `G M^-1 G^T`'s within a few times).
    pub fn observe_rows(&mut self, sys: &mut System, t: f64, stats: &mut Stats) -> Passage {
        if !sys.has_loops() {
            return Passage::None;
        }
        let groups = self.groups.get_or_insert_with(|| sys.loop_row_groups());
        let mut now = std::mem::take(&mut self.now);
        let g2 = sys.loop_row_pivots(groups, &mut now);
        self.now = now;
        let heaviest = sys
            .model
            .bodies
            .iter()
            .map(|b| b.kind.mass())
            .fold(0.0, f64::max);
        self.scale = if heaviest > 0.0 { g2 / heaviest } else { g2 };
        let nc = sys.n_c();
        self.decide(sys, nc, t, stats)
    }

    /// The passage state machine on the normalized observation in `now` (blocks of `nc` rows).
    fn decide(&mut self, sys: &mut System, nc: usize, t: f64, stats: &mut Stats) -> Passage {
        if self.baseline.len() != self.now.len() {
            self.baseline.clone_from(&self.now);
            return Passage::None;
        }
        let mut smallest = f64::INFINITY;
        let mut rows = Vec::new();
        for (k, (p, b)) in self.now.iter().zip(&self.baseline).enumerate() {
            if *b <= 0.0 {
                continue;
            }
            let ratio = p / b;
            if ratio < smallest {
                smallest = ratio;
                self.weakest = Some(k % nc);
            }
            if ratio < RANK_DROP {
                rows.push(k % nc);
            }
        }
        self.smallest = smallest;
        if !self.inside {
            if rows.is_empty() {
                return Passage::None;
            }
            self.inside = true;
            stats.singular_configurations += 1;
            let mut joints: Vec<usize> = rows
                .iter()
                .filter_map(|&r| sys.joint_of_active_row(r))
                .collect();
            joints.sort_unstable();
            joints.dedup();
            if !self.reported.contains(&joints) {
                sys.push_solver_note(format!(
                    "singular configuration at t = {t:.6} s: the constraints of joint(s) {} lose rank (pivot ratio {smallest:.1e}); further passages of these joints are only counted (Stats::singular_configurations)",
                    joint_names(sys, &joints)
                ));
                self.reported.push(joints.clone());
            }
            self.last = Some((joints, t));
            Passage::Entered
        } else {
            if smallest > RANK_BACK {
                self.inside = false;
                return Passage::Left;
            }
            Passage::None
        }
    }
}

/// The joints' names, quoted and comma-separated.
fn joint_names(sys: &System, joints: &[usize]) -> String {
    joints
        .iter()
        .filter_map(|&j| sys.model.joints.get(j))
        .map(|j| format!("'{}'", j.name))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::RankMonitor;

    #[test]
    fn written_monitor_reads_back_and_corrupt_values_are_refused() {
        let m = RankMonitor {
            baseline: vec![1.0, 0.5],
            smallest: 0.25,
            scale: 3.0,
            inside: true,
            weakest: Some(1),
            ..RankMonitor::default()
        };
        let mut v = Vec::new();
        m.write(&mut v);
        v.push(42.0); // what follows is left alone
        let mut r = RankMonitor::default();
        assert_eq!(r.read(&v), Ok(v.len() - 1));
        assert_eq!(
            (r.baseline.clone(), r.smallest, r.scale, r.inside, r.weakest),
            (vec![1.0, 0.5], 0.25, 3.0, true, Some(1))
        );
        assert_eq!(r.conditioning_amplification(), 4.0);
        for (i, bad) in [(0, 9.0), (0, -1.0), (4, -1.0), (5, 0.5), (6, 2.5)] {
            let mut w = v.clone();
            w[i] = bad;
            assert!(RankMonitor::default().read(&w).is_err(), "{i} = {bad}");
        }
        assert!(RankMonitor::default().read(&v[..4]).is_err());
    }
}
