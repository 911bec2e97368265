//! # mbcosim: multibody dynamics packaged as FMI 2.0 and FMI 3.0 co-simulation FMUs
//!
//! Floors, top first; a module imports only from the floors below its own
//! (`tests/layering.rs`, `imports_follow_the_floors_of_the_map`, checks every arrow; the two
//! exceptions and their reasons: docs/architecture.md):
//!
//! ```text
//! fmi                          C boundary (FMI 2.0 and 3.0), modelDescription.xml, FMU packing
//! scene                        co-simulation framework, the models, their demos and studies
//! report                       plots, spectra, work-precision tables   (imports scene: exception)
//! sim                          system + state + integrator, snapshots
//! integrator                   generalized-alpha, BDF, DOPRI5, joint-coordinate RK pairs
//! tree                         joint coordinates of kinematic trees
//! dae                          the system as integrators see it, Newton solves
//! rope                         rope physics (material coordinates, shell contact)
//! effect                       force elements and joint constraints
//! model                        bodies, joints, elements; the builder   (imports effect: exception)
//! contact   flex   state       contact laws and latch geometry; modal bodies; the state
//! math   bounded_file          nalgebra aliases, SO(3) maps; size-limited file reads
//! ```
//!
//! - [`math`]: nalgebra aliases, SO(3) exponential/logarithm maps.
//! - [`bounded_file`]: file reads with a size limit (scene files, meshes).
//! - [`state`]: the mutable state, a plain `Clone`.
//! - [`contact`]: contact force laws (Hertz, Lankarani-Nikravesh, Hunt-Crossley, Flores) and the
//!   latch pin/groove geometry.
//! - [`flex`]: plate/beam finite elements, modal reduction (Craig-Bampton, free-interface) and
//!   the inertia invariants of floating-frame flexible bodies.
//! - [`model`]: immutable description of bodies, joints and force elements (validating builder).
//! - [`effect`]: force elements and joint constraints with analytic Jacobians.
//! - [`rope`]: the rope effect, its memory view, shell meshes and contact geometry.
//! - [`dae`]: the system as integrators see it; sparse/dense Newton solves.
//! - [`tree`]: joint coordinates of kinematic trees (detection, mapping, joint-space dynamics).
//! - [`integrator`]: generalized-alpha, BDF, DOPRI5 (maximal coordinates), DOPRI5 and Verner
//!   pairs in joint coordinates, behind one trait.
//! - [`sim`]: a simulation (system + state + integrator) with snapshots.
//! - [`report`]: plots (SVG), spectra and the work-precision report.
//! - [`scene`]: the co-simulation framework (the FMI-agnostic [`scene::CoSimModel`], variable
//!   tables, the parameter spec, the port store, the step check and clock, state bytes) and the
//!   models ([`scene::panel_lock`], [`scene::rope_block`], [`scene::pid`],
//!   [`scene::spring_mass_damper`], the smallest example of a model on the solver).
//! - [`fmi`]: the FMI 2.0 and FMI 3.0 Co-Simulation wrappers, `modelDescription.xml` writers and
//!   FMU packer; the only module with `unsafe` code and the only panic boundary.
//!
//! Units are SI throughout. Nothing outside `fmi` knows that FMI exists.
#![deny(unsafe_code)]

pub mod bounded_file;
pub mod contact;
pub mod dae;
pub mod effect;
pub mod flex;
pub mod fmi;
pub mod integrator;
pub mod math;
pub mod model;
pub mod report;
pub mod rope;
pub mod scene;
pub mod sim;
pub mod state;
pub mod tree;
