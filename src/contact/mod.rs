//! Normal contact: force laws for impacts (Hertz and three hysteresis-damped variants) and the
//! pin-in-groove geometry of the solar-array hinge latch.
//!
//! # Laws
//! [`ContactLaw`] evaluates, for penetration `delta` [m] and penetration rate `delta_dot` [m/s]
//! (positive while approaching),
//!
//! ```text
//! F = k delta^n [1 + chi(e) delta_dot / delta_dot_minus]      (delta > 0;  F = 0 otherwise)
//! ```
//!
//! with `chi = 0` (Hertz), `3(1-e^2)/4` (Lankarani-Nikravesh), `3(1-e)/2` (Hunt-Crossley) or
//! `8(1-e)/(5e)` (Flores), and returns `F` with `dF/d delta` and `dF/d delta_dot` for the Newton
//! matrices of implicit integrators ([`ContactForce`]).
//!
//! Decisions:
//! - **No adhesion**: a contact never pulls. When the bracket turns negative during restitution
//!   the force is clamped to 0 and both derivatives are 0, consistent with the clamp. The
//!   effective-restitution reference table (mass 1 kg, 1 m/s, `n = 1.5`, nominal e 0.95 ... 0.2)
//!   is reproduced with this clamp and equally without it, because in an isolated impact the
//!   clamp can never act: as the rate approaches `-delta_dot_minus / chi` the bracket, and with it
//!   the deceleration, tends to zero, so the rebound speed stays below that threshold (Flores at
//!   e = 0.2 comes closest: 0.15554 v0 against 0.15625 v0). The clamp acts when other forces pull
//!   the bodies apart faster than that during restitution (tested with a constant pull).
//! - **Approach speed** `delta_dot_minus`: recorded by the caller at contact onset with
//!   [`ApproachMemory`]; the law divides by `max(delta_dot_minus, v_floor)` with the floor
//!   [`DEFAULT_MIN_APPROACH_SPEED`] = 1e-4 m/s (configurable). Unknown speed (0 or NaN) uses the
//!   floor, i.e. the strongest damping the law allows.
//! - Energy: [`ContactLaw::potential_energy`] is the elastic energy `k delta^(n+1)/(n+1)` and
//!   [`ContactForce::dissipated_power`] is `F_damp delta_dot >= 0`.
//!
//! # Latch
//! [`latch`] computes, from the relative hinge angle, the penetration of the latch pin into the
//! two side walls of the groove with parry3d-f64, their normals, moment arms and `d delta/d theta`.
//!
//! Conversions: parry3d-f64 0.31 works in glam types; this module converts at its boundary and
//! exposes only `nalgebra` types ([`crate::math::Vec3`]) and `f64`.

mod approach;
mod error;
pub mod flores;
pub mod hertz;
pub mod hunt_crossley;
pub mod lankarani_nikravesh;
pub mod latch;
mod law;

pub use approach::ApproachMemory;
pub use error::ContactError;
pub use latch::{LatchContact, LatchGeometry, LatchParams, Wall, WallContact};
pub use law::{ContactForce, ContactLaw, DEFAULT_MIN_APPROACH_SPEED, LawKind};
