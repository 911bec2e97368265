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

/// Verner's "most efficient" 13-stage 8(7) pair (J. H. Verner's published coefficients of
/// "RKV87.IIa Efficient", rounded to the nearest doubles): advances with the 8th-order weights
/// (12 of the 13 stages), estimates with the difference to the 7th-order weights (the 13th stage
/// only there); 13 evaluations per step. For tolerances of about 1e-6 and tighter: on the
/// 8-rod chain at rtol 1e-5 it took 36 steps where the 6(5) pair took 80.
pub static VERNER87: Tableau = Tableau {
    name: "verner87-tree",
    c: &[
        0.0,
        0.05,
        0.1065625,
        0.15984375,
        0.39,
        0.465,
        0.155,
        0.943,
        0.901802041735857,
        0.909,
        0.94,
        1.0,
        1.0,
    ],
    a: &[
        &[],
        &[0.05],
        &[-0.0069931640625, 0.1135556640625],
        &[0.0399609375, 0.0, 0.1198828125],
        &[
            0.36139756280045754,
            0.0,
            -1.3415240667004928,
            1.3701265039000352,
        ],
        &[
            0.049047202797202795,
            0.0,
            0.0,
            0.23509720422144048,
            0.18085559298135673,
        ],
        &[
            0.06169289044289044,
            0.0,
            0.0,
            0.11236568314640277,
            -0.03885046071451367,
            0.01979188712522046,
        ],
        &[
            -1.767630240222327,
            0.0,
            0.0,
            -62.5,
            -6.061889377376669,
            5.6508231982227635,
            65.62169641937624,
        ],
        &[
            -1.1809450665549708,
            0.0,
            0.0,
            -41.50473441114321,
            -4.434438319103725,
            4.260408188586133,
            43.75364022446172,
            0.00787142548991231,
        ],
        &[
            -1.2814059994414884,
            0.0,
            0.0,
            -45.047139960139866,
            -4.731362069449577,
            4.514967016593808,
            47.44909557172985,
            0.010592282971116612,
            -0.0057468422638446166,
        ],
        &[
            -1.7244701342624853,
            0.0,
            0.0,
            -60.92349008483054,
            -5.951518376222393,
            5.556523730698456,
            63.98301198033305,
            0.014642028250414961,
            0.06460408772358203,
            -0.0793032316900888,
        ],
        &[
            -3.301622667747079,
            0.0,
            0.0,
            -118.01127235975251,
            -10.141422388456112,
            9.139311332232058,
            123.37594282840426,
            4.62324437887458,
            -3.3832777380682018,
            4.527592100324618,
            -5.828495485811623,
        ],
        &[
            -3.039515033766309,
            0.0,
            0.0,
            -109.26086808941763,
            -9.290642497400293,
            8.43050498176491,
            114.20100103783314,
            -0.9637271342145479,
            -5.0348840888021895,
            5.958130824002923,
            0.0,
            0.0,
        ],
    ],
    b: &[
        0.04427989419007951,
        0.0,
        0.0,
        0.0,
        0.0,
        0.3541049391724449,
        0.2479692154956438,
        -15.694202038838084,
        25.084064965558564,
        -31.738367786260277,
        22.938283273988784,
        -0.2361324633071542,
        0.0,
    ],
    e: &[
        -3.2721039010281375e-05,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.0005046250618777704,
        0.0001211723589784759,
        -20.142336771313868,
        5.2371785994398286,
        -8.156744408794658,
        22.938283273988784,
        -0.2361324633071542,
        0.36016794372897754,
    ],
    order: 8.0,
    fsal: false,
};

#[cfg(test)]
mod tests {
    use super::{DOPRI5, Tableau, VERNER65, VERNER87};

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

    /// A rooted tree: its subtrees at the root (the order is the node count).
    #[derive(Clone)]
    struct Tree(Vec<Tree>);

    impl Tree {
        fn order(&self) -> usize {
            1 + self.0.iter().map(Tree::order).sum::<usize>()
        }

        /// `gamma(t)`: the order times the subtrees' gammas.
        fn gamma(&self) -> f64 {
            self.order() as f64 * self.0.iter().map(Tree::gamma).product::<f64>()
        }

        /// The elementary weights `Phi_i(t)` per stage: 1 for the single node, else the
        /// product over the subtrees of `sum_j a_ij Phi_j(subtree)`.
        fn phi(&self, t: &Tableau) -> Vec<f64> {
            let s = t.c.len();
            let mut out = vec![1.0; s];
            for sub in &self.0 {
                let p = sub.phi(t);
                for (i, o) in out.iter_mut().enumerate() {
                    *o *= (0..i).map(|j| t.a[i][j] * p[j]).sum::<f64>();
                }
            }
            out
        }
    }

    /// Every rooted tree with up to `max` nodes, by order: a tree of order `n` is a root over a
    /// multiset of smaller trees of total order `n - 1` (taken in non-decreasing list index,
    /// so each multiset once).
    fn trees(max: usize) -> Vec<Vec<Tree>> {
        fn multisets(
            all: &[(usize, Tree)],
            from: usize,
            left: usize,
            cur: &mut Vec<Tree>,
            out: &mut Vec<Tree>,
        ) {
            if left == 0 {
                out.push(Tree(cur.clone()));
                return;
            }
            for (k, (n, t)) in all.iter().enumerate().skip(from) {
                if *n <= left {
                    cur.push(t.clone());
                    multisets(all, k, left - n, cur, out);
                    cur.pop();
                }
            }
        }
        let mut by: Vec<Vec<Tree>> = vec![Vec::new(), vec![Tree(Vec::new())]];
        for n in 2..=max {
            let all: Vec<(usize, Tree)> = (1..n)
                .flat_map(|k| by[k].iter().map(move |t| (k, t.clone())))
                .collect();
            let mut out = Vec::new();
            multisets(&all, 0, n - 1, &mut Vec::new(), &mut out);
            by.push(out);
        }
        by
    }

    /// The order conditions `sum_i b_i Phi_i(t) = 1 / gamma(t)` for every rooted tree up to the
    /// pair's order (the solution weights) and one less (the embedded weights `b - e`), and
    /// their failure one order above: a mistyped coefficient breaks one of the 200 conditions
    /// of order 8 (the tree counts 1, 1, 2, 4, 9, 20, 48, 115 are checked too).
    #[test]
    fn pairs_satisfy_the_order_conditions() {
        let by = trees(9);
        let counts: Vec<usize> = by.iter().skip(1).map(Vec::len).collect();
        assert_eq!(counts, [1, 1, 2, 4, 9, 20, 48, 115, 286]);
        for (t, p) in [(&DOPRI5, 5), (&VERNER65, 6), (&VERNER87, 8)] {
            let hat: Vec<f64> = t.b.iter().zip(t.e).map(|(b, e)| b - e).collect();
            let residual = |w: &[f64], n: usize| {
                by[n]
                    .iter()
                    .map(|tree| {
                        let phi = tree.phi(t);
                        let s: f64 = w.iter().zip(&phi).map(|(w, f)| w * f).sum();
                        (s - 1.0 / tree.gamma()).abs() * tree.gamma()
                    })
                    .fold(0.0, f64::max)
            };
            for n in 1..=p {
                let r = residual(t.b, n);
                assert!(r < 1e-11, "{}: order {n} condition off by {r:e}", t.name);
            }
            for n in 1..p {
                let r = residual(&hat, n);
                assert!(
                    r < 1e-11,
                    "{} embedded: order {n} condition off by {r:e}",
                    t.name
                );
            }
            assert!(
                residual(t.b, p + 1) > 1e-6,
                "{}: not of order {}",
                t.name,
                p + 1
            );
            assert!(
                residual(&hat, p) > 1e-6,
                "{} embedded: of order {p}",
                t.name
            );
        }
    }
}
