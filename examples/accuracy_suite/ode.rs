//! The reference integrator: Gragg-Bulirsch-Stoer extrapolation (modified midpoint rule with
//! n = 2, 4, ..., 2K substeps, Aitken-Neville extrapolation in h^2), written here so that the
//! references share no code with the solver under test.
//!
//! Two uses: fixed macro steps refined by halving until two successive solutions agree (smooth
//! problems: chains, four-bar), and adaptive macro steps with sign-change events located by
//! bisection on the step length (the impacts, whose contact force is not smooth at onset and
//! separation).

/// Right-hand side `dy = f(t, y)`.
pub trait Rhs {
    fn eval(&self, t: f64, y: &[f64], dy: &mut [f64]);
}

impl<F: Fn(f64, &[f64], &mut [f64])> Rhs for F {
    fn eval(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self(t, y, dy)
    }
}

/// Extrapolation depth: K = 8 gives order 16.
pub const K: usize = 8;

/// One macro step of length `h` from `(t, y)`: the extrapolated solution and an estimate of its
/// error per component (difference of the last two diagonal tableau entries).
///
/// The midpoint recursion and the extrapolation work on increments `z - y`, not on `z`, and `y`
/// is added once at the end: the round-off of the tableau (whose weights amplify it) is then
/// relative to the increment `h f`, not to `y`, which keeps the reference's round-off floor
/// near 1e-15 over thousands of macro steps.
pub fn gbs_step(f: &dyn Rhs, t: f64, y: &[f64], h: f64) -> (Vec<f64>, Vec<f64>) {
    let n = y.len();
    let mut f0 = vec![0.0; n];
    f.eval(t, y, &mut f0);
    // table[k][j]: extrapolation of order 2(j+1) from the rows with 2(k-j+1) .. 2(k+1) substeps
    let mut table: Vec<Vec<Vec<f64>>> = Vec::with_capacity(K);
    let (mut d0, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut arg, mut dz) = (vec![0.0; n], vec![0.0; n]);
    for k in 0..K {
        let m = 2 * (k + 1);
        let s = h / m as f64;
        d0.fill(0.0);
        for i in 0..n {
            d1[i] = s * f0[i];
        }
        for step in 1..=m {
            for i in 0..n {
                arg[i] = y[i] + d1[i];
            }
            f.eval(t + step as f64 * s, &arg, &mut dz);
            if step == m {
                break;
            }
            for i in 0..n {
                d2[i] = d0[i] + 2.0 * s * dz[i];
            }
            std::mem::swap(&mut d0, &mut d1);
            std::mem::swap(&mut d1, &mut d2);
        }
        // Gragg's smoothing at the end of the row
        let first: Vec<f64> = (0..n).map(|i| 0.5 * (d1[i] + d0[i] + s * dz[i])).collect();
        let mut row = vec![first];
        for j in 1..=k {
            let ratio = (m as f64 / (2 * (k - j + 1)) as f64).powi(2) - 1.0;
            let prev_row = &table[k - 1];
            let cur = &row[j - 1];
            let next: Vec<f64> = (0..n)
                .map(|i| cur[i] + (cur[i] - prev_row[j - 1][i]) / ratio)
                .collect();
            row.push(next);
        }
        table.push(row);
    }
    let best: Vec<f64> = (0..n).map(|i| y[i] + table[K - 1][K - 1][i]).collect();
    let err = (0..n)
        .map(|i| (table[K - 1][K - 1][i] - table[K - 1][K - 2][i]).abs())
        .collect();
    (best, err)
}

/// Integrates from `t0` to `t1` in `steps` equal macro steps.
pub fn fixed(f: &dyn Rhs, y0: &[f64], t0: f64, t1: f64, steps: usize) -> Vec<f64> {
    let h = (t1 - t0) / steps as f64;
    let mut y = y0.to_vec();
    for k in 0..steps {
        y = gbs_step(f, t0 + k as f64 * h, &y, h).0;
    }
    y
}

/// A converged fixed-step solution: the output `out(y(t1))` at the finest resolution and the
/// difference to the previous resolution (its estimated error, conservative: at order 16 the
/// finer solution is far more accurate than the difference says).
pub struct Converged {
    pub output: Vec<f64>,
    pub estimated_error: f64,
    pub macro_steps: usize,
}

/// Halves the macro step, starting from `steps0`, until two successive outputs agree to `tol`
/// (Euclidean norm), or the change stops shrinking below 1e-11 (the round-off floor: the
/// estimate is then the larger of the last two changes), or `max_halvings` is reached.
pub fn converge(
    f: &dyn Rhs,
    y0: &[f64],
    t1: f64,
    steps0: usize,
    tol: f64,
    max_halvings: usize,
    out: &dyn Fn(&[f64]) -> Vec<f64>,
) -> Converged {
    let mut steps = steps0;
    let mut prev = out(&fixed(f, y0, 0.0, t1, steps));
    let (mut diff, mut last) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..max_halvings {
        steps *= 2;
        let cur = out(&fixed(f, y0, 0.0, t1, steps));
        diff = dist(&cur, &prev);
        if std::env::var_os("ACCURACY_SUITE_DEBUG").is_some() {
            eprintln!("reference: {steps} macro steps, change {diff:.2e}");
        }
        prev = cur;
        if diff < tol {
            break;
        }
        if diff < 1e-11 && diff > 0.25 * last {
            diff = diff.max(last);
            break;
        }
        last = diff;
    }
    Converged {
        output: prev,
        estimated_error: diff,
        macro_steps: steps,
    }
}

/// Converged fixed-step solutions at several times: outputs `out(y(t_k))` at `times`
/// (ascending, after 0), and the largest change over the times between the last two
/// resolutions (the estimated error).
pub struct ConvergedSamples {
    pub outputs: Vec<Vec<f64>>,
    pub estimated_error: f64,
    /// Macro steps over the whole interval at the finest resolution.
    pub macro_steps: usize,
}

/// [`converge`] over a grid of output times: each interval `[t_{k-1}, t_k]` gets
/// `ceil(steps0 (t_k - t_{k-1}) / t_last)` macro steps (at least one), all doubled per halving,
/// the state carried across the intervals; the change is the largest over the times. Same
/// stopping rule as [`converge`].
pub fn converge_samples(
    f: &dyn Rhs,
    y0: &[f64],
    times: &[f64],
    steps0: usize,
    tol: f64,
    max_halvings: usize,
    out: &dyn Fn(&[f64]) -> Vec<f64>,
) -> ConvergedSamples {
    let t_last = *times.last().expect("at least one output time");
    let mut per: Vec<usize> = {
        let mut prev = 0.0;
        times
            .iter()
            .map(|&t| {
                let n = ((steps0 as f64 * (t - prev) / t_last).ceil() as usize).max(1);
                prev = t;
                n
            })
            .collect()
    };
    let solve = |per: &[usize]| -> Vec<Vec<f64>> {
        let (mut y, mut t0) = (y0.to_vec(), 0.0);
        times
            .iter()
            .zip(per)
            .map(|(&t1, &n)| {
                y = fixed(f, &y, t0, t1, n);
                t0 = t1;
                out(&y)
            })
            .collect()
    };
    let mut prev = solve(&per);
    let (mut diff, mut last) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..max_halvings {
        per.iter_mut().for_each(|n| *n *= 2);
        let cur = solve(&per);
        diff = cur
            .iter()
            .zip(&prev)
            .map(|(a, b)| dist(a, b))
            .fold(0.0, f64::max);
        prev = cur;
        if diff < tol {
            break;
        }
        if diff < 1e-11 && diff > 0.25 * last {
            diff = diff.max(last);
            break;
        }
        last = diff;
    }
    ConvergedSamples {
        outputs: prev,
        estimated_error: diff,
        macro_steps: per.iter().sum(),
    }
}

/// Euclidean distance.
pub fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Adaptive integration with error control (`atol + rtol |y|` per component) from `(t, y)`
/// towards `t1`, stopping early at the first step end where `event(y) <= 0` (the event is
/// positive during the phase; only step ends are checked, so it may start at 0); the event time
/// is located by bisection on the length of that macro step to 1e-15 s. Returns the time
/// reached, the state (just past the event), and whether an event stopped it.
pub fn adaptive_until(
    f: &dyn Rhs,
    t: f64,
    y: &[f64],
    t1: f64,
    rtol: f64,
    atol: f64,
    event: &dyn Fn(&[f64]) -> f64,
) -> (f64, Vec<f64>, bool) {
    let (mut t, mut y) = (t, y.to_vec());
    let mut h = ((t1 - t) / 100.0).min(1e-4);
    while t < t1 {
        let hh = h.min(t1 - t);
        let (yn, err) = gbs_step(f, t, &y, hh);
        let e = err
            .iter()
            .zip(&yn)
            .map(|(e, v)| e / (atol + rtol * v.abs()))
            .fold(0.0, f64::max);
        let factor = (0.9 * e.max(1e-30).powf(-1.0 / (2 * K - 1) as f64)).clamp(0.2, 4.0);
        if e > 1.0 {
            h = hh * factor;
            continue;
        }
        if event(&yn) <= 0.0 {
            // bisection on the step length: the state reached from (t, y) in one macro step
            let (mut lo, mut hi) = (0.0, hh);
            while hi - lo > 1e-15 {
                let mid = 0.5 * (lo + hi);
                let ym = gbs_step(f, t, &y, mid).0;
                if event(&ym) <= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let ye = gbs_step(f, t, &y, hi).0;
            return (t + hi, ye, true);
        }
        t += hh;
        y = yn;
        h = hh * factor;
    }
    (t, y, false)
}
