//! Locating a contact event (a closing or an opening) inside a step and recording it once a step
//! lands on it, shared by the integrators that land their steps on events (DOPRI5 and adaptive
//! generalized-alpha); each supplies its own interpolant inside the step.

use super::time_eps;
use crate::dae::System;
use crate::effect::MemoryChange;
use crate::state::State;

/// Fraction of a step to which an event is located.
pub const LOCATION_TOLERANCE: f64 = 1e-12;

/// The first crossing of an event function inside a step: `g0 = f(0) <= 0 < f(1) = g1`, with
/// `f(theta)` the function at the fraction `theta` of the step on the integrator's interpolant.
/// Illinois (modified regula falsi) to [`LOCATION_TOLERANCE`] of the step; returns the end of
/// the final bracket where the function is positive (the event has happened there).
pub fn first_crossing(g0: f64, g1: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    if g0 == 0.0 {
        return 0.0;
    }
    let (mut a, mut fa, mut b, mut fb) = (0.0, g0, 1.0, g1);
    // which end was kept by the last update (-1: `a`, 1: `b`), to halve the stale end's value
    let mut kept = 0i8;
    for _ in 0..100 {
        if b - a <= LOCATION_TOLERANCE {
            break;
        }
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
        }
        let fm = f(m);
        if !fm.is_finite() {
            break;
        }
        if fm > 0.0 {
            (b, fb) = (m, fm);
            if kept == 1 {
                fa *= 0.5;
            }
            kept = 1;
        } else {
            (a, fa) = (m, fm);
            if kept == -1 {
                fb *= 0.5;
            }
            kept = -1;
        }
    }
    b
}

/// The earliest contact events inside a step, from the event functions at its start (`g0`) and
/// end (`g1`) and `gap(theta, i)`, event function `i` at the fraction `theta` of the step on the
/// integrator's interpolant. Returns that fraction and leaves in `landing` every event located
/// within 1e-9 of it (a symmetric body landing on several points lands on all at once); `None`
/// when no function goes from `<= 0` to `> 0`. `roots` is scratch.
fn earliest_events(
    g0: &[f64],
    g1: &[f64],
    roots: &mut Vec<(usize, f64)>,
    landing: &mut Vec<usize>,
    mut gap: impl FnMut(f64, usize) -> f64,
) -> Option<f64> {
    landing.clear();
    roots.clear();
    for (i, (&a, &b)) in g0.iter().zip(g1).enumerate() {
        if a <= 0.0 && b > 0.0 {
            roots.push((i, first_crossing(a, b, |m| gap(m, i))));
        }
    }
    let first = roots.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
    if !first.is_finite() {
        return None;
    }
    let same = first + 1e-9;
    landing.extend(roots.iter().filter(|r| r.1 <= same).map(|r| r.0));
    Some(first)
}

/// The buffers and bookkeeping of contact-event location for one integrator (sized only for
/// models with contact events, see [`System::n_contact_events`]).
#[derive(Debug, Clone, Default)]
pub struct EventLocator {
    /// Event functions at the step's start, at its end and at a trial instant.
    pub g0: Vec<f64>,
    pub g1: Vec<f64>,
    pub gt: Vec<f64>,
    /// Events located in a step (index, fraction of the step).
    roots: Vec<(usize, f64)>,
    /// Events the step being retaken ends on: recorded after it is accepted.
    pub landing: Vec<usize>,
    /// The state's effect memory before the step hook of a step that lands on events.
    step_start_memory: Vec<f64>,
}

impl EventLocator {
    /// Sizes the buffers for the event functions of `sys`, and an integrator's scratch for its
    /// interpolant inside a step (chart coordinates and speeds of `n_v`, positions of `n_q`):
    /// nothing for models without contact events.
    pub fn size_for(
        &mut self,
        sys: &System,
        xd: &mut Vec<f64>,
        vd: &mut Vec<f64>,
        qd: &mut Vec<f64>,
    ) {
        let n_on = sys.n_contact_events();
        if n_on == 0 {
            return;
        }
        self.resize(n_on);
        xd.resize(sys.n_v(), 0.0);
        vd.resize(sys.n_v(), 0.0);
        qd.resize(sys.n_q(), 0.0);
    }

    /// Sizes the buffers for `n` event functions.
    pub fn resize(&mut self, n: usize) {
        for g in [&mut self.g0, &mut self.g1, &mut self.gt] {
            g.resize(n, 0.0);
        }
    }

    /// At the start of a trial step: the step cut to land on an event (`cut`, taken), or `None`
    /// for a step of the integrator's own choice, which forgets the events of a previous trial.
    pub fn begin_trial(&mut self, cut: &mut Option<f64>) -> Option<f64> {
        let h_on = cut.take();
        if h_on.is_none() {
            self.landing.clear();
        }
        h_on
    }

    /// Whether an event function is positive at the step's end (`g1`, filled by the caller).
    pub fn end_has_event(&self) -> bool {
        self.g1.iter().any(|g| *g > 0.0)
    }

    /// After a step from `st` whose end's event functions are in `g1`: the earliest contact
    /// closing or opening inside it, as a fraction of the step, located to
    /// [`LOCATION_TOLERANCE`] of the step; `fill(sys, theta, out)` writes every event function at
    /// the fraction `theta` on the integrator's interpolant. `landing` then holds the events at
    /// that instant. `None`: no contact closes or opens.
    pub fn locate(
        &mut self,
        sys: &mut System,
        st: &State,
        mut fill: impl FnMut(&mut System, f64, &mut [f64]),
    ) -> Option<f64> {
        self.landing.clear();
        if !self.end_has_event() {
            return None;
        }
        sys.contact_event_functions(st.t, &st.q, &st.v, &mut self.g0);
        let EventLocator {
            g0,
            g1,
            gt,
            roots,
            landing,
            ..
        } = self;
        earliest_events(g0, g1, roots, landing, |m, i| {
            fill(sys, m, gt);
            gt[i]
        })
    }

    /// What a step of `h` [s] from `t` [s] does about an event located at the fraction `theta`
    /// of it: `Some(h_on)`, the step to take instead so that it ends at the event; `None` when
    /// the step may stand (the event is at its end, `landing` kept, or at its start, where there
    /// is nothing to land on: `landing` cleared).
    pub fn landing_step(&mut self, theta: f64, t: f64, h: f64) -> Option<f64> {
        let h_on = theta * h;
        if h_on <= time_eps(t) {
            self.landing.clear();
            None
        } else if (1.0 - theta) * h > time_eps(t + h) {
            Some(h_on)
        } else {
            None
        }
    }

    /// Before the step hook of an accepted step: keeps the memory at the step's start, under
    /// which the events it lands on are defined.
    pub fn before_hook(&mut self, st: &State) {
        if !self.landing.is_empty() {
            self.step_start_memory.clone_from(&st.memory);
        }
    }

    /// After the step hook (whose memory update decides by the sign of a penetration that is
    /// zero to the step's accuracy): records that the events the step landed on happen at `st`,
    /// and forgets them. Returns whether the forces jump there.
    pub fn record(&mut self, sys: &mut System, st: &mut State) -> bool {
        let mut jump = false;
        for &i in &self.landing {
            let (q, v, mem) = (&st.q, &st.v, &mut st.memory);
            jump |= sys.record_contact_event(st.t, q, v, &self.step_start_memory, mem, i)
                == MemoryChange::Discontinuous;
        }
        self.landing.clear();
        jump
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_root_of_a_cubic_to_the_tolerance() {
        // f(x) = (x - 0.3) (1 + x^2) crosses once at 0.3
        let f = |x: f64| (x - 0.3) * (1.0 + x * x);
        let r = first_crossing(f(0.0), f(1.0), f);
        assert!((r - 0.3).abs() <= 2.0 * LOCATION_TOLERANCE, "root {r}");
        assert!(f(r) > 0.0);
    }

    #[test]
    fn a_function_zero_at_the_start_crosses_there() {
        assert_eq!(first_crossing(0.0, 1.0, |x| x), 0.0);
    }
}
