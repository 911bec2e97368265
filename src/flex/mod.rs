//! Flexible panels: finite elements, modal reduction and the data of a floating-frame body.
//!
//! Pipeline (the paper's "FE model -> model reduction -> rigid-flexible model"):
//!
//! ```text
//! PanelSpec --PlateModel::new--> K, M (ACM plate, consistent mass)
//!          --reduce::{craig_bampton, free_interface}--> ReducedModel (T, M_r, K_r, D_r)
//!          --ModalBodyData::{from_craig_bampton, from_free_interface}--> node data + Invariants
//!          --Invariants::{mass_matrix, quadratic_velocity, gravity_force}--> M(a), h, f_g
//!          --text_format::{to_text, from_text}--> plain-text exchange with other FE tools
//! ```
//!
//! - [`plate`], [`plate_element`]: rectangular Kirchhoff panel, 12-DOF ACM elements
//!   (w, theta_x = dw/dy, theta_y = -dw/dx per node), out-of-plane bending only.
//! - [`beam`]: Euler-Bernoulli Hermite beam (validation of the solver chain).
//! - [`eigen`]: dense generalized symmetric eigen-solver with clamped DOFs (faer).
//! - [`reduce`]: free-interface modes and Craig-Bampton, modal damping ratio `zeta`.
//! - [`body`]: [`body::ModalBodyData`], node positions/masses/mode shapes, reduced matrices,
//!   attachment nodes, exact inertia invariants, node kinematics for joints and contacts.
//! - [`invariants`]: **the floating-frame equations the multibody side implements**: exact
//!   formulas for the mass matrix blocks `M(a)`, the quadratic-velocity vector
//!   `h(a, omega, a_dot)` and gravity, in terms of the invariants `m, S, J0, C_t, Q_j, P_ij,
//!   M_ee`, with generalized speeds `[v_ref (world), omega (body), a_dot]`; see that module's
//!   doc. Equations of motion: `M(a) y_dot + h = f_ext - [0; 0; K a + D a_dot]`.
//! - [`text_format`]: documented plain-text import/export (version 1).
//!
//! Units SI throughout; every vector of a body is in its body frame unless it says world.
//!
//! # Known limit of linear modes
//! The body deforms as `u = Phi a`, a linear superposition of small-deflection modes of the
//! undeformed, unloaded panel. What this leaves out:
//!
//! - **No geometric (stress) stiffening.** In-plane stresses from centrifugal loads or preloads
//!   (cable tension of the closed cable loop, hinge preload, gravity in a ground test) change
//!   the bending stiffness, and the modes do not know it. The floating-frame equations still
//!   contain the centrifugal *softening* terms (through `P_ij` in `J(a)` and `h_a`), so for a
//!   body spun up about an axis in its plane the linear model predicts frequencies that drop
//!   with spin rate and, near the first bending frequency, a spurious instability (the classic
//!   spin-up beam of Kane, Ryan and Banerjee). Rule of thumb: the error in a bending frequency
//!   is of order `(Omega / omega_1)^2`; keep the body's spin rate well below its first
//!   frequency, or add a geometric-stiffness matrix (not provided here).
//! - **No foreshortening, no membrane action.** A bent panel's points do not move in-plane at
//!   second order (a tip deflection `w` on a span `L` shortens it by about `0.6 w^2 / L`), and
//!   plate membrane stiffening, which starts at deflections of the order of the thickness in
//!   edge-restrained plates, is absent. Cantilevered panels have little membrane restraint, so
//!   the limit there is deflections beyond a few percent of the span.
//! - **Out-of-plane bending only.** In-plane (membrane) flexibility is rigid, in-plane node
//!   shape rows are zero; rotary inertia through the thickness is neglected.
//!
//! For a deploying solar array: the deployment itself is slow (hinge rates of a fraction of a
//! rad/s against a first locked frequency near 0.17 Hz = 1.07 rad/s), and the lock-up impact
//! excites tip deflections of centimetres on metre-size panels, both well inside the linear
//! range. It matters (1) on a spin-stabilized spacecraft deploying its arrays, where the spin
//! rate is a sizeable fraction of the first frequency (0.3 rad/s gives an error of order 8 %);
//! (2) when the cable loop or hinge springs load the panels in-plane (stiffening or buckling
//! softening); (3) in 1 g ground tests without off-loading (gravity sag and its pre-stress);
//! (4) when the post-lock frequency is tuned against test to a few percent, since
//! pre-stress from the latch preload shifts it by a comparable amount.

pub mod beam;
pub mod body;
pub mod eigen;
pub mod error;
pub mod invariants;
pub mod plate;
pub mod plate_element;
pub mod reduce;
pub mod text_format;

pub use body::{ModalBodyData, ModalBodyParts};
pub use error::FlexError;
pub use invariants::Invariants;
pub use plate::{PanelSpec, PlateModel};

#[cfg(test)]
mod body_tests;
#[cfg(test)]
mod invariants_tests;
#[cfg(test)]
mod reduction_tests;
#[cfg(test)]
mod text_format_tests;
#[cfg(test)]
mod validation;
