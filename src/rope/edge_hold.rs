//! The hold of a contact node along its plate edge: a stiff spring-damper on the node's
//! coordinate along the edge, whose anchor the contact manager moves between steps when the
//! spring force exceeds the friction capacity (the Coulomb return mapping of the paper's pseudo
//! friction coefficient: the node moves along the edge by the unbalanced share).
//!
//! The node is held on the edge line by a two-row joint; its coordinate along the edge is
//! `u = (R e) . (p - r - R a)` [m] (`p` the node, `r`, `R` the block's position and orientation,
//! `a` a point of the edge and `e` its unit direction in the block frame). The force on that
//! coordinate is `F = -(k (u - u0) + c u_dot)` with the anchor `u0` from the memory: a linear
//! element within every step, so Newton's method sees a smooth function (a spring that saturates
//! at the friction limit inside an iteration makes Newton stall on a stick window of micrometres).
//! While sticking the node moves by at most `cap / k` along the edge (micrometres for the default
//! stiffness).
//!
//! The generalized forces are `F g` with `g = du/dq`: `R e` on the node, `-R e` on the block's
//! translation and `e x s` on its rotation (`s = R^T (p - r)`); the Jacobians are exact:
//! `K = g (k g + c H^T v)^T - F H`, `D = c g g^T`, `H` the Hessian of `u` on the rotation group.

use super::assemble::PointRef;
use crate::effect::JacobianSink;
use crate::math::{Mat3, Matrix6, Vec3, skew};
use crate::model::kinematics::BodyKin;

/// The evaluated element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hold {
    /// Coordinate along the edge [m] and its rate [m/s].
    pub u: f64,
    pub u_dot: f64,
    /// Force on the coordinate [N] (on the node along the edge).
    pub force: f64,
    /// `dF/du` [N/m] and `dF/du_dot` [N s/m].
    pub df_du: f64,
    pub df_dudot: f64,
}

/// The node's coordinate `u` [m] along the edge and its rate `u_dot` [m/s] (node `node`, block
/// `block`, edge point `a` and direction `e` in the block frame).
fn coordinate(node: &BodyKin, block: &BodyKin, a: &Vec3, e: &Vec3) -> (f64, f64) {
    let ew = block.rot * e;
    let u = ew.dot(&(node.r - block.point(a)));
    let s = block.rot.transpose() * (node.r - block.r);
    // u_dot = g . v
    let u_dot = ew.dot(&(node.v - block.v)) + e.cross(&s).dot(&block.omega);
    (u, u_dot)
}

/// Evaluates the element for node `node` (a particle), block `block`, edge point `a` and
/// direction `e` (block frame), anchor `u0` [m], stiffness `k` [N/m] and damping `c` [N s/m].
#[allow(clippy::too_many_arguments)]
pub fn eval(node: &BodyKin, block: &BodyKin, a: &Vec3, e: &Vec3, u0: f64, k: f64, c: f64) -> Hold {
    let (u, u_dot) = coordinate(node, block, a, e);
    Hold {
        u,
        u_dot,
        force: -(k * (u - u0) + c * u_dot),
        df_du: -k,
        df_dudot: -c,
    }
}

/// The element while the node slides along its edge: Coulomb's sliding friction, the constant
/// force `force` [N] on the coordinate (the contact manager sets it to the cone's capacity along
/// the edge against the slide after every accepted step), no spring and no damping. The rope's
/// pull beyond it moves the node along the edge through the dynamics, with the rope's tensions
/// continuous through the node.
pub fn sliding(node: &BodyKin, block: &BodyKin, a: &Vec3, e: &Vec3, force: f64) -> Hold {
    let (u, u_dot) = coordinate(node, block, a, e);
    Hold {
        u,
        u_dot,
        force,
        df_du: 0.0,
        df_dudot: 0.0,
    }
}

/// Adds the generalized forces of `h` to `f`.
pub fn add_forces(h: &Hold, node: &BodyKin, block: &BodyKin, e: &Vec3, f: &mut [f64]) {
    let ew = block.rot * e;
    let np = PointRef {
        kin: node,
        s: Vec3::zeros(),
    };
    super::assemble::add_force(&np, &(ew * h.force), f);
    if block.is_free() {
        let s = block.rot.transpose() * (node.r - block.r);
        let c = block.col;
        for i in 0..3 {
            f[c + i] -= h.force * ew[i];
        }
        if block.rotational {
            let t = e.cross(&s) * h.force;
            for i in 0..3 {
                f[c + 3 + i] += t[i];
            }
        }
    }
}

/// Emits the four K/D blocks (node-node, node-block, block-node, block-block).
pub fn add_jacobian(
    h: &Hold,
    node: &BodyKin,
    block: &BodyKin,
    e: &Vec3,
    sink: &mut dyn JacobianSink,
) {
    let rot = block.rot;
    let ew = rot * e;
    let s = rot.transpose() * (node.r - block.r);
    let (ex, sx) = (skew(e), skew(&s));
    // g and H^T v, split per body (node: 3, block: 6)
    let g_n = ew;
    let mut g_b = Vector6::zeros();
    g_b.fixed_rows_mut::<3>(0).copy_from(&(-ew));
    g_b.fixed_rows_mut::<3>(3).copy_from(&e.cross(&s));
    let w = block.omega;
    let htv_n = -rot * e.cross(&w);
    let mut htv_b = Vector6::zeros();
    htv_b.fixed_rows_mut::<3>(0).copy_from(&(rot * e.cross(&w)));
    htv_b
        .fixed_rows_mut::<3>(3)
        .copy_from(&(e.cross(&(rot.transpose() * (node.v - block.v))) + s.cross(&e.cross(&w))));
    // Hessian blocks
    let h_n_th: Mat3 = -rot * ex;
    let h_r_th: Mat3 = rot * ex;
    let h_th_n: Mat3 = ex * rot.transpose();
    let h_th_r: Mat3 = -ex * rot.transpose();
    let h_th_th: Mat3 = ex * sx;
    // K = g (a)^T - F H with a = -(dF/du g + dF/du_dot H^T v); D = -dF/du_dot g g^T
    let a_n = -(g_n * h.df_du + htv_n * h.df_dudot);
    let a_b = -(g_b * h.df_du + htv_b * h.df_dudot);
    let f = h.force;
    let mut k_nn = Matrix6::zeros();
    k_nn.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(g_n * a_n.transpose()));
    let mut k_nb = Matrix6::zeros();
    let nb = g_n * a_b.transpose();
    k_nb.fixed_view_mut::<3, 6>(0, 0).copy_from(&nb);
    let hn = k_nb.fixed_view::<3, 3>(0, 3) - h_n_th * f;
    k_nb.fixed_view_mut::<3, 3>(0, 3).copy_from(&hn);
    let mut k_bn = Matrix6::zeros();
    let bn = g_b * a_n.transpose();
    k_bn.fixed_view_mut::<6, 3>(0, 0).copy_from(&bn);
    let hb = k_bn.fixed_view::<3, 3>(3, 0) - h_th_n * f;
    k_bn.fixed_view_mut::<3, 3>(3, 0).copy_from(&hb);
    let mut k_bb = g_b * a_b.transpose();
    let krt = k_bb.fixed_view::<3, 3>(0, 3) - h_r_th * f;
    k_bb.fixed_view_mut::<3, 3>(0, 3).copy_from(&krt);
    let ktr = k_bb.fixed_view::<3, 3>(3, 0) - h_th_r * f;
    k_bb.fixed_view_mut::<3, 3>(3, 0).copy_from(&ktr);
    let ktt = k_bb.fixed_view::<3, 3>(3, 3) - h_th_th * f;
    k_bb.fixed_view_mut::<3, 3>(3, 3).copy_from(&ktt);
    let cd = -h.df_dudot;
    let mut d_nn = Matrix6::zeros();
    d_nn.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(g_n * g_n.transpose() * cd));
    let mut d_nb = Matrix6::zeros();
    d_nb.fixed_view_mut::<3, 6>(0, 0)
        .copy_from(&(g_n * g_b.transpose() * cd));
    let mut d_bn = Matrix6::zeros();
    d_bn.fixed_view_mut::<6, 3>(0, 0)
        .copy_from(&(g_b * g_n.transpose() * cd));
    let d_bb = g_b * g_b.transpose() * cd;
    sink.add(node, node, &k_nn, &d_nn);
    sink.add(node, block, &k_nb, &d_nb);
    sink.add(block, node, &k_bn, &d_bn);
    sink.add(block, block, &k_bb, &d_bb);
}

type Vector6 = nalgebra::Vector6<f64>;
