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

mod build;
mod cosim;
mod demo;
pub mod flex_panel;
mod params;
pub mod ports;
mod run;
pub mod study;

pub use build::{Layout, build};
pub use cosim::{PanelLockModel, create};
pub use demo::run_demo;
pub use params::{DEFAULT_PANEL_E, PanelLockParams, Reduction};
pub use ports::info;
pub use run::{HingeOutput, PanelLock, PanelLockOutputs};
