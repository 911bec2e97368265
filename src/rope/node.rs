//! Mass, momentum and rope-length bookkeeping when a contact node is inserted into a segment or
//! removed from the rope (the paper's eq. 1 and its inverse).
//!
//! Insertion at `Q` between `P1` and `P2`, `l1 = |P1 Q|`, `l2 = |Q P2|`:
//! `m_Q = 1/2 min(m_P1, m_P2)`, `m_P1' = m_P1 - l2/(l1+l2) m_Q`, `m_P2' = m_P2 - l1/(l1+l2) m_Q`.
//! A neighbour that is not a rope node (a hook, a lug, a test weight) gives no mass; the other
//! neighbour then gives all of it. The node's velocity is the mass-weighted velocity of what it
//! took, so linear momentum is unchanged; its material coordinate splits the segment's rest length
//! in the ratio `l1 : l2`, so the rope length is unchanged.
//!
//! Removal returns the node's mass in the same proportions (`l2/(l1+l2)` to `P1`) to the
//! neighbours that are rope nodes, each keeping its momentum plus the share's momentum.

use crate::math::Vec3;

/// Masses [kg] taken from the two neighbours and the new node's mass and velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Insertion {
    /// Mass of the new node [kg].
    pub mass: f64,
    /// Mass taken from the previous and the next neighbour [kg].
    pub take_prev: f64,
    pub take_next: f64,
    /// Velocity of the new node [m/s] (world).
    pub velocity: Vec3,
}

/// Eq. (1) for neighbours of masses `m_prev`, `m_next` (`None` when not a rope node) at distances
/// `l1`, `l2` [m] from the new node, moving at `v_prev`, `v_next` [m/s]. `None` when neither
/// neighbour is a rope node.
pub fn insertion(
    m_prev: Option<f64>,
    m_next: Option<f64>,
    l1: f64,
    l2: f64,
    v_prev: &Vec3,
    v_next: &Vec3,
) -> Option<Insertion> {
    let sum = (l1 + l2).max(1e-300);
    let (w_prev, w_next) = (l2 / sum, l1 / sum);
    let (mass, take_prev, take_next) = match (m_prev, m_next) {
        (Some(a), Some(b)) => {
            let m = 0.5 * a.min(b);
            (m, w_prev * m, w_next * m)
        }
        (Some(a), None) => (0.5 * a, 0.5 * a, 0.0),
        (None, Some(b)) => (0.5 * b, 0.0, 0.5 * b),
        (None, None) => return None,
    };
    Some(Insertion {
        mass,
        take_prev,
        take_next,
        velocity: (v_prev * take_prev + v_next * take_next) / mass,
    })
}

/// Shares of a removed node's mass for the previous and next neighbour (summing to 1), given the
/// distances `l1`, `l2` [m] and which neighbours are rope nodes; `None` if neither is.
pub fn removal_shares(l1: f64, l2: f64, prev_node: bool, next_node: bool) -> Option<(f64, f64)> {
    let sum = (l1 + l2).max(1e-300);
    match (prev_node, next_node) {
        (true, true) => Some((l2 / sum, l1 / sum)),
        (true, false) => Some((1.0, 0.0)),
        (false, true) => Some((0.0, 1.0)),
        (false, false) => None,
    }
}
