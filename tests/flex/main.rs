//! Flexible bodies against references (one test binary for build speed, as `tests/rope/`):
//! clamped, free and hinged plates, the flexible pendulum and the flexible-body Jacobians.

#[path = "../common/mod.rs"]
mod common;

mod flex_clamped;
mod flex_free;
mod flex_hinged;
mod flex_jacobians;
mod flex_pendulum;
