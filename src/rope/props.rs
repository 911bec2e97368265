//! Material and section properties of a wire rope, with realistic steel-wire-rope defaults.

/// Properties of one rope, constant along its length.
///
/// Defaults: a 60 mm 6x36 IWRC steel wire rope (about 15 kg/m, EA about 1.6e8 N, minimum breaking
/// load about 2.5 MN), friction on steel 0.15, no bending stiffness, no drag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RopeProps {
    /// Mass per unstretched length [kg/m].
    pub mass_per_length: f64,
    /// Axial stiffness EA [N] (tension = EA x strain).
    pub ea: f64,
    /// Axial (Kelvin-Voigt) damping [N s]: tension += damping x strain rate. The default is
    /// `1e-3 s x EA`, which damps the node-scale axial modes strongly and the whole-rope modes
    /// lightly (a 200 t block bouncing on 22 m slings gets a damping ratio of about 0.6 %).
    pub axial_damping: f64,
    /// Bending stiffness EI [N m^2]; `0` switches the effect off.
    pub bending_stiffness: f64,
    /// Nominal diameter [m] (drag area).
    pub diameter: f64,
    /// Drag coefficient of the rope cross-section [-]; `0` switches drag off.
    pub drag_coefficient: f64,
    /// Density of the surrounding fluid [kg/m^3] (air 1.225, sea water 1025).
    pub fluid_density: f64,
    /// Coulomb friction coefficient between rope and plate edges [-]; `0` is frictionless.
    pub friction: f64,
    /// Minimum breaking load [N] (reported, never enforced).
    pub breaking_load: f64,
    /// How a contact node's cone splits friction between edge and rope when it slides
    /// ([`super::friction::FrictionLaw`]; edge first by default).
    pub friction_law: super::friction::FrictionLaw,
}

impl Default for RopeProps {
    fn default() -> Self {
        RopeProps {
            mass_per_length: 15.0,
            ea: 1.6e8,
            axial_damping: 1.6e5,
            bending_stiffness: 0.0,
            diameter: 0.06,
            drag_coefficient: 0.0,
            fluid_density: 1.225,
            friction: 0.15,
            breaking_load: 2.5e6,
            friction_law: super::friction::FrictionLaw::EdgeFirst,
        }
    }
}

impl RopeProps {
    /// A 40 mm 6x36 IWRC steel wire rope: 5.5 kg/m, EA 7e7 N, breaking load 1 MN.
    pub fn steel_40mm() -> Self {
        RopeProps {
            mass_per_length: 5.5,
            ea: 7.0e7,
            axial_damping: 7.0e4,
            diameter: 0.04,
            breaking_load: 1.0e6,
            ..Self::default()
        }
    }

    /// Drag factor `1/2 rho_f C_d d` [kg/m^2]: drag force per node = factor x length x |v| v.
    pub fn drag_factor(&self) -> f64 {
        0.5 * self.fluid_density * self.drag_coefficient * self.diameter
    }

    /// Axial wave speed `sqrt(EA / mass_per_length)` [m/s].
    pub fn wave_speed(&self) -> f64 {
        (self.ea / self.mass_per_length).sqrt()
    }

    /// Checks every value; `Err` names the property, its value and what is expected.
    pub fn validate(&self, owner: &str) -> Result<(), String> {
        let pos = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{owner}: {name} must be finite and > 0, got {v}"))
            }
        };
        let nonneg = |name: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(format!("{owner}: {name} must be finite and >= 0, got {v}"))
            }
        };
        pos("mass per length [kg/m]", self.mass_per_length)?;
        pos("axial stiffness EA [N]", self.ea)?;
        nonneg("axial damping [N s]", self.axial_damping)?;
        nonneg("bending stiffness EI [N m^2]", self.bending_stiffness)?;
        pos("diameter [m]", self.diameter)?;
        nonneg("drag coefficient [-]", self.drag_coefficient)?;
        nonneg("fluid density [kg/m^3]", self.fluid_density)?;
        nonneg("friction coefficient [-]", self.friction)?;
        nonneg("breaking load [N]", self.breaking_load)?;
        if self.friction > 10.0 {
            return Err(format!(
                "{owner}: friction coefficient {} is beyond any rope-on-steel value (expected 0 ... 10)",
                self.friction
            ));
        }
        Ok(())
    }
}
