//! Rectangular honeycomb panel meshed with ACM plate-bending elements (see
//! [`super::plate_element`]), assembled into dense stiffness and consistent mass matrices.
//!
//! Panel frame: origin at one corner, x along the side of length `a`, y along the side of length
//! `b`, z normal to the panel (out-of-plane deflection). The mid-surface is the plane z = 0.
//! Nodes form an `(nx + 1) x (ny + 1)` grid; node `(i, j)` (i along x, j along y) has index
//! `j (nx + 1) + i` and DOFs `3 k + 0` (w [m]), `3 k + 1` (theta_x [rad]), `3 k + 2`
//! (theta_y [rad]).
//!
//! Mass: the consistent element mass is assembled. The eigen-solution needs it to reach 1 % on
//! the cantilever-plate frequencies at a fast mesh, and it makes the inertia invariants of the
//! floating-frame body exact integrals over the panel (see [`super::body`]). For users who want
//! point masses, [`PlateModel::lumped_node_masses`] gives tributary-area masses (exact total mass
//! and first moment).

use nalgebra::DMatrix;

use super::error::{FlexError, check_non_negative, check_positive, invalid};
use super::plate_element::AcmElement;
use crate::math::Vec3;

/// Physical description of a rectangular panel with an equivalent isotropic material.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelSpec {
    /// Side length along x [m].
    pub a: f64,
    /// Side length along y [m].
    pub b: f64,
    /// Thickness [m] (of the equivalent homogeneous plate).
    pub thickness: f64,
    /// Equivalent Young's modulus [Pa].
    pub youngs_modulus: f64,
    /// Poisson ratio [-], in (-1, 0.5).
    pub poisson: f64,
    /// Equivalent density [kg/m^3].
    pub density: f64,
    /// Non-structural areal mass (solar cells, harness, inserts) [kg/m^2], >= 0.
    pub non_structural_mass: f64,
}

impl PanelSpec {
    /// Checks every field: sizes, thickness, modulus and density finite and > 0, Poisson ratio
    /// in (-1, 0.5), non-structural mass finite and >= 0.
    pub fn validate(&self) -> Result<(), FlexError> {
        check_positive("panel side a [m]", self.a)?;
        check_positive("panel side b [m]", self.b)?;
        check_positive("panel thickness [m]", self.thickness)?;
        check_positive("Young's modulus [Pa]", self.youngs_modulus)?;
        check_positive("density [kg/m^3]", self.density)?;
        check_non_negative("non-structural mass [kg/m^2]", self.non_structural_mass)?;
        if !(self.poisson.is_finite() && self.poisson > -1.0 && self.poisson < 0.5) {
            return invalid(format!(
                "Poisson ratio must be in (-1, 0.5), got {}",
                self.poisson
            ));
        }
        Ok(())
    }

    /// Bending rigidity `D = E t^3 / (12 (1 - nu^2))` [N m].
    pub fn bending_rigidity(&self) -> f64 {
        self.youngs_modulus * self.thickness.powi(3) / (12.0 * (1.0 - self.poisson.powi(2)))
    }

    /// Areal mass `mu = rho t + non-structural mass` [kg/m^2].
    pub fn areal_mass(&self) -> f64 {
        self.density * self.thickness + self.non_structural_mass
    }

    /// Total mass `mu a b` [kg].
    pub fn total_mass(&self) -> f64 {
        self.areal_mass() * self.a * self.b
    }
}

/// Assembled finite-element model of a panel (out-of-plane bending only).
#[derive(Debug, Clone)]
pub struct PlateModel {
    spec: PanelSpec,
    nx: usize,
    ny: usize,
    /// Global stiffness, `n_dof x n_dof`, unconstrained (free-free).
    stiffness: DMatrix<f64>,
    /// Global consistent mass, `n_dof x n_dof`, unconstrained.
    mass: DMatrix<f64>,
}

/// Number of DOFs per plate node (w, theta_x, theta_y).
pub const PLATE_DOFS_PER_NODE: usize = 3;

impl PlateModel {
    /// Meshes `spec` with `nx` x `ny` equal elements (`nx, ny >= 1`) and assembles K and M.
    pub fn new(spec: &PanelSpec, nx: usize, ny: usize) -> Result<Self, FlexError> {
        spec.validate()?;
        if nx < 1 || ny < 1 {
            return invalid(format!(
                "mesh must have at least 1 x 1 elements, got {nx} x {ny}"
            ));
        }
        // Dense storage: keep the model to a size a dense eigen-solver handles.
        const MAX_NODES: usize = 20_000;
        let n_nodes = (nx + 1)
            .checked_mul(ny + 1)
            .filter(|&n| n <= MAX_NODES)
            .ok_or_else(|| {
                FlexError::InvalidInput(format!(
                    "mesh {nx} x {ny} has more than {MAX_NODES} nodes (dense matrices)"
                ))
            })?;
        let hx = spec.a / nx as f64;
        let hy = spec.b / ny as f64;
        let el = AcmElement::new(
            hx,
            hy,
            spec.bending_rigidity(),
            spec.poisson,
            spec.areal_mass(),
        )?;
        let n_dof = PLATE_DOFS_PER_NODE * n_nodes;
        let mut stiffness = DMatrix::zeros(n_dof, n_dof);
        let mut mass = DMatrix::zeros(n_dof, n_dof);
        for ej in 0..ny {
            for ei in 0..nx {
                let nodes = [
                    ej * (nx + 1) + ei,
                    ej * (nx + 1) + ei + 1,
                    (ej + 1) * (nx + 1) + ei + 1,
                    (ej + 1) * (nx + 1) + ei,
                ];
                let dofs: Vec<usize> = nodes
                    .iter()
                    .flat_map(|&n| (0..PLATE_DOFS_PER_NODE).map(move |d| 3 * n + d))
                    .collect();
                for (r, &gr) in dofs.iter().enumerate() {
                    for (c, &gc) in dofs.iter().enumerate() {
                        stiffness[(gr, gc)] += el.stiffness[(r, c)];
                        mass[(gr, gc)] += el.mass[(r, c)];
                    }
                }
            }
        }
        Ok(Self {
            spec: spec.clone(),
            nx,
            ny,
            stiffness,
            mass,
        })
    }

    /// The panel description.
    pub fn spec(&self) -> &PanelSpec {
        &self.spec
    }

    /// Elements along x and along y.
    pub fn mesh(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Number of nodes `(nx + 1)(ny + 1)`.
    pub fn n_nodes(&self) -> usize {
        (self.nx + 1) * (self.ny + 1)
    }

    /// Number of DOFs `3 n_nodes`.
    pub fn n_dofs(&self) -> usize {
        PLATE_DOFS_PER_NODE * self.n_nodes()
    }

    /// Global stiffness matrix (free-free) [SI per DOF pair].
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.stiffness
    }

    /// Global consistent mass matrix (free-free).
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }

    /// Index of grid node `(i, j)`, `i <= nx` along x, `j <= ny` along y.
    pub fn node_index(&self, i: usize, j: usize) -> Result<usize, FlexError> {
        if i > self.nx || j > self.ny {
            return invalid(format!(
                "grid node ({i}, {j}) outside the {} x {} node grid",
                self.nx + 1,
                self.ny + 1
            ));
        }
        Ok(j * (self.nx + 1) + i)
    }

    /// Index of the node nearest to the point (x, y) [m] of the panel frame.
    pub fn nearest_node(&self, x: f64, y: f64) -> Result<usize, FlexError> {
        if !(x.is_finite() && y.is_finite()) {
            return invalid(format!("point ({x}, {y}) must be finite"));
        }
        let i = (x / self.spec.a * self.nx as f64)
            .round()
            .clamp(0.0, self.nx as f64) as usize;
        let j = (y / self.spec.b * self.ny as f64)
            .round()
            .clamp(0.0, self.ny as f64) as usize;
        self.node_index(i, j)
    }

    /// Position of node `k` in the panel frame [m] (z = 0).
    pub fn node_position(&self, k: usize) -> Vec3 {
        let i = k % (self.nx + 1);
        let j = k / (self.nx + 1);
        Vec3::new(
            self.spec.a * i as f64 / self.nx as f64,
            self.spec.b * j as f64 / self.ny as f64,
            0.0,
        )
    }

    /// Positions of all nodes in the panel frame [m].
    pub fn node_positions(&self) -> Vec<Vec3> {
        (0..self.n_nodes()).map(|k| self.node_position(k)).collect()
    }

    /// The three DOF indices (w, theta_x, theta_y) of `node`, or an error if out of range.
    pub fn node_dofs(&self, node: usize) -> Result<[usize; 3], FlexError> {
        if node >= self.n_nodes() {
            return invalid(format!(
                "node {node} out of range (mesh has {} nodes)",
                self.n_nodes()
            ));
        }
        Ok([3 * node, 3 * node + 1, 3 * node + 2])
    }

    /// All DOFs of the nodes on the edge x = 0 (clamping them gives a cantilever).
    pub fn edge_x0_dofs(&self) -> Vec<usize> {
        (0..=self.ny)
            .flat_map(|j| {
                let k = j * (self.nx + 1);
                [3 * k, 3 * k + 1, 3 * k + 2]
            })
            .collect()
    }

    /// Tributary-area lumped node masses [kg]: each element gives a quarter of its mass to each
    /// corner. Exact total mass and first moment; second moments carry an O(h^2) error.
    pub fn lumped_node_masses(&self) -> Vec<f64> {
        let quarter =
            0.25 * self.spec.areal_mass() * self.spec.a * self.spec.b / (self.nx * self.ny) as f64;
        let mut m = vec![0.0; self.n_nodes()];
        for ej in 0..self.ny {
            for ei in 0..self.nx {
                for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                    m[(ej + dj) * (self.nx + 1) + ei + di] += quarter;
                }
            }
        }
        m
    }

    /// Nodal DOF vector (length `n_dofs`) interpolating exactly the linear field
    /// `w(x, y) = c0 + cx x + cy y` [m]: w = field, theta_x = cy, theta_y = -cx.
    pub fn linear_field(&self, c0: f64, cx: f64, cy: f64) -> nalgebra::DVector<f64> {
        let mut v = nalgebra::DVector::zeros(self.n_dofs());
        for k in 0..self.n_nodes() {
            let p = self.node_position(k);
            v[3 * k] = c0 + cx * p.x + cy * p.y;
            v[3 * k + 1] = cy;
            v[3 * k + 2] = -cx;
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> PanelSpec {
        PanelSpec {
            a: 2.0,
            b: 1.5,
            thickness: 0.02,
            youngs_modulus: 7e10,
            poisson: 0.3,
            density: 100.0,
            non_structural_mass: 1.5,
        }
    }

    #[test]
    fn assembled_mass_integrates_rigid_fields_exactly() {
        let s = spec();
        let p = PlateModel::new(&s, 3, 4).unwrap();
        let one = p.linear_field(1.0, 0.0, 0.0);
        let x = p.linear_field(0.0, 1.0, 0.0);
        let m = (one.transpose() * p.mass() * &one)[0];
        let mu = s.areal_mass();
        assert!((m - s.total_mass()).abs() < 1e-12 * m);
        // int mu x dA = mu b a^2 / 2, int mu x^2 dA = mu b a^3 / 3.
        let sx = (x.transpose() * p.mass() * &one)[0];
        assert!((sx - mu * s.b * s.a * s.a / 2.0).abs() < 1e-12 * sx);
        let jxx = (x.transpose() * p.mass() * &x)[0];
        assert!((jxx - mu * s.b * s.a.powi(3) / 3.0).abs() < 1e-12 * jxx);
        // Rigid fields are stiffness-free.
        assert!((p.stiffness() * &x).norm() < 1e-9 * p.stiffness().norm());
        let lumped: f64 = p.lumped_node_masses().iter().sum();
        assert!((lumped - s.total_mass()).abs() < 1e-12 * lumped);
    }

    #[test]
    fn rejects_bad_panels_and_meshes() {
        let mut s = spec();
        s.thickness = -0.01;
        let e = PlateModel::new(&s, 4, 4).unwrap_err();
        assert!(e.to_string().contains("thickness"), "{e}");
        let mut s = spec();
        s.youngs_modulus = f64::NAN;
        assert!(PlateModel::new(&s, 4, 4).is_err());
        let e = PlateModel::new(&spec(), 0, 4).unwrap_err();
        assert!(e.to_string().contains("at least 1 x 1"), "{e}");
        let p = PlateModel::new(&spec(), 2, 2).unwrap();
        assert!(p.node_dofs(9).is_err());
        assert!(p.node_index(3, 0).is_err());
        assert_eq!(p.nearest_node(2.0, 1.5).unwrap(), 8);
    }
}
