//! Finds the independent constraint rows of a model at its initial configuration.
//!
//! Only joints in a connected component of the joint graph that contains a closed loop can be
//! redundant (a tree of standard joints never is), so the check runs over those components only:
//! a chain of a thousand bodies costs nothing here. Within them, rows are kept greedily by a
//! Gram-Schmidt pass in joint order (loop-closing joints come last), dropping a row whose
//! component outside the span of the kept rows is below `1e-9` of its norm.

use crate::effect::constraint::RowEval;
use crate::model::{BodyId, Model};

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Union-find of the joint graph: for each full row whether its joint closes a loop, the
/// parent array and the body-graph node of each body.
fn loop_graph(model: &Model, n_rows: usize) -> (Vec<bool>, Vec<usize>) {
    let nb = model.bodies.len();
    let node = |b: BodyId| b.index().unwrap_or(nb);
    let mut parent: Vec<usize> = (0..=nb).collect();
    let mut closes_loop = vec![false; n_rows];
    let mut r0 = 0;
    for j in &model.joints {
        let n = j.kind.n_rows();
        let (a, b) = (
            find(&mut parent, node(j.frame_i.body)),
            find(&mut parent, node(j.frame_j.body)),
        );
        if a == b {
            closes_loop[r0..r0 + n].fill(true);
        } else {
            parent[a] = b;
        }
        r0 += n;
    }
    (closes_loop, parent)
}

/// For each full row, whether it lies in a connected component of the joint graph that
/// contains a closed loop: only such rows can become dependent as the mechanism moves (a tree
/// of standard joints never loses rank), so only they are watched for singular configurations.
pub fn rows_in_loops(model: &Model, row_bodies: &[[BodyId; 2]]) -> Vec<bool> {
    let nb = model.bodies.len();
    let node = |b: BodyId| b.index().unwrap_or(nb);
    let (closes_loop, mut parent) = loop_graph(model, row_bodies.len());
    let loop_roots: Vec<usize> = (0..row_bodies.len())
        .filter(|&r| closes_loop[r])
        .map(|r| find(&mut parent, node(row_bodies[r][0])))
        .collect();
    (0..row_bodies.len())
        .map(|r| loop_roots.contains(&find(&mut parent, node(row_bodies[r][0]))))
        .collect()
}

/// Returns the indices of the independent rows among `rows` (all rows of all joints, in order).
pub fn independent_rows(
    model: &Model,
    row_bodies: &[[BodyId; 2]],
    rows: &[RowEval],
    add_modal_columns: &dyn Fn(usize, &mut [f64]),
) -> Result<Vec<usize>, String> {
    let nb = model.bodies.len();
    let node = |b: BodyId| b.index().unwrap_or(nb);
    let (closes_loop, mut parent) = loop_graph(model, row_bodies.len());
    if !closes_loop.iter().any(|&c| c) {
        return Ok((0..rows.len()).collect());
    }
    let loop_roots: Vec<usize> = (0..rows.len())
        .filter(|&r| closes_loop[r])
        .map(|r| find(&mut parent, node(row_bodies[r][0])))
        .collect();
    let in_loop_component = |parent: &mut Vec<usize>, r: usize| {
        loop_roots.contains(&find(parent, node(row_bodies[r][0])))
    };
    // tree rows first, loop-closing rows last, within the loop components
    let mut order: Vec<usize> = (0..rows.len()).filter(|&r| !closes_loop[r]).collect();
    order.extend((0..rows.len()).filter(|&r| closes_loop[r]));
    let mut kept_dense: Vec<Vec<f64>> = Vec::new();
    let mut active = Vec::with_capacity(rows.len());
    for r in order {
        if !in_loop_component(&mut parent, r) {
            active.push(r);
            continue;
        }
        let mut dense = vec![0.0; model.n_v];
        for (side, b) in row_bodies[r].iter().enumerate() {
            if let Some(bi) = b.index() {
                let body = &model.bodies[bi];
                for k in 0..body.kind.n_v().min(6) {
                    dense[body.v_offset + k] += rows[r].g[side][k];
                }
            }
        }
        add_modal_columns(r, &mut dense);
        let norm0 = dense.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm0 == 0.0 {
            continue;
        }
        for basis in &kept_dense {
            let c: f64 = basis.iter().zip(&dense).map(|(a, b)| a * b).sum();
            for (d, b) in dense.iter_mut().zip(basis) {
                *d -= c * b;
            }
        }
        let norm = dense.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 1e-9 * norm0 {
            dense.iter_mut().for_each(|x| *x /= norm);
            kept_dense.push(dense);
            active.push(r);
        }
    }
    active.sort_unstable();
    Ok(active)
}
