//! Shared builders for the integration tests.
#![allow(dead_code)]

pub mod chain3d;
pub mod flex;
pub mod jacobian;
pub mod outputs;
pub mod packed;
pub mod panel_lock;

use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, Model, ModelBuilder};

pub const G: f64 = 9.81;

/// A 1 kg particle at height `z0` [m] moving along z at `vz0` [m/s] above the plane z = 0, with
/// the contact law `law`; gravity `G` along -z when `gravity`.
pub fn particle_on_floor(
    law: mbcosim::contact::ContactLaw,
    z0: f64,
    vz0: f64,
    gravity: bool,
) -> Model {
    use mbcosim::effect::plane_contact::{PlaneContact, PlaneContacts};
    let mut b = ModelBuilder::new();
    if gravity {
        b.set_gravity(Some(Vec3::new(0.0, 0.0, -G))).unwrap();
    }
    let p = b
        .add_particle(
            "ball",
            1.0,
            Vec3::new(0.0, 0.0, z0),
            Vec3::new(0.0, 0.0, vz0),
        )
        .unwrap();
    b.add_force_effect(std::sync::Arc::new(PlaneContacts {
        elements: vec![PlaneContact {
            name: "floor".into(),
            point: Frame::new(p, Vec3::zeros()),
            normal: Vec3::z(),
            offset: 0.0,
            law,
        }],
    }));
    b.build().unwrap()
}

/// Names of the force effects a model assembled.
pub fn force_effect_names(model: &Model) -> Vec<String> {
    model.forces.iter().map(|f| f.name().to_string()).collect()
}

/// Inertia of a thin rod of `mass` and `length` along the body x axis, with a small radius.
pub fn rod_inertia(mass: f64, length: f64) -> Mat3 {
    let r = 0.01;
    let ixx = 0.5 * mass * r * r;
    let iyy = mass * (3.0 * r * r + length * length) / 12.0;
    Mat3::from_diagonal(&Vec3::new(ixx, iyy, iyy))
}

/// A point-like pendulum bob: rod of length `l` from a ground pivot at the origin, released at
/// `angle0` [rad] from the downward vertical, swinging in the x-y plane (gravity -y), pivot axis z.
/// The bob has mass 1 kg and a tiny inertia, so the period is that of the mathematical pendulum.
pub fn simple_pendulum(l: f64, angle0: f64) -> Model {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let pos = Vec3::new(l * angle0.sin(), -l * angle0.cos(), 0.0);
    let tiny = Mat3::from_diagonal(&Vec3::new(1e-6, 1e-6, 1e-6));
    let bob = b
        .add_rigid_body("bob", 1.0, tiny, BodyInit::at(pos))
        .unwrap();
    // joint frame on the bob at the pivot, expressed in the bob frame (identity orientation)
    b.add_joint(
        "pivot",
        JointKind::Revolute,
        Frame::new(BodyId::GROUND, Vec3::zeros()),
        Frame::new(bob, -pos),
    )
    .unwrap();
    b.build().unwrap()
}

/// A double pendulum of two rods (1 m, 1 kg each) with revolute joints about z, gravity -y,
/// released from angles `a1`, `a2` [rad] (absolute, from the downward vertical).
pub fn double_pendulum(a1: f64, a2: f64) -> Model {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let l = 1.0;
    let dir = |a: f64| Vec3::new(a.sin(), -a.cos(), 0.0);
    let rot = |a: f64| Quat::from_axis_angle(&Vec3::z_axis(), a - std::f64::consts::FRAC_PI_2);
    let c1 = dir(a1) * 0.5 * l;
    let c2 = dir(a1) * l + dir(a2) * 0.5 * l;
    let r1 = b
        .add_rigid_body(
            "rod1",
            1.0,
            rod_inertia(1.0, l),
            BodyInit::at(c1).oriented(rot(a1)),
        )
        .unwrap();
    let r2 = b
        .add_rigid_body(
            "rod2",
            1.0,
            rod_inertia(1.0, l),
            BodyInit::at(c2).oriented(rot(a2)),
        )
        .unwrap();
    let half = Vec3::new(0.5 * l, 0.0, 0.0);
    b.add_joint(
        "j1",
        JointKind::Revolute,
        Frame::new(BodyId::GROUND, Vec3::zeros()),
        Frame::new(r1, -half),
    )
    .unwrap();
    b.add_joint(
        "j2",
        JointKind::Revolute,
        Frame::new(r1, half),
        Frame::new(r2, -half),
    )
    .unwrap();
    b.build().unwrap()
}

/// Distance [m] between two points of the x-y plane.
pub fn planar_distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The x-y position [m] at `t_end` [s] of the point `local` (body frame) of the rigid body whose
/// coordinates start at `offset` in `q`, simulated by `kind` at `rtol` (atol = rtol), or the
/// failure's message.
pub fn simulated_planar_point(
    model: &Model,
    (offset, local): (usize, Vec3),
    kind: mbcosim::integrator::IntegratorKind,
    rtol: f64,
    t_end: f64,
) -> Result<[f64; 2], String> {
    let s = mbcosim::integrator::Settings {
        rtol,
        atol: rtol,
        max_steps: 10_000_000,
        ..mbcosim::integrator::Settings::default()
    };
    let mut sim =
        mbcosim::sim::Simulation::new(model.clone(), kind, s, 0.0).map_err(|e| format!("{e:?}"))?;
    sim.advance_to(t_end).map_err(|e| format!("{e:?}"))?;
    let q = &sim.state.q;
    let p = Vec3::new(q[offset], q[offset + 1], q[offset + 2])
        + mbcosim::model::kinematics::quat_at(q, offset + 3) * local;
    Ok([p.x, p.y])
}

/// The planar rod chain of the accuracy suite: `n` rods (1 m, 1 kg, inertia diag(1e-4, 1/12,
/// 1/12) kg m^2) hinged about z end to end from the origin, released at rest along +x, gravity
/// `G` along -y.
pub fn planar_rod_chain(n: usize) -> Model {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let inertia = Mat3::from_diagonal(&Vec3::new(1e-4, 1.0 / 12.0, 1.0 / 12.0));
    let half = Vec3::new(0.5, 0.0, 0.0);
    let mut prev = (BodyId::GROUND, Vec3::zeros());
    for k in 0..n {
        let id = b
            .add_rigid_body(
                &format!("rod{k}"),
                1.0,
                inertia,
                BodyInit::at(Vec3::new(k as f64 + 0.5, 0.0, 0.0)),
            )
            .unwrap();
        b.add_joint(
            &format!("hinge{k}"),
            JointKind::Revolute,
            Frame::new(prev.0, prev.1),
            Frame::new(id, -half),
        )
        .unwrap();
        prev = (id, half);
    }
    b.build().unwrap()
}

/// Largest absolute difference of two equally long slices.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
