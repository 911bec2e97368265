//! The step loops of all integrators (the three of the FMU enumeration and the joint-coordinate
//! ones) do not allocate once warmed up (dense and sparse Newton solves), measured with a
//! counting global allocator.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::*;
use mbcosim::sim::Simulation;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn chain(n: usize) -> Model {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -9.81, 0.0))).unwrap();
    let l = 0.1;
    let rot = Quat::from_axis_angle(&Vec3::z_axis(), -1.0);
    let dir = rot * Vec3::x();
    let inertia = Mat3::from_diagonal(&Vec3::new(1e-5, 1e-4, 1e-4));
    let half = Vec3::new(0.5 * l, 0.0, 0.0);
    let mut prev = (BodyId::GROUND, Vec3::zeros());
    for k in 0..n {
        let id = b
            .add_rigid_body(
                &format!("r{k}"),
                0.1,
                inertia,
                BodyInit::at(dir * (l * k as f64 + 0.5 * l)).oriented(rot),
            )
            .unwrap();
        b.add_joint(
            &format!("j{k}"),
            JointKind::Revolute,
            Frame::new(prev.0, prev.1),
            Frame::new(id, -half),
        )
        .unwrap();
        prev = (id, half);
    }
    b.build().unwrap()
}

#[test]
fn integrators_step_without_allocating() {
    for kind in IntegratorKind::ALL
        .into_iter()
        .chain(IntegratorKind::LIBRARY_ONLY)
    {
        for n in [2, 20] {
            // 2 bodies: 22 unknowns (dense LU); 20 bodies: 220 unknowns (sparse LU)
            let s = Settings {
                rtol: 1e-6,
                atol: 1e-8,
                h_max: 1e-3,
                ..Settings::default()
            };
            let mut sim = Simulation::new(chain(n), kind, s, 0.0).unwrap();
            sim.advance_to(0.1).unwrap();
            let (before, steps) = (ALLOCATIONS.load(Ordering::Relaxed), sim.stats().steps);
            sim.advance_to(0.2).unwrap();
            let count = ALLOCATIONS.load(Ordering::Relaxed) - before;
            let taken = sim.stats().steps - steps;
            assert!(taken >= 50, "{}: only {taken} steps", kind.name());
            let st = sim.stats();
            assert_eq!(
                count,
                0,
                "{} with {n} bodies: {count} allocations in {taken} steps (newton failures {}, rejected {})",
                kind.name(),
                st.newton_failures,
                st.rejected
            );
        }
    }
}
