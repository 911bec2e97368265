//! RopeBlock physics tests against independent references (one test binary for build speed).

mod at_rest;
mod bordered;
mod capstan;
mod cone;
mod edge;
mod friction;
mod geometry;
mod hanging;
mod hard_cases;
mod jacobian;
mod lift_cone;
mod mass_split;
mod memory;
mod pull_speed;
mod pulled;
mod reported_cone;
mod reports;
mod rig;
mod slings;
