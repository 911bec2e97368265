//! The paper's eq. (1) mass split at a node's insertion and its inverse at removal, against the
//! formula written out here by hand; mass, linear momentum and rope length conserved to
//! round-off through insertion and removal.

use super::{insert_node, remove_node};
use crate::math::Vec3;
use crate::scene::rope_block::RopeBlockParams;
use crate::scene::rope_block::structure::Structure;

/// The default lift's structure with every rope node moving (distinct velocities), so that the
/// momentum bookkeeping is exercised.
fn moving_structure() -> Structure {
    let mut s = RopeBlockParams::default().structure().expect("structure");
    for (r, rope) in s.ropes.iter_mut().enumerate() {
        for (i, n) in rope.nodes.iter_mut().enumerate() {
            n.velocity = Vec3::new(0.1 * i as f64, -0.05 * r as f64, 0.3 - 0.02 * i as f64);
        }
    }
    s
}

/// Total node mass [kg], node momentum [kg m/s] and the material span of rope `r`.
fn totals(s: &Structure, r: usize) -> (f64, Vec3, f64) {
    let rope = &s.ropes[r];
    let m: f64 = rope.nodes.iter().map(|n| n.mass).sum();
    let p: Vec3 = rope.nodes.iter().map(|n| n.velocity * n.mass).sum();
    (m, p, rope.sigma_end - rope.sigma_start)
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 4.0 * f64::EPSILON * scale
}

#[test]
fn insertion_between_two_rope_nodes_splits_mass_by_eq_1_and_removal_returns_it() {
    let mut s = moving_structure();
    let r = 0;
    assert!(s.ropes[r].nodes.len() >= 4);
    // segment between rope nodes 1 and 2 (points 2 and 3), the new node 30 % of the way
    let (i1, i2) = (1, 2);
    // unequal neighbours, so that the min of eq. (1) matters
    s.ropes[r].nodes[i1].mass *= 1.5;
    let before = s.ropes[r].nodes.clone();
    let (p1, p2) = (before[i1], before[i2]);
    let q = p1.position + 0.3 * (p2.position - p1.position);
    let (l1, l2) = ((q - p1.position).norm(), (p2.position - q).norm());
    let (m0, mom0, span0) = totals(&s, r);
    assert!(insert_node(&mut s, r, i1 + 1, q, None));
    let after = &s.ropes[r].nodes;
    // eq. (1): m_Q = 1/2 min(m_P1, m_P2); P1 gives l2/(l1+l2) of it, P2 l1/(l1+l2)
    let m_q = 0.5 * p1.mass.min(p2.mass);
    let scale = p1.mass.max(p2.mass);
    assert!(
        close(after[i1 + 1].mass, m_q, scale),
        "{} {}",
        after[i1 + 1].mass,
        m_q
    );
    assert!(close(after[i1].mass, p1.mass - l2 / (l1 + l2) * m_q, scale));
    assert!(close(
        after[i2 + 1].mass,
        p2.mass - l1 / (l1 + l2) * m_q,
        scale
    ));
    // the node's material coordinate splits the segment l1 : l2; nothing else moved
    let sigma = p1.sigma + (p2.sigma - p1.sigma) * l1 / (l1 + l2);
    assert!(close(after[i1 + 1].sigma, sigma, p2.sigma.abs().max(1.0)));
    assert!((after[i1 + 1].position - q).norm() == 0.0);
    let (m1, mom1, span1) = totals(&s, r);
    assert!(close(m1, m0, m0), "mass {m0} -> {m1}");
    assert!(
        (mom1 - mom0).norm() <= 16.0 * f64::EPSILON * m0,
        "momentum {mom0} -> {mom1}"
    );
    assert_eq!(span1, span0);
    // removal returns l2/(l1+l2) of m_Q to P1 and l1/(l1+l2) to P2: the masses come back
    remove_node(&mut s, r, i1 + 1);
    let back = &s.ropes[r].nodes;
    assert_eq!(back.len(), before.len());
    for (a, b) in back.iter().zip(&before) {
        assert!(close(a.mass, b.mass, scale), "{} {}", a.mass, b.mass);
    }
    let (m2, mom2, _) = totals(&s, r);
    assert!(close(m2, m0, m0), "mass {m0} -> {m2}");
    assert!(
        (mom2 - mom0).norm() <= 16.0 * f64::EPSILON * m0,
        "momentum {mom0} -> {mom2}"
    );
}

#[test]
fn insertion_next_to_a_rope_end_takes_half_the_rope_neighbours_mass_from_it_alone() {
    let mut s = moving_structure();
    let r = 0;
    // segment 0 runs from the hook (not a rope node) to rope node 0
    let before = s.ropes[r].nodes.clone();
    let p2 = before[0];
    let (m0, mom0, _) = totals(&s, r);
    let q = p2.position + Vec3::new(0.0, 0.0, 0.1);
    assert!(insert_node(&mut s, r, 0, q, None));
    let after = &s.ropes[r].nodes;
    assert!(close(after[0].mass, 0.5 * p2.mass, p2.mass));
    assert!(close(after[1].mass, 0.5 * p2.mass, p2.mass));
    assert!((after[0].velocity - p2.velocity).norm() <= 4.0 * f64::EPSILON * p2.velocity.norm());
    let (m1, mom1, _) = totals(&s, r);
    assert!(close(m1, m0, m0) && (mom1 - mom0).norm() <= 16.0 * f64::EPSILON * m0);
    // removal gives it all back to the one rope neighbour
    remove_node(&mut s, r, 0);
    assert!(close(s.ropes[r].nodes[0].mass, p2.mass, p2.mass));
    assert!(close(totals(&s, r).0, m0, m0));
}
