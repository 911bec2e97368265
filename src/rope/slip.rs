//! A chain of rope segments over contact nodes that slip: the rope slides through the nodes with
//! the friction-limited tension ratio, its material flowing without inertia (algebraically).
//!
//! Points `p_0 .. p_m` (world [m]) bound `m >= 2` segments; the interior points `1 .. m-1` are
//! slipping contact nodes, the two end points have fixed material coordinates, so the total rest
//! length `L_tot` of the chain is fixed while its split into `L_0 .. L_{m-1}` is not. At node `i`
//! the rope turns by `theta_i` (`cos theta_i = u_{i-1} . u_i`) and the sharp-edge friction limit is
//!
//! ```text
//! r_i = (1 + mu_i tan(theta_i/2)) / (1 - mu_i tan(theta_i/2)),   T_i = r_i^{s_i} T_{i-1}
//! ```
//!
//! with `s_i = +1` when the rope slides towards the higher index (segment `i` the taut side) and
//! `-1` the other way. So `T_j = c_j T_0` with `c_j = exp(sum_{i<=j} s_i ln r_i)`, and with the
//! linear law `L_j = l_j / (1 + T_j / EA)` the one unknown `T_0` solves
//! `sum_j l_j / (1 + c_j T_0 / EA) = L_tot` (monotone and convex, Newton from `T_0 = 0` converges
//! monotonically). The chain is slack (all tensions zero) when `sum_j l_j <= L_tot`.
//! No axial (Kelvin-Voigt) damping acts in a slipping chain: that law damps the strain rate of
//! *material* segments, while here the rest lengths flow with the rope, and damping on `l_dot / L`
//! would resist the sliding like a viscous brake. Integrator damping and the damping of every
//! material segment take care of the high axial modes.
//!
//! Every derivative with respect to the point positions (through the lengths, the directions and
//! the turning angles) is exact, so the Newton matrices of implicit integrators see the true
//! Jacobian.

use crate::math::{Mat3, Vec3};

/// One slipping node inside a chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipNode {
    /// Slip direction `s_i` (+1: the higher-index side is the taut one).
    pub direction: f64,
    /// Friction coefficient available for sliding along the rope [-].
    pub mu: f64,
}

/// Largest `mu tan(theta/2)` used (a ratio of about 2000); beyond it the node self-locks and the
/// caller keeps it sticking.
pub const MAX_MU_TAN: f64 = 0.999;

/// The result of evaluating a slipping chain.
#[derive(Debug, Clone, Default)]
pub struct ChainEval {
    /// Tension of each segment [N].
    pub tension: Vec<f64>,
    /// Rest length of each segment [m].
    pub rest: Vec<f64>,
    /// Stretched length [m].
    pub length: Vec<f64>,
    /// Rate of change of each rest length [m/s] (material flow).
    pub rest_rate: Vec<f64>,
    /// Force on each point [N] (world), length `m + 1`.
    pub force: Vec<Vec3>,
    /// `dF_a/dp_b` [N/m], row-major `(m+1) x (m+1)`.
    pub jac: Vec<Mat3>,
    /// Elastic energy [J].
    pub energy: f64,
    /// Power dissipated by friction at the slipping nodes [W].
    pub friction_power: f64,
}

/// Ratio `r` of the sharp-edge friction limit and `d ln r / d theta`, for `mu tan(theta/2)`
/// clamped to [`MAX_MU_TAN`] (derivative zero where clamped).
pub fn edge_ratio(mu: f64, theta: f64) -> (f64, f64) {
    let t = (0.5 * theta).tan();
    let mut x = mu * t;
    let mut deriv = mu * (1.0 + t * t) / (1.0 - x * x).max(1e-12);
    if x > MAX_MU_TAN {
        x = MAX_MU_TAN;
        deriv = 0.0;
    }
    ((1.0 + x) / (1.0 - x), deriv)
}

/// Evaluates a chain of `m = pos.len() - 1 >= 2` segments with the slipping interior nodes
/// `nodes` (length `m - 1`), total rest length `rest_total` [m] and axial stiffness `ea` [N].
/// `vel` are the point velocities [m/s] (for the rate of material flow).
pub fn eval_chain(
    pos: &[Vec3],
    vel: &[Vec3],
    nodes: &[SlipNode],
    rest_total: f64,
    ea: f64,
) -> ChainEval {
    let np = pos.len();
    let m = np - 1;
    debug_assert!(m >= 2 && nodes.len() == m - 1 && vel.len() == np);
    let mut u = vec![Vec3::zeros(); m];
    let mut l = vec![0.0; m];
    let mut proj = vec![Mat3::zeros(); m];
    for j in 0..m {
        let d = pos[j + 1] - pos[j];
        l[j] = d.norm().max(1e-12);
        u[j] = d / l[j];
        proj[j] = Mat3::identity() - u[j] * u[j].transpose();
    }
    // log-ratios and their gradients w.r.t. the three points around each node
    let mut lam = vec![0.0; m]; // lam[i] for node i (index 0 unused)
    let mut dlam: Vec<[Vec3; 3]> = vec![[Vec3::zeros(); 3]; m];
    for i in 1..m {
        let nd = nodes[i - 1];
        let c = u[i - 1].dot(&u[i]).clamp(-1.0, 1.0);
        let theta = c.acos();
        let (r, dlnr) = edge_ratio(nd.mu, theta);
        lam[i] = nd.direction * r.ln();
        let sin = (1.0 - c * c).max(0.0).sqrt();
        if sin > 1e-9 && dlnr != 0.0 {
            let k = nd.direction * dlnr * (-1.0 / sin);
            let g1 = proj[i - 1] * u[i] / l[i - 1];
            let g2 = proj[i] * u[i - 1] / l[i];
            dlam[i] = [-g1 * k, (g1 - g2) * k, g2 * k];
        }
    }
    let mut cj = vec![1.0; m];
    for j in 1..m {
        cj[j] = cj[j - 1] * lam[j].exp();
    }
    let sum_l: f64 = l.iter().sum();
    let mut out = ChainEval {
        tension: vec![0.0; m],
        rest: vec![0.0; m],
        length: l.clone(),
        rest_rate: vec![0.0; m],
        force: vec![Vec3::zeros(); np],
        jac: vec![Mat3::zeros(); np * np],
        ..Default::default()
    };
    if sum_l <= rest_total {
        for (r, lj) in out.rest[..m].iter_mut().zip(&l[..m]) {
            *r = lj * rest_total / sum_l;
        }
        return out;
    }
    // T0 by Newton from zero (monotone for this convex decreasing function); the residual is
    // resolved to round-off of the lengths, which the Newton steps reach in a few iterations
    let mut t0 = 0.0;
    let floor = 4.0 * f64::EPSILON * sum_l;
    for _ in 0..60 {
        let mut f = -rest_total;
        let mut df = 0.0;
        for j in 0..m {
            let w = 1.0 / (1.0 + cj[j] * t0 / ea);
            f += l[j] * w;
            df -= l[j] * cj[j] / ea * w * w;
        }
        if f.abs() <= floor {
            break;
        }
        t0 -= f / df;
    }
    let w: Vec<f64> = (0..m).map(|j| 1.0 / (1.0 + cj[j] * t0 / ea)).collect();
    let dd: f64 = (0..m).map(|j| l[j] * cj[j] * w[j] * w[j] / ea).sum();
    // dT0/dlam_i = -(sum_{j>=i} l_j c_j w_j^2 T0/EA) / Dd
    let mut dt0_dlam = vec![0.0; m];
    let mut acc = 0.0;
    for i in (1..m).rev() {
        acc += l[i] * cj[i] * w[i] * w[i] * t0 / ea;
        dt0_dlam[i] = -acc / dd;
    }
    // gradients of the elastic tensions and rest lengths w.r.t. the points
    let mut dte = vec![Vec3::zeros(); m * np];
    for j in 0..m {
        for i in 0..m {
            let g = cj[j] * w[i] / dd;
            dte[j * np + i + 1] += u[i] * g;
            dte[j * np + i] -= u[i] * g;
        }
        for i in 1..m {
            let g = cj[j] * (dt0_dlam[i] + if i <= j { t0 } else { 0.0 });
            if g != 0.0 {
                for (k, a) in [i - 1, i, i + 1].into_iter().enumerate() {
                    dte[j * np + a] += dlam[i][k] * g;
                }
            }
        }
    }
    for j in 0..m {
        let te = cj[j] * t0;
        let rest = l[j] * w[j];
        out.rest[j] = rest;
        let eps = l[j] / rest - 1.0;
        out.energy += 0.5 * ea * eps * eps * rest;
        // dL_j/dp_a = w_j dl_j/dp_a - l_j w_j^2 / EA dTe_j/dp_a
        let mut lrate = 0.0;
        for a in 0..np {
            let mut g = -dte[j * np + a] * (l[j] * w[j] * w[j] / ea);
            if a == j + 1 {
                g += u[j] * w[j];
            } else if a == j {
                g -= u[j] * w[j];
            }
            lrate += g.dot(&vel[a]);
        }
        out.rest_rate[j] = lrate;
        out.friction_power += te * (1.0 + 0.5 * eps) * lrate;
        let t = te;
        if t <= 0.0 {
            continue;
        }
        out.tension[j] = t;
        for a in 0..np {
            let blk = u[j] * dte[j * np + a].transpose();
            out.jac[j * np + a] += blk;
            out.jac[(j + 1) * np + a] -= blk;
        }
        let geo = proj[j] * (t / l[j]);
        out.jac[j * np + j + 1] += geo;
        out.jac[j * np + j] -= geo;
        out.jac[(j + 1) * np + j + 1] -= geo;
        out.jac[(j + 1) * np + j] += geo;
        out.force[j] += u[j] * t;
        out.force[j + 1] -= u[j] * t;
    }
    out
}
