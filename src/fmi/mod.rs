//! FMI 2.0 and FMI 3.0 Co-Simulation wrapper around any [`crate::scene::CoSimModel`].
//!
//! FMI 3.0 (docs/fmi3.md) drives the same [`instance::Instance`], state machine and variable
//! table: [`types3`], [`variables3`] (FMI 3.0 value references), [`arrays3`] (families of
//! outputs as FMI 3.0 arrays), `exports3` (every `fmi3*` function), [`model_description3`], and
//! [`package::pack3`] for `dist/fmi3/<Model>.fmu`.
//!
//! The only module with `unsafe` code and the C ABI. One generic wrapper serves every model in
//! [`crate::scene::registry()`]: `fmi2Instantiate` picks the model by GUID, and the same shared
//! library ships in every FMU as `binaries/linux64/<modelIdentifier>.so`, built for x86_64
//! Windows and aarch64 Linux beside it ([`platform`]).
//!
//! - [`types`]: hand-written `#[repr(C)]` FMI 2.0 types.
//! - [`exports`](self#functions): the 34 `fmi2*` functions (re-exported here).
//! - [`boundary`]: panic guard and pointer conversions; [`handle`]: instance handles (magic
//!   number, freed handles, calls from inside the instance's callbacks); [`instance`]: the state machine and the
//!   function bodies in safe Rust; [`machine`]: states and per-function masks; [`logger`]: log
//!   categories and filters; [`resource_location`]: the resources folder and its scene file; [`snapshot`]: FMU states and their byte format.
//! - [`model_description`] and [`units`]: `modelDescription.xml` from a variable table;
//!   [`package`] and [`documentation`]: the `.fmu` archive.
//! - `c_math`: the C math symbols (`sin`, `pow`, ...) every artifact links to, from the `libm`
//!   crate, so that every platform computes the same bits (docs/platforms.md).
#![allow(unsafe_code, non_snake_case, non_upper_case_globals)]

pub mod arrays3;
pub mod boundary;
#[cfg(any(
    all(
        target_arch = "x86_64",
        any(target_os = "linux", target_os = "windows")
    ),
    all(target_arch = "aarch64", target_os = "linux")
))]
pub mod c_math;
pub mod documentation;
mod exports;
mod exports3;
pub mod handle;
pub mod instance;
pub mod intermediate;
pub mod logger;
pub mod machine;
pub mod metadata;
pub mod model_description;
pub mod model_description3;
pub mod osp;
pub mod package;
pub mod platform;
pub mod resource_location;
pub mod sketch;
pub mod snapshot;
#[cfg(test)]
mod test_probe;
pub mod types;
pub mod types3;
pub mod units;
pub mod variables3;

pub use exports::*;
pub use exports3::*;
