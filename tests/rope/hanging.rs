//! Hanging ropes: the catenary between two points (shape and tensions, convergence order in N),
//! the first three pendulum modes of a chain hanging from one end (Bessel zeros), and a block
//! bouncing on a vertical rope (x tan x = m_rope / M_block).

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::Vec3;
use mbcosim::rope::{HookInit, RopeProps};
use mbcosim::scene::rope_block::statics;
use mbcosim::scene::rope_block::{
    ContactSettings, EndSpec, LoadSpec, NodeSpec, RopeBlockSim, RopeSpec, Structure,
};

const G: f64 = 9.81;

fn no_contact() -> ContactSettings {
    ContactSettings {
        detect: false,
        ..Default::default()
    }
}

fn rope(props: RopeProps, start: EndSpec, end: EndSpec, pts: &[Vec3], rest: &[f64]) -> RopeSpec {
    let n = pts.len();
    let mut sigma = vec![0.0];
    for r in rest {
        sigma.push(sigma.last().unwrap() + r);
    }
    let nodes = (0..n)
        .map(|i| NodeSpec {
            mass: props.mass_per_length * 0.5 * (rest[i] + rest[i + 1]),
            sigma: sigma[i + 1],
            position: pts[i],
            velocity: Vec3::zeros(),
            contact: None,
        })
        .collect();
    RopeSpec {
        name: "rope".into(),
        props,
        nominal_segment: rest[0],
        start,
        end,
        sigma_start: 0.0,
        sigma_end: sigma[n + 1],
        nodes,
    }
}

/// Catenary parameter `a` [m] for span `s` and length `l`: 2 a sinh(s / 2a) = l.
fn catenary_a(span: f64, len: f64) -> f64 {
    let (mut lo, mut hi) = (0.1, 1e4);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 2.0 * mid * (0.5 * span / mid).sinh() > len {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Sag [m], horizontal tension [N] and end-link tension [N] of an `n`-link chain.
fn lumped_catenary(n: usize) -> (f64, f64, f64) {
    let (span, len, w) = (20.0, 22.0, 62.8);
    let props = RopeProps {
        mass_per_length: w / G,
        ea: 1e10,
        axial_damping: 0.0,
        friction: 0.0,
        ..RopeProps::default()
    };
    // start on a parabola of sag 4.2 m, nodes at equal arc length (every link taut)
    let para = |x: f64| 4.2 * ((x / 10.0).powi(2) - 1.0);
    let m = 20000;
    let mut arc = vec![0.0];
    for k in 0..m {
        let x0 = -10.0 + span * k as f64 / m as f64;
        let x1 = -10.0 + span * (k + 1) as f64 / m as f64;
        arc.push(arc[k] + ((x1 - x0).powi(2) + (para(x1) - para(x0)).powi(2)).sqrt());
    }
    let total = arc[m];
    let pts: Vec<Vec3> = (1..n)
        .map(|i| {
            let target = total * i as f64 / n as f64;
            let k = arc.partition_point(|&a| a < target).min(m);
            let x = -10.0 + span * k as f64 / m as f64;
            Vec3::new(x, 0.0, para(x))
        })
        .collect();
    let rest = vec![len / n as f64; n];
    let s = Structure {
        gravity: Some(Vec3::new(0.0, 0.0, -G)),
        hooks: vec![
            HookInit::at(Vec3::new(-10.0, 0.0, 0.0)),
            HookInit::at(Vec3::new(10.0, 0.0, 0.0)),
        ],
        ropes: vec![rope(props, EndSpec::Hook(0), EndSpec::Hook(1), &pts, &rest)],
        ..Default::default()
    };
    let mut sim = RopeBlockSim::new(
        s,
        IntegratorKind::GenAlpha,
        Settings::default(),
        no_contact(),
        0.0,
    )
    .unwrap();
    let rep = statics::solve(&mut sim, 1e-4, 200).unwrap();
    let p = sim.rope_points(0);
    let ten = sim.rope_tensions(0);
    let sag = -p.iter().map(|x| x.z).fold(f64::INFINITY, f64::min);
    let u = (p[1] - p[0]).normalize();
    let h = ten[0].0 * u.x;
    println!(
        "  n = {n}: {} Newton iterations, residual {:.1e} N",
        rep.iterations, rep.residual
    );
    (sag, h, ten[0].0)
}

#[test]
fn catenary_shape_and_tensions_converge() {
    let (w, len) = (62.8, 22.0);
    let a = catenary_a(20.0, len);
    let sag = a * ((10.0 / a).cosh() - 1.0);
    let h = w * a;
    let tmax = w * a * (10.0 / a).cosh();
    assert!((a - 13.099).abs() < 1e-3 && (sag - 4.006).abs() < 1e-3);
    // the published H = 822.4 N and T_max = 1073.9 N are rounded from a = 13.096 m
    assert!((h / 822.4 - 1.0).abs() < 5e-4 && (tmax / 1073.9 - 1.0).abs() < 5e-4);
    let mut prev: Option<(f64, f64, f64)> = None;
    for n in [8usize, 16, 32, 64] {
        let (s, hh, te) = lumped_catenary(n);
        // an end link's tension is the continuous tension at the link's middle
        let arc = 0.5 * len - 0.5 * len / n as f64;
        let t_link = w * (a * a + arc * arc).sqrt();
        let e = ((s - sag) / sag, (hh - h) / h, (te - t_link) / t_link);
        let order = prev.map(|p| {
            (
                (p.0 / e.0).abs().log2(),
                (p.1 / e.1).abs().log2(),
                (p.2 / e.2).abs().log2(),
            )
        });
        println!(
            "n = {n:2}: sag {s:.4} m ({:+.3e}), H {hh:.2} N ({:+.3e}), end link T {te:.2} N ({:+.3e}) vs T_max {tmax:.1} N; observed order {order:.2?}",
            e.0, e.1, e.2
        );
        if n == 16 {
            assert!(e.0.abs() < 0.005 && e.1.abs() < 0.005 && e.2.abs() < 0.005);
        }
        if let Some(o) = order {
            assert!(o.0 > 1.8 && o.1 > 1.8 && o.2 > 1.8, "order {o:?}");
        }
        prev = Some(e);
    }
}

/// Upward zero crossings of `x(t)` (linear interpolation), mean period [s].
fn mean_period(t: &[f64], x: &[f64]) -> (f64, usize) {
    let mut cross = Vec::new();
    for k in 1..x.len() {
        if x[k - 1] < 0.0 && x[k] >= 0.0 {
            cross.push(t[k - 1] + (t[k] - t[k - 1]) * (-x[k - 1]) / (x[k] - x[k - 1]));
        }
    }
    let n = cross.len() - 1;
    ((cross[n] - cross[0]) / n as f64, n)
}

/// A vertical rope of `n` segments hanging from a hook at the origin, with a bottom load of mass
/// `m_end`, initially at rest in its static state, displaced by `dx(s)` (s from the top [m],
/// world x) and moving with `vz(s)` (world z).
#[allow(clippy::too_many_arguments)]
fn hanging(
    props: RopeProps,
    len: f64,
    n: usize,
    m_end: f64,
    dx: &dyn Fn(f64) -> f64,
    vz: &dyn Fn(f64) -> f64,
) -> RopeBlockSim {
    let seg = len / n as f64;
    let rho = props.mass_per_length;
    // static tension of segment j (from the top): weight below its lower node
    let tension = |j: usize| G * (m_end + rho * seg * (n - 1 - j) as f64);
    // the lateral displacement keeps every segment at its static length (no axial excitation)
    let mut z = 0.0;
    let mut pts = Vec::new();
    let mut sigma = vec![0.0];
    for j in 0..n {
        let l = seg * (1.0 + tension(j) / props.ea);
        let dxj = dx(seg * (j + 1) as f64) - dx(seg * j as f64);
        z -= (l * l - dxj * dxj).sqrt();
        sigma.push(seg * (j + 1) as f64);
        if j + 1 < n {
            pts.push(Vec3::new(0.0, 0.0, z));
        }
    }
    let nodes: Vec<NodeSpec> = pts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let s = sigma[i + 1];
            NodeSpec {
                mass: rho * seg,
                sigma: s,
                position: p + Vec3::new(dx(s), 0.0, 0.0),
                velocity: Vec3::new(0.0, 0.0, vz(s)),
                contact: None,
            }
        })
        .collect();
    let s = Structure {
        gravity: Some(Vec3::new(0.0, 0.0, -G)),
        hooks: vec![HookInit::at(Vec3::zeros())],
        loads: vec![LoadSpec {
            name: "end".into(),
            mass: m_end,
            position: Vec3::new(dx(len), 0.0, z),
            velocity: Vec3::new(0.0, 0.0, vz(len)),
        }],
        ropes: vec![RopeSpec {
            name: "rope".into(),
            props,
            nominal_segment: seg,
            start: EndSpec::Hook(0),
            end: EndSpec::Load(0),
            sigma_start: 0.0,
            sigma_end: len,
            nodes,
        }],
        ..Default::default()
    };
    let settings = Settings {
        rtol: 1e-6,
        atol: 1e-9,
        h_max: 1e-3,
        ..Settings::default()
    };
    RopeBlockSim::new(s, IntegratorKind::GenAlpha, settings, no_contact(), 0.0).unwrap()
}

/// Bessel function J0 by its power series (|x| < 12 is plenty here).
fn j0(x: f64) -> f64 {
    let mut term = 1.0;
    let mut sum = 1.0;
    for k in 1..60 {
        term *= -(x * x / 4.0) / (k * k) as f64;
        sum += term;
    }
    sum
}

#[test]
fn hanging_chain_first_three_frequencies() {
    let zeros = [2.4048, 5.5201, 8.6537];
    let len = 10.0;
    let n = 50;
    let props = RopeProps {
        mass_per_length: 1.0,
        ea: 1e6,
        axial_damping: 1e3,
        friction: 0.0,
        ..RopeProps::default()
    };
    for (k, &jk) in zeros.iter().enumerate() {
        assert!(j0(jk).abs() < 1e-4);
        let f_ref = 0.5 * jk * (G / len).sqrt() / (2.0 * std::f64::consts::PI);
        // the k-th mode shape, J0(j_k sqrt(x / L)) with x from the free end
        let shape = move |s: f64| 0.01 * j0(jk * ((len - s).max(0.0) / len).sqrt());
        let mut sim = hanging(
            props,
            len,
            n,
            props.mass_per_length * len / n as f64 * 0.5,
            &shape,
            &|_| 0.0,
        );
        let periods = 3.0;
        let t_end = periods / f_ref;
        let dt = 0.005;
        // modal coordinate: the lateral displacement projected on the mode shape (mass weighted)
        let (mut ts, mut x) = (Vec::new(), Vec::new());
        let mut t = 0.0;
        while t < t_end {
            t += dt;
            sim.advance_to(t).unwrap();
            ts.push(t);
            let pts = sim.rope_points(0);
            let q: f64 = pts[1..]
                .iter()
                .enumerate()
                .map(|(i, p)| p.x * shape(len * (i + 1) as f64 / n as f64))
                .sum();
            x.push(q);
        }
        let (period, cycles) = mean_period(&ts, &x);
        let f = 1.0 / period;
        let rel = (f - f_ref) / f_ref;
        println!(
            "mode {}: {f:.4} Hz over {cycles} cycles (reference {f_ref:.4} Hz), rel err {rel:+.2e}, {} steps",
            k + 1,
            sim.sim.stats().steps
        );
        assert!(rel.abs() < 0.02);
    }
}

#[test]
fn block_bouncing_on_a_vertical_rope() {
    let len = 22.0;
    let props = RopeProps {
        axial_damping: 0.0,
        friction: 0.0,
        ..RopeProps::default()
    };
    let c = props.wave_speed();
    let m_rope = props.mass_per_length * len;
    for m_block in [2.0 * m_rope, 5.0e4] {
        let ratio = m_rope / m_block;
        // x tan x = m / M by Newton from the spring-mass estimate
        let mut x = ratio.sqrt();
        for _ in 0..50 {
            let f = x * x.tan() - ratio;
            let df = x.tan() + x / x.cos().powi(2);
            x -= f / df;
        }
        let f_ref = x * c / len / (2.0 * std::f64::consts::PI);
        // start in the first mode: velocity sin(x s / L) / sin(x) times 1 cm/s
        let shape = move |s: f64| -0.01 * (x * s / len).sin() / x.sin();
        let mut sim = hanging(props, len, 40, m_block, &|_| 0.0, &shape);
        let dt = 2e-4;
        let t_end = 6.0 / f_ref;
        let (mut ts, mut vs) = (Vec::new(), Vec::new());
        let mut t = 0.0;
        while t < t_end {
            t += dt;
            sim.advance_to(t).unwrap();
            sim.sync();
            ts.push(t);
            vs.push(sim.structure.loads[0].velocity.z);
        }
        let (period, cycles) = mean_period(&ts, &vs);
        let f = 1.0 / period;
        let rel = (f - f_ref) / f_ref;
        println!(
            "block {m_block:.0} kg on {m_rope:.0} kg of rope: x = {x:.5}, {f:.4} Hz over {cycles} cycles (reference {f_ref:.4} Hz), rel err {rel:+.2e}"
        );
        assert!(rel.abs() < 0.01);
    }
}
