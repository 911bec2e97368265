//! The contact node's reaction split into normal and friction forces, and the Coulomb decisions.
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
        let f = self.friction();
        let cap = mu * self.normal.max(0.0);
        if f <= cap { 1.0 } else { cap / f }
    }

    /// The friction coefficient left for sliding along the rope once the load along the edge is
    /// carried: `sqrt(mu^2 - (F_e/N)^2)`, at least 0.
    pub fn rope_share(&self, mu: f64) -> f64 {
        if self.normal <= 0.0 {
            return 0.0;
        }
        let fe = self.along_edge / self.normal;
        (mu * mu - fe * fe).max(0.0).sqrt()
    }

    /// Friction capacity left along the edge [N] when the rope-direction load is carried.
    pub fn edge_capacity(&self, mu: f64) -> f64 {
        let cap = mu * self.normal.max(0.0);
        (cap * cap - self.along_rope * self.along_rope)
            .max(0.0)
            .sqrt()
    }
}
