//! PanelLock: deployment and lock-up of a solar array (yoke and panels joined by hinge bodies,
//! preloaded torsion springs, pin/groove latches with a Hertz-type contact law).
//!
//! # Default numbers and why
//! - Panels 2.0 m x 1.5 m, 1.5 kg/m^2 (carbon/aluminium honeycomb with cells): 4.5 kg each,
//!   25 mm thick; three panels, a 1.0 m yoke of 2 kg: typical of a small-satellite wing.
//! - Hinge bodies of 0.3 kg (a bracket pair and shaft) with 30 mm radius of gyration.
//! - Deployment springs: 0.6 N m at lock for the root hinge (0.1 N m/rad), 0.4 N m for the panel
//!   hinges (0.05 N m/rad): a preload at lock of the order of 1/3 of the stowed torque, so the
//!   latch seats with margin; hinge shaft damping 0.02 N m s/rad.
//! - Latch: cam radius 30 mm, groove 12 mm wide and 8 mm deep, pin radius 5 mm (2 mm of play).
//! - Contact: Lankarani-Nikravesh, k = 1e7 N/m^1.5, n = 1.5 (steel on steel), e = 0.8: the
//!   paper's recommended set.
//! - Root hinge locks at 90 deg, panel hinges at 180 deg; panels stowed 5 deg open (the gap of a
//!   stowed stack), which also keeps the hinge travel below 180 deg.
//! - Gravity off (orbit), satellite fixed; BDF with rtol 1e-6, atol 1e-8, h_max 20 ms.
//!
//! # Free-floating satellite (`free_satellite`)
//! A rigid body of `satellite_mass`, principal moments `satellite_inertia` and centre of mass
//! `satellite_cg` (relative to the root attachment point), with input-driven force and torque
//! in the world or body frame and attitude, rate, position and momentum outputs; frames in
//! [`satellite`] and docs/panel_lock_satellite.md. The flexible panels' deflection outputs:
//! [`flex_outputs`].
//!
//! # Flexible panels (`flexible_panels`, `n_modes`)
//! Each panel becomes a modal body: an ACM plate model (`panel_mesh` 8 x 4 elements) of the
//! equivalent homogeneous honeycomb plate, reduced by Craig-Bampton with the body frame clamped
//! at the inboard hinge node (mid-width of the inboard edge) and, on inner panels, the outboard
//! hinge node (mid-width of the outboard edge) as interface; the hinge bolts and the next
//! hinge's shaft, latch, spring and stop frames ride on those nodes. `n_modes` fixed-interface
//! modes per panel (plus 3 interface coordinates on inner panels). Off: rigid panels, no modal
//! coordinates. The FE model and reduction are cached per panel description (see
//! [`flex_panel`]): 6.5 ms per inner + outer panel at the default mesh, 0.3 s at 20 x 10.
//!
//! Defaults of the panel plate and why:
//! - `panel_youngs_modulus` 3.0 GPa, Poisson 0.3 over the 25 mm thickness: the bending rigidity
//!   `D = 4.3 kN m` of a CFRP-face sandwich (two 0.2 mm faces of 70 GPa on a 25 mm core); first
//!   cantilever mode of a 2 m panel about 7.5 Hz, typical of deployed-array panels.
//! - `panel_nonstructural_mass` 0.6 kg/m^2 (cells and harness) of the 1.5 kg/m^2 total, so the
//!   equivalent structural density is 36 kg/m^3. The panel mass is the same as the rigid one.
//! - `modal_damping_ratio` 0.005 (0.5 %, a bonded-honeycomb structure).
//!
//! The paper configuration [`PanelLockParams::flexible`] also sets **zero-backlash latches**
//! (groove width = pin diameter) on a **50 mm cam**. Why: with the default 2 mm of play the
//! locked array does not vibrate as a structure; the pins rattle between the groove walls and the
//! tip velocity is dominated by a 0.05 Hz slosh that hardly depends on the contact stiffness,
//! whereas the paper's post-lock frequency doubles from k = 1e7 to 1e8 (the contact is part of
//! the locked structure). With the pin seated against the front wall by the deployment-spring
//! preload, each hinge has the linearized stiffness `n k delta^(n-1) r_s^2` at the static
//! penetration `delta`; with `r_s` = 47 mm the recommended set (k = 1e7, n = 1.5) gives
//! 0.161 Hz for the three-panel array (paper: 0.167 Hz measured and simulated), k = 1e8 gives
//! 0.340 Hz (paper 0.317). The panel modulus barely moves these numbers (the latches are an
//! order of magnitude softer than the panels, as the paper's 1.9 frequency ratio against the
//! contact-only 2.15 suggests), so the tuning is done on the latch geometry, the panel
//! properties stay at physical values. The rigid defaults keep the 2 mm play (rigid tests).

pub mod array;
mod array_file;
mod build;
pub mod calibration;
mod cosim;
mod demo;
mod dependencies;
mod events;
pub mod flex_outputs;
pub mod flex_panel;
pub mod interface;
pub mod locked_frequency;
mod params;
pub mod ports;
pub mod power_ports;
mod run;
pub mod satellite;
pub mod study;
pub mod trace;
mod view;

pub use array::{HingeTable, HingeValues, PanelTable, PanelValues};
pub use build::{Layout, build};
pub use cosim::{PanelLockModel, create};
pub use demo::run_demo;
pub use params::{
    DEFAULT_ATOL, DEFAULT_PANEL_E, DEFAULT_RTOL, ErrorControl, LoadFrame, PanelLockParams,
    Reduction, TREE_ATOL, TREE_RTOL, default_tolerances,
};
pub use ports::info;
pub use run::{HingeOutput, PanelLock, PanelLockOutputs};
pub use satellite::SatelliteOutput;
pub use view::SATELLITE_EDGE;
