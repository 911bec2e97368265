//! Mass properties of a block whose mass is spread uniformly over its shell plates (a thin-shell
//! model of a welded steel block: plates and stiffeners, no solid interior).
//!
//! For a triangle with vertices `a, b, c` and area `A`, with uniform areal density,
//! `int x dA = A (a + b + c) / 3` and `int x x^T dA = A/12 (a a^T + b b^T + c c^T + s s^T)`,
//! `s = a + b + c`. The inertia about the centre of mass follows from the parallel-axis theorem.

use super::ShellMesh;
use crate::math::{Mat3, Vec3};

/// Centre of mass [m] (mesh frame) and inertia tensor about it [kg m^2] of a shell of total mass
/// `mass` [kg] spread uniformly over the mesh area.
pub fn shell_mass_properties(mesh: &ShellMesh, mass: f64) -> (Vec3, Mat3) {
    let mut area = 0.0;
    let mut first = Vec3::zeros();
    let mut second = Mat3::zeros();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let ar = 0.5 * (b - a).cross(&(c - a)).norm();
        let s = a + b + c;
        area += ar;
        first += s * (ar / 3.0);
        second += (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose())
            * (ar / 12.0);
    }
    let rho = mass / area;
    let com = first / area;
    // second moment about the origin -> about the centre of mass
    let s_com = second * rho - com * com.transpose() * mass;
    let inertia = Mat3::identity() * s_com.trace() - s_com;
    (com, inertia)
}
