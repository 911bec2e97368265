//! Checks of output values that no other test covered (issue #42, item 5: an independent check
//! for every output; the list is `tests/output_contract/checks.rs`). Each compares an output with
//! something the code that computes it does not use: a hand calculation, the derivative of
//! another output, a conservation or work balance, or the solver's own counters read another way.
//! One test binary for build speed: `cargo test --release --test output_checks`.

#[path = "../common/mod.rs"]
mod common;
mod panel_lock;
mod panel_lock_bonds;
mod pid;
mod rope_block;
mod rope_bonds;

/// Largest absolute value in `xs` (0 for none).
pub fn largest(xs: impl IntoIterator<Item = f64>) -> f64 {
    xs.into_iter().fold(0.0, |a, x| a.max(x.abs()))
}
