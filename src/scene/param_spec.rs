//! One parameter specification for every model (issue #43 item 3, docs/parameter_spec.md).
//!
//! A model declares each real parameter once as a [`RealSpec`] over its own parameter struct
//! `P`: name, unit, description, the range it accepts ([`Bounds`]), its start value (the default
//! of `P` unless given) and how it is read from and written onto `P`. The variable table
//! ([`RealSpec::port`]), and through it `modelDescription.xml`, the variable documentation, the
//! CLI's `--set` checks, the FMU's set checks and the adversarial envelope (which reads the
//! declared ranges), all read this declaration. The solver knobs `rtol`, `atol` and `h_max` are
//! declared once, here ([`solver`]), for every model that has them ([`SolverKnobs`]).

use super::port::{PortSpec, ValueRef, Variability};

/// Decades either side of a parameter's default that an envelope range spans
/// ([`Bounds::Positive`], [`Bounds::NonNegative`]).
pub const ENVELOPE_DECADES: i32 = 3;

/// A parameter's accepted set: inclusive bounds as the validation writes them, `open[0]` /
/// `open[1]` when the bound itself is refused; `None`: no bound on that side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower bound (in the parameter's unit).
    pub min: Option<f64>,
    /// Upper bound (in the parameter's unit).
    pub max: Option<f64>,
    /// The lower (`[0]`) or upper (`[1]`) bound is excluded.
    pub open: [bool; 2],
    /// With `min` 0 meaning a default: the smallest positive value in the set (values in
    /// `(0, floor)` are not).
    pub floor: Option<f64>,
}

impl Range {
    /// `[min, max]`, either end optional.
    pub const fn closed(min: Option<f64>, max: Option<f64>) -> Self {
        Range {
            min,
            max,
            open: [false; 2],
            floor: None,
        }
    }

    /// `{0} U [floor, max]`: 0 means a default (the solver tolerances).
    pub const fn zero_or(floor: f64, max: f64) -> Self {
        Range {
            min: Some(0.0),
            max: Some(max),
            open: [false; 2],
            floor: Some(floor),
        }
    }

    /// True when `v` is finite and in the set.
    pub fn contains(&self, v: f64) -> bool {
        let below = self
            .min
            .is_some_and(|lo| v < lo || (self.open[0] && v == lo));
        let above = self
            .max
            .is_some_and(|hi| v > hi || (self.open[1] && v == hi));
        let in_gap = self.floor.is_some_and(|f| v != 0.0 && v < f);
        v.is_finite() && !below && !above && !in_gap
    }
}

/// How a real parameter's range is declared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bounds {
    /// Finite and > 0, within [`ENVELOPE_DECADES`] either side of the default, and at most
    /// `cap` when given (the model's generic positivity check applies).
    Positive {
        /// Upper bound below the envelope's (e.g. 1 for a restitution).
        cap: Option<f64>,
    },
    /// Finite and >= 0, at most [`ENVELOPE_DECADES`] above the default (no upper bound for a
    /// default of 0), and at most `cap` when given.
    NonNegative {
        /// Upper bound below the envelope's.
        cap: Option<f64>,
    },
    /// A range of its own (checked by the model's rules for that parameter).
    Fixed(Range),
}

impl Bounds {
    /// The range these bounds give for a parameter whose default is `default`.
    pub fn range(&self, default: f64) -> Range {
        let k = 10f64.powi(ENVELOPE_DECADES);
        let capped = |hi: Option<f64>, cap: Option<f64>| match (hi, cap) {
            (Some(h), Some(c)) => Some(h.min(c)),
            (h, None) => h,
            (None, c) => c,
        };
        match *self {
            Bounds::Positive { cap } => {
                Range::closed(Some(default / k), capped(Some(default * k), cap))
            }
            Bounds::NonNegative { cap } => Range::closed(
                Some(0.0),
                capped((default > 0.0).then_some(default * k), cap),
            ),
            Bounds::Fixed(r) => r,
        }
    }
}

/// One real parameter of a model whose parameters are the struct `P`.
pub struct RealSpec<P> {
    /// Variable name (`rtol`, `panel_length`).
    pub name: &'static str,
    /// SI unit symbol, `None` for dimensionless values (or where no unit can be declared).
    pub unit: Option<&'static str>,
    /// Unit shown in the documentation where none can be declared (`N/m^n`).
    pub unit_note: Option<&'static str>,
    /// What the value is.
    pub description: &'static str,
    /// A model's sentence appended to a shared declaration's description (e.g. over what the
    /// tolerance is held).
    pub note: Option<&'static str>,
    /// Fixed (before initialization) or tunable.
    pub variability: Variability,
    /// The accepted range.
    pub bounds: Bounds,
    /// The value acts only once the model moves: no output depends on it at initialization (the
    /// model's `dependencies` of its initial unknowns leave it out).
    pub motion_only: bool,
    /// Start value where it is not `get` of `P`'s default (an effect switched off by default
    /// that keeps a value for when it is switched on).
    pub start: Option<f64>,
    /// Reads the value from the model's parameters.
    pub get: fn(&P) -> f64,
    /// Writes the value onto the model's parameters.
    pub set: fn(&mut P, f64),
}

impl<P> RealSpec<P> {
    /// A fixed parameter with a start taken from `P`'s default.
    pub const fn new(
        name: &'static str,
        unit: Option<&'static str>,
        bounds: Bounds,
        description: &'static str,
        get: fn(&P) -> f64,
        set: fn(&mut P, f64),
    ) -> Self {
        RealSpec {
            name,
            unit,
            unit_note: None,
            description,
            note: None,
            variability: Variability::Fixed,
            bounds,
            motion_only: false,
            start: None,
            get,
            set,
        }
    }

    /// The same with the documentation's unit `note` ([`RealSpec::unit_note`]).
    pub const fn unit_note(mut self, note: &'static str) -> Self {
        self.unit_note = Some(note);
        self
    }

    /// The same with the model's sentence after the description ([`RealSpec::note`]).
    pub const fn note(mut self, note: &'static str) -> Self {
        self.note = Some(note);
        self
    }

    /// The same, tunable (settable between communication steps).
    pub const fn tunable(mut self) -> Self {
        self.variability = Variability::Tunable;
        self
    }

    /// The same, acting only once the model moves ([`RealSpec::motion_only`]).
    pub const fn motion_only(mut self) -> Self {
        self.motion_only = true;
        self
    }

    /// The same with its own start value ([`RealSpec::start`]).
    pub const fn start(mut self, start: f64) -> Self {
        self.start = Some(start);
        self
    }

    /// The start value, with `default` the model's default parameters.
    pub fn start_value(&self, default: &P) -> f64 {
        self.start.unwrap_or_else(|| (self.get)(default))
    }

    /// The accepted range, with `default` the model's default parameters.
    pub fn range(&self, default: &P) -> Range {
        self.bounds.range((self.get)(default))
    }

    /// The description with the model's note.
    pub fn full_description(&self) -> String {
        match self.note {
            Some(n) => format!("{} {n}", self.description),
            None => self.description.to_string(),
        }
    }

    /// The variable-table row at value reference `vr`.
    pub fn port(&self, vr: ValueRef, default: &P) -> PortSpec {
        let mut spec = PortSpec::real_parameter(
            self.name,
            vr,
            self.variability,
            self.start_value(default),
            self.unit,
            &self.full_description(),
        );
        let r = self.range(default);
        if let Some(lo) = r.min {
            spec = if r.open[0] {
                spec.with_open_min(lo)
            } else {
                spec.with_min(lo)
            };
        }
        if let Some(hi) = r.max {
            spec = if r.open[1] {
                spec.with_open_max(hi)
            } else {
                spec.with_max(hi)
            };
        }
        if let Some(note) = self.unit_note {
            spec = spec.with_unit_note(note);
        }
        if let Some(f) = r.floor {
            spec = spec.with_floor(f);
        }
        spec
    }
}

/// Names of the parameters in `table` that act only once the model moves
/// ([`RealSpec::motion_only`]).
pub fn motion_only_names<P>(table: &[RealSpec<P>]) -> impl Iterator<Item = &'static str> + '_ {
    table.iter().filter(|s| s.motion_only).map(|s| s.name)
}

/// The spec named `name` in a model's table.
pub fn find<'a, P>(table: &'a [RealSpec<P>], name: &str) -> Option<&'a RealSpec<P>> {
    table.iter().find(|s| s.name == name)
}

/// Parameters that carry the shared integrator settings.
pub trait SolverKnobs {
    /// `[rtol, atol, h_max]`.
    fn knobs(&self) -> [f64; 3];
    /// The same, to write.
    fn knobs_mut(&mut self) -> [&mut f64; 3];
}

/// The shared solver knobs `rtol`, `atol` and `h_max`, declared once for every model
/// (docs/parameter_spec.md gives the ranges' reasons).
pub mod solver {
    use super::{Bounds, Range, RealSpec, SolverKnobs};
    use crate::integrator::{MIN_ATOL, MIN_RTOL};

    /// Largest `rtol` [-]: a tenth, beyond which error control no longer controls anything.
    pub const MAX_RTOL: f64 = 0.1;
    /// Largest `atol` (m, rad, m/s, rad/s): the size of the models' own coordinates.
    pub const MAX_ATOL: f64 = 1.0;
    /// Smallest `h_max` [s] a model accepts: bounds the work of one communication step (at
    /// 1e-6 s RopeBlock's default lift took over 60 s CPU for 0.5 s, PanelLock's 2.4 s per
    /// simulated second at 1e-5 s); the integrators' own floor,
    /// [`crate::integrator::MIN_H_MAX`] (1e-8 s), stays for scenes built in Rust.
    pub const MIN_H_MAX: f64 = 1e-4;
    /// Largest `h_max` [s]: both models' communication steps are far below it.
    pub const MAX_H_MAX: f64 = 1.0;

    fn get<P: SolverKnobs, const I: usize>(p: &P) -> f64 {
        p.knobs()[I]
    }

    fn set<P: SolverKnobs, const I: usize>(p: &mut P, v: f64) {
        let knobs = p.knobs_mut();
        *knobs[I] = v;
    }

    /// `rtol`: relative error tolerance (like `atol` and `h_max`, it acts only once the model
    /// moves).
    pub const fn rtol<P: SolverKnobs>() -> RealSpec<P> {
        RealSpec::new(
            "rtol",
            None,
            Bounds::Fixed(Range::zero_or(MIN_RTOL, MAX_RTOL)),
            "Relative error tolerance of the adaptive integrators; 0: the integrator's own default (listed with the model's integrators); otherwise at least 1e3 machine epsilons (2.2e-13).",
            get::<P, 0>,
            set::<P, 0>,
        )
        .motion_only()
    }

    /// `atol`: absolute error tolerance.
    pub const fn atol<P: SolverKnobs>() -> RealSpec<P> {
        RealSpec::new(
            "atol",
            None,
            Bounds::Fixed(Range::zero_or(MIN_ATOL, MAX_ATOL)),
            "Absolute error tolerance of the integrator (m, rad, m/s, rad/s); 0: the integrator's own default (listed with the model's integrators); otherwise at least 1e-15.",
            get::<P, 1>,
            set::<P, 1>,
        )
        .motion_only()
        .unit_note("m, rad, m/s, rad/s")
    }

    /// `h_max`: largest internal step.
    pub const fn h_max<P: SolverKnobs>() -> RealSpec<P> {
        RealSpec::new(
            "h_max",
            Some("s"),
            Bounds::Fixed(Range::closed(Some(MIN_H_MAX), Some(MAX_H_MAX))),
            "Largest internal step.",
            get::<P, 2>,
            set::<P, 2>,
        )
        .motion_only()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Default)]
    struct Knobs([f64; 3]);

    impl SolverKnobs for Knobs {
        fn knobs(&self) -> [f64; 3] {
            self.0
        }
        fn knobs_mut(&mut self) -> [&mut f64; 3] {
            let [a, b, c] = &mut self.0;
            [a, b, c]
        }
    }

    #[test]
    fn shared_knobs_read_and_write_their_own_slot() {
        let specs = [solver::rtol::<Knobs>(), solver::atol(), solver::h_max()];
        let mut k = Knobs::default();
        for (i, s) in specs.iter().enumerate() {
            (s.set)(&mut k, i as f64 + 1.0);
        }
        assert_eq!(k.0, [1.0, 2.0, 3.0]);
        assert_eq!(specs.map(|s| (s.get)(&k)), [1.0, 2.0, 3.0]);
    }

    #[test]
    fn envelope_bounds_span_three_decades_and_obey_their_cap() {
        let r = Bounds::Positive { cap: Some(1.0) }.range(0.8);
        assert_eq!((r.min, r.max), (Some(0.8e-3), Some(1.0)));
        let r = Bounds::Positive { cap: None }.range(2.0);
        assert_eq!((r.min, r.max), (Some(2e-3), Some(2e3)));
        let r = Bounds::NonNegative { cap: None }.range(0.0);
        assert_eq!((r.min, r.max), (Some(0.0), None));
        let r = Bounds::NonNegative { cap: Some(1.0) }.range(0.0);
        assert_eq!((r.min, r.max), (Some(0.0), Some(1.0)));
    }

    #[test]
    fn open_bounds_are_refused_and_closed_ones_accepted() {
        let r = Range {
            min: Some(0.0),
            max: Some(1.0),
            open: [false, true],
            floor: None,
        };
        assert!(r.contains(0.0));
        assert!(!r.contains(1.0));
        assert!(r.contains(1.0f64.next_down()));
        assert!(!r.contains(f64::NAN));
        assert!(!r.contains(-1e-300));
    }

    #[test]
    fn the_port_carries_range_start_and_note() {
        let s = solver::rtol::<Knobs>().note("Held per step.").start(1e-4);
        let p = s.port(7, &Knobs::default());
        assert_eq!(p.vr, 7);
        assert_eq!(
            p.description,
            "Relative error tolerance of the adaptive integrators; 0: the integrator's own default (listed with the model's integrators); otherwise at least 1e3 machine epsilons (2.2e-13). Held per step."
        );
        match p.ty {
            crate::scene::port::PortType::Real {
                start, min, max, ..
            } => {
                assert_eq!(start, Some(1e-4));
                // 0 is the integrator's own default; (0, 1e3 eps) is refused where it is set
                assert_eq!(min, Some(0.0));
                let r = s.range(&Knobs::default());
                assert!(r.contains(0.0) && r.contains(1e3 * f64::EPSILON) && !r.contains(1e-14));
                assert_eq!(max, Some(0.1));
            }
            _ => panic!("not real"),
        }
    }
}
