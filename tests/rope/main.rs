//! RopeBlock physics tests against independent references (one test binary for build speed).

mod geometry;
mod jacobian;
