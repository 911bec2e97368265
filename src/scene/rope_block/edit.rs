//! Applies structural edits (insert, remove, relocate, merge, split) to a synchronized
//! [`Structure`], conserving mass, linear momentum and rope length (see [`crate::rope::node`]).

use super::manager::{Counters, Edit};
use super::structure::{
    EndSpec, INITIAL_EDGE_CAPACITY, NodeContact, NodeSpec, RopeSpec, Structure,
};
use crate::math::Vec3;
use crate::rope::SlipMode;
use crate::rope::node::{insertion, removal_shares};

/// Position [m], velocity [m/s] (world) and material coordinate [m] of rope point `k`
/// (0 = start, `i + 1` = node `i`, `n + 1` = end).
fn point(s: &Structure, r: &RopeSpec, k: usize) -> (Vec3, Vec3, f64) {
    let n = r.nodes.len();
    if (1..=n).contains(&k) {
        let nd = &r.nodes[k - 1];
        return (nd.position, nd.velocity, nd.sigma);
    }
    let (end, sigma, sign) = if k == 0 {
        (&r.start, r.sigma_start, -1.0)
    } else {
        (&r.end, r.sigma_end, 1.0)
    };
    match *end {
        EndSpec::Hook(h) => {
            let hk = &s.hooks[h];
            (hk.position, hk.velocity, sigma + sign * hk.payout)
        }
        EndSpec::Block { block, local } => {
            let b = &s.blocks[block];
            let rot = b.orientation.to_rotation_matrix().into_inner();
            (
                b.position + rot * local,
                b.velocity + rot * b.omega.cross(&local),
                sigma,
            )
        }
        EndSpec::Load(l) => (s.loads[l].position, s.loads[l].velocity, sigma),
    }
}

fn node_mass(r: &RopeSpec, k: usize) -> Option<f64> {
    (1..=r.nodes.len())
        .contains(&k)
        .then(|| r.nodes[k - 1].mass)
}

/// Removes interior node `i` of rope `r`, returning its mass and momentum to the neighbouring
/// rope nodes; a node without rope-node neighbours becomes a material node instead.
fn remove_node(s: &mut Structure, r: usize, i: usize) {
    let rope = &s.ropes[r];
    let (pp, _, _) = point(s, rope, i);
    let (pn, _, _) = point(s, rope, i + 2);
    let q = rope.nodes[i];
    let (l1, l2) = ((q.position - pp).norm(), (pn - q.position).norm());
    let n = rope.nodes.len();
    let shares = removal_shares(l1, l2, i >= 1, i + 1 < n);
    let rope = &mut s.ropes[r];
    let Some((a, b)) = shares else {
        rope.nodes[i].contact = None;
        return;
    };
    for (k, share) in [(i.wrapping_sub(1), a), (i + 1, b)] {
        if share > 0.0 {
            let nb = &mut rope.nodes[k];
            let m = nb.mass + share * q.mass;
            nb.velocity = (nb.velocity * nb.mass + q.velocity * (share * q.mass)) / m;
            nb.mass = m;
        }
    }
    rope.nodes.remove(i);
}

/// Inserts a node between points `seg` and `seg + 1` at `pos` [m, world] with the eq. (1) masses;
/// returns `false` if the segment has no rope node to take mass from.
fn insert_node(
    s: &mut Structure,
    r: usize,
    seg: usize,
    pos: Vec3,
    contact: Option<NodeContact>,
) -> bool {
    let rope = &s.ropes[r];
    let (pa, va, sa) = point(s, rope, seg);
    let (pb, vb, sb) = point(s, rope, seg + 1);
    let (l1, l2) = ((pos - pa).norm(), (pb - pos).norm());
    let Some(ins) = insertion(
        node_mass(rope, seg),
        node_mass(rope, seg + 1),
        l1,
        l2,
        &va,
        &vb,
    ) else {
        return false;
    };
    let sigma = sa + (sb - sa) * l1 / (l1 + l2).max(1e-300);
    let rope = &mut s.ropes[r];
    if ins.take_prev > 0.0 {
        rope.nodes[seg - 1].mass -= ins.take_prev;
    }
    if ins.take_next > 0.0 {
        rope.nodes[seg].mass -= ins.take_next;
    }
    rope.nodes.insert(
        seg,
        NodeSpec {
            mass: ins.mass,
            sigma,
            position: pos,
            velocity: ins.velocity,
            contact,
        },
    );
    true
}

/// Applies `edits` in an order that keeps indices valid; an edit touching points already changed
/// in this pass is skipped (the manager finds it again after the next step if still needed).
pub fn apply(s: &mut Structure, edits: &[Edit], counters: &mut Counters) {
    let key = |e: &Edit| -> (usize, f64) {
        match *e {
            Edit::Insert { rope, seg, .. } | Edit::Split { rope, seg } => (rope, seg as f64 + 0.5),
            Edit::Remove { rope, node } | Edit::Merge { rope, node } => (rope, node as f64 + 1.0),
        }
    };
    let mut order: Vec<&Edit> = edits.iter().collect();
    order.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0).then(kb.1.total_cmp(&ka.1))
    });
    let mut touched: Vec<(usize, f64)> = Vec::new();
    for e in order {
        let (r, pos) = key(e);
        if touched
            .iter()
            .any(|&(tr, tp)| tr == r && (tp - pos).abs() < 1.6)
        {
            continue;
        }
        touched.push((r, pos));
        match *e {
            Edit::Insert {
                rope,
                seg,
                block,
                edge,
                point: local,
            } => {
                let b = &s.blocks[block];
                let world = b.position + b.orientation * local;
                let mu = s.ropes[rope].props.friction;
                let contact = NodeContact {
                    block,
                    edge,
                    anchor: local,
                    mode: if mu > 0.0 {
                        SlipMode::Stick
                    } else {
                        SlipMode::SlipForward
                    },
                    mu_rope: mu,
                    cap: INITIAL_EDGE_CAPACITY,
                };
                if insert_node(s, rope, seg, world, Some(contact)) {
                    counters.inserted += 1;
                }
            }
            Edit::Remove { rope, node } => {
                remove_node(s, rope, node);
                counters.removed += 1;
            }
            Edit::Merge { rope, node } => {
                remove_node(s, rope, node);
                counters.merged += 1;
            }
            Edit::Split { rope, seg } => {
                let rs = &s.ropes[rope];
                let (pa, _, _) = point(s, rs, seg);
                let (pb, _, _) = point(s, rs, seg + 1);
                if insert_node(s, rope, seg, 0.5 * (pa + pb), None) {
                    counters.split += 1;
                }
            }
        }
    }
}

/// Inserts contact nodes wherever a rope segment of `s` crosses a plate edge, repeating until no
/// crossing is left (at most `max_passes` passes); returns the number inserted.
pub fn insert_initial_contacts(
    s: &mut Structure,
    tolerance: f64,
    max_depth: f64,
    max_passes: usize,
) -> usize {
    use crate::rope::shell::detect::segment_crossing;
    let mut count = Counters::default();
    let mut scratch = Vec::new();
    for _ in 0..max_passes {
        let mut edits = Vec::new();
        for (r, rope) in s.ropes.iter().enumerate() {
            let n = rope.nodes.len();
            for k in 0..=n {
                let (p, _, _) = point(s, rope, k);
                let (q, _, _) = point(s, rope, k + 1);
                for (b, blk) in s.blocks.iter().enumerate() {
                    let Some(mesh) = blk.mesh.as_ref() else {
                        continue;
                    };
                    let mut skip = Vec::new();
                    for j in [k, k + 1] {
                        if let Some(c) = (1..=n)
                            .contains(&j)
                            .then(|| rope.nodes[j - 1].contact)
                            .flatten()
                            && c.block == b
                        {
                            skip.push(c.edge);
                        }
                    }
                    let inv = blk.orientation.inverse();
                    let (pl, ql) = (inv * (p - blk.position), inv * (q - blk.position));
                    if let Some(c) =
                        segment_crossing(mesh, &pl, &ql, &skip, tolerance, max_depth, &mut scratch)
                    {
                        edits.push(Edit::Insert {
                            rope: r,
                            seg: k,
                            block: b,
                            edge: c.edge,
                            point: c.point,
                        });
                        break;
                    }
                }
            }
        }
        if edits.is_empty() {
            break;
        }
        apply(s, &edits, &mut count);
    }
    count.inserted as usize
}

#[cfg(test)]
#[path = "edit_tests.rs"]
mod tests;
