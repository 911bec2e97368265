//! The Coulomb cone of a contact node settled at an accepted state: what the rope-block manager
//! decides after each step ([`super::friction`] is the law; this is its settlement), as functions
//! of what acts at the node. The manager evaluates the nodes, applies these decisions to the
//! memory and books the energy they remove.
//!
//! - A node sticking along the rope whose friction is outside its cone slides, towards the larger
//!   tension, with the share the cone leaves ([`NodeCone::slide_out`]).
//! - A node the rope slides through whose friction is outside its cone, or below its boundary
//!   by more than [`SLIDE_BAND`], gets the share its edge load and geometry leave
//!   ([`NodeCone::settled_share`]; a fixed point, since `N` moves with the share:
//!   [`ShareSearch`]). So while the rope slides, friction is `mu N`: Coulomb's law both ways.
//! - A hold whose force exceeds what the cone leaves along the edge is cut to that capacity
//!   ([`NodeCone::clipped_hold`]), at sliding nodes and wherever the edge load alone exceeds
//!   `mu N`.
//! - A node whose hold's force alone exceeds `mu N` slides along its edge against a constant
//!   friction force on the cone, until it stops ([`edge_friction`]); while it slides the cut
//!   of the previous point sets that force.
//!
//! "Outside" means friction above `mu N (1 + 1e-12)` with `N > 0`.

use super::friction::{self, ContactFrame, Reaction};
use super::layout::SlipMode;
use crate::math::Vec3;

/// Relative tolerance of the cone's boundary.
const CONE_TOL: f64 = 1e-12;

/// How far below `mu N` a sliding node's friction may fall before its share is settled again
/// (relative): Coulomb's law wants it on the cone while the rope slides. Each settlement is a
/// small jump of the friction force; bands of 1e-3, 1e-6 and 1e-9 gave the same step counts to
/// 4 % on the rope tests (docs/rope_friction.md), so the band is the test's own tolerance.
pub const SLIDE_BAND: f64 = 1e-9;

/// A contact node at an accepted state, as the cone settlement sees it.
#[derive(Debug, Clone, Copy)]
pub struct NodeCone<'a> {
    /// Cone coefficient `mu` [-].
    pub mu: f64,
    /// How the cone splits friction between edge and rope ([`friction::FrictionLaw`]).
    pub law: friction::FrictionLaw,
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
        let share = self.law.rope_share(
            self.mu,
            self.pull.normal,
            self.hold_force,
            self.pull.along_rope,
        );
        let forward = self.t_next > self.t_prev;
        let mode = if forward {
            SlipMode::SlipForward
        } else {
            SlipMode::SlipBackward
        };
        Some((mode, self.coefficient(share, forward)))
    }

    /// A node the rope slides through whose friction is outside its cone, or more than
    /// [`SLIDE_BAND`] below its boundary: the coefficient of the share its edge load and geometry
    /// leave ([`Self::share_target`]); `None` otherwise.
    pub fn settled_share(&self) -> Option<f64> {
        if self.beyond() || self.below() {
            self.share_target()
        } else {
            None
        }
    }

    /// The coefficient of the share the cone leaves a node the rope slides through at this
    /// state ([`friction::rope_share`] of its edge load, as the sharp-edge coefficient of
    /// [`friction::plane_coefficients`]); `None` where it sticks or `N <= 0`.
    pub fn share_target(&self) -> Option<f64> {
        let n = self.pull.normal;
        if self.mode == SlipMode::Stick || n <= 0.0 {
            return None;
        }
        let want = friction::rope_share(self.mu, n, self.hold_force);
        Some(self.coefficient(want, self.mode == SlipMode::SlipForward))
    }

    /// Under the pseudo friction coefficient, a node the rope slides through whose friction is
    /// outside its cone: the rope's part `|F_r| / |F|` of the trial's direction, which the radial
    /// scaling keeps (the rope then slides with the share `mu |F_r| / |F|`,
    /// [`Self::radial_target`], and the hold is cut to what that leaves along the edge,
    /// `mu N |F_e| / |F|`, [`Self::clipped_hold`]). `None` under edge first, while the rope
    /// sticks, or inside the cone (a sliding node below the cone gets [`Self::share_target`]
    /// under both laws: the edge's load is inside its radial part, so only the rope moves).
    pub fn radial_fraction(&self) -> Option<f64> {
        let sliding = self.mode != SlipMode::Stick && self.pull.normal > 0.0;
        if self.law != friction::FrictionLaw::PseudoCoefficient || !sliding || !self.beyond() {
            return None;
        }
        let trial = Reaction {
            normal: self.pull.normal,
            along_edge: self.hold_force,
            along_rope: self.pull.along_rope,
        };
        // rho |F_r| / (mu N) = |F_r| / |F| beyond the cone
        Some(trial.pseudo_friction(self.mu) * self.pull.along_rope.abs() / (self.mu * trial.normal))
    }

    /// The coefficient of the share `mu fraction` (the rope's part of the radially scaled
    /// force, [`Self::radial_fraction`]) at this geometry; `None` where the rope sticks or
    /// `N <= 0`.
    pub fn radial_target(&self, fraction: f64) -> Option<f64> {
        if self.mode == SlipMode::Stick || self.pull.normal <= 0.0 {
            return None;
        }
        Some(self.coefficient(self.mu * fraction, self.mode == SlipMode::SlipForward))
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

    /// Whether the node's friction is below the cone's boundary by more than [`SLIDE_BAND`].
    pub fn below(&self) -> bool {
        self.friction() < self.mu * self.pull.normal * (1.0 - SLIDE_BAND)
    }

    /// Whether a node sticking along the rope has friction outside its cone.
    pub fn sticks_outside(&self) -> bool {
        self.slide_out().is_some()
    }
}

/// What a node's friction along its edge does after an accepted step ([`edge_friction`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EdgeFriction {
    /// The hold's spring keeps the node where it is.
    Stick,
    /// The node slides along its edge against the constant friction force [N] on its coordinate
    /// (the hold's sign: against the rope's pull along the edge, so against the slide).
    Slide(f64),
    /// The slide stopped (the node moves along its friction force, or not at all): the spring
    /// holds it again, carrying this force [N] at first (continuous across the switch).
    Restick(f64),
}

/// Coulomb along the edge for a node at normal force `normal` [N] (the rope's pull), friction
/// along the rope `along_rope` [N], the hold's force `hold_force` [N] and the node's rate along
/// the edge `u_dot` [m/s]; `slide` is the sign of the friction force while the node slides along
/// its edge (0 while it sticks there). A sticking node whose spring carries more than `mu N`
/// starts sliding against the spring's sign; a sliding one keeps sliding while it moves against
/// its friction (the force follows the cone: [`friction::edge_capacity`], `mu N` where the rope
/// has no friction along it; 0 without normal force), so the edge's friction is on the cone while
/// the node slides and the rope's tensions stay continuous through it (the node moves with the
/// dynamics, not by jumps). Once it moves along its friction's sign (the slide turned within the
/// step) it sticks again.
pub fn edge_friction(
    mu: f64,
    normal: f64,
    along_rope: f64,
    hold_force: f64,
    slide: f64,
    u_dot: f64,
) -> EdgeFriction {
    let capacity = friction::edge_capacity(mu, normal, along_rope);
    if slide == 0.0 {
        if normal > 0.0 && hold_force.abs() > mu * normal {
            return EdgeFriction::Slide(hold_force.signum() * capacity);
        }
        return EdgeFriction::Stick;
    }
    if u_dot * slide > 0.0 {
        EdgeFriction::Restick(hold_force)
    } else {
        EdgeFriction::Slide(slide.signum() * capacity)
    }
}

/// The fixed point `c = G(c)` of one node's share coefficient, `G` the target the cone leaves
/// at the state the share `c` gives ([`NodeCone::share_target`]; `N` moves with the share, so
/// the target moves too). Plain iteration cycles near the cone's tip (edge load near `mu N`,
/// where `G` falls to 0 at a slope well below -1). Here each step is a secant step on
/// `h(c) = G(c)^2 - c^2`, which has the sign of `G(c) - c` without the square root's infinite
/// slope at the tip (`G^2` is smooth in `N`), kept inside the bracket of the signs of `h` seen
/// so far (bisection where it leaves it).
#[derive(Debug, Clone, Copy, Default)]
pub struct ShareSearch {
    /// Latest iterate and its `h`.
    last: Option<(f64, f64)>,
    /// Iterates with `h > 0` (share too small) and `h < 0` (too large) nearest the root.
    below: Option<f64>,
    above: Option<f64>,
}

impl ShareSearch {
    /// The next share coefficient, given the present one `c` and its target `g = G(c)`.
    pub fn next(&mut self, c: f64, g: f64) -> f64 {
        let h = g * g - c * c;
        if h > 0.0 {
            self.below = Some(self.below.map_or(c, |b| b.max(c)));
        } else if h < 0.0 {
            self.above = Some(self.above.map_or(c, |a| a.min(c)));
        }
        let secant = match self.last {
            Some((cp, hp)) if hp != h && cp != c => c - h * (c - cp) / (h - hp),
            _ => g,
        };
        self.last = Some((c, h));
        let (lo, hi) = (
            self.below.unwrap_or(0.0),
            self.above.unwrap_or(f64::INFINITY),
        );
        if secant > lo && secant < hi {
            secant
        } else if hi.is_finite() && self.below.is_some() {
            0.5 * (lo + hi)
        } else {
            g.max(0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MU: f64 = 0.2;

    #[test]
    fn edge_friction_starts_keeps_and_ends_a_slide_on_the_cone() {
        let (n, fr) = (1e3, 120.0);
        let capacity = ((MU * n).powi(2) - fr * fr).sqrt();
        // sticking: the spring inside mu N keeps it; beyond mu N (either sign) the node slides
        // against the spring's sign with the capacity the rope's friction leaves
        assert_eq!(
            edge_friction(MU, n, fr, 199.0, 0.0, 0.0),
            EdgeFriction::Stick
        );
        assert_eq!(
            edge_friction(MU, n, fr, 260.0, 0.0, 0.0),
            EdgeFriction::Slide(capacity)
        );
        assert_eq!(
            edge_friction(MU, n, fr, -260.0, 0.0, 0.0),
            EdgeFriction::Slide(-capacity)
        );
        // no normal force: no slide starts
        assert_eq!(
            edge_friction(MU, -n, 0.0, 260.0, 0.0, 0.0),
            EdgeFriction::Stick
        );
        // sliding against the force: keeps sliding, force updated to the capacity at this N
        assert_eq!(
            edge_friction(MU, 2.0 * n, 0.0, 150.0, 1.0, -0.1),
            EdgeFriction::Slide(2.0 * MU * n)
        );
        // moving with the force: sticks again, the spring taking the force over
        assert_eq!(
            edge_friction(MU, n, fr, -150.0, -1.0, -0.1),
            EdgeFriction::Restick(-150.0)
        );
        // no normal force (the rope lifting off): slides on freely, whatever the signs
        assert_eq!(
            edge_friction(MU, 0.0, 0.0, -0.0, -1.0, 50.0),
            EdgeFriction::Slide(-0.0)
        );
    }

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
            law: friction::FrictionLaw::EdgeFirst,
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
            }
        }
    }

    #[test]
    fn sliding_node_gets_its_share_again_off_the_cone_either_way() {
        let theta = 0.6;
        let t1 = 1e4;
        // beyond the cone, on it, and further below it than the slide band
        for (q, off) in [(1.0 + 1e-6, true), (1.0, false), (1.0 - 1e-3, true)] {
            let t2 = ratio(MU, theta) * q * t1;
            let g = planar(theta, t1, t2);
            let s = node(&g, SlipMode::SlipForward, 0.0, theta, (t1, t2)).settled_share();
            match s {
                // in the plane across the edge, with no load along the edge: mu itself
                Some(k) => assert!(off && (k - MU).abs() < 1e-12, "q {q}: {k}"),
                None => assert!(!off, "q {q}: no share"),
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

    /// A node near the cone's tip: edge load `F_e` just below `mu N(0)`, `N` falling with the
    /// share as `N(c) = N0 (1 - a c)` (more friction along the rope, less pull on the plate).
    /// Plain iteration `c <- G(c)` cycles between 0 and a positive share; the search lands on
    /// the fixed point to 1e-12 within 10 passes, from below and from above.
    #[test]
    fn the_share_search_finds_the_fixed_point_where_plain_iteration_cycles() {
        let (n0, a) = (2.33e6, 0.5);
        let fe = 0.1985 * n0;
        let g = |c: f64| friction::rope_share(MU, n0 * (1.0 - a * c), fe);
        // plain iteration: 0 -> G(0) -> G(G(0)) = 0 again
        let c1 = g(0.0);
        assert!(c1 > 0.02 && g(c1) == 0.0, "no cycle: {c1} {}", g(c1));
        // the root of G(c) = c by bisection (G falls, c rises)
        let (mut lo, mut hi) = (0.0, MU);
        for _ in 0..200 {
            let m = 0.5 * (lo + hi);
            if g(m) > m { lo = m } else { hi = m }
        }
        let root = 0.5 * (lo + hi);
        for start in [0.0, 0.2] {
            let mut search = ShareSearch::default();
            let mut c = start;
            let mut passes = 0;
            while (g(c) - c).abs() > 1e-12 * root {
                c = search.next(c, g(c));
                passes += 1;
                assert!(
                    passes <= 10,
                    "from {start}: {c} after {passes} passes, root {root}"
                );
            }
            assert!((c - root).abs() < 1e-10 * root, "{c} against {root}");
        }
    }
}
