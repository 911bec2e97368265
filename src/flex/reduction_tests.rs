//! Convergence of Craig-Bampton and free-interface reductions to the full FE model, and the
//! modal damping construction (tests only).

use nalgebra::DMatrix;

use super::eigen::{generalized_eigenvalues, solve_generalized};
use super::plate::{PanelSpec, PlateModel};
use super::reduce::{ReducedCoordinate, RigidModes, craig_bampton, free_interface, modal_damping};

/// A 2 m x 1 m honeycomb-like panel, 16 x 8 mesh, hinges at (0, 0.25 m) and (0, 0.75 m).
pub(crate) fn panel() -> (PlateModel, [usize; 2]) {
    let s = PanelSpec {
        a: 2.0,
        b: 1.0,
        thickness: 0.025,
        youngs_modulus: 1.2e9,
        poisson: 0.3,
        density: 60.0,
        non_structural_mass: 1.2,
    };
    let p = PlateModel::new(&s, 16, 8).unwrap();
    let hinges = [p.node_index(0, 2).unwrap(), p.node_index(0, 6).unwrap()];
    (p, hinges)
}

fn hinge_dofs(p: &PlateModel, hinges: &[usize]) -> Vec<usize> {
    hinges
        .iter()
        .flat_map(|&h| p.node_dofs(h).unwrap())
        .collect()
}

/// Eigenvalues of (k, m) restricted to the null space of the rows `g` (g q = 0).
fn constrained_eigenvalues(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    g: &DMatrix<f64>,
    n: usize,
) -> Vec<f64> {
    let gtg = g.transpose() * g;
    let eye = DMatrix::identity(gtg.nrows(), gtg.nrows());
    let sol = solve_generalized(&gtg, &eye, &[], gtg.nrows()).unwrap();
    let tol = 1e-10 * sol.omega2.last().unwrap();
    let cols: Vec<usize> = (0..gtg.nrows()).filter(|&c| sol.omega2[c] <= tol).collect();
    let null = sol.modes.select_columns(&cols);
    let kc = null.transpose() * k * &null;
    let mc = null.transpose() * m * &null;
    let kc = 0.5 * (&kc + kc.transpose());
    let mc = 0.5 * (&mc + mc.transpose());
    generalized_eigenvalues(&kc, &mc, &[], n).unwrap()
}

/// Relative frequency errors sqrt(l_r / l_full) - 1.
fn freq_errors(reduced: &[f64], full: &[f64]) -> Vec<f64> {
    reduced
        .iter()
        .zip(full)
        .map(|(r, f)| (r / f).sqrt() - 1.0)
        .collect()
}

/// Number of elastic frequencies compared.
const N_CHECK: usize = 6;
/// Fixed-interface mode counts of the Craig-Bampton study.
const CB_COUNTS: [usize; 6] = [4, 8, 16, 32, 64, 96];
/// Elastic free-interface mode counts (the modes are nested, so one solve serves all).
const FI_COUNTS: [usize; 5] = [12, 24, 48, 96, 192];

/// Checks that every error is >= 0 (reduced frequencies are Rayleigh-Ritz upper bounds) and
/// does not grow as modes are added (nested Ritz spaces).
fn assert_monotone(history: &[Vec<f64>], what: &str) {
    for w in history.windows(2) {
        for (e_prev, e_next) in w[0].iter().zip(&w[1]) {
            assert!(
                *e_next >= -1e-9,
                "{what}: Ritz value below the full model: {e_next}"
            );
            assert!(
                *e_next <= e_prev + 1e-9,
                "{what}: error grew {e_prev} -> {e_next}"
            );
        }
    }
}

fn max_err(e: &[f64]) -> f64 {
    e.iter().cloned().fold(0.0, f64::max)
}

/// Free-free panel, interface = both hinge nodes (6 DOFs): the CB model's first six elastic
/// frequencies against the full FE model's.
#[test]
fn craig_bampton_converges_to_free_free_fe_frequencies() {
    let (p, hinges) = panel();
    let full = generalized_eigenvalues(p.stiffness(), p.mass(), &[], 3 + N_CHECK).unwrap();
    let mut history = Vec::new();
    for n in CB_COUNTS {
        let cb = craig_bampton(
            p.stiffness(),
            p.mass(),
            &[],
            &hinge_dofs(&p, &hinges),
            n,
            0.0,
        )
        .unwrap();
        assert_eq!(cb.coordinates.len(), 6 + n);
        let red = generalized_eigenvalues(&cb.stiffness, &cb.mass, &[], 3 + N_CHECK).unwrap();
        // Three rigid modes are kept exactly by the constraint modes.
        assert!(red[..3].iter().all(|&l| l.abs() < 1e-9 * full[3]));
        let err = freq_errors(&red[3..], &full[3..]);
        println!(
            "CB n = {n:2}: max rel. frequency error {:.3e}",
            max_err(&err)
        );
        history.push(err);
    }
    assert_monotone(&history, "Craig-Bampton");
    assert!(
        max_err(history.last().unwrap()) < 1e-5,
        "{:?}",
        history.last()
    );
}

/// Free-interface modes (3 rigid + n elastic) of the free panel, then constrained: (a) w only
/// at three support points, (b) both hinge nodes fully clamped. Converges, monotonically, but
/// slowly for (b): point rotation clamps excite mesh-scale modes, which is why the
/// floating-frame body uses Craig-Bampton for hinged panels.
#[test]
fn free_interface_modes_converge_to_fe_frequencies_of_the_supported_panel() {
    let (p, hinges) = panel();
    let n_all = p.n_dofs() - 3;
    let fi = free_interface(p.stiffness(), p.mass(), &[], n_all, RigidModes::Keep, 0.0).unwrap();
    assert_eq!(fi.n_rigid, 3);
    assert_eq!(fi.coordinates[2], ReducedCoordinate::RigidMode);
    assert!(matches!(fi.coordinates[3], ReducedCoordinate::Mode { .. }));
    let supports = vec![
        3 * hinges[0],
        3 * hinges[1],
        3 * p.node_index(16, 4).unwrap(),
    ];
    let clamps = hinge_dofs(&p, &hinges);
    for (case, fixed) in [("w-only supports", supports), ("clamped hinges", clamps)] {
        let full = generalized_eigenvalues(p.stiffness(), p.mass(), &fixed, N_CHECK).unwrap();
        let mut history = Vec::new();
        for n in FI_COUNTS.into_iter().chain([n_all]) {
            let cols: Vec<usize> = (0..3 + n).collect();
            let k = fi.stiffness.select_rows(&cols).select_columns(&cols);
            let m = fi.mass.select_rows(&cols).select_columns(&cols);
            let g = fi.basis.select_rows(&fixed).select_columns(&cols);
            let err = freq_errors(&constrained_eigenvalues(&k, &m, &g, N_CHECK), &full);
            println!(
                "FI {case}, n = {n:3}: max rel. frequency error {:.3e}",
                max_err(&err)
            );
            history.push(err);
        }
        assert_monotone(&history, case);
        // The complete modal basis reproduces the full model.
        assert!(
            max_err(history.last().unwrap()) < 1e-8,
            "{case}: {:?}",
            history.last()
        );
        if case == "w-only supports" {
            let e = history.iter().map(|h| max_err(h)).collect::<Vec<_>>();
            // Observed order in n between 48 and 192 modes (about 1.4 here).
            let rate = (e[2] / e[4]).log2() / 2.0;
            println!("FI {case}: observed rate n^-{rate:.2}");
            assert!(rate > 1.0 && e[4] < 3e-3, "{e:?}");
        }
    }
}

#[test]
fn modal_damping_gives_each_mode_the_requested_ratio() {
    let (p, hinges) = panel();
    let cb = craig_bampton(
        p.stiffness(),
        p.mass(),
        &[],
        &hinge_dofs(&p, &hinges),
        5,
        0.02,
    )
    .unwrap();
    let sol = solve_generalized(&cb.stiffness, &cb.mass, &[], cb.mass.nrows()).unwrap();
    let modal = sol.modes.transpose() * &cb.damping * &sol.modes;
    for (i, &l) in sol.omega2.iter().enumerate() {
        let target = if i < 3 { 0.0 } else { 2.0 * 0.02 * l.sqrt() };
        assert!(
            (modal[(i, i)] - target).abs() < 1e-8 * (1.0 + target),
            "mode {i}: {} vs {target}",
            modal[(i, i)]
        );
    }
    let off = modal.clone() - DMatrix::from_diagonal(&modal.diagonal());
    assert!(off.amax() < 1e-8 * modal.amax());
    assert!(modal_damping(&cb.stiffness, &cb.mass, -0.1).is_err());
}

#[test]
fn reductions_reject_bad_requests() {
    let (p, hinges) = panel();
    let nd = p.n_dofs();
    let e = free_interface(p.stiffness(), p.mass(), &[], nd, RigidModes::Exclude, 0.0).unwrap_err();
    assert!(e.to_string().contains("elastic modes"), "{e}");
    let e = craig_bampton(p.stiffness(), p.mass(), &[], &[0], 3, 0.0).unwrap_err();
    assert!(e.to_string().contains("do not restrain"), "{e}");
    let e = craig_bampton(p.stiffness(), p.mass(), &[nd], &[0], 3, 0.0).unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
    let dofs = hinge_dofs(&p, &hinges);
    let e = craig_bampton(p.stiffness(), p.mass(), &dofs[..1], &dofs, 3, 0.0).unwrap_err();
    assert!(e.to_string().contains("both fixed and an interface"), "{e}");
    let e = craig_bampton(p.stiffness(), p.mass(), &[], &dofs, nd, 0.0).unwrap_err();
    assert!(e.to_string().contains("interior DOFs"), "{e}");
}
