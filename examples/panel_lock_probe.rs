use mbcosim::scene::panel_lock::*;
fn main() {
    let mut p = PanelLockParams::default();
    if let Ok(s) = std::env::var("INTEG") {
        p.integrator = match s.as_str() {
            "ga" => mbcosim::integrator::IntegratorKind::GenAlpha,
            "rk" => mbcosim::integrator::IntegratorKind::Dopri5,
            _ => p.integrator,
        };
    }
    let mut s = PanelLock::new(p).unwrap();
    let t0 = std::time::Instant::now();
    let mut e0 = None;
    for k in 0..=600 {
        let t = 0.1 * k as f64;
        if let Err(e) = s.advance_to(t) {
            println!("ERR {e}");
            break;
        }
        let o = s.outputs();
        let bal = o.kinetic + o.potential + o.dissipated - o.input_work;
        let e0v = *e0.get_or_insert(bal);
        if k % 50 == 0 {
            let a: Vec<String> = o
                .hinges
                .iter()
                .map(|h| {
                    format!(
                        "{:.1}{}",
                        h.angle.to_degrees(),
                        if h.engaged { "*" } else { "" }
                    )
                })
                .collect();
            println!(
                "t={t:5.1} angles {:?} F={:?} tipv={:.4} KE={:.4} bal={:.3e}",
                a,
                o.hinges
                    .iter()
                    .map(|h| (h.peak_force * 10.0).round() / 10.0)
                    .collect::<Vec<_>>(),
                o.tip_normal_velocity,
                o.kinetic,
                bal - e0v
            );
        }
    }
    let o = s.outputs();
    println!(
        "lock times {:?}",
        o.hinges.iter().map(|h| h.lock_time).collect::<Vec<_>>()
    );
    println!("cpu {:?} stats {:?}", t0.elapsed(), s.sim.stats());
}
