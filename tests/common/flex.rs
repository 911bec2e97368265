//! Shared builders for the flexible-body tests: a small honeycomb-like panel and its modal data.

use mbcosim::flex::{ModalBodyData, PanelSpec, PlateModel};
use mbcosim::math::{Mat3, Vec3};
use mbcosim::model::kinematics::quat_at;
use nalgebra::DVector;

/// A 2 m x 1 m panel, 1.2 GPa equivalent modulus, 2.7 kg/m^2 (5.4 kg).
pub fn panel_spec() -> PanelSpec {
    PanelSpec {
        a: 2.0,
        b: 1.0,
        thickness: 0.025,
        youngs_modulus: 1.2e9,
        poisson: 0.3,
        density: 60.0,
        non_structural_mass: 1.2,
    }
}

/// Plate model of [`panel_spec`] on an `nx` x `ny` element mesh.
pub fn panel(nx: usize, ny: usize) -> PlateModel {
    PlateModel::new(&panel_spec(), nx, ny).unwrap()
}

/// Pose, modal coordinates and speeds of the modal body whose coordinates start at `qo`, `vo`.
pub struct ModalState {
    pub r: Vec3,
    pub rot: Mat3,
    pub v: Vec3,
    pub omega: Vec3,
    pub a: DVector<f64>,
    pub a_dot: DVector<f64>,
}

pub fn modal_state(q: &[f64], v: &[f64], qo: usize, vo: usize, n: usize) -> ModalState {
    ModalState {
        r: Vec3::new(q[qo], q[qo + 1], q[qo + 2]),
        rot: quat_at(q, qo + 3).to_rotation_matrix().into_inner(),
        v: Vec3::new(v[vo], v[vo + 1], v[vo + 2]),
        omega: Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]),
        a: DVector::from_column_slice(&q[qo + 7..qo + 7 + n]),
        a_dot: DVector::from_column_slice(&v[vo + 6..vo + 6 + n]),
    }
}

/// Linear momentum [N s] and angular momentum about the world origin [N m s], world frame:
/// `p` = rows 0..3 of `M y`, `L = r x p + A (rows 3..6 of M y)` (body-frame angular momentum
/// about the frame origin, `S(a) x A^T v + J(a) omega + C_r(a) a_dot`).
pub fn momenta(data: &ModalBodyData, s: &ModalState) -> (Vec3, Vec3) {
    let m = data.invariants().mass_matrix(&s.rot, &s.a).unwrap();
    let n = s.a.len();
    let mut y = DVector::zeros(6 + n);
    y.fixed_rows_mut::<3>(0).copy_from(&s.v);
    y.fixed_rows_mut::<3>(3).copy_from(&s.omega);
    y.rows_mut(6, n).copy_from(&s.a_dot);
    let my = m * y;
    let p = Vec3::new(my[0], my[1], my[2]);
    let h = Vec3::new(my[3], my[4], my[5]);
    (p, s.r.cross(&p) + s.rot * h)
}

/// Lowest eigenpair `(omega^2, x)` of `K x = omega^2 M x` (M symmetric positive definite).
pub fn lowest_mode(
    k: &nalgebra::DMatrix<f64>,
    m: &nalgebra::DMatrix<f64>,
) -> (f64, nalgebra::DVector<f64>) {
    let l = m.clone().cholesky().unwrap().l();
    let li = l.clone().try_inverse().unwrap();
    let c = &li * k * li.transpose();
    let c = 0.5 * (&c + c.transpose());
    let eig = c.symmetric_eigen();
    let (i, w2) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, w)| (i, *w))
        .unwrap();
    let x = li.transpose() * eig.eigenvectors.column(i);
    (w2, x)
}

/// Times of the upward zero crossings of `signal` sampled while advancing `sim` to `t_end` in
/// steps `dt` (linear interpolation between samples).
pub fn upward_crossings(
    sim: &mut mbcosim::sim::Simulation,
    t_end: f64,
    dt: f64,
    signal: &dyn Fn(&mbcosim::state::State) -> f64,
) -> Vec<f64> {
    let mut out = Vec::new();
    let (mut t0, mut s0) = (sim.state.t, signal(&sim.state));
    while sim.state.t < t_end - 1e-12 {
        sim.advance_to((sim.state.t + dt).min(t_end)).unwrap();
        let (t1, s1) = (sim.state.t, signal(&sim.state));
        if s0 < 0.0 && s1 >= 0.0 {
            out.push(t0 + (t1 - t0) * (-s0) / (s1 - s0));
        }
        (t0, s0) = (t1, s1);
    }
    out
}

/// Small motions of a panel hanging from a hinge about its body y axis through `rho_f` (body
/// x pointing down, `A0 = R_Y(pi/2)`, gravity `g` [m/s^2] along world -Z): mass and stiffness
/// matrices over `[theta; a]` (derivation in `tests/flex/flex_pendulum.rs`).
pub fn hanging_linearization(
    data: &ModalBodyData,
    rho_f: &Vec3,
    g: f64,
) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
    use nalgebra::DMatrix;
    let inv = data.invariants();
    let n = data.n_modes();
    let a0_rot = mbcosim::math::Quat::from_axis_angle(&Vec3::y_axis(), std::f64::consts::FRAC_PI_2)
        .to_rotation_matrix()
        .into_inner();
    let mut nmap = DMatrix::zeros(6 + n, 1 + n);
    let ey = Vec3::y();
    let v_col = a0_rot * ey.cross(&(-rho_f));
    for k in 0..3 {
        nmap[(k, 0)] = v_col[k];
        nmap[(3 + k, 0)] = ey[k];
    }
    for j in 0..n {
        nmap[(6 + j, 1 + j)] = 1.0;
    }
    let m0 = inv.mass_matrix(&a0_rot, &DVector::zeros(n)).unwrap();
    let m_l = nmap.transpose() * &m0 * &nmap;
    let s_x = inv.first_moment.x - inv.mass * rho_f.x;
    let mut k_l = DMatrix::zeros(1 + n, 1 + n);
    k_l[(0, 0)] = g * s_x;
    for j in 0..n {
        k_l[(0, 1 + j)] = -g * inv.c_t[(2, j)];
        k_l[(1 + j, 0)] = -g * inv.c_t[(2, j)];
        for i in 0..n {
            k_l[(1 + i, 1 + j)] = data.stiffness()[(i, j)];
        }
    }
    (m_l, k_l)
}
