//! Lumped-mass wire rope with contact nodes on the plate edges of a rigid block (seed 001).
//!
//! Filled in with the mechanics decisions below.

pub mod assemble;
pub mod bending;
pub mod cone;
pub mod drag;
pub mod edge_hold;
pub mod effect;
pub mod friction;
pub mod layout;
pub mod memory;
pub mod node;
pub mod props;
pub mod run;
pub mod segment;
pub mod shell;
pub mod slip;
#[cfg(test)]
mod slip_dense;
#[cfg(test)]
mod winch_pull_tests;

pub use effect::{NodeSegments, RopeEffect};
pub use layout::{
    ContactInit, EdgeHold, HookInit, HookMode, LayoutPoint, LayoutRope, PointAt, SlipMode, hermite,
    ramped,
};
pub use memory::{CONTACT_MEM, ContactRecord, HOOK_MEM, HookRecord, RopeMemory};
pub use props::RopeProps;
