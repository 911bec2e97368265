//! Lagrange weights on BDF's variable grid.

/// Largest magnitude in `a` (0 when empty).
pub(super) fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Weights `w` with `p(tau) = sum w_j y_j` for the polynomial through `(ts[j], y_j)`.
pub(super) fn interp_weights(ts: &[f64], tau: f64, w: &mut [f64]) {
    for j in 0..ts.len() {
        let mut l = 1.0;
        for i in 0..ts.len() {
            if i != j {
                l *= (tau - ts[i]) / (ts[j] - ts[i]);
            }
        }
        w[j] = l;
    }
}

/// Weights `w` with `p'(ts[0]) = sum w_j y_j`.
pub(super) fn derivative_weights(ts: &[f64], w: &mut [f64]) {
    let tau = ts[0];
    for j in 0..ts.len() {
        let mut d = 0.0;
        for m in 0..ts.len() {
            if m == j {
                continue;
            }
            let mut p = 1.0 / (ts[j] - ts[m]);
            for i in 0..ts.len() {
                if i != j && i != m {
                    p *= (tau - ts[i]) / (ts[j] - ts[i]);
                }
            }
            d += p;
        }
        w[j] = d;
    }
}
