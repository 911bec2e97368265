//! Optional bending stiffness of the lumped rope: a discrete hinge at every interior material node.
//!
//! At node `i` with neighbours `i-1`, `i+1`, unit segment directions `u1 = (p_i - p_{i-1})/l1` and
//! `u2 = (p_{i+1} - p_i)/l2`, the energy is `V = k (1 - u1 . u2)` with `k = EI / L_nom`
//! (`EI` [N m^2], `L_nom` [m] the nominal segment length): for a small kink angle `phi` it is
//! `EI phi^2 / (2 L_nom)`, the beam energy `EI kappa^2 L / 2` of curvature `kappa = phi / L`.
//! Contact nodes carry no bending term: a rope bends sharply over a plate edge.

use crate::math::{Mat3, Vec3};

/// Energy [J], forces on the three points [N], and `dF_a/dp_b` [N/m] (row-major 3x3 blocks).
#[derive(Debug, Clone, Copy)]
pub struct Hinge {
    pub energy: f64,
    pub force: [Vec3; 3],
    pub jac: [[Mat3; 3]; 3],
}

/// Evaluates the bending hinge of stiffness `k` [N m] at points `p0, p1, p2`.
pub fn hinge(k: f64, p0: &Vec3, p1: &Vec3, p2: &Vec3) -> Hinge {
    let d1 = p1 - p0;
    let d2 = p2 - p1;
    let l1 = d1.norm().max(1e-12);
    let l2 = d2.norm().max(1e-12);
    let u1 = d1 / l1;
    let u2 = d2 / l2;
    let c = u1.dot(&u2);
    let pr1 = Mat3::identity() - u1 * u1.transpose();
    let pr2 = Mat3::identity() - u2 * u2.transpose();
    let g1 = pr1 * u2 / l1;
    let g2 = pr2 * u1 / l2;
    let h11 = -(u1 * g1.transpose() + g1 * u1.transpose() + pr1 * (c / l1)) / l1;
    let h22 = -(u2 * g2.transpose() + g2 * u2.transpose() + pr2 * (c / l2)) / l2;
    let h12 = pr1 * pr2 / (l1 * l2);
    let h21 = h12.transpose();
    let s1 = [-1.0, 1.0, 0.0];
    let s2 = [0.0, -1.0, 1.0];
    let mut jac = [[Mat3::zeros(); 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            jac[a][b] = (h11 * (s1[a] * s1[b])
                + h12 * (s1[a] * s2[b])
                + h21 * (s2[a] * s1[b])
                + h22 * (s2[a] * s2[b]))
                * k;
        }
    }
    Hinge {
        energy: k * (1.0 - c),
        force: [-g1 * k, (g1 - g2) * k, g2 * k],
        jac,
    }
}
