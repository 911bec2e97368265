//! A double pendulum of two 3D rigid rods through the public API (the README's example).
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder};
use mbcosim::sim::Simulation;

fn main() -> Result<(), String> {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -9.81, 0.0)))?;
    let rod = Mat3::from_diagonal(&Vec3::new(1e-4, 1.0 / 12.0, 1.0 / 12.0)); // 1 kg, 1 m along x
    let down = Quat::from_axis_angle(&Vec3::z_axis(), -0.3); // both rods start rotated 0.3 rad
    let (d, half) = (down * Vec3::x(), Vec3::new(0.5, 0.0, 0.0));
    let r1 = b.add_rigid_body("rod1", 1.0, rod, BodyInit::at(0.5 * d).oriented(down))?;
    let r2 = b.add_rigid_body("rod2", 1.0, rod, BodyInit::at(1.5 * d).oriented(down))?;
    b.add_joint(
        "shoulder",
        JointKind::Revolute,
        Frame::new(BodyId::GROUND, Vec3::zeros()),
        Frame::new(r1, -half),
    )?;
    b.add_joint(
        "elbow",
        JointKind::Revolute,
        Frame::new(r1, half),
        Frame::new(r2, -half),
    )?;
    let settings = Settings {
        rtol: 1e-8,
        atol: 1e-10,
        ..Settings::default()
    };
    let mut sim = Simulation::new(b.build()?, IntegratorKind::Bdf, settings, 0.0)?;
    for k in 1..=10 {
        sim.advance_to(0.2 * k as f64).map_err(|e| e.to_string())?;
        let e = sim.energy();
        println!(
            "t = {:.1} s  rod2 centre y = {:+.6} m  energy balance = {:.3e} J",
            sim.state.t,
            sim.state.q[8],
            e.balance()
        );
    }
    Ok(())
}
