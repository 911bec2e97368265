//! The dense O(m^2) evaluation of a slipping chain that `slip::eval_chain` replaced (issue #19),
//! kept only as the test reference of the structured one: every tension's gradient is built as a
//! full row over the chain's points, every Jacobian block from those rows.

use super::slip::{ChainEval, SlipNode, edge_ratio};
use crate::math::{Mat3, Vec3};

/// Evaluates a chain of `m = pos.len() - 1 >= 2` segments with the slipping interior nodes
/// `nodes` (length `m - 1`), total rest length `rest_total` [m] and axial stiffness `ea` [N].
/// `vel` are the point velocities [m/s] (for the rate of material flow).
pub fn eval_chain_dense(
    pos: &[Vec3],
    vel: &[Vec3],
    nodes: &[SlipNode],
    rest_total: f64,
    ea: f64,
) -> ChainEval {
    let np = pos.len();
    let m = np - 1;
    debug_assert!(m >= 2 && nodes.len() == m - 1 && vel.len() == np);
    let mut u = vec![Vec3::zeros(); m];
    let mut l = vec![0.0; m];
    let mut proj = vec![Mat3::zeros(); m];
    for j in 0..m {
        let d = pos[j + 1] - pos[j];
        l[j] = d.norm().max(1e-12);
        u[j] = d / l[j];
        proj[j] = Mat3::identity() - u[j] * u[j].transpose();
    }
    // log-ratios and their gradients w.r.t. the three points around each node
    let mut lam = vec![0.0; m]; // lam[i] for node i (index 0 unused)
    let mut dlam: Vec<[Vec3; 3]> = vec![[Vec3::zeros(); 3]; m];
    for i in 1..m {
        let nd = nodes[i - 1];
        let c = u[i - 1].dot(&u[i]).clamp(-1.0, 1.0);
        let theta = c.acos();
        let (r, dlnr) = edge_ratio(nd.mu, theta);
        lam[i] = nd.direction * r.ln();
        let sin = (1.0 - c * c).max(0.0).sqrt();
        if sin > 1e-9 && dlnr != 0.0 {
            let k = nd.direction * dlnr * (-1.0 / sin);
            let g1 = proj[i - 1] * u[i] / l[i - 1];
            let g2 = proj[i] * u[i - 1] / l[i];
            dlam[i] = [-g1 * k, (g1 - g2) * k, g2 * k];
        }
    }
    let mut cj = vec![1.0; m];
    for j in 1..m {
        cj[j] = cj[j - 1] * lam[j].exp();
    }
    let sum_l: f64 = l.iter().sum();
    let mut out = ChainEval {
        tension: vec![0.0; m],
        rest: vec![0.0; m],
        length: l.clone(),
        rest_rate: vec![0.0; m],
        force: vec![Vec3::zeros(); np],
        jac: vec![Mat3::zeros(); np * np],
        ..Default::default()
    };
    if sum_l <= rest_total {
        for (r, lj) in out.rest[..m].iter_mut().zip(&l[..m]) {
            *r = lj * rest_total / sum_l;
        }
        return out;
    }
    // T0 by Newton from zero (monotone for this convex decreasing function); the residual is
    // resolved to round-off of the lengths, which the Newton steps reach in a few iterations
    let mut t0 = 0.0;
    let floor = 4.0 * f64::EPSILON * sum_l;
    for _ in 0..60 {
        let mut f = -rest_total;
        let mut df = 0.0;
        for j in 0..m {
            let w = 1.0 / (1.0 + cj[j] * t0 / ea);
            f += l[j] * w;
            df -= l[j] * cj[j] / ea * w * w;
        }
        if f.abs() <= floor {
            break;
        }
        t0 -= f / df;
    }
    let w: Vec<f64> = (0..m).map(|j| 1.0 / (1.0 + cj[j] * t0 / ea)).collect();
    let dd: f64 = (0..m).map(|j| l[j] * cj[j] * w[j] * w[j] / ea).sum();
    // dT0/dlam_i = -(sum_{j>=i} l_j c_j w_j^2 T0/EA) / Dd
    let mut dt0_dlam = vec![0.0; m];
    let mut acc = 0.0;
    for i in (1..m).rev() {
        acc += l[i] * cj[i] * w[i] * w[i] * t0 / ea;
        dt0_dlam[i] = -acc / dd;
    }
    // gradients of the elastic tensions and rest lengths w.r.t. the points
    let mut dte = vec![Vec3::zeros(); m * np];
    for j in 0..m {
        for i in 0..m {
            let g = cj[j] * w[i] / dd;
            dte[j * np + i + 1] += u[i] * g;
            dte[j * np + i] -= u[i] * g;
        }
        for i in 1..m {
            let g = cj[j] * (dt0_dlam[i] + if i <= j { t0 } else { 0.0 });
            if g != 0.0 {
                for (k, a) in [i - 1, i, i + 1].into_iter().enumerate() {
                    dte[j * np + a] += dlam[i][k] * g;
                }
            }
        }
    }
    for j in 0..m {
        let te = cj[j] * t0;
        let rest = l[j] * w[j];
        out.rest[j] = rest;
        let eps = l[j] / rest - 1.0;
        out.energy += 0.5 * ea * eps * eps * rest;
        // dL_j/dp_a = w_j dl_j/dp_a - l_j w_j^2 / EA dTe_j/dp_a
        let mut lrate = 0.0;
        for a in 0..np {
            let mut g = -dte[j * np + a] * (l[j] * w[j] * w[j] / ea);
            if a == j + 1 {
                g += u[j] * w[j];
            } else if a == j {
                g -= u[j] * w[j];
            }
            lrate += g.dot(&vel[a]);
        }
        out.rest_rate[j] = lrate;
        out.friction_power += te * (1.0 + 0.5 * eps) * lrate;
        let t = te;
        if t <= 0.0 {
            continue;
        }
        out.tension[j] = t;
        for a in 0..np {
            let blk = u[j] * dte[j * np + a].transpose();
            out.jac[j * np + a] += blk;
            out.jac[(j + 1) * np + a] -= blk;
        }
        let geo = proj[j] * (t / l[j]);
        out.jac[j * np + j + 1] += geo;
        out.jac[j * np + j] -= geo;
        out.jac[(j + 1) * np + j + 1] -= geo;
        out.jac[(j + 1) * np + j] += geo;
        out.force[j] += u[j] * t;
        out.force[j + 1] -= u[j] * t;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::eval_chain_dense;
    use crate::math::{Mat3, Vec3};
    use crate::rope::slip::{ChainEval, Derivatives, SlipNode, eval_chain};

    /// A small deterministic generator (64-bit LCG, top bits) of uniform numbers in [0, 1).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn vec(&mut self, scale: f64) -> Vec3 {
            Vec3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * (2.0 * scale)
        }
    }

    /// A random taut chain of `m` segments wound around a circle of radius 0.5 m (turn per node
    /// `span / (m - 1)`), points jittered in 3D by 1 % of a chord, with random slip directions
    /// and coefficients (some frictionless), stretched to `strain`.
    fn random_chain(
        rng: &mut Lcg,
        m: usize,
        span: f64,
        strain: f64,
    ) -> (Vec<Vec3>, Vec<Vec3>, Vec<SlipNode>, f64) {
        let r = 0.5;
        let d = span / (m - 1).max(1) as f64;
        let chord = 2.0 * r * (0.5 * d).sin();
        let pos: Vec<Vec3> = (0..=m)
            .map(|j| {
                let a = d * (j as f64 - 0.5);
                Vec3::new(r * a.cos(), r * a.sin(), 0.0) + rng.vec(0.01 * chord)
            })
            .collect();
        let vel: Vec<Vec3> = (0..=m).map(|_| rng.vec(0.3)).collect();
        let nodes: Vec<SlipNode> = (1..m)
            .map(|_| SlipNode {
                direction: if rng.next() < 0.5 { -1.0 } else { 1.0 },
                mu: if rng.next() < 0.1 {
                    0.0
                } else {
                    0.4 * rng.next()
                },
            })
            .collect();
        let len: f64 = pos.windows(2).map(|p| (p[1] - p[0]).norm()).sum();
        (pos, vel, nodes, len / (1.0 + strain))
    }

    fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
        v.fold(0.0, |a, x| a.max(x.abs()))
    }

    /// The entries of a list of vectors or matrices, one after another.
    fn flat<const R: usize, const C: usize>(v: &[nalgebra::SMatrix<f64, R, C>]) -> Vec<f64> {
        v.iter().flat_map(|x| x.iter().copied()).collect()
    }

    /// Largest difference between two evaluations relative to each quantity's scale.
    fn difference(a: &ChainEval, b: &ChainEval) -> [f64; 5] {
        let rel = |x: &[f64], y: &[f64]| {
            let s = max_abs(x.iter().copied()).max(1e-300);
            max_abs(x.iter().zip(y).map(|(p, q)| p - q)) / s
        };
        let (fa, fb) = (flat(&a.force), flat(&b.force));
        let (ja, jb) = (flat(&a.jac), flat(&b.jac));
        [
            rel(&a.tension, &b.tension),
            rel(&a.rest, &b.rest),
            rel(&a.rest_rate, &b.rest_rate),
            rel(&fa, &fb),
            rel(&ja, &jb),
        ]
    }

    #[test]
    fn structured_chain_equals_the_dense_reference_on_random_chains() {
        let mut rng = Lcg(19);
        let mut worst = [0.0f64; 5];
        let mut cases = 0;
        for &m in &[2usize, 3, 5, 9, 33, 65, 130] {
            for &(span, strain) in &[(0.3, 1e-4), (std::f64::consts::PI, 3e-3), (5.0, 1e-6)] {
                for _ in 0..3 {
                    let (pos, vel, nodes, rest) = random_chain(&mut rng, m, span, strain);
                    let ea = 7.5e7;
                    let new = eval_chain(&pos, &vel, &nodes, rest, ea, Derivatives::Dense);
                    let old = eval_chain_dense(&pos, &vel, &nodes, rest, ea);
                    assert!(new.tension.iter().all(|t| *t > 0.0), "chain not taut");
                    let d = difference(&new, &old);
                    for (w, x) in worst.iter_mut().zip(d) {
                        *w = w.max(x);
                    }
                    let e = (new.energy - old.energy).abs() / old.energy;
                    // the friction power is a sum of flows that cancel where mu is small
                    let flow: f64 = (0..m)
                        .map(|j| (old.tension[j] * old.rest_rate[j]).abs())
                        .sum();
                    let p = (new.friction_power - old.friction_power).abs() / flow;
                    assert!(
                        e < 1e-11 && p < 1e-9,
                        "m {m}: energy {e:.2e}, power {p:.2e}"
                    );
                    // without the Jacobian: the same forces, bit for bit, and no blocks
                    let lean = eval_chain(&pos, &vel, &nodes, rest, ea, Derivatives::None);
                    assert!(lean.jac.is_empty() && lean.force == new.force);
                    cases += 1;
                }
            }
        }
        println!(
            "{cases} chains: tension {:.1e}, rest {:.1e}, rest rate {:.1e}, force {:.1e}, jacobian {:.1e}",
            worst[0], worst[1], worst[2], worst[3], worst[4]
        );
        // round-off of sums over up to 130 segments (the rates and the Jacobian are differences
        // of terms of the size of the tensions)
        assert!(worst[..2].iter().all(|x| *x < 1e-13), "{worst:?}");
        assert!(worst[2..].iter().all(|x| *x < 1e-12), "{worst:?}");
    }

    /// The bordered form's factors, multiplied out, plus its geometric blocks give the Jacobian
    /// of the old dense evaluation (which formed every block from full gradient rows).
    #[test]
    fn bordered_factors_multiply_out_to_the_dense_jacobian() {
        let mut rng = Lcg(23);
        let mut worst = 0.0f64;
        for &m in &[2usize, 3, 8, 33, 130] {
            for &(span, strain) in &[(0.3, 1e-4), (std::f64::consts::PI, 3e-3)] {
                let (pos, vel, nodes, rest) = random_chain(&mut rng, m, span, strain);
                let ea = 7.5e7;
                let old = eval_chain_dense(&pos, &vel, &nodes, rest, ea);
                let ev = eval_chain(&pos, &vel, &nodes, rest, ea, Derivatives::Bordered);
                let br = ev.border.as_ref().expect("taut chain has factors");
                let np = m + 1;
                let mut jac = ev.jac.clone();
                for j in 0..m {
                    let mut h = Vec3::zeros();
                    // h_jb = sum_{1<=i<=j} dlam_i/dp_b, built point by point
                    for b in 0..np {
                        h.fill(0.0);
                        for i in 1..=j.min(m - 1) {
                            if b + 1 >= i && b + 1 - i < 3 {
                                h += br.dlam[i][b + 1 - i];
                            }
                        }
                        let blk = br.uc[j] * (br.g[b] + h * br.t0).transpose();
                        jac[j * np + b] += blk;
                        jac[(j + 1) * np + b] -= blk;
                    }
                }
                let scale = max_abs(flat(&old.jac).into_iter());
                let d = max_abs(flat(&jac).iter().zip(flat(&old.jac)).map(|(a, b)| a - b));
                worst = worst.max(d / scale);
                assert_eq!(
                    ev.force,
                    eval_chain(&pos, &vel, &nodes, rest, ea, Derivatives::None).force
                );
            }
        }
        println!("bordered factors against the dense Jacobian: {worst:.1e}");
        assert!(worst < 1e-12, "{worst:.2e}");
    }

    #[test]
    fn slack_chain_equals_the_dense_reference() {
        let mut rng = Lcg(7);
        let (pos, vel, nodes, rest) = random_chain(&mut rng, 6, 1.0, -1e-3);
        let new = eval_chain(&pos, &vel, &nodes, rest, 7.5e7, Derivatives::Dense);
        let old = eval_chain_dense(&pos, &vel, &nodes, rest, 7.5e7);
        assert!(new.tension.iter().all(|t| *t == 0.0));
        assert_eq!(new.rest, old.rest);
        assert!(new.jac.iter().all(|b| *b == Mat3::zeros()));
    }

    /// The structured Jacobian and material flow against central differences of the forces and
    /// rest lengths (independent of both implementations' derivative code).
    #[test]
    fn structured_chain_matches_finite_differences() {
        let mut rng = Lcg(3);
        for &m in &[3usize, 12, 40] {
            let (pos, vel, nodes, rest) = random_chain(&mut rng, m, 2.5, 2e-3);
            let ea = 7.5e7;
            let ev = eval_chain(&pos, &vel, &nodes, rest, ea, Derivatives::Dense);
            let np = m + 1;
            let h = 1e-7;
            let scale = max_abs(flat(&ev.jac).into_iter());
            let mut worst = 0.0f64;
            for b in 0..np {
                for c in 0..3 {
                    let (mut pp, mut pm) = (pos.clone(), pos.clone());
                    pp[b][c] += h;
                    pm[b][c] -= h;
                    let fp = eval_chain(&pp, &vel, &nodes, rest, ea, Derivatives::None).force;
                    let fm = eval_chain(&pm, &vel, &nodes, rest, ea, Derivatives::None).force;
                    for a in 0..np {
                        let fd = (fp[a] - fm[a]) / (2.0 * h);
                        let an = ev.jac[a * np + b].column(c).into_owned();
                        worst = worst.max((fd - an).amax() / scale);
                    }
                }
            }
            // material flow: d rest / dt along the velocities
            let ht = 1e-7;
            let shift =
                |s: f64| -> Vec<Vec3> { pos.iter().zip(&vel).map(|(p, v)| p + v * s).collect() };
            let rp = eval_chain(&shift(ht), &vel, &nodes, rest, ea, Derivatives::None).rest;
            let rm = eval_chain(&shift(-ht), &vel, &nodes, rest, ea, Derivatives::None).rest;
            let rate_scale = max_abs(ev.rest_rate.iter().copied());
            let rate_err = max_abs((0..m).map(|j| (rp[j] - rm[j]) / (2.0 * ht) - ev.rest_rate[j]))
                / rate_scale;
            println!("m = {m}: jacobian FD rel err {worst:.2e}, rest rate {rate_err:.2e}");
            assert!(
                worst < 1e-5 && rate_err < 1e-5,
                "m {m}: {worst:.2e}, {rate_err:.2e}"
            );
        }
    }
}
