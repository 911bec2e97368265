//! The spinning 3D chain of the chain-scaling benchmark (`examples/bench_core.rs chain3d`, which
//! includes this file) and of `tests/constraint_stiffness.rs`.

use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, Model, ModelBuilder};

/// A 3D chain of `n` rods (0.1 m, 0.1 kg, radius 1 cm) joined by spherical joints, hanging from
/// the ground at 0.5 rad from the vertical and spinning as one rigid line about the vertical
/// through the pivot at `sqrt(g / L)` for its length `L` (consistent initial velocities; the same
/// motion in units of the chain's own time scale at every `n`), gravity 9.81 m/s^2 along -y: a
/// conical swing that turns into 3D motion of every rod.
pub fn spinning_chain(n: usize) -> Model {
    let g = 9.81;
    let (m, l, r) = (0.1, 0.1, 0.01);
    let inertia = Mat3::from_diagonal(&Vec3::new(
        0.5 * m * r * r,
        m * (3.0 * r * r + l * l) / 12.0,
        m * (3.0 * r * r + l * l) / 12.0,
    ));
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -g, 0.0))).unwrap();
    let a = 0.5f64;
    let dir = Vec3::new(a.sin(), -a.cos(), 0.0);
    let rot = Quat::from_axis_angle(&Vec3::z_axis(), a - std::f64::consts::FRAC_PI_2);
    let spin = Vec3::new(0.0, (g / (n as f64 * l)).sqrt(), 0.0);
    let half = Vec3::new(0.5 * l, 0.0, 0.0);
    let mut prev = (BodyId::GROUND, Vec3::zeros());
    for k in 0..n {
        let c = dir * (l * k as f64 + 0.5 * l);
        // `moving` takes the angular velocity in the body frame
        let init = BodyInit::at(c)
            .oriented(rot)
            .moving(spin.cross(&c), rot.inverse() * spin);
        let id = b
            .add_rigid_body(&format!("rod{k}"), m, inertia, init)
            .unwrap();
        b.add_joint(
            &format!("s{k}"),
            JointKind::Spherical,
            Frame::new(prev.0, prev.1),
            Frame::new(id, -half),
        )
        .unwrap();
        prev = (id, half);
    }
    b.build().unwrap()
}
