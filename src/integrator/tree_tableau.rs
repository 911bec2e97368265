//! Embedded explicit Runge-Kutta pairs for the joint-coordinate integrators
//! ([`super::tree_rk`]).

use super::dopri;

/// An embedded explicit Runge-Kutta pair: the solution advances with `b`, the local error is
/// estimated by `h sum e_i k_i` (`e = b - b_hat`, of order `order` in `h`).
#[derive(Debug)]
pub struct Tableau {
    /// Short name for messages.
    pub name: &'static str,
    /// Nodes and the lower-triangular stage matrix (row `i` read up to `i`).
    pub c: &'static [f64],
    pub a: &'static [&'static [f64]],
    pub b: &'static [f64],
    pub e: &'static [f64],
    /// Order of the local error estimate (`h^order`): the step proposal's exponent is
    /// `1 / order`, `1 / (order - 1)` with error per unit step.
    pub order: f64,
    /// The last stage is evaluated at the new solution (first same as last): it is the next
    /// step's first stage.
    pub fsal: bool,
}

/// Dormand-Prince 5(4), the coefficients of [`super::dopri`] (7 stages, FSAL: 6 evaluations per
/// step).
pub static DOPRI5: Tableau = Tableau {
    name: "dopri5-tree",
    c: &dopri::C,
    a: &[
        &dopri::A[0],
        &dopri::A[1],
        &dopri::A[2],
        &dopri::A[3],
        &dopri::A[4],
        &dopri::A[5],
        &dopri::A[6],
    ],
    b: &dopri::B,
    e: &dopri::E,
    order: 5.0,
    fsal: true,
};

const VA: f64 = 1.0 / 18_158_040_000.0;
const VB: f64 = 1.0 / 10_838_520.0;
const VH: f64 = 1.0 / 29_920.0;

/// Verner's 8-stage 6(5) pair (J. H. Verner, SIAM J. Numer. Anal. 15 (1978) 772-790): advances
/// with the 6th-order weights, 8 evaluations per step; for tight tolerances, where DOPRI5's
/// steps become short.
pub static VERNER65: Tableau = Tableau {
    name: "verner65-tree",
    c: &[
        0.0,
        5.0 / 30.0,
        8.0 / 30.0,
        20.0 / 30.0,
        25.0 / 30.0,
        1.0,
        2.0 / 30.0,
        1.0,
    ],
    a: &[
        &[],
        &[3_026_340_000.0 * VA],
        &[968_428_800.0 * VA, 3_873_715_200.0 * VA],
        &[
            15_131_700_000.0 * VA,
            -48_421_440_000.0 * VA,
            45_395_100_000.0 * VA,
        ],
        &[
            -46_813_696_875.0 * VA,
            166_448_700_000.0 * VA,
            -120_580_734_375.0 * VA,
            16_077_431_250.0 * VA,
        ],
        &[
            43_579_296_000.0 * VA,
            -145_264_320_000.0 * VA,
            119_125_050_000.0 * VA,
            -5_548_290_000.0 * VA,
            6_266_304_000.0 * VA,
        ],
        &[
            -10_002_658_968.0 * VA,
            30_021_292_800.0 * VA,
            -17_170_029_000.0 * VA,
            -5_883_204_960.0 * VA,
            4_245_136_128.0 * VA,
            0.0,
        ],
        &[
            36_960_057_000.0 * VA,
            -126_684_000_000.0 * VA,
            102_559_875_000.0 * VA,
            -2_494_580_000.0 * VA,
            5_198_688_000.0 * VA,
            0.0,
            2_618_000_000.0 * VA,
        ],
    ],
    b: &[
        812_889.0 * VB,
        0.0,
        4_226_250.0 * VB,
        3_462_305.0 * VB,
        1_463_616.0 * VB,
        0.0,
        116_875.0 * VB,
        756_585.0 * VB,
    ],
    e: &[
        812_889.0 * VB - 2_431.0 * VH,
        0.0,
        4_226_250.0 * VB - 11_875.0 * VH,
        3_462_305.0 * VB - 9_350.0 * VH,
        1_463_616.0 * VB - 4_224.0 * VH,
        -2_040.0 * VH,
        116_875.0 * VB,
        756_585.0 * VB,
    ],
    order: 6.0,
    fsal: false,
};

#[cfg(test)]
mod tests {
    use super::{DOPRI5, Tableau, VERNER65};

    /// One step of `y' = y cos(t) + 1` from `y(0) = 1`: the solution and the error estimate.
    fn step(t: &Tableau, h: f64) -> (f64, f64) {
        let f = |t: f64, y: f64| y * t.cos() + 1.0;
        let mut k = vec![0.0; t.c.len()];
        for i in 0..k.len() {
            let y = 1.0 + h * (0..i).map(|j| t.a[i][j] * k[j]).sum::<f64>();
            k[i] = f(t.c[i] * h, y);
        }
        let y = 1.0 + h * (0..k.len()).map(|i| t.b[i] * k[i]).sum::<f64>();
        let e = h * (0..k.len()).map(|i| t.e[i] * k[i]).sum::<f64>();
        (y, e)
    }

    #[test]
    fn pairs_have_their_orders() {
        for (t, p) in [(&DOPRI5, 5), (&VERNER65, 6)] {
            for (i, a) in t.a.iter().enumerate() {
                let row: f64 = a.iter().take(i).sum();
                assert!((row - t.c[i]).abs() < 1e-14, "{} row {i}", t.name);
            }
            assert!((t.b.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(t.e.iter().sum::<f64>().abs() < 1e-14);
            // reference: the same pair with 64 substeps (local errors O(h^(p+1)) each)
            let exact = |h: f64| {
                let _ = h;
                let n = 64;
                let mut y = 1.0;
                let hs = h / n as f64;
                let f = |t: f64, y: f64| y * t.cos() + 1.0;
                for s in 0..n {
                    let t0 = s as f64 * hs;
                    let mut k = vec![0.0; t.c.len()];
                    for i in 0..k.len() {
                        let yi = y + hs * (0..i).map(|j| t.a[i][j] * k[j]).sum::<f64>();
                        k[i] = f(t0 + t.c[i] * hs, yi);
                    }
                    y += hs * (0..k.len()).map(|i| t.b[i] * k[i]).sum::<f64>();
                }
                y
            };
            let errs: Vec<f64> = [0.4, 0.2]
                .iter()
                .map(|&h| (step(t, h).0 - exact(h)).abs())
                .collect();
            let ratio = errs[0] / errs[1];
            let want = 2f64.powi(p + 1);
            assert!(
                ratio > 0.7 * want && ratio < 1.5 * want,
                "{}: local error ratio {ratio} (want {want})",
                t.name
            );
            let ests: Vec<f64> = [0.4, 0.2].iter().map(|&h| step(t, h).1.abs()).collect();
            let ratio = ests[0] / ests[1];
            let want = 2f64.powi(p);
            assert!(
                ratio > 0.6 * want && ratio < 1.6 * want,
                "{}: estimate ratio {ratio} (want {want})",
                t.name
            );
        }
    }
}
