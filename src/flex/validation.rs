//! Validation of the FE models against analytic and published frequencies, with mesh
//! convergence (tests only).
//!
//! References: cantilever beam roots of `1 + cos(x) cosh(x) = 0` (refined here by Newton from
//! the tabulated 1.875104, 4.694091, 7.854757, 10.995541); simply supported square plate,
//! exact `lambda^2 = pi^2 (m^2 + n^2)`; square cantilever plate, nu = 0.3 (Leissa):
//! `lambda^2 = 3.492, 8.525, 21.43, 27.33, 31.11, 54.44` with
//! `lambda^2 = omega a^2 sqrt(rho t / D)`.
//!
//! Observed: the ACM cantilever-plate values settle 0.2-0.6 % *below* Leissa's (16 x 16:
//! 3.4711, 8.507, 21.30, 27.19, 30.96, 54.09). Leissa's table comes from few-term Ritz series,
//! which are upper bounds; later, more converged solutions in the literature sit near 3.471 and
//! 8.508 for the first two modes, so the offset is in the reference, not a mesh error. Mesh
//! convergence is therefore asserted on successive mesh differences for that case, and against
//! the exact Navier solution for the simply supported plate.

use std::f64::consts::PI;

use super::beam::{BeamModel, BeamSpec};
use super::eigen::generalized_eigenvalues;
use super::plate::{PanelSpec, PlateModel};

const BETA_L_TABLE: [f64; 4] = [1.875104, 4.694091, 7.854757, 10.995541];
const LEISSA_LAMBDA2: [f64; 6] = [3.492, 8.525, 21.43, 27.33, 31.11, 54.44];

/// Root of `1 + cos x cosh x` near `x0` (Newton).
fn cantilever_root(x0: f64) -> f64 {
    let mut x = x0;
    for _ in 0..20 {
        let f = 1.0 + x.cos() * x.cosh();
        let df = -x.sin() * x.cosh() + x.cos() * x.sinh();
        x -= f / df;
    }
    x
}

/// Relative frequency errors of the cantilever beam with `n_el` elements, modes 1-4.
fn beam_errors(n_el: usize) -> Vec<f64> {
    let s = BeamSpec {
        length: 2.0,
        youngs_modulus: 7e10,
        second_moment: 2e-9,
        density: 2700.0,
        area: 3e-4,
    };
    let b = BeamModel::new(&s, n_el).unwrap();
    let l2 = generalized_eigenvalues(b.stiffness(), b.mass(), &b.root_dofs(), 4).unwrap();
    let scale =
        (s.youngs_modulus * s.second_moment / (s.density * s.area * s.length.powi(4))).sqrt();
    l2.iter()
        .zip(BETA_L_TABLE)
        .map(|(&w2, bl)| w2.sqrt() / (cantilever_root(bl).powi(2) * scale) - 1.0)
        .collect()
}

fn square_plate(n: usize) -> PlateModel {
    let s = PanelSpec {
        a: 1.0,
        b: 1.0,
        thickness: 0.01,
        youngs_modulus: 7e10,
        poisson: 0.3,
        density: 2700.0,
        non_structural_mass: 0.0,
    };
    PlateModel::new(&s, n, n).unwrap()
}

/// The first `k` values of `lambda^2 = omega a^2 sqrt(mu / D)` of `plate` with `clamped`.
fn plate_lambda2(plate: &PlateModel, clamped: &[usize], k: usize) -> Vec<f64> {
    let s = plate.spec();
    let l2 = generalized_eigenvalues(plate.stiffness(), plate.mass(), clamped, k).unwrap();
    let scale = s.a * s.a * (s.areal_mass() / s.bending_rigidity()).sqrt();
    l2.iter().map(|&w2| w2.sqrt() * scale).collect()
}

/// Simply supported edges: w and the tangential rotation vanish (the Navier solution does).
fn simply_supported_dofs(p: &PlateModel) -> Vec<usize> {
    let (nx, ny) = p.mesh();
    let mut dofs = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let k = p.node_index(i, j).unwrap();
            let on_x_edge = i == 0 || i == nx; // edge parallel to y: dw/dy = theta_x = 0
            let on_y_edge = j == 0 || j == ny; // edge parallel to x: -dw/dx = theta_y = 0
            if on_x_edge || on_y_edge {
                dofs.push(3 * k);
            }
            if on_x_edge {
                dofs.push(3 * k + 1);
            }
            if on_y_edge {
                dofs.push(3 * k + 2);
            }
        }
    }
    dofs
}

/// Numbers in short scientific notation, for the printed convergence tables.
fn sci(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:+.2e}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// log2 of the error ratio between two meshes, one twice as fine as the other.
fn order(coarse: f64, fine: f64) -> f64 {
    (coarse.abs() / fine.abs()).log2()
}

#[test]
fn cantilever_beam_frequencies_converge_at_fourth_order() {
    let meshes = [2, 4, 8, 16];
    let errs: Vec<Vec<f64>> = meshes.iter().map(|&n| beam_errors(n)).collect();
    for (n, e) in meshes.iter().zip(&errs) {
        println!("beam {n:2} elements: rel. errors {}", sci(e));
    }
    // Within 1 % at 8 elements.
    assert!(errs[2].iter().all(|e| e.abs() < 1e-2), "{:?}", errs[2]);
    for mode in 0..4 {
        for w in errs.windows(2) {
            assert!(
                w[1][mode].abs() < w[0][mode].abs(),
                "mode {mode}: no convergence"
            );
        }
        // Hermite cubics: eigenvalue and frequency errors O(h^4).
        let p = order(errs[2][mode], errs[3][mode]);
        println!("beam mode {}: observed order {p:.2}", mode + 1);
        assert!((3.6..4.4).contains(&p), "mode {mode}: order {p}");
    }
}

#[test]
fn simply_supported_plate_converges_to_navier_solution_at_second_order() {
    // Modes (1,1), (1,2)/(2,1), (2,2), (1,3)/(3,1).
    let exact: Vec<f64> = [2.0, 5.0, 5.0, 8.0, 10.0, 10.0]
        .iter()
        .map(|s| s * PI * PI)
        .collect();
    let meshes = [4, 8, 16];
    let errs: Vec<Vec<f64>> = meshes
        .iter()
        .map(|&n| {
            let p = square_plate(n);
            let l2 = plate_lambda2(&p, &simply_supported_dofs(&p), 6);
            l2.iter().zip(&exact).map(|(a, b)| a / b - 1.0).collect()
        })
        .collect();
    for (n, e) in meshes.iter().zip(&errs) {
        println!("SS plate {n:2}x{n:2}: rel. errors {}", sci(e));
    }
    let rows = errs[0].iter().zip(&errs[1]).zip(&errs[2]);
    for (mode, ((e4, e8), e16)) in rows.enumerate() {
        assert!(e16.abs() < e8.abs() && e8.abs() < e4.abs(), "mode {mode}");
        let p = order(*e8, *e16);
        println!("SS plate mode {}: observed order {p:.2}", mode + 1);
        assert!((1.7..2.3).contains(&p), "mode {mode}: order {p}");
    }
}

#[test]
fn square_cantilever_plate_matches_leissa_within_one_percent() {
    let meshes = [4, 8, 16];
    let l2: Vec<Vec<f64>> = meshes
        .iter()
        .map(|&n| {
            let p = square_plate(n);
            plate_lambda2(&p, &p.edge_x0_dofs(), 6)
        })
        .collect();
    for (n, v) in meshes.iter().zip(&l2) {
        let e: Vec<f64> = v
            .iter()
            .zip(LEISSA_LAMBDA2)
            .map(|(a, b)| a / b - 1.0)
            .collect();
        println!(
            "cantilever plate {n:2}x{n:2}: lambda^2 {v:.4?}, rel. errors {}",
            sci(&e)
        );
    }
    for mode in 0..6 {
        let err16 = l2[2][mode] / LEISSA_LAMBDA2[mode] - 1.0;
        assert!(err16.abs() < 1e-2, "mode {mode}: {err16}");
        // Mesh convergence: successive changes shrink at about second order.
        let d1 = l2[1][mode] - l2[0][mode];
        let d2 = l2[2][mode] - l2[1][mode];
        let p = order(d1, d2);
        println!("cantilever plate mode {}: observed order {p:.2}", mode + 1);
        assert!(p > 1.5, "mode {mode}: order {p}");
        // Richardson extrapolation (order 2) also within 1 % of Leissa.
        let extrap = l2[2][mode] + d2 / 3.0;
        assert!((extrap / LEISSA_LAMBDA2[mode] - 1.0).abs() < 1e-2);
    }
}
