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
//! Jacobian. The forces, rest lengths and material flow cost O(m) ([`eval_chain`]); the Jacobian
//! couples every pair of the chain's points (a pull anywhere changes `T_0`), so it has `(m + 1)^2`
//! blocks, each formed in O(1) and only when asked for.

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

/// Which derivatives [`eval_chain`] forms.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Derivatives {
    /// Forces, rest lengths and flow only.
    None,
    /// The full Jacobian `(m + 1)^2` blocks.
    Dense,
    /// The Jacobian's sparse part (the geometric stiffness of each segment) in
    /// [`ChainEval::jac`], and its dense part in factors ([`ChainEval::border`]).
    Bordered,
}

/// The dense part of a taut chain's Jacobian as factors: with `E_aj = +1` for `a = j`, `-1` for
/// `a = j + 1` (the two ends of segment `j`),
///
/// ```text
/// dF_a/dp_b (dense part) = sum_j E_aj uc_j (g_b + t0 h_jb)^T,   h_jb = sum_{1<=i<=j} dlam_i/dp_b,
/// ```
///
/// so with auxiliary unknowns `y = sum_b g_b . dp_b` and `z_j = z_{j-1} + dlam_j . dp`
/// (`z_0 = 0`) the coupling is `dF_a = sum_j E_aj uc_j (y + t0 z_j)`: O(m) entries instead of
/// `(m + 1)^2` blocks.
#[derive(Debug, Clone, Default)]
pub struct ChainBorder {
    /// Tension factor `T_0` [N] (`T_j = c_j T_0`).
    pub t0: f64,
    /// `G_b = dT_0/dp_b` [N/m], one per point.
    pub g: Vec<Vec3>,
    /// `d lam_i/dp` [1/m] w.r.t. the points `i - 1, i, i + 1`, one per segment (index 0 unused).
    pub dlam: Vec<[Vec3; 3]>,
    /// `u_j c_j` [-], one per segment (zero for a segment without tension).
    pub uc: Vec<Vec3>,
}

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
    /// `dF_a/dp_b` [N/m], row-major `(m+1) x (m+1)` (with [`Derivatives::Bordered`] only the
    /// geometric stiffness, the rest in `border`).
    pub jac: Vec<Mat3>,
    /// The dense part of the Jacobian as factors ([`Derivatives::Bordered`], taut chains).
    pub border: Option<ChainBorder>,
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
/// `vel` are the point velocities [m/s] (for the rate of material flow). The derivatives are
/// formed as `deriv` asks (`ChainEval::jac` stays empty with [`Derivatives::None`]).
///
/// Cost O(m) without the Jacobian: every tension is `T_j = c_j T_0`, so its gradient is
/// `c_j (G + T_0 sum_{i<=j} d lam_i)` with one shared gradient `G = dT_0/dp` (built once from the
/// lengths and the log-ratios, each touching two or three points) and prefix sums of the
/// log-ratio gradients (each touching three points); the material flow uses the same sums
/// contracted with the velocities. With the Jacobian every one of its `(m + 1)^2` blocks is
/// formed in O(1) from those factors.
pub fn eval_chain(
    pos: &[Vec3],
    vel: &[Vec3],
    nodes: &[SlipNode],
    rest_total: f64,
    ea: f64,
    deriv: Derivatives,
) -> ChainEval {
    let with_jac = deriv != Derivatives::None;
    let np = pos.len();
    let m = np - 1;
    debug_assert!(m >= 2 && nodes.len() == m - 1 && vel.len() == np);
    let mut u = vec![Vec3::zeros(); m];
    let mut l = vec![0.0; m];
    for j in 0..m {
        let d = pos[j + 1] - pos[j];
        l[j] = d.norm().max(1e-12);
        u[j] = d / l[j];
    }
    let proj = |j: usize| Mat3::identity() - u[j] * u[j].transpose();
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
            let g1 = proj(i - 1) * u[i] / l[i - 1];
            let g2 = proj(i) * u[i - 1] / l[i];
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
        jac: if with_jac {
            vec![Mat3::zeros(); np * np]
        } else {
            Vec::new()
        },
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
    // dT0/dlam_i = -(sum_{j>=i} l_j c_j w_j^2 T0/EA) / Dd, a suffix sum
    let mut dt0_dlam = vec![0.0; m];
    let mut acc = 0.0;
    for i in (1..m).rev() {
        acc += l[i] * cj[i] * w[i] * w[i] * t0 / ea;
        dt0_dlam[i] = -acc / dd;
    }
    // G_a = dT0/dp_a: through each length (dT0/dl_i = w_i / Dd) and each log-ratio
    let mut g = vec![Vec3::zeros(); np];
    for i in 0..m {
        let s = u[i] * (w[i] / dd);
        g[i + 1] += s;
        g[i] -= s;
    }
    for i in 1..m {
        for k in 0..3 {
            g[i - 1 + k] += dlam[i][k] * dt0_dlam[i];
        }
    }
    // rates: dT0/dt = G . v, d lam_i/dt = dlam_i . v (prefix-summed along the chain)
    let t0_rate: f64 = g.iter().zip(vel).map(|(a, b)| a.dot(b)).sum();
    let mut lam_rate_sum = 0.0;
    for j in 0..m {
        if j > 0 {
            lam_rate_sum += (0..3).map(|k| dlam[j][k].dot(&vel[j - 1 + k])).sum::<f64>();
        }
        let te = cj[j] * t0;
        let rest = l[j] * w[j];
        out.rest[j] = rest;
        let eps = l[j] / rest - 1.0;
        out.energy += 0.5 * ea * eps * eps * rest;
        // dL_j/dt = w_j dl_j/dt - l_j w_j^2 / EA dTe_j/dt
        let te_rate = cj[j] * (t0_rate + t0 * lam_rate_sum);
        let lrate = w[j] * u[j].dot(&(vel[j + 1] - vel[j])) - l[j] * w[j] * w[j] / ea * te_rate;
        out.rest_rate[j] = lrate;
        out.friction_power += te * (1.0 + 0.5 * eps) * lrate;
        if te <= 0.0 {
            continue;
        }
        out.tension[j] = te;
        out.force[j] += u[j] * te;
        out.force[j + 1] -= u[j] * te;
    }
    match deriv {
        Derivatives::None => {}
        Derivatives::Dense => fill_jacobian(&mut out, &u, &l, &cj, t0, &g, &dlam),
        Derivatives::Bordered => {
            fill_geometric(&mut out, &u, &l);
            let uc = (0..m)
                .map(|j| {
                    if out.tension[j] > 0.0 {
                        u[j] * cj[j]
                    } else {
                        Vec3::zeros()
                    }
                })
                .collect();
            out.border = Some(ChainBorder { t0, g, dlam, uc });
        }
    }
    out
}

/// Adds the geometric stiffness `T_j P_j / l_j` of every taut segment to the Jacobian.
fn fill_geometric(out: &mut ChainEval, u: &[Vec3], l: &[f64]) {
    let np = u.len() + 1;
    for j in 0..u.len() {
        let t = out.tension[j];
        if t <= 0.0 {
            continue;
        }
        let geo = (Mat3::identity() - u[j] * u[j].transpose()) * (t / l[j]);
        out.jac[j * np + j + 1] += geo;
        out.jac[j * np + j] -= geo;
        out.jac[(j + 1) * np + j + 1] -= geo;
        out.jac[(j + 1) * np + j] += geo;
    }
}

/// Fills the Jacobian `dF_a/dp_b` of an evaluated, taut chain: for each taut segment `j` the
/// blocks `u_j (dT_j/dp_b)^T` on its two ends, `dT_j/dp_b = c_j (G_b + T_0 sum_{1<=i<=j}
/// dlam_i/dp_b)` (only `i` in `b-1 ..= b+1` touch `p_b`), and the geometric stiffness `T_j P_j /
/// l_j`.
fn fill_jacobian(
    out: &mut ChainEval,
    u: &[Vec3],
    l: &[f64],
    cj: &[f64],
    t0: f64,
    g: &[Vec3],
    dlam: &[[Vec3; 3]],
) {
    let m = u.len();
    let np = m + 1;
    for j in 0..m {
        let t = out.tension[j];
        if t <= 0.0 {
            continue;
        }
        for b in 0..np {
            // sum over i in max(1, b-1) ..= min(j, b+1, m-1) of dlam_i w.r.t. p_b
            let mut h = Vec3::zeros();
            let lo = b.saturating_sub(1).max(1);
            let hi = j.min(b + 1).min(m - 1);
            for i in lo..=hi {
                h += dlam[i][b + 1 - i];
            }
            let d = (g[b] + h * t0) * cj[j];
            let blk = u[j] * d.transpose();
            out.jac[j * np + b] += blk;
            out.jac[(j + 1) * np + b] -= blk;
        }
        let geo = (Mat3::identity() - u[j] * u[j].transpose()) * (t / l[j]);
        out.jac[j * np + j + 1] += geo;
        out.jac[j * np + j] -= geo;
        out.jac[(j + 1) * np + j + 1] -= geo;
        out.jac[(j + 1) * np + j] += geo;
    }
}
