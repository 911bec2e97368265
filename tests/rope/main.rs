//! RopeBlock physics tests against independent references (one test binary for build speed).

mod edge;
mod geometry;
mod jacobian;
mod rig;
