//! The RopeBlock scene: wire ropes (lumped masses) lifting a ship block, contacting its shell plate
//! edges through contact nodes.
//!
//! - [`structure`]: the scene as plain data (blocks, loads, hooks, ropes and their nodes);
//! - [`build`]: the multibody model assembled from it, and the state carried back into it;
//! - [`manager`]: the contact manager after every step (stick/slip, leaving the edge, sliding
//!   along it, new crossings, re-meshing);
//! - [`edit`]: structural edits that conserve mass, momentum and rope length;
//! - [`runner`]: the running simulation with rebuilds;
//! - [`cosim`], [`ports`], [`persist`]: the co-simulation model (variable table, state bytes).

pub mod bonds;
pub mod build;
pub mod cosim;
pub mod demo;
pub mod demo_plots;
mod dependencies;
pub mod edit;
mod events;
pub mod manager;
pub mod params;
pub mod persist;
pub mod ports;
pub mod power_ports;
pub mod rig;
pub mod rig_checks;
pub mod rig_dampers;
pub mod rig_digest;
pub mod rig_file;
pub mod rigging;
pub mod runner;
pub mod scene;
pub mod statics;
pub mod structure;
pub mod view;

pub use cosim::{RopeBlockModel, create};
pub use manager::{ContactSettings, Counters, Edit, NodeReport};
pub use params::{RopeBlockParams, Route};
pub use ports::info;
pub use rig::{BlockGeometry, BlockPose, BlockRig, Lug, Plate, Rig, RigHook, RigSling};
pub use runner::RopeBlockSim;
pub use scene::RopeBlockScene;
pub use structure::{
    BlockSpec, BodyRef, DamperSpec, EndSpec, ForceSpec, LoadSpec, NodeContact, NodeSpec, RopeSpec,
    Structure,
};
