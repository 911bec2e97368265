//! Validation of the FE models against analytic and published frequencies (tests only).

use super::beam::{BeamModel, BeamSpec};
use super::eigen::solve_generalized;
use super::plate::{PanelSpec, PlateModel};

/// Cantilever beam: beta_n L (exact roots of 1 + cos cosh = 0).
const BETA_L: [f64; 4] = [1.875104, 4.694091, 7.854757, 10.995541];
/// Square cantilever plate, nu = 0.3 (Leissa): lambda^2 = omega a^2 sqrt(rho t / D).
const PLATE_LAMBDA2: [f64; 6] = [3.492, 8.525, 21.43, 27.33, 31.11, 54.44];

fn beam_errors(n_el: usize) -> Vec<f64> {
    let s = BeamSpec {
        length: 2.0,
        youngs_modulus: 7e10,
        second_moment: 2e-9,
        density: 2700.0,
        area: 3e-4,
    };
    let b = BeamModel::new(&s, n_el).unwrap();
    let sol = solve_generalized(b.stiffness(), b.mass(), &b.root_dofs(), 4).unwrap();
    let scale =
        (s.youngs_modulus * s.second_moment / (s.density * s.area * s.length.powi(4))).sqrt();
    sol.omega2
        .iter()
        .zip(BETA_L)
        .map(|(&w2, bl)| w2.sqrt() / (bl * bl * scale) - 1.0)
        .collect()
}

fn plate_errors(n: usize) -> Vec<f64> {
    let s = PanelSpec {
        a: 1.0,
        b: 1.0,
        thickness: 0.01,
        youngs_modulus: 7e10,
        poisson: 0.3,
        density: 2700.0,
        non_structural_mass: 0.0,
    };
    let p = PlateModel::new(&s, n, n).unwrap();
    let sol = solve_generalized(p.stiffness(), p.mass(), &p.edge_x0_dofs(), 6).unwrap();
    let scale = (s.bending_rigidity() / s.areal_mass()).sqrt() / (s.a * s.a);
    sol.omega2
        .iter()
        .zip(PLATE_LAMBDA2)
        .map(|(&w2, l2)| w2.sqrt() / (l2 * scale) - 1.0)
        .collect()
}

#[test]
fn explore() {
    for n in [2, 4, 8, 16] {
        println!("beam {n}: {:?}", beam_errors(n));
    }
    for n in [4, 8, 12, 16, 20, 24] {
        let t = std::time::Instant::now();
        println!("plate {n}: {:?} {:?}", plate_errors(n), t.elapsed());
    }
}
