//! Early return and intermediate updates within one communication step, for any scene.
//!
//! A step that nobody watches runs the scene's integrator straight to its end. A watched step
//! runs one accepted integrator step at a time: after each, the watcher hears the step's end
//! (an importer's intermediate update, which may ask for an early end), and a scene asked to
//! stop at its events compares its [`Watchable::marks`] with those of the previous accepted
//! step. At the first step in which an event happened, the event is located by bisection:
//! fresh integrations from the scene at the previous accepted step (a copy of the scene at the
//! communication step's start, integrated again to there), to trial times inside the step,
//! until the first time at which the event has happened is known to [`EVENT_RESOLUTION`]. The scene is left there, with the event registered, so the importer's
//! step ends exactly at the event with the model in its post-event state.
//!
//! Times are on the scene's own axis (0 at the start); the watcher is told importer times
//! (`start + t`).

use super::clock::{Clock, Step};

/// Resolution to which events are located [s], relative to `max(1 s, |t|)`: the FMU's time
/// resolution (1 ns, see [`super::clock::RESOLUTION`]).
pub const EVENT_RESOLUTION: f64 = 1e-9;

/// Largest number of bisection trials when locating one event (an internal step of 1e4 s is
/// located to 1e-9 s in 44).
const MAX_TRIALS: usize = 60;

/// What an importer follows during one communication step.
pub trait StepWatch {
    /// True: end the step at the scene's first event (early return allowed).
    fn stop_at_events(&self) -> bool;
    /// True: [`StepWatch::internal_step`] wants to hear every accepted internal step.
    fn wants_internal_steps(&self) -> bool;
    /// After an accepted internal step ending at importer time `t` [s], before the end of the
    /// communication step: `Some(t_stop)` asks the step to end at `t_stop` [s] (at once when
    /// `t_stop <= t`).
    fn internal_step(&mut self, t: f64) -> Option<f64>;
}

/// Nobody watches: the step runs to its end.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoWatch;

impl StepWatch for NoWatch {
    fn stop_at_events(&self) -> bool {
        false
    }
    fn wants_internal_steps(&self) -> bool {
        false
    }
    fn internal_step(&mut self, _t: f64) -> Option<f64> {
        None
    }
}

/// How a communication step ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StepEnd {
    /// At the end of the communication step.
    Complete,
    /// Before it, at the model's current time; `reason` names the event or the request.
    Early { reason: String },
}

/// A scene that can be advanced one accepted step at a time, copied, and asked which of its
/// events have happened.
pub trait Watchable: Clone {
    /// What the scene's events change (counters, flags).
    type Marks: Clone;
    /// The scene's time [s] on its own axis.
    fn now(&self) -> f64;
    /// Advances towards `end` [s]; with `one_step`, stops after the first accepted step.
    fn advance(&mut self, end: f64, one_step: bool) -> Result<(), String>;
    /// The marks at the current state.
    fn marks(&mut self) -> Self::Marks;
    /// The events that happened between `before` and `after`, in words (`None`: none).
    fn happened(&self, before: &Self::Marks, after: &Self::Marks) -> Option<String>;
    /// Checks a watched step once at its end (single-step advances leave out what a whole
    /// advance checks at its end); the default checks nothing.
    fn check_at_end(&mut self) -> Result<(), String> {
        Ok(())
    }
}

/// What [`advance_watched`] did.
#[derive(Debug, Clone, PartialEq)]
pub enum Stopped {
    /// It reached `end`.
    AtEnd,
    /// An event happened; the scene is at its located time.
    Event(String),
    /// The watcher asked for an end before `end`; the scene is there.
    Requested,
}

impl Stopped {
    /// How the importer's step ended, with `clock` moved to the end of `step`, or to `now`
    /// [s, scene axis] when the step ended early.
    pub fn finish(self, clock: &mut Clock, step: &Step, now: f64) -> StepEnd {
        match self {
            Stopped::AtEnd => {
                clock.advance(step);
                StepEnd::Complete
            }
            Stopped::Event(reason) => {
                clock.advance_early(now);
                StepEnd::Early { reason }
            }
            Stopped::Requested => {
                clock.advance_early(now);
                StepEnd::Early {
                    reason: "the importer asked for an early return".into(),
                }
            }
        }
    }
}

/// Advances `scene` to `end` [s, scene axis] under `watch` (see the module documentation);
/// `start` [s] is the importer's start time, added to the times the watcher hears.
pub fn advance_watched<S: Watchable>(
    scene: &mut S,
    end: f64,
    start: f64,
    watch: &mut dyn StepWatch,
) -> Result<Stopped, String> {
    let events = watch.stop_at_events();
    let listen = watch.wants_internal_steps();
    if !events && !listen {
        scene.advance(end, false)?;
        return Ok(Stopped::AtEnd);
    }
    let stopped = single_steps(scene, end, start, watch, events, listen)?;
    scene.check_at_end()?;
    Ok(stopped)
}

/// [`advance_watched`]'s loop of single accepted steps, without the check at its end.
fn single_steps<S: Watchable>(
    scene: &mut S,
    end: f64,
    start: f64,
    watch: &mut dyn StepWatch,
    events: bool,
    listen: bool,
) -> Result<Stopped, String> {
    let mut target = end;
    // the scene at the step's start and its marks: an event is located from a copy of it
    // integrated again to the last accepted step before the event (a copy per accepted step
    // would cost more than that second integration)
    let origin = events.then(|| (scene.clone(), scene.marks()));
    let mut marks = origin.as_ref().map(|o| o.1.clone());
    while scene.now() < target {
        let t0 = scene.now();
        scene.advance(target, true)?;
        if scene.now() <= t0 {
            return Err(format!(
                "the integrator made no progress from t = {t0} s (internal error)"
            ));
        }
        if let (Some(m0), Some(origin)) = (marks.as_ref(), origin.as_ref()) {
            let m1 = scene.marks();
            if let Some(seen) = scene.happened(m0, &m1) {
                let (located, reason) = locate_event(origin, m0, t0, scene, seen)?;
                *scene = located;
                return Ok(Stopped::Event(reason));
            }
            marks = Some(m1);
        }
        if listen
            && scene.now() < target
            && let Some(stop) = watch.internal_step(start + scene.now())
        {
            let stop = stop - start;
            if stop <= scene.now() {
                return Ok(Stopped::Requested);
            }
            target = target.min(stop);
        }
    }
    Ok(if target < end {
        Stopped::Requested
    } else {
        Stopped::AtEnd
    })
}

/// The scene at an event that `after` has against the marks `m0` of the last accepted step
/// before it, at `t0` (`seen`: its words), with the event's words: located from the step's
/// start `origin` (scene and marks), integrated again to `t0`.
fn locate_event<S: Watchable>(
    (first, m_first): &(S, S::Marks),
    m0: &S::Marks,
    t0: f64,
    after: &S,
    seen: String,
) -> Result<(S, String), String> {
    let mut prev = first.clone();
    prev.advance(t0, false)?;
    let m_prev = prev.marks();
    if let Some(early) = prev.happened(m0, &m_prev) {
        // integrated again, the event came before `t0` (a state that flips back, such as a
        // sling's slack, may not differ from the step's start: then the words are those seen
        // at `t0`)
        let (at, words) = locate(first.clone(), prev, m_first)?;
        Ok((at, words.unwrap_or(early)))
    } else {
        let (at, words) = locate(prev, after.clone(), m0)?;
        Ok((at, words.unwrap_or(seen)))
    }
}

/// The scene at the first time in `(prev.now(), after.now()]` at which an event has happened
/// (`after` has it, `prev` with marks `m0` has not), located by bisection on integrations from
/// `prev`, with the event's words (`None` if `after` itself has none against `m0`).
fn locate<S: Watchable>(prev: S, after: S, m0: &S::Marks) -> Result<(S, Option<String>), String> {
    let (mut lo, mut hi) = (prev.now(), after.now());
    let mut best = after;
    let tol = EVENT_RESOLUTION * 1f64.max(hi.abs());
    for _ in 0..MAX_TRIALS {
        if hi - lo <= tol {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let mut trial = prev.clone();
        trial.advance(mid, false)?;
        let m = trial.marks();
        if trial.happened(m0, &m).is_some() {
            hi = mid;
            best = trial;
        } else {
            lo = mid;
        }
    }
    let m = best.marks();
    let reason = best.happened(m0, &m);
    Ok((best, reason))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x' = 1 from x = 0 in steps of 0.3; the event is x >= 1 (at t = 1).
    #[derive(Clone)]
    struct Ramp {
        t: f64,
        h: f64,
    }

    impl Watchable for Ramp {
        type Marks = bool;
        fn now(&self) -> f64 {
            self.t
        }
        fn advance(&mut self, end: f64, one_step: bool) -> Result<(), String> {
            while self.t < end {
                self.t = (self.t + self.h).min(end);
                if one_step {
                    break;
                }
            }
            Ok(())
        }
        fn marks(&mut self) -> bool {
            self.t >= 1.0
        }
        fn happened(&self, before: &bool, after: &bool) -> Option<String> {
            (!before && *after).then(|| "crossed".into())
        }
    }

    struct Listen {
        events: bool,
        heard: Vec<f64>,
        stop_at: Option<f64>,
    }

    impl StepWatch for Listen {
        fn stop_at_events(&self) -> bool {
            self.events
        }
        fn wants_internal_steps(&self) -> bool {
            true
        }
        fn internal_step(&mut self, t: f64) -> Option<f64> {
            self.heard.push(t);
            self.stop_at
        }
    }

    #[test]
    fn an_event_is_located_to_the_resolution() {
        let mut r = Ramp { t: 0.0, h: 0.3 };
        let mut w = Listen {
            events: true,
            heard: vec![],
            stop_at: None,
        };
        let s = advance_watched(&mut r, 2.0, 10.0, &mut w).unwrap();
        assert_eq!(s, Stopped::Event("crossed".into()));
        assert!(r.t >= 1.0 && r.t - 1.0 <= 2.0 * EVENT_RESOLUTION, "{}", r.t);
        // internal steps before the event were heard, in importer time
        assert_eq!(w.heard.len(), 3);
        assert!((w.heard[2] - 10.9).abs() < 1e-12);
    }

    #[test]
    fn a_request_ends_the_step_where_asked() {
        let mut r = Ramp { t: 0.0, h: 0.3 };
        let mut w = Listen {
            events: false,
            heard: vec![],
            stop_at: Some(0.5),
        };
        assert_eq!(
            advance_watched(&mut r, 2.0, 0.0, &mut w).unwrap(),
            Stopped::Requested
        );
        assert_eq!(r.t, 0.5);
        let mut r = Ramp { t: 0.0, h: 0.3 };
        w.stop_at = Some(0.1);
        assert_eq!(
            advance_watched(&mut r, 2.0, 0.0, &mut w).unwrap(),
            Stopped::Requested
        );
        assert_eq!(r.t, 0.3, "a past request ends the step at once");
    }

    #[test]
    fn unwatched_and_eventless_steps_reach_the_end() {
        let mut r = Ramp { t: 0.0, h: 0.3 };
        assert_eq!(
            advance_watched(&mut r, 0.9, 0.0, &mut NoWatch).unwrap(),
            Stopped::AtEnd
        );
        assert!((r.t - 0.9).abs() < 1e-15);
        let mut w = Listen {
            events: true,
            heard: vec![],
            stop_at: None,
        };
        assert_eq!(
            advance_watched(&mut r, 0.95, 0.0, &mut w).unwrap(),
            Stopped::AtEnd
        );
    }
}
