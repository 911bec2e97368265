//! The Coulomb cone of a contact node settled at an accepted state: what the rope-block manager
//! decides after each step ([`super::friction`] is the law; this is its settlement), as functions
//! of what acts at the node. The manager evaluates the nodes, applies these decisions to the
//! memory and books the energy they remove.
//!
//! - A node sticking along the rope whose friction is outside its cone slides, towards the larger
//!   tension, with the share the cone leaves ([`NodeCone::slide_out`]).
//! - A node the rope slides through whose friction is outside its cone gets the share its edge
//!   load and geometry leave ([`NodeCone::settled_share`]).
//! - A hold whose force exceeds what the cone leaves along the edge is cut to that capacity
//!   ([`NodeCone::clipped_hold`]), at sliding nodes and wherever the edge load alone exceeds
//!   `mu N`.
//!
//! "Outside" means friction above `mu N (1 + 1e-12)` with `N > 0`.

use super::friction::{self, ContactFrame, Reaction};
use super::layout::SlipMode;
use crate::math::Vec3;

/// Relative tolerance of the cone's boundary.
const CONE_TOL: f64 = 1e-12;

/// A contact node at an accepted state, as the cone settlement sees it.
#[derive(Debug, Clone, Copy)]
pub struct NodeCone<'a> {
    /// Cone coefficient `mu` [-].
    pub mu: f64,
    /// Slip mode along the rope.
    pub mode: SlipMode,
    /// The rope's pull on the node in the contact frame ([`friction::rope_pull`]) [N].
    pub pull: &'a Reaction,
    /// The hold's force along the edge `F_e` [N].
    pub hold_force: f64,
    /// Contact frame and unit vectors from the node to its neighbours (world).
    pub frame: &'a ContactFrame,
    pub e_prev: &'a Vec3,
    pub e_next: &'a Vec3,
    /// Turning angle of the rope at the node [rad].
    pub turn: f64,
    /// Tensions of the node's previous and next segments [N].
    pub t_prev: f64,
    pub t_next: f64,
}

impl NodeCone<'_> {
    /// Friction `|(F_e, F_r)|` [N].
    fn friction(&self) -> f64 {
        self.hold_force.hypot(self.pull.along_rope)
    }

    /// Whether the node's friction is beyond the cone's boundary (any `N`).
    fn beyond(&self) -> bool {
        self.friction() > self.mu * self.pull.normal * (1.0 + CONE_TOL)
    }

    /// The sharp-edge coefficient of `share` in the rope's plane for sliding `forward` or back
    /// ([`friction::plane_coefficients`]; `share` itself where there is none).
    fn coefficient(&self, share: f64, forward: bool) -> f64 {
        let [fwd, bwd] =
            friction::plane_coefficients(self.frame, self.e_prev, self.e_next, self.turn, share);
        if forward { fwd } else { bwd }.unwrap_or(share)
    }

    /// A node sticking along the rope with friction outside its cone: the mode (towards the
    /// larger tension) and the coefficient it slides with; `None` otherwise.
    pub fn slide_out(&self) -> Option<(SlipMode, f64)> {
        if !(self.mode == SlipMode::Stick && self.pull.normal > 0.0 && self.beyond()) {
            return None;
        }
        let share = friction::rope_share(self.mu, self.pull.normal, self.hold_force);
        let forward = self.t_next > self.t_prev;
        let mode = if forward {
            SlipMode::SlipForward
        } else {
            SlipMode::SlipBackward
        };
        Some((mode, self.coefficient(share, forward)))
    }

    /// A node the rope slides through with friction outside its cone: the coefficient of the
    /// share its edge load and geometry leave; `None` otherwise (only where the cone is left: a
    /// share changed at every step would be a force discontinuity at every step, BDF's steps
    /// collapsed on the default lift).
    pub fn settled_share(&self) -> Option<f64> {
        let n = self.pull.normal;
        if self.mode == SlipMode::Stick || n <= 0.0 || !self.beyond() {
            return None;
        }
        let want = friction::rope_share(self.mu, n, self.hold_force);
        Some(self.coefficient(want, self.mode == SlipMode::SlipForward))
    }

    /// The force [N] the hold is cut to ([`friction::edge_capacity`] with the hold's sign) where
    /// it exceeds what the cone leaves along the edge, at a sliding node or where the edge load
    /// alone exceeds `mu N`; `None` otherwise.
    pub fn clipped_hold(&self) -> Option<f64> {
        let cap = friction::edge_capacity(self.mu, self.pull.normal, self.pull.along_rope);
        let fe = self.hold_force.abs();
        let sticks = self.mode == SlipMode::Stick;
        (fe > cap && (!sticks || fe > self.mu * self.pull.normal.max(0.0)))
            .then(|| self.hold_force.signum() * cap)
    }

    /// Whether a node sticking along the rope has friction outside its cone.
    pub fn sticks_outside(&self) -> bool {
        self.slide_out().is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MU: f64 = 0.2;

    /// A rope over an edge along z (plate normal +y) turning by `theta` in the plane across it,
    /// with tensions `t_prev`, `t_next` [N]: the frame, the unit vectors and the pull.
    fn planar(theta: f64, t_prev: f64, t_next: f64) -> (ContactFrame, Vec3, Vec3, Reaction) {
        let h = 0.5 * (std::f64::consts::PI - theta);
        let e_prev = Vec3::new(-h.sin(), -h.cos(), 0.0);
        let e_next = Vec3::new(h.sin(), -h.cos(), 0.0);
        let frame = ContactFrame::new(&Vec3::z(), &Vec3::y(), &e_prev, &e_next);
        let pull = friction::rope_pull(&frame, &e_prev, &e_next, t_prev, t_next);
        (frame, e_prev, e_next, pull)
    }

    fn node<'a>(
        (frame, e_prev, e_next, pull): &'a (ContactFrame, Vec3, Vec3, Reaction),
        mode: SlipMode,
        hold_force: f64,
        theta: f64,
        (t_prev, t_next): (f64, f64),
    ) -> NodeCone<'a> {
        NodeCone {
            mu: MU,
            mode,
            pull,
            hold_force,
            frame,
            e_prev,
            e_next,
            turn: theta,
            t_prev,
            t_next,
        }
    }

    /// The sharp-edge ratio `(1 + c tan(theta/2)) / (1 - c tan(theta/2))`.
    fn ratio(c: f64, theta: f64) -> f64 {
        let x = c * (0.5 * theta).tan();
        (1.0 + x) / (1.0 - x)
    }

    #[test]
    fn sticking_node_slides_out_only_beyond_the_sharp_edge_ratio() {
        let theta = 0.6;
        let t1 = 1e4;
        for (q, outside) in [(1.0 - 1e-9, false), (1.0 + 1e-6, true)] {
            let t2 = ratio(MU, theta) * q * t1;
            for (tp, tn, mode) in [
                (t1, t2, SlipMode::SlipForward),
                (t2, t1, SlipMode::SlipBackward),
            ] {
                let g = planar(theta, tp, tn);
                let c = node(&g, SlipMode::Stick, 0.0, theta, (tp, tn));
                match c.slide_out() {
                    // in the plane across the edge the coefficient is mu itself
                    Some((m, k)) => {
                        assert!(outside && m == mode, "{m:?}");
                        assert!((k - MU).abs() < 1e-12, "{k}");
                    }
                    None => assert!(!outside),
                }
                // a sliding node at that state: a share only where the cone is left
                let s = node(&g, mode, 0.0, theta, (tp, tn)).settled_share();
                assert_eq!(s.is_some(), outside);
            }
        }
    }

    #[test]
    fn hold_is_cut_to_what_the_cone_leaves_along_the_edge() {
        let theta = 0.6;
        let (tp, tn) = (1e4, 1.1e4);
        let g = planar(theta, tp, tn);
        let (n, fr) = (g.3.normal, g.3.along_rope);
        assert!(n > 0.0 && fr.abs() < MU * n);
        let capacity = ((MU * n).powi(2) - fr * fr).sqrt();
        // sliding: any hold beyond the capacity is cut to it, with its sign
        for fe in [1.01 * capacity, -1.5 * capacity] {
            let cut = node(&g, SlipMode::SlipForward, fe, theta, (tp, tn)).clipped_hold();
            let want = fe.signum() * capacity;
            assert!(
                (cut.unwrap() - want).abs() < 1e-9 * capacity,
                "{cut:?} vs {want}"
            );
        }
        assert!(
            node(&g, SlipMode::SlipForward, 0.99 * capacity, theta, (tp, tn))
                .clipped_hold()
                .is_none()
        );
        // sticking: only an edge load beyond mu N by itself is cut
        let stick = |fe: f64| node(&g, SlipMode::Stick, fe, theta, (tp, tn)).clipped_hold();
        assert!(stick(0.5 * (capacity + MU * n)).is_none());
        assert!((stick(1.01 * MU * n).unwrap() - capacity).abs() < 1e-9 * capacity);
    }
}
