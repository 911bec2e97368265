//! Locating a contact event (a closing or an opening) inside a step, shared by the integrators
//! that land their steps on events.

/// Fraction of a step to which an event is located.
pub const LOCATION_TOLERANCE: f64 = 1e-12;

/// The first crossing of an event function inside a step: `g0 = f(0) <= 0 < f(1) = g1`, with
/// `f(theta)` the function at the fraction `theta` of the step on the integrator's interpolant.
/// Illinois (modified regula falsi) to [`LOCATION_TOLERANCE`] of the step; returns the end of
/// the final bracket where the function is positive (the event has happened there).
pub fn first_crossing(g0: f64, g1: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    if g0 == 0.0 {
        return 0.0;
    }
    let (mut a, mut fa, mut b, mut fb) = (0.0, g0, 1.0, g1);
    // which end was kept by the last update (-1: `a`, 1: `b`), to halve the stale end's value
    let mut kept = 0i8;
    for _ in 0..100 {
        if b - a <= LOCATION_TOLERANCE {
            break;
        }
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
        }
        let fm = f(m);
        if !fm.is_finite() {
            break;
        }
        if fm > 0.0 {
            (b, fb) = (m, fm);
            if kept == 1 {
                fa *= 0.5;
            }
            kept = 1;
        } else {
            (a, fa) = (m, fm);
            if kept == -1 {
                fb *= 0.5;
            }
            kept = -1;
        }
    }
    b
}

/// The earliest contact events inside a step, from the event functions at its start (`g0`) and
/// end (`g1`) and `gap(theta, i)`, event function `i` at the fraction `theta` of the step on the
/// integrator's interpolant. Returns that fraction and leaves in `landing` every event located
/// within 1e-9 of it (a symmetric body landing on several points lands on all at once); `None`
/// when no function goes from `<= 0` to `> 0`. `roots` is scratch.
pub fn earliest_events(
    g0: &[f64],
    g1: &[f64],
    roots: &mut Vec<(usize, f64)>,
    landing: &mut Vec<usize>,
    mut gap: impl FnMut(f64, usize) -> f64,
) -> Option<f64> {
    landing.clear();
    roots.clear();
    for (i, (&a, &b)) in g0.iter().zip(g1).enumerate() {
        if a <= 0.0 && b > 0.0 {
            roots.push((i, first_crossing(a, b, |m| gap(m, i))));
        }
    }
    let first = roots.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
    if !first.is_finite() {
        return None;
    }
    let same = first + 1e-9;
    landing.extend(roots.iter().filter(|r| r.1 <= same).map(|r| r.0));
    Some(first)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_root_of_a_cubic_to_the_tolerance() {
        // f(x) = (x - 0.3) (1 + x^2) crosses once at 0.3
        let f = |x: f64| (x - 0.3) * (1.0 + x * x);
        let r = first_crossing(f(0.0), f(1.0), f);
        assert!((r - 0.3).abs() <= 2.0 * LOCATION_TOLERANCE, "root {r}");
        assert!(f(r) > 0.0);
    }

    #[test]
    fn a_function_zero_at_the_start_crosses_there() {
        assert_eq!(first_crossing(0.0, 1.0, |x| x), 0.0);
    }
}
