//! One interface over the four normal-contact laws: force and both partial derivatives for Newton
//! iterations, elastic potential energy and dissipated power for energy bookkeeping, and the
//! static quantities (penetration under a static force, linearized stiffness) for model tests.
//!
//! Every law has the form `F = k delta^n [1 + chi(e) delta_dot / v_minus]` for `delta > 0`, with
//! `chi` from the law's own file ([`super::hertz`], [`super::lankarani_nikravesh`],
//! [`super::hunt_crossley`], [`super::flores`]) and `v_minus` the approach speed at contact onset.
//!
//! Decisions (see also the module documentation of [`crate::contact`]):
//! - **No adhesion.** During restitution (`delta_dot < 0`) the bracket can turn negative when
//!   `|delta_dot| > v_minus / chi`; the force is then clamped to 0, and so are both derivatives (the
//!   exact derivatives of the clamped function). At the switch itself the one-sided derivatives
//!   differ; the clamped side (zero) is returned. In an isolated impact the clamp never acts
//!   (the bracket only tends to zero); it does when other forces pull the bodies apart.
//! - **Approach-speed floor.** The law divides by `max(v_minus, v_floor)`, with `v_floor` the
//!   law's [`ContactLaw::min_approach_speed`] (default [`DEFAULT_MIN_APPROACH_SPEED`]). An unknown
//!   approach speed is passed as `0.0` (or NaN) and so uses the floor, which gives the largest
//!   damping the law allows: a conservative, dissipative choice for a contact that starts closed.

use super::error::{ContactError, positive_parameter};
use super::{flores, hertz, hunt_crossley, lankarani_nikravesh};

/// Default floor on the approach speed, 1e-4 m/s: below it the damping term no longer grows.
///
/// With it, the damping coefficient `chi k delta^n / v_minus` [N s/m] stays bounded for grazing
/// contacts and for slow re-contacts after many rebounds, which keeps the Newton matrix of an
/// implicit integrator well conditioned. Real lock impacts (pin speeds of mm/s to m/s) are above it.
pub const DEFAULT_MIN_APPROACH_SPEED: f64 = 1e-4;

/// Which normal-contact law a [`ContactLaw`] evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LawKind {
    /// Elastic Hertz `k delta^n` (restitution ignored: no loss).
    Hertz,
    /// Lankarani-Nikravesh, `chi = 3(1 - e^2)/4` (accurate for `e >= 0.9`).
    LankaraniNikravesh,
    /// Hunt-Crossley, `chi = 3(1 - e)/2`.
    HuntCrossley,
    /// Flores et al., `chi = 8(1 - e)/(5e)` (close to nominal `e` over the whole range).
    Flores,
}

impl LawKind {
    /// All laws, in the order of their integer codes 0..=3 (Hertz, L-N, H-C, Flores).
    pub const ALL: [LawKind; 4] = [
        LawKind::Hertz,
        LawKind::LankaraniNikravesh,
        LawKind::HuntCrossley,
        LawKind::Flores,
    ];

    /// The law for an integer code (0 Hertz, 1 Lankarani-Nikravesh, 2 Hunt-Crossley, 3 Flores),
    /// e.g. from an FMI integer parameter; any other code is refused.
    pub fn from_code(code: i32) -> Result<Self, ContactError> {
        usize::try_from(code)
            .ok()
            .and_then(|i| Self::ALL.get(i).copied())
            .ok_or(ContactError::InvalidParameter {
                name: "contact law code",
                value: f64::from(code),
                expected: "0 (Hertz), 1 (Lankarani-Nikravesh), 2 (Hunt-Crossley) or 3 (Flores)",
            })
    }

    /// Hysteresis factor `chi(e)` [-] of this law for restitution `e` [-].
    pub fn hysteresis_factor(self, restitution: f64) -> f64 {
        match self {
            LawKind::Hertz => hertz::hysteresis_factor(restitution),
            LawKind::LankaraniNikravesh => lankarani_nikravesh::hysteresis_factor(restitution),
            LawKind::HuntCrossley => hunt_crossley::hysteresis_factor(restitution),
            LawKind::Flores => flores::hysteresis_factor(restitution),
        }
    }
}

/// Result of one evaluation of a contact law, for `delta` [m] and `delta_dot` [m/s].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactForce {
    /// Normal force `F` [N], `>= 0` (compressive; it pushes the bodies apart).
    pub force: f64,
    /// `dF/d delta` [N/m] at fixed `delta_dot` (and fixed approach speed).
    pub d_force_d_delta: f64,
    /// `dF/d delta_dot` [N s/m] at fixed `delta`.
    pub d_force_d_delta_dot: f64,
    /// Elastic part `k delta^n` [N] (not clamped).
    pub elastic_force: f64,
    /// Damping part `F - k delta^n` [N]; with the no-adhesion clamp active it is `-k delta^n`.
    pub damping_force: f64,
    /// Power dissipated by the contact, `damping_force * delta_dot` [W], `>= 0`.
    pub dissipated_power: f64,
    /// True when the no-adhesion clamp set the force to zero.
    pub clamped: bool,
}

/// A validated normal-contact law with stiffness `k` [N/m^n], exponent `n` [-] and restitution `e`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    kind: LawKind,
    stiffness: f64,
    exponent: f64,
    restitution: f64,
    min_approach_speed: f64,
    chi: f64,
}

impl ContactLaw {
    /// Builds a law, refusing `k` or `n` not finite and `> 0`, and `e` outside (0, 1].
    ///
    /// `stiffness` k [N/m^n], `exponent` n [-], `restitution` e [-] (validated for every law, also
    /// for Hertz which ignores it, so that a bad parameter is caught whichever law is selected).
    /// The approach-speed floor is [`DEFAULT_MIN_APPROACH_SPEED`]; see
    /// [`ContactLaw::with_min_approach_speed`].
    pub fn new(
        kind: LawKind,
        stiffness: f64,
        exponent: f64,
        restitution: f64,
    ) -> Result<Self, ContactError> {
        let stiffness = positive_parameter("stiffness k", stiffness, "finite and > 0 N/m^n")?;
        let exponent = positive_parameter("exponent n", exponent, "finite and > 0")?;
        if !(restitution > 0.0 && restitution <= 1.0) {
            return Err(ContactError::InvalidParameter {
                name: "restitution e",
                value: restitution,
                expected: "a number in (0, 1]",
            });
        }
        Ok(Self {
            kind,
            stiffness,
            exponent,
            restitution,
            min_approach_speed: DEFAULT_MIN_APPROACH_SPEED,
            chi: kind.hysteresis_factor(restitution),
        })
    }

    /// The elastic Hertz law `k delta^n` (restitution 1).
    pub fn hertz(stiffness: f64, exponent: f64) -> Result<Self, ContactError> {
        Self::new(LawKind::Hertz, stiffness, exponent, 1.0)
    }

    /// The same law with another approach-speed floor `v_floor` [m/s] (finite and `> 0`).
    pub fn with_min_approach_speed(mut self, v_floor: f64) -> Result<Self, ContactError> {
        self.min_approach_speed = positive_parameter(
            "minimum approach speed v_floor",
            v_floor,
            "finite and > 0 m/s",
        )?;
        Ok(self)
    }

    /// Which law this is.
    pub fn kind(&self) -> LawKind {
        self.kind
    }

    /// Stiffness `k` [N/m^n].
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// Exponent `n` [-].
    pub fn exponent(&self) -> f64 {
        self.exponent
    }

    /// Nominal restitution coefficient `e` [-].
    pub fn restitution(&self) -> f64 {
        self.restitution
    }

    /// Hysteresis factor `chi` [-] of the damping bracket `1 + chi delta_dot / v_minus`.
    pub fn hysteresis_factor(&self) -> f64 {
        self.chi
    }

    /// Floor `v_floor` [m/s] applied to the approach speed before dividing by it.
    pub fn min_approach_speed(&self) -> f64 {
        self.min_approach_speed
    }

    /// The approach speed [m/s] the law actually divides by: `max(approach_speed, v_floor)`.
    /// NaN, zero and negative inputs ("not known") give `v_floor`.
    pub fn effective_approach_speed(&self, approach_speed: f64) -> f64 {
        // f64::max returns the other operand when one is NaN.
        approach_speed.max(self.min_approach_speed)
    }

    /// Force and derivatives at penetration `delta` [m] and penetration rate `delta_dot` [m/s]
    /// (positive while the bodies approach), for the approach speed `approach_speed` [m/s]
    /// recorded at contact onset (see [`super::ApproachMemory`]; pass 0.0 if unknown).
    ///
    /// `delta <= 0` (separated) gives all zeros. The force never pulls (no-adhesion clamp). Never
    /// panics; non-finite `delta` or `delta_dot` give non-finite results for the caller to detect.
    pub fn evaluate(&self, delta: f64, delta_dot: f64, approach_speed: f64) -> ContactForce {
        if delta <= 0.0 {
            return ContactForce::default();
        }
        let k = self.stiffness;
        let n = self.exponent;
        let elastic = k * delta.powf(n);
        let d_elastic = n * k * delta.powf(n - 1.0);
        let c = self.chi / self.effective_approach_speed(approach_speed);
        let bracket = 1.0 + c * delta_dot;
        if bracket <= 0.0 {
            // No adhesion: zero force, and zero derivatives (exact for the clamped branch).
            return ContactForce {
                force: 0.0,
                d_force_d_delta: 0.0,
                d_force_d_delta_dot: 0.0,
                elastic_force: elastic,
                damping_force: -elastic,
                dissipated_power: -elastic * delta_dot,
                clamped: true,
            };
        }
        let damping = elastic * c * delta_dot;
        ContactForce {
            force: elastic * bracket,
            d_force_d_delta: d_elastic * bracket,
            d_force_d_delta_dot: elastic * c,
            elastic_force: elastic,
            damping_force: damping,
            dissipated_power: damping * delta_dot,
            clamped: false,
        }
    }

    /// Elastic potential energy `k delta^(n+1) / (n+1)` [J] stored at penetration `delta` [m]
    /// (0 when separated). The work done on the contact equals the change of this energy plus the
    /// time integral of [`ContactForce::dissipated_power`].
    pub fn potential_energy(&self, delta: f64) -> f64 {
        if delta <= 0.0 {
            return 0.0;
        }
        let n1 = self.exponent + 1.0;
        self.stiffness * delta.powf(n1) / n1
    }

    /// Static penetration `delta_s = (F_s / k)^(1/n)` [m] under a static normal force `F_s` [N]
    /// (at rest the damping term vanishes, so this holds for every law). `F_s` must be finite and
    /// `>= 0`.
    pub fn static_penetration(&self, static_force: f64) -> Result<f64, ContactError> {
        if !(static_force.is_finite() && static_force >= 0.0) {
            return Err(ContactError::InvalidArgument {
                name: "static force F_s",
                value: static_force,
                expected: "finite and >= 0 N (a contact cannot pull)",
            });
        }
        Ok((static_force / self.stiffness).powf(1.0 / self.exponent))
    }

    /// Linearized contact stiffness `n k delta_s^(n-1)` [N/m] at a static penetration
    /// `delta_s` [m] (finite and `>= 0`). At `delta_s = 0` it is 0 for `n > 1`, `k` for `n = 1`,
    /// and unbounded for `n < 1`, which is refused.
    pub fn linearized_stiffness(&self, static_penetration: f64) -> Result<f64, ContactError> {
        let d = static_penetration;
        if !(d.is_finite() && d >= 0.0) {
            return Err(ContactError::InvalidArgument {
                name: "static penetration delta_s",
                value: d,
                expected: "finite and >= 0 m",
            });
        }
        let n = self.exponent;
        if d == 0.0 && n < 1.0 {
            return Err(ContactError::InvalidArgument {
                name: "static penetration delta_s",
                value: d,
                expected: "> 0 m when the exponent n < 1 (the stiffness is unbounded at zero)",
            });
        }
        Ok(n * self.stiffness * d.powf(n - 1.0))
    }
}
