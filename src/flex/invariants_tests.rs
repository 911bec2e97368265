//! Tests of the floating-frame mass matrix and quadratic-velocity vector against brute-force
//! sums over point masses, and of the point kinematics behind them by finite differences.

use nalgebra::{DMatrix, DVector, Matrix3xX};

use super::invariants::Invariants;
use crate::math::{Mat3, Vec3, exp_so3, skew};

/// Small deterministic generator (xorshift64*), uniform in [-1, 1).
pub(crate) struct Rng(pub u64);

impl Rng {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (r >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    pub(crate) fn vec3(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next())
    }
    pub(crate) fn dvec(&mut self, n: usize) -> DVector<f64> {
        DVector::from_fn(n, |_, _| self.next())
    }
}

struct Cloud {
    masses: Vec<f64>,
    positions: Vec<Vec3>,
    shapes: Vec<Matrix3xX<f64>>,
}

fn cloud(rng: &mut Rng, nodes: usize, modes: usize) -> Cloud {
    Cloud {
        masses: (0..nodes).map(|_| 1.5 + rng.next()).collect(),
        positions: (0..nodes).map(|_| 2.0 * rng.vec3()).collect(),
        shapes: (0..nodes)
            .map(|_| Matrix3xX::from_fn(modes, |_, _| 0.3 * rng.next()))
            .collect(),
    }
}

/// `B_k = [I, -A u~, A Phi_k]` for one point.
fn b_matrix(rot: &Mat3, u: &Vec3, phi: &Matrix3xX<f64>) -> DMatrix<f64> {
    let n = phi.ncols();
    let mut b = DMatrix::zeros(3, 6 + n);
    b.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
    b.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-rot * skew(u)));
    b.view_mut((0, 6), (3, n)).copy_from(&(rot * phi));
    b
}

fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).norm() / b.norm()
}

#[test]
fn mass_matrix_and_quadratic_velocity_match_brute_force_node_sums() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for (nodes, modes) in [(7, 4), (12, 1), (5, 6)] {
        let c = cloud(&mut rng, nodes, modes);
        let inv = Invariants::from_nodes(&c.masses, &c.positions, &c.shapes).unwrap();
        inv.validate().unwrap();
        let rot = exp_so3(&(2.0 * rng.vec3()))
            .to_rotation_matrix()
            .into_inner();
        let a = 0.5 * rng.dvec(modes);
        let omega = 3.0 * rng.vec3();
        let a_dot = 2.0 * rng.dvec(modes);
        let g = Vec3::new(0.3, -9.81, 1.1);
        let mut m_bf = DMatrix::zeros(6 + modes, 6 + modes);
        let mut h_bf = DVector::zeros(6 + modes);
        let mut f_bf = DVector::zeros(6 + modes);
        for k in 0..nodes {
            let phi = &c.shapes[k];
            let u = c.positions[k] + phi * &a;
            let b = b_matrix(&rot, &u, phi);
            m_bf += c.masses[k] * b.transpose() * &b;
            let w = rot * (omega.cross(&omega.cross(&u)) + 2.0 * omega.cross(&(phi * &a_dot)));
            h_bf += c.masses[k] * b.transpose() * w;
            f_bf += c.masses[k] * b.transpose() * g;
        }
        let m = inv.mass_matrix(&rot, &a).unwrap();
        let h = inv.quadratic_velocity(&rot, &a, &omega, &a_dot).unwrap();
        let f = inv.gravity_force(&rot, &a, &g).unwrap();
        println!(
            "{nodes} nodes, {modes} modes: rel. error M {:.1e}, h {:.1e}",
            rel(&m, &m_bf),
            (&h - &h_bf).norm() / h_bf.norm()
        );
        assert!(rel(&m, &m_bf) < 1e-12, "M: {}", rel(&m, &m_bf));
        let hv = DMatrix::from_column_slice(6 + modes, 1, h.as_slice());
        let hv_bf = DMatrix::from_column_slice(6 + modes, 1, h_bf.as_slice());
        assert!(rel(&hv, &hv_bf) < 1e-12, "h: {}", rel(&hv, &hv_bf));
        assert!((&f - &f_bf).norm() < 1e-12 * f_bf.norm());
        // Named derived invariants against their defining sums.
        for j in 0..modes {
            let mut cr = Vec3::zeros();
            let mut rpt = Mat3::zeros();
            for k in 0..nodes {
                let pj: Vec3 = c.shapes[k].column(j).into();
                cr += c.masses[k] * c.positions[k].cross(&pj);
                rpt += c.masses[k] * skew(&c.positions[k]) * skew(&pj);
            }
            assert!((inv.c_r().column(j) - cr).norm() < 1e-12 * cr.norm());
            assert!((inv.rho_tilde_phi_tilde(j) - rpt).norm() < 1e-12 * rpt.norm());
        }
        let (i, j) = (0, modes - 1);
        let mut ppt = Vec3::zeros();
        for k in 0..nodes {
            let pi: Vec3 = c.shapes[k].column(i).into();
            let pj: Vec3 = c.shapes[k].column(j).into();
            ppt += c.masses[k] * pi.cross(&pj);
        }
        assert!((inv.phi_tilde_phi(i, j) - ppt).norm() <= 1e-12 * ppt.norm().max(1.0));
    }
}

/// Position of a material point at time t along y(t) = y0 + t y1, starting at r = 0, A = A0,
/// a = a0: `r + A u`.
pub(crate) fn point_at(
    t: f64,
    a0_rot: &Mat3,
    rho: &Vec3,
    phi: &Matrix3xX<f64>,
    y0: &DVector<f64>,
    y1: &DVector<f64>,
    a0: &DVector<f64>,
) -> Vec3 {
    let n = phi.ncols();
    let v0 = Vec3::new(y0[0], y0[1], y0[2]);
    let v1 = Vec3::new(y1[0], y1[1], y1[2]);
    let w0 = Vec3::new(y0[3], y0[4], y0[5]);
    let w1 = Vec3::new(y1[3], y1[4], y1[5]);
    let r = v0 * t + 0.5 * v1 * t * t;
    // Body angular velocity w0 + t w1: to second order A(t) = A0 exp(w0 t + w1 t^2 / 2).
    let rot = a0_rot
        * exp_so3(&(w0 * t + 0.5 * w1 * t * t))
            .to_rotation_matrix()
            .into_inner();
    let a = a0 + y0.rows(6, n) * t + 0.5 * y1.rows(6, n) * t * t;
    r + rot * (rho + phi * a)
}

#[test]
fn point_acceleration_is_b_ydot_plus_w_by_finite_differences() {
    let mut rng = Rng(42);
    let n = 3;
    let rho = rng.vec3();
    let phi = Matrix3xX::from_fn(n, |_, _| rng.next());
    let rot = exp_so3(&rng.vec3()).to_rotation_matrix().into_inner();
    let a0 = rng.dvec(n);
    let y0 = rng.dvec(6 + n);
    let y1 = rng.dvec(6 + n);
    let hstep = 1e-4;
    let p = |t| point_at(t, &rot, &rho, &phi, &y0, &y1, &a0);
    let acc_fd = (p(hstep) - 2.0 * p(0.0) + p(-hstep)) / (hstep * hstep);
    let vel_fd = (p(hstep) - p(-hstep)) / (2.0 * hstep);
    let u = rho + &phi * &a0;
    let b = b_matrix(&rot, &u, &phi);
    let omega = Vec3::new(y0[3], y0[4], y0[5]);
    let ad = y0.rows(6, n).into_owned();
    let w = rot * (omega.cross(&omega.cross(&u)) + 2.0 * omega.cross(&(&phi * ad)));
    let acc = &b * &y1 + w;
    let vel = &b * &y0;
    assert!((vel_fd - Vec3::new(vel[0], vel[1], vel[2])).norm() < 1e-7);
    assert!((acc_fd - Vec3::new(acc[0], acc[1], acc[2])).norm() < 1e-5);
}

#[test]
fn rejects_inconsistent_node_data() {
    let e = Invariants::from_nodes(&[1.0], &[], &[]).unwrap_err();
    assert!(e.to_string().contains("counts must agree"), "{e}");
    let e = Invariants::from_nodes(&[-1.0], &[Vec3::zeros()], &[Matrix3xX::zeros(2)]).unwrap_err();
    assert!(e.to_string().contains("node 0: mass"), "{e}");
    let inv = Invariants::from_nodes(&[1.0], &[Vec3::zeros()], &[Matrix3xX::zeros(2)]).unwrap();
    let e = inv
        .mass_matrix(&Mat3::identity(), &DVector::zeros(3))
        .unwrap_err();
    assert!(e.to_string().contains("length 3"), "{e}");
}
