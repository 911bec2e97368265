//! Linear translational spring-dampers between two body points.

use super::point_force::TwoPointForce;
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::math::{Mat3, Vec3};
use crate::model::SpringDamper;
use crate::model::kinematics::kin_of;

/// All translational spring-dampers of a model.
#[derive(Debug, Clone)]
pub struct SpringDampers {
    pub elements: Vec<SpringDamper>,
}

/// Length [m], unit direction a->b, rate [m/s], and the two-point force of one element.
fn evaluate<'a>(e: &SpringDamper, ctx: &'a EvalCtx) -> (f64, f64, TwoPointForce<'a>) {
    let ka = kin_of(ctx.kins, e.a.body);
    let kb = kin_of(ctx.kins, e.b.body);
    let d = kb.point(&e.b.origin) - ka.point(&e.a.origin);
    let d_dot = kb.point_velocity(&e.b.origin) - ka.point_velocity(&e.a.origin);
    let l = d.norm().max(1e-300);
    let n = d / l;
    let l_dot = n.dot(&d_dot);
    let tension = e.stiffness * (l - e.free_length) + e.damping * l_dot;
    let proj = Mat3::identity() - n * n.transpose();
    let kd = e.stiffness * n * n.transpose()
        + (tension / l) * proj
        + e.damping * n * (proj * d_dot / l).transpose();
    let cd = e.damping * n * n.transpose();
    let force: Vec3 = tension * n;
    let tp = TwoPointForce {
        a: ka,
        s_a: e.a.origin,
        b: kb,
        s_b: e.b.origin,
        force,
        kd,
        cd,
    };
    (l, l_dot, tp)
}

impl ForceEffect for SpringDampers {
    fn name(&self) -> &str {
        "spring-damper"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            evaluate(e, ctx).2.add_forces(f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            evaluate(e, ctx).2.add_jacobian(sink);
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let (l, _, _) = evaluate(e, ctx);
                0.5 * e.stiffness * (l - e.free_length).powi(2)
            })
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let (_, l_dot, _) = evaluate(e, ctx);
                e.damping * l_dot * l_dot
            })
            .sum()
    }
}
