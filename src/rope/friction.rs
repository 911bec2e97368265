//! The friction model of a contact node: one Coulomb cone for the friction along the edge and
//! along the rope, and the return mapping onto it.
//!
//! At a contact node `Q` on a plate edge with unit direction `e` (world), the rope arrives from
//! its neighbours along the unit vectors `e_a` (towards the previous point) and `e_b` (towards the
//! next). The contact normal `n` is the outward bisector of the rope's turn, `-(e_a + e_b)` made
//! perpendicular to `e` (the edge's mean plate normal when the rope is straight); `t = e x n`
//! points across the edge, along the rope. The reaction `R` of the block on the node (from the
//! joint's Lagrange multipliers) gives the normal force `N = R . n` (positive when the plate
//! pushes), the friction along the edge `F_e = R . e`, along the rope `F_r = R . t`, and
//! `|F| = sqrt(F_e^2 + F_r^2)`. Coulomb: `|F| <= mu N`. The pseudo friction coefficient is
//! `rho = 1` while that holds and `rho = mu N / |F|` beyond.
//!
//! # One cone, one return mapping
//!
//! The model's friction at a node has two parts that act through different elements: along the
//! edge the hold ([`super::edge_hold`], a stiff spring on the node's coordinate along the edge
//! whose anchor lives in the memory), so `F_e` is the hold's force; along the rope the limited
//! tension ratio across the node ([`super::slip`]), so `F_r` and `N` are the components of the
//! rope's pull `-(T_prev e_prev + T_next e_next)` on the node (`e_*` unit vectors from the node
//! to its neighbours). Both share one cone `F_e^2 + F_r^2 <= (mu N)^2`, decided by one return
//! mapping, [`return_map`]: a trial state inside the cone sticks both ways; outside it, the
//! friction goes to the closest point of the cone in the metric of the two elements'
//! compliances, which for the stiff hold means the rope gives way first: the edge keeps its
//! load `F_e` (up to `mu N`) and the rope slides with what is left.
//!
//! - Along the rope the mapping runs inside every evaluation of a run ([`super::run`]), from the
//!   trial where the node sticks: the rope starts sliding through the node when its tensions
//!   leave the band of the share the cone leaves along the rope, [`rope_share`]
//!   `s = sqrt(mu^2 - (F_e/N)^2)`, and slides with it (as the sharp-edge law's coefficient in
//!   the rope's own plane that gives `|F_r| / N = s` in the edge's frame, [`plane_coefficients`]);
//!   the coefficient is part of the node's memory and of the decisions frozen for a Newton
//!   iteration, and after every accepted step the contact manager sets it again for the load
//!   along the edge and the geometry there wherever friction is off the cone (above it, or more
//!   than [`super::cone::SLIDE_BAND`] below it; a fixed point, since `N` moves with it).
//! - Along the edge the mapping runs after every accepted step (the contact manager): a hold
//!   whose force exceeds `mu N` moves the node along the edge (as before the cone); then every
//!   hold whose force exceeds what the cone leaves once the rope's friction is carried,
//!   [`edge_capacity`] `= sqrt((mu N)^2 - F_r^2)`, is clipped to it by moving its anchor. So at
//!   every accepted state `|F| <= mu N` holds to round-off, and `|F| = mu N` where the rope
//!   slides.

use crate::math::Vec3;

/// Unit vectors of a contact node (world).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFrame {
    /// Along the edge.
    pub edge: Vec3,
    /// Outward contact normal.
    pub normal: Vec3,
    /// Across the edge, along the rope (`edge x normal`).
    pub across: Vec3,
}

impl ContactFrame {
    /// The frame for edge direction `edge`, edge mean normal `mean_normal` (both world, unit) and
    /// the unit vectors `e_a`, `e_b` from the node towards its rope neighbours.
    pub fn new(edge: &Vec3, mean_normal: &Vec3, e_a: &Vec3, e_b: &Vec3) -> Self {
        let mut n = -(e_a + e_b);
        n -= edge * edge.dot(&n);
        let n = if n.norm() > 1e-9 {
            n.normalize()
        } else {
            let m = mean_normal - edge * edge.dot(mean_normal);
            m.normalize()
        };
        ContactFrame {
            edge: *edge,
            normal: n,
            across: edge.cross(&n),
        }
    }
}

impl ContactFrame {
    /// The frame with its normal turned to the plate's side of the edge (`plate_normal`: the
    /// edge's mean outward plate normal, world, unit). A rope that bends away from the edge (the
    /// plates on the outside of its turn) has its turn's bisector pointing into the plates; there
    /// the plates could only hold the node by pulling, so the normal force `N = R . n` must come
    /// out negative (and the node leave the edge), not positive with the bisector's sign.
    pub fn facing_plate(mut self, plate_normal: &Vec3) -> Self {
        if self.normal.dot(plate_normal) < 0.0 {
            self.normal = -self.normal;
            self.across = -self.across;
        }
        self
    }
}

/// The reaction of the block on a contact node, decomposed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Reaction {
    /// Normal force `N` [N] (positive: the plate pushes the rope).
    pub normal: f64,
    /// Friction along the edge `F_e` [N].
    pub along_edge: f64,
    /// Friction across the edge, along the rope `F_r` [N].
    pub along_rope: f64,
}

impl Reaction {
    /// Decomposes the reaction `r` [N] (world) in `frame`.
    pub fn new(r: &Vec3, frame: &ContactFrame) -> Self {
        Reaction {
            normal: r.dot(&frame.normal),
            along_edge: r.dot(&frame.edge),
            along_rope: r.dot(&frame.across),
        }
    }

    /// Magnitude of the friction force `|F|` [N].
    pub fn friction(&self) -> f64 {
        self.along_edge.hypot(self.along_rope)
    }

    /// Pseudo friction coefficient `rho` for friction coefficient `mu`: 1 while
    /// `|F| <= mu N`, else `mu N / |F|` (0 when the normal force pulls).
    pub fn pseudo_friction(&self, mu: f64) -> f64 {
        if self.normal < 0.0 {
            return 0.0;
        }
        let f = self.friction();
        let cap = mu * self.normal;
        if f <= cap { 1.0 } else { cap / f }
    }
}

/// How a node's Coulomb cone splits its friction between the edge and the rope when the trial
/// friction leaves the cone (the RopeBlock parameter `friction_law`). Both laws share the cone
/// `|(F_e, F_r)| <= mu N` and decide stick and slide alike; they differ only in where on the cone
/// the friction lands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrictionLaw {
    /// The closest point of the cone in the metric of the two elements' compliances, in the
    /// limit of the stiff hold: the edge keeps its load (up to `mu N`) and the rope slides with
    /// the share `sqrt(mu^2 - (F_e/N)^2)` ([`return_map`], [`rope_share`]). The default.
    #[default]
    EdgeFirst,
    /// Servin's pseudo friction coefficient, as the rope paper uses it: the whole tangential
    /// force is scaled radially by `rho` ([`Reaction::pseudo_friction`]), keeping the direction
    /// of the trial `(F_e, F_r)`; the rope slides with the share `mu |F_r| / |F|` and the edge
    /// keeps `mu N |F_e| / |F|` ([`radial_map`], [`FrictionLaw::rope_share`]).
    PseudoCoefficient,
}

/// Items of the `friction_law` choice (1-based codes: [`FrictionLaw::code`]).
pub static FRICTION_LAWS: &[(&str, &str)] = &[
    (
        "edge_first",
        "the edge keeps its load, the rope slides with what the cone leaves, sqrt(mu^2 - (F_e/N)^2)",
    ),
    (
        "pseudo_coefficient",
        "the rope paper's pseudo friction coefficient: the combined tangential force scaled radially by rho = min(1, mu N / |F|)",
    ),
];

impl FrictionLaw {
    /// The law's code, 1-based as in [`FRICTION_LAWS`].
    pub fn code(self) -> i32 {
        match self {
            FrictionLaw::EdgeFirst => 1,
            FrictionLaw::PseudoCoefficient => 2,
        }
    }

    /// The law of code `code` (1-based); `None` for any other code.
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            1 => Some(FrictionLaw::EdgeFirst),
            2 => Some(FrictionLaw::PseudoCoefficient),
            _ => None,
        }
    }

    /// The law named `name` ([`FRICTION_LAWS`]).
    pub fn from_name(name: &str) -> Option<Self> {
        FRICTION_LAWS
            .iter()
            .position(|(n, _)| *n == name)
            .and_then(|i| Self::from_code(i as i32 + 1))
    }

    /// The law's item name.
    pub fn name(self) -> &'static str {
        FRICTION_LAWS[(self.code() - 1) as usize].0
    }

    /// The return mapping of the trial friction (`along_edge`, `along_rope` [N]) at normal
    /// force `normal` [N] onto the cone of coefficient `mu` [-] under this law.
    pub fn map(self, mu: f64, normal: f64, along_edge: f64, along_rope: f64) -> ConeStep {
        match self {
            FrictionLaw::EdgeFirst => return_map(mu, normal, along_edge, along_rope),
            FrictionLaw::PseudoCoefficient => radial_map(mu, normal, along_edge, along_rope),
        }
    }

    /// The friction coefficient [-] with which the rope slides through the node for the trial
    /// friction (`along_edge`, `along_rope` [N]) at normal force `normal` [N]: its friction along
    /// the rope over `N` once the trial is mapped onto the cone. The rope leaves the band of
    /// this share exactly when the trial leaves the cone, under both laws. Edge first:
    /// [`rope_share`] (the rope's own trial does not enter). Pseudo coefficient:
    /// `mu |F_r| / |F|`, the rope's part of the radially scaled force (`mu` without any
    /// friction in the trial, and without a normal force).
    pub fn rope_share(self, mu: f64, normal: f64, along_edge: f64, along_rope: f64) -> f64 {
        match self {
            FrictionLaw::EdgeFirst => rope_share(mu, normal, along_edge),
            FrictionLaw::PseudoCoefficient => {
                let f = along_edge.hypot(along_rope);
                if normal <= 0.0 || f == 0.0 {
                    mu
                } else {
                    mu * along_rope.abs() / f
                }
            }
        }
    }
}

/// The pseudo friction coefficient's mapping: the trial (`along_edge`, `along_rope` [N]) scaled
/// by `rho` ([`Reaction::pseudo_friction`] at `normal` [N] and `mu` [-]), its direction kept:
/// the closest point of the cone in the plain (Euclidean) metric. No friction while the plate
/// would pull.
pub fn radial_map(mu: f64, normal: f64, along_edge: f64, along_rope: f64) -> ConeStep {
    let trial = Reaction {
        normal,
        along_edge,
        along_rope,
    };
    let rho = trial.pseudo_friction(mu);
    ConeStep {
        inside: rho == 1.0,
        along_edge: rho * along_edge,
        along_rope: rho * along_rope,
    }
}

/// The node's friction after the return mapping onto the cone `|(F_e, F_r)| <= mu N`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConeStep {
    /// Whether the trial friction lies inside the cone (the node sticks along the edge and along
    /// the rope).
    pub inside: bool,
    /// Friction along the edge `F_e` and along the rope `F_r` after the mapping [N].
    pub along_edge: f64,
    pub along_rope: f64,
}

/// The return mapping of a trial friction (`along_edge`, `along_rope` [N]) at normal force
/// `normal` [N] onto the cone of coefficient `mu` [-]: unchanged inside; outside, the closest
/// point of the cone in the metric of the two elements' compliances. The hold along the edge is
/// far stiffer than the rope along itself (ten times a nominal segment's axial stiffness), so in
/// that limit the rope gives way first: the edge keeps its load and the rope what is left, `F_r* =
/// sqrt((mu N)^2 - F_e^2)`; only a load along the edge beyond `mu N` itself is cut to `mu N` (and
/// the rope keeps nothing). No friction while the plate would pull (`normal <= 0`).
pub fn return_map(mu: f64, normal: f64, along_edge: f64, along_rope: f64) -> ConeStep {
    let cap = mu * normal.max(0.0);
    if along_edge.hypot(along_rope) <= cap {
        return ConeStep {
            inside: true,
            along_edge,
            along_rope,
        };
    }
    let fe = along_edge.clamp(-cap, cap);
    ConeStep {
        inside: false,
        along_edge: fe,
        along_rope: along_rope.signum() * (cap * cap - fe * fe).max(0.0).sqrt(),
    }
}

/// The friction coefficient [-] the node's cone leaves along the rope once the load along the
/// edge `along_edge` [N] is carried, at normal force `normal` [N]: `sqrt(mu^2 - (F_e/N)^2)`, at
/// least 0 (the share of [`return_map`]). Without a normal force (`normal <= 0`: the plate would
/// pull and the contact manager lets the rope leave the edge) the cone says nothing and the node
/// keeps `mu`.
///
/// Whether the rope slides through the node is the band of this share
/// ([`super::slip::edge_ratio`] with [`plane_coefficients`]), which agrees with the cone
/// wherever the cone can see the tension difference: not at a fold (turn of 180 degrees), where
/// the rope's pull has no component along the rope however unequal the tensions.
pub fn rope_share(mu: f64, normal: f64, along_edge: f64) -> f64 {
    if normal <= 0.0 {
        return mu;
    }
    let fe = along_edge / normal;
    (mu * mu - fe * fe).max(0.0).sqrt()
}

/// Friction capacity [N] the cone leaves along the edge once the friction along the rope
/// `along_rope` [N] is carried: `sqrt((mu N)^2 - F_r^2)`, at least 0.
pub fn edge_capacity(mu: f64, normal: f64, along_rope: f64) -> f64 {
    let cap = mu * normal.max(0.0);
    (cap * cap - along_rope * along_rope).max(0.0).sqrt()
}

/// The rope's pull on a contact node (what the plate supplies to a massless node) split in the
/// node's frame: `-(t_prev e_prev + t_next e_next)`, tensions [N], unit vectors from the node
/// towards its neighbours (world).
///
/// Along the rope only the tensions' difference pulls: with `T = (t_prev + t_next) / 2` and
/// `D = (t_next - t_prev) / 2` the pull is `-T (e_prev + e_next) - D (e_next - e_prev)`, and the
/// frame's normal is the bisector `-(e_prev + e_next)` made perpendicular to the edge, so the
/// first part has no component across the edge (`t`). `F_r` is formed from the second part
/// alone: equal tensions (a frictionless node) give exactly 0 instead of the round-off of `T`
/// projected on `t` (1e-11 N at 0.5 MN). Where the rope runs straight over the edge (the
/// fallback normal, `|e_prev + e_next| <= 1e-9`) the part left out is below `1e-9 T`.
pub fn rope_pull(
    frame: &ContactFrame,
    e_prev: &Vec3,
    e_next: &Vec3,
    t_prev: f64,
    t_next: f64,
) -> Reaction {
    let mut pull = Reaction::new(&-(e_prev * t_prev + e_next * t_next), frame);
    let half_difference = 0.5 * (t_next - t_prev);
    pull.along_rope = -half_difference * (e_next - e_prev).dot(&frame.across);
    pull
}

/// The coefficients `[forward, backward]` of the sharp-edge law in the rope's own plane
/// ([`super::slip::edge_ratio`] at turn `turn` [rad]) with which the rope's pull on the node has
/// exactly `|F_r| / N = share` in the node's frame (`e_prev`, `e_next` unit vectors from the node
/// to its neighbours): forward for `T_next > T_prev`, backward for the other way. In the plane
/// across the edge both equal `share`; with the rope tilted along the edge the friction of the
/// law, measured in the edge's frame, differs by a geometric factor, which these take out.
/// `None` where no positive tension ratio gives that share.
pub fn plane_coefficients(
    frame: &ContactFrame,
    e_prev: &Vec3,
    e_next: &Vec3,
    turn: f64,
    share: f64,
) -> [Option<f64>; 2] {
    // F_r / N = (a_t + rho b_t) / (a_n + rho b_n) for rho = T_next / T_prev
    let (at, an) = (e_prev.dot(&frame.across), e_prev.dot(&frame.normal));
    let (bt, bn) = (e_next.dot(&frame.across), e_next.dot(&frame.normal));
    let half = (0.5 * turn).tan();
    let mut out = [None, None];
    for q in [share, -share] {
        let den = bt - q * bn;
        if den == 0.0 || half <= 0.0 {
            continue;
        }
        let rho = (q * an - at) / den;
        if !(rho > 0.0 && rho.is_finite()) {
            continue;
        }
        // the law's ratio r = (1 + x) / (1 - x), x = coefficient tan(turn/2)
        let (slot, r) = if rho >= 1.0 { (0, rho) } else { (1, 1.0 / rho) };
        let c = (r - 1.0) / (r + 1.0) / half;
        if out[slot].is_none() {
            out[slot] = Some(c);
        }
    }
    out
}

/// A unit vector perpendicular to the unit vector `edge` (the fallback normal of a straight rope).
pub fn any_normal(edge: &Vec3) -> Vec3 {
    let a = if edge.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    (a - edge * edge.dot(&a)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn return_map_lands_on_the_cone_rope_first() {
        let (mu, n) = (0.2, 1e4);
        // inside: unchanged
        let m = return_map(mu, n, 1e3, -1e3);
        assert!(m.inside && m.along_edge == 1e3 && m.along_rope == -1e3);
        // outside: on the cone, the edge keeping its load, the rope the rest (sign kept)
        let m = return_map(mu, n, 1.2e3, -4e3);
        assert!(!m.inside && m.along_edge == 1.2e3);
        assert!((m.along_rope + 1.6e3).abs() < 1e-9);
        // the edge alone beyond the cone: cut to mu N, nothing left for the rope
        let m = return_map(mu, n, -3e3, 5e2);
        assert!(m.along_edge == -2e3 && m.along_rope == 0.0);
        // the rope's share: sqrt(0.2^2 - 0.12^2) = 0.16; the full coefficient without edge load
        assert!((rope_share(mu, n, 1.2e3) - 0.16).abs() < 1e-15);
        assert!((rope_share(mu, n, 0.0) - mu).abs() < 1e-15);
        assert_eq!(rope_share(mu, n, 5e3), 0.0);
        assert_eq!(rope_share(mu, -1.0, 1.0), mu);
        // what the edge keeps once the rope's friction is carried, and the plate pulling
        let c = edge_capacity(mu, n, 0.8 * mu * n);
        assert!((c - 0.6 * mu * n).abs() < 1e-9);
        assert_eq!(return_map(mu, -1.0, 1.0, 0.0).along_edge, 0.0);
    }

    #[test]
    fn the_pseudo_coefficient_scales_the_trial_radially() {
        let (mu, n) = (0.2, 1e4);
        let law = FrictionLaw::PseudoCoefficient;
        // inside: unchanged, as edge first
        let m = law.map(mu, n, 1e3, -1e3);
        assert!(m.inside && m.along_edge == 1e3 && m.along_rope == -1e3);
        // outside: (1.2e3, -4e3) has |F| = 4176.1 N against mu N = 2e3: rho = 0.47891, both
        // components scaled by it, the direction kept (hand calculation)
        let m = law.map(mu, n, 1.2e3, -4e3);
        let rho = 2e3 / (1.2e3f64.powi(2) + 4e3f64.powi(2)).sqrt();
        assert!(!m.inside);
        assert!((m.along_edge - 1.2e3 * rho).abs() < 1e-9);
        assert!((m.along_rope + 4e3 * rho).abs() < 1e-9);
        assert!((m.along_edge.hypot(m.along_rope) - mu * n).abs() < 1e-9);
        // where edge first keeps the edge's load and cuts the rope to 1.6e3 N
        let e = FrictionLaw::EdgeFirst.map(mu, n, 1.2e3, -4e3);
        assert!(e.along_edge == 1.2e3 && (e.along_rope + 1.6e3).abs() < 1e-9);
        // the rope's share is its part of the scaled force, mu |F_r| / |F|
        let s = law.rope_share(mu, n, 1.2e3, -4e3);
        assert!((s * n - 4e3 * rho).abs() < 1e-9);
        // no edge load: both laws give the rope mu; no friction at all: mu; plate pulling: none
        assert_eq!(law.rope_share(mu, n, 0.0, 5e3), mu);
        assert_eq!(law.rope_share(mu, n, 0.0, 0.0), mu);
        assert_eq!(law.map(mu, -1.0, 1.0, 1.0).along_edge, 0.0);
        // names and codes
        for l in [FrictionLaw::EdgeFirst, law] {
            assert_eq!(FrictionLaw::from_code(l.code()), Some(l));
            assert_eq!(FrictionLaw::from_name(l.name()), Some(l));
        }
        assert_eq!(FrictionLaw::default(), FrictionLaw::EdgeFirst);
    }

    #[test]
    fn a_rope_bent_away_from_the_plates_pulls_on_them() {
        // a deck edge along x: deck normal +z, side normal +y, mean (0, 1, 1)/sqrt 2. Wrapped: the
        // rope runs down the side and inboard over the deck, the plates push (N = T sqrt 2)
        let edge = Vec3::x();
        let plate = Vec3::new(0.0, 1.0, 1.0).normalize();
        let (down, inboard) = (-Vec3::z(), -Vec3::y());
        let frame = ContactFrame::new(&edge, &plate, &down, &inboard).facing_plate(&plate);
        let p = rope_pull(&frame, &down, &inboard, 1e3, 1e3);
        assert!((p.normal - 1e3 * 2f64.sqrt()).abs() < 1e-9);
        // bent away: down the side, then out and up (the hook back above the lug); the turn's
        // bisector points into the plates, which could hold the node only by pulling
        let up_out = Vec3::new(0.0, 0.6, 0.8);
        let bisector = ContactFrame::new(&edge, &plate, &down, &up_out);
        let frame = bisector.facing_plate(&plate);
        assert_eq!(frame.normal, -bisector.normal);
        assert_eq!(frame.across, frame.edge.cross(&frame.normal));
        let p = rope_pull(&frame, &down, &up_out, 1e3, 1e3);
        assert!(p.normal < 0.0, "{p:?}");
        assert_eq!(p.pseudo_friction(0.2), 0.0);
    }

    #[test]
    fn planar_pull_obeys_the_sharp_edge_ratio() {
        // a rope turning by theta in the plane across the edge, sliding at the ratio
        // (1 + mu tan(theta/2)) / (1 - mu tan(theta/2)): F_r = mu N exactly
        let (mu, theta) = (0.2f64, 1.1f64);
        let x = mu * (0.5 * theta).tan();
        let r = (1.0 + x) / (1.0 - x);
        let g = 0.5 * (std::f64::consts::PI - theta);
        let (ea, eb) = (
            Vec3::new(-g.sin(), -g.cos(), 0.0),
            Vec3::new(g.sin(), -g.cos(), 0.0),
        );
        let edge = Vec3::z();
        let frame = ContactFrame::new(&edge, &any_normal(&edge), &ea, &eb);
        let p = rope_pull(&frame, &ea, &eb, 1e4, r * 1e4);
        assert!(p.along_edge.abs() < 1e-9);
        assert!((p.along_rope.abs() - mu * p.normal).abs() < 1e-12 * p.normal);
        // in that plane the law's coefficients are the share itself, both ways
        let [fwd, bwd] = plane_coefficients(&frame, &ea, &eb, theta, mu);
        assert!((fwd.unwrap() - mu).abs() < 1e-12 && (bwd.unwrap() - mu).abs() < 1e-12);
    }

    #[test]
    fn tilted_pull_at_the_plane_coefficient_has_the_share() {
        // the next strand tilted 20 degrees along the edge: the law's coefficient from
        // plane_coefficients puts |F_r| / N at the share in the edge's frame, both ways
        let (share, g, a) = (0.13, 0.25 * std::f64::consts::PI, 20f64.to_radians());
        let ea = Vec3::new(-g.sin(), -g.cos(), 0.0);
        let eb = Vec3::new(g.sin() * a.cos(), -g.cos() * a.cos(), a.sin());
        let edge = Vec3::z();
        let frame = ContactFrame::new(&edge, &any_normal(&edge), &ea, &eb);
        let turn = std::f64::consts::PI - ea.dot(&eb).acos();
        let [fwd, bwd] = plane_coefficients(&frame, &ea, &eb, turn, share);
        for (c, forward) in [(fwd.unwrap(), true), (bwd.unwrap(), false)] {
            let x = c * (0.5 * turn).tan();
            let r = (1.0 + x) / (1.0 - x);
            let (tp, tn) = if forward {
                (1e4, r * 1e4)
            } else {
                (r * 1e4, 1e4)
            };
            let p = rope_pull(&frame, &ea, &eb, tp, tn);
            assert!(
                (p.along_rope.abs() / p.normal - share).abs() < 1e-12,
                "{forward}"
            );
        }
        // and they differ from the share itself (the geometric factor is not trivial)
        assert!((fwd.unwrap() - share).abs() > 1e-4);
    }
}
