//! The 12-DOF ACM (Adini-Clough-Melosh) rectangular Kirchhoff plate-bending element.
//!
//! Element of size `hx` x `hy` [m] in the panel's x-y plane, out-of-plane deflection `w` along z.
//! Nodes are the corners in the order (-,-), (+,-), (+,+), (-,+) (counter-clockwise from the
//! corner with the smallest x and y). Each node carries three DOFs, in this order:
//!
//! - `w` [m], deflection along +z,
//! - `theta_x = dw/dy` [rad], small rotation about +x,
//! - `theta_y = -dw/dx` [rad], small rotation about +y,
//!
//! so that (`theta_x`, `theta_y`, 0) is the small rotation vector of the plate normal (right-hand
//! rule). The deflection is the 12-term polynomial
//! `1, x, y, x^2, xy, y^2, x^3, x^2 y, x y^2, y^3, x^3 y, x y^3` (complete cubic plus two quartic
//! terms); the element is non-conforming (normal slope not continuous across edges) but passes the
//! patch test, so it converges, with eigenvalue errors O(h^2).
//!
//! Stiffness `K = int B^T D B dA` with curvatures `(w_xx, w_yy, 2 w_xy)` and the isotropic
//! bending rigidity `D = E t^3 / (12 (1 - nu^2)) [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu)/2]]`.
//! Consistent mass `M = mu int N^T N dA` with the areal mass `mu` [kg/m^2] (Kirchhoff theory:
//! no rotary inertia). Both integrals use 4 x 4 Gauss points, exact for these polynomials.

use nalgebra::{SMatrix, SVector};

use super::error::{FlexError, check_positive};

/// 12 x 12 element matrix.
pub type ElementMatrix = SMatrix<f64, 12, 12>;

type Row12 = SVector<f64, 12>;

/// Corner coordinates in natural coordinates (xi, eta), node order of the element.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// Gauss-Legendre points and weights on [-1, 1], 4 points (exact to degree 7).
const GAUSS4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// Exponents (i, j) of the 12 monomials xi^i eta^j.
const MONOMIALS: [(i32, i32); 12] = [
    (0, 0),
    (1, 0),
    (0, 1),
    (2, 0),
    (1, 1),
    (0, 2),
    (3, 0),
    (2, 1),
    (1, 2),
    (0, 3),
    (3, 1),
    (1, 3),
];

/// Value of d^dx/dxi^dx d^dy/deta^dy of every monomial at (xi, eta).
fn monomial_derivs(xi: f64, eta: f64, dx: i32, dy: i32) -> Row12 {
    let mut r = Row12::zeros();
    for (k, &(i, j)) in MONOMIALS.iter().enumerate() {
        r[k] = deriv_1d(xi, i, dx) * deriv_1d(eta, j, dy);
    }
    r
}

/// d^d/dx^d of x^p.
fn deriv_1d(x: f64, p: i32, d: i32) -> f64 {
    if d > p {
        return 0.0;
    }
    let mut c = 1.0;
    for k in 0..d {
        c *= f64::from(p - k);
    }
    c * x.powi(p - d)
}

/// Stiffness and consistent mass matrices of one ACM element.
#[derive(Debug, Clone)]
pub struct AcmElement {
    /// Element stiffness (SI; N/m, N/rad or N m/rad depending on the DOF pair), DOF order of
    /// the module doc.
    pub stiffness: ElementMatrix,
    /// Element consistent mass (SI; kg, kg m or kg m^2 depending on the DOF pair).
    pub mass: ElementMatrix,
}

impl AcmElement {
    /// Builds the element of size `hx` x `hy` [m] with bending rigidity `d_bend` =
    /// E t^3 / (12 (1 - nu^2)) [N m], Poisson ratio `nu` and areal mass `mu` [kg/m^2].
    pub fn new(hx: f64, hy: f64, d_bend: f64, nu: f64, mu: f64) -> Result<Self, FlexError> {
        check_positive("element length hx [m]", hx)?;
        check_positive("element length hy [m]", hy)?;
        check_positive("bending rigidity D [N m]", d_bend)?;
        check_positive("areal mass [kg/m^2]", mu)?;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(FlexError::InvalidInput(format!(
                "Poisson ratio must be in (-1, 0.5), got {nu}"
            )));
        }
        // Physical derivatives: d/dx = (2/hx) d/dxi, d/dy = (2/hy) d/deta.
        let sx = 2.0 / hx;
        let sy = 2.0 / hy;
        // Rows of C: nodal DOFs (w, dw/dy, -dw/dx) of each monomial.
        let mut c = ElementMatrix::zeros();
        for (n, &(xi, eta)) in CORNERS.iter().enumerate() {
            c.set_row(3 * n, &monomial_derivs(xi, eta, 0, 0).transpose());
            c.set_row(
                3 * n + 1,
                &(sy * monomial_derivs(xi, eta, 0, 1)).transpose(),
            );
            c.set_row(
                3 * n + 2,
                &(-sx * monomial_derivs(xi, eta, 1, 0)).transpose(),
            );
        }
        let c_inv = c.try_inverse().ok_or_else(|| {
            FlexError::Numerical(format!(
                "ACM interpolation matrix singular for element {hx} m x {hy} m"
            ))
        })?;
        let d11 = d_bend;
        let d12 = nu * d_bend;
        let d33 = 0.5 * (1.0 - nu) * d_bend;
        let jac = 0.25 * hx * hy;
        let mut stiffness = ElementMatrix::zeros();
        let mut mass = ElementMatrix::zeros();
        for &(xi, wx) in &GAUSS4 {
            for &(eta, wy) in &GAUSS4 {
                let wgt = wx * wy * jac;
                // Shape functions and curvature rows, each as a row over the 12 nodal DOFs.
                let n = c_inv.transpose() * monomial_derivs(xi, eta, 0, 0);
                let kxx = c_inv.transpose() * (sx * sx * monomial_derivs(xi, eta, 2, 0));
                let kyy = c_inv.transpose() * (sy * sy * monomial_derivs(xi, eta, 0, 2));
                let kxy = c_inv.transpose() * (2.0 * sx * sy * monomial_derivs(xi, eta, 1, 1));
                stiffness += wgt
                    * (d11 * (kxx * kxx.transpose() + kyy * kyy.transpose())
                        + d12 * (kxx * kyy.transpose() + kyy * kxx.transpose())
                        + d33 * kxy * kxy.transpose());
                mass += (wgt * mu) * n * n.transpose();
            }
        }
        // Remove round-off asymmetry.
        let stiffness = 0.5 * (stiffness + stiffness.transpose());
        let mass = 0.5 * (mass + mass.transpose());
        Ok(Self { stiffness, mass })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodal DOF vector of the field w = c0 + c1 x + c2 y (+ quadratic terms) on an element
    /// centred at the origin.
    fn nodal(hx: f64, hy: f64, f: impl Fn(f64, f64) -> (f64, f64, f64)) -> Row12 {
        let mut v = Row12::zeros();
        for (n, &(xi, eta)) in CORNERS.iter().enumerate() {
            let (w, wx, wy) = f(0.5 * hx * xi, 0.5 * hy * eta);
            v[3 * n] = w;
            v[3 * n + 1] = wy;
            v[3 * n + 2] = -wx;
        }
        v
    }

    #[test]
    fn rigid_modes_carry_no_strain_energy_and_total_mass_is_exact() {
        let (hx, hy, mu) = (0.3, 0.2, 2.5);
        let e = AcmElement::new(hx, hy, 7.0, 0.3, mu).unwrap();
        let rigid = [
            nodal(hx, hy, |_, _| (1.0, 0.0, 0.0)),
            nodal(hx, hy, |x, _| (x, 1.0, 0.0)),
            nodal(hx, hy, |_, y| (y, 0.0, 1.0)),
        ];
        for r in &rigid {
            assert!((e.stiffness * r).norm() < 1e-10 * e.stiffness.norm());
        }
        // int mu * 1 * 1 dA = mu hx hy; int mu x^2 dA = mu hx^3 hy / 12.
        let m = (rigid[0].transpose() * e.mass * rigid[0])[0];
        assert!((m - mu * hx * hy).abs() < 1e-14);
        let jy = (rigid[1].transpose() * e.mass * rigid[1])[0];
        assert!((jy - mu * hx.powi(3) * hy / 12.0).abs() < 1e-15);
    }

    #[test]
    fn constant_curvature_gives_exact_bending_energy() {
        // w = x^2/2 + y^2/2 + xy: curvatures (1, 1, 2): energy density
        // D/2 (1 + 2 nu + 1 + (1-nu)/2 * 4) = D/2 (4) over the area.
        let (hx, hy, d, nu) = (0.4, 0.25, 3.0, 0.3);
        let e = AcmElement::new(hx, hy, d, nu, 1.0).unwrap();
        let v = nodal(hx, hy, |x, y| {
            (0.5 * x * x + 0.5 * y * y + x * y, x + y, y + x)
        });
        let energy = 0.5 * (v.transpose() * e.stiffness * v)[0];
        let exact = 0.5 * d * (1.0 + 2.0 * nu + 1.0 + 2.0 * (1.0 - nu)) * hx * hy;
        assert!((energy - exact).abs() < 1e-12 * exact);
    }

    #[test]
    fn rejects_bad_input() {
        assert!(AcmElement::new(0.0, 1.0, 1.0, 0.3, 1.0).is_err());
        assert!(AcmElement::new(1.0, f64::NAN, 1.0, 0.3, 1.0).is_err());
        let err = AcmElement::new(1.0, 1.0, 1.0, 0.7, 1.0).unwrap_err();
        assert!(err.to_string().contains("Poisson"));
    }
}
