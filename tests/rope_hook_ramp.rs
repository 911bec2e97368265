//! `hook_ramp_time` (issue #21): the hook reaches a new velocity command linearly over the ramp
//! (its height against the integral of that profile, by hand), a ramp of 0 steps the velocity,
//! and with the integrator's history kept across continuous commands a command changing every
//! communication step still follows a tight-tolerance reference.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::RopeBlockModel;

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info().port_by_name(name).unwrap().vr
}

fn started(values: &[(&str, f64)]) -> RopeBlockModel {
    let mut m = RopeBlockModel::new();
    let seg = vr(&m, "segments");
    m.set_integer(seg, 20).unwrap();
    for (n, v) in values {
        let r = vr(&m, n);
        m.set_real(r, *v).unwrap();
    }
    m.initialize(0.0).unwrap();
    m
}

/// Hook height [m] after commanding `v` [m/s] at 0.5 s, at 0.05 s steps up to `t_end` [s].
fn hook_rise(ramp: f64, v: f64, t_end: f64) -> (f64, f64) {
    let mut m = started(&[("hook_ramp_time", ramp)]);
    let (z, vz) = (vr(&m, "hook0_z"), vr(&m, "hook0_vz"));
    let z0 = m.get_real(z).unwrap();
    let h = 0.05;
    let n = (t_end / h).round() as usize;
    for k in 0..n {
        if k == 10 {
            m.set_real(vz, v).unwrap();
        }
        m.do_step(k as f64 * h, h).unwrap();
    }
    (m.get_real(z).unwrap() - z0, m.time())
}

#[test]
fn the_hook_follows_the_commanded_ramp() {
    let v = 0.2;
    for ramp in [0.0, 0.5, 1.2] {
        let (rise, t) = hook_rise(ramp, v, 3.0);
        // velocity linear from 0 to v over `ramp` from 0.5 s, then held
        let hand = v * (t - 0.5 - 0.5 * ramp);
        println!("ramp {ramp} s: hook rose {rise:.9} m by {t} s, by hand {hand:.9} m");
        assert!(
            (rise - hand).abs() < 1e-9,
            "ramp {ramp}: {rise} against {hand}"
        );
    }
}

/// Hook load [N] and block height [m] per step with a sine velocity command, changed every step.
fn sine_run(rtol: f64) -> Vec<(f64, f64)> {
    let mut m = started(&[("rtol", rtol)]);
    let (vz, load, z) = (vr(&m, "hook0_vz"), vr(&m, "hook0_load"), vr(&m, "block_z"));
    let h = 0.05;
    let mut out = Vec::new();
    for k in 0..80 {
        let t = k as f64 * h;
        m.set_real(vz, 0.3 * (std::f64::consts::PI * t / 3.0).sin())
            .unwrap();
        m.do_step(t, h).unwrap();
        out.push((m.get_real(load).unwrap(), m.get_real(z).unwrap()));
    }
    out
}

#[test]
fn commands_changing_every_step_follow_a_tight_reference() {
    let run = sine_run(3e-5);
    let reference = sine_run(1e-8);
    let weight = reference[0].0;
    let (mut dl, mut dz) = (0.0f64, 0.0f64);
    for (a, b) in run.iter().zip(&reference) {
        dl = dl.max((a.0 - b.0).abs());
        dz = dz.max((a.1 - b.1).abs());
    }
    println!(
        "sine command, 4 s: hook load within {dl:.1} N ({:.2e} of the load), block height within {dz:.2e} m",
        dl / weight
    );
    assert!(dl < 1e-3 * weight && dz < 1e-4);
}
