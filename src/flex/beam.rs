//! Euler-Bernoulli beam in bending, meshed with 2-node Hermite-cubic elements (consistent mass).
//!
//! The beam lies along x from 0 to `length` [m] and deflects along z. Node `k` sits at
//! x = k L / n_elements and carries DOFs `2 k` (w [m]) and `2 k + 1` (slope dw/dx [rad]).
//! Element matrices (length `h`): stiffness `EI/h^3 [[12, 6h, -12, 6h], [6h, 4h^2, -6h, 2h^2],
//! [-12, -6h, 12, -6h], [6h, 2h^2, -6h, 4h^2]]` and consistent mass
//! `rho A h / 420 [[156, 22h, 54, -13h], [22h, 4h^2, 13h, -3h^2], [54, 13h, 156, -22h],
//! [-13h, -3h^2, -22h, 4h^2]]` (both exact for the cubic interpolation). The cantilever's
//! eigenvalue error falls as O(h^4).

use nalgebra::DMatrix;

use super::error::{FlexError, check_positive, invalid};

/// Physical description of a uniform beam.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamSpec {
    /// Length [m].
    pub length: f64,
    /// Young's modulus [Pa].
    pub youngs_modulus: f64,
    /// Second moment of area about the bending axis [m^4].
    pub second_moment: f64,
    /// Density [kg/m^3].
    pub density: f64,
    /// Cross-section area [m^2].
    pub area: f64,
}

/// Assembled beam model (free-free; clamp DOFs at solve time).
#[derive(Debug, Clone)]
pub struct BeamModel {
    spec: BeamSpec,
    n_elements: usize,
    stiffness: DMatrix<f64>,
    mass: DMatrix<f64>,
}

impl BeamModel {
    /// Meshes `spec` with `n_elements >= 1` equal elements and assembles K and M.
    pub fn new(spec: &BeamSpec, n_elements: usize) -> Result<Self, FlexError> {
        check_positive("beam length [m]", spec.length)?;
        check_positive("Young's modulus [Pa]", spec.youngs_modulus)?;
        check_positive("second moment of area [m^4]", spec.second_moment)?;
        check_positive("density [kg/m^3]", spec.density)?;
        check_positive("cross-section area [m^2]", spec.area)?;
        if n_elements < 1 {
            return invalid("beam mesh must have at least 1 element, got 0");
        }
        if n_elements > 10_000 {
            return invalid(format!(
                "beam mesh of {n_elements} elements exceeds 10000 (dense matrices)"
            ));
        }
        let h = spec.length / n_elements as f64;
        let ei = spec.youngs_modulus * spec.second_moment / h.powi(3);
        let ke = [
            [12.0, 6.0 * h, -12.0, 6.0 * h],
            [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
            [-12.0, -6.0 * h, 12.0, -6.0 * h],
            [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
        ];
        let mc = spec.density * spec.area * h / 420.0;
        let me = [
            [156.0, 22.0 * h, 54.0, -13.0 * h],
            [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
            [54.0, 13.0 * h, 156.0, -22.0 * h],
            [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
        ];
        let n_dof = 2 * (n_elements + 1);
        let mut stiffness = DMatrix::zeros(n_dof, n_dof);
        let mut mass = DMatrix::zeros(n_dof, n_dof);
        for e in 0..n_elements {
            for r in 0..4 {
                for c in 0..4 {
                    stiffness[(2 * e + r, 2 * e + c)] += ei * ke[r][c];
                    mass[(2 * e + r, 2 * e + c)] += mc * me[r][c];
                }
            }
        }
        Ok(Self {
            spec: spec.clone(),
            n_elements,
            stiffness,
            mass,
        })
    }

    /// The beam description.
    pub fn spec(&self) -> &BeamSpec {
        &self.spec
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.n_elements
    }

    /// Global stiffness matrix, `2 (n_elements + 1)` square.
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.stiffness
    }

    /// Global consistent mass matrix, `2 (n_elements + 1)` square.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }

    /// DOFs of the node at x = 0 (clamping them gives a cantilever).
    pub fn root_dofs(&self) -> Vec<usize> {
        vec![0, 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input() {
        let s = BeamSpec {
            length: 1.0,
            youngs_modulus: 2e11,
            second_moment: 1e-8,
            density: 7800.0,
            area: 1e-4,
        };
        assert!(BeamModel::new(&s, 0).is_err());
        let bad = BeamSpec {
            area: f64::NAN,
            ..s.clone()
        };
        assert!(
            BeamModel::new(&bad, 4)
                .unwrap_err()
                .to_string()
                .contains("area")
        );
        let m = BeamModel::new(&s, 5).unwrap();
        // Total mass: the rigid translation vector (w = 1, slope 0) through M.
        let mut one = nalgebra::DVector::zeros(12);
        for k in 0..6 {
            one[2 * k] = 1.0;
        }
        let mt = (one.transpose() * m.mass() * &one)[0];
        assert!((mt - 7800.0 * 1e-4).abs() < 1e-12);
    }
}
