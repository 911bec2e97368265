//! RopeBlock physics tests against independent references (one test binary for build speed).

mod edge;
mod friction;
mod geometry;
mod hanging;
mod hard_cases;
mod jacobian;
mod rig;
mod slings;
