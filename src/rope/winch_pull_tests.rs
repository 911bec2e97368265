//! The winch's line pull on one segment against the formula written out by hand: the power
//! conjugate of the pay-out rate is `-dV/dL` of the strain energy, `EA (e + e^2/2)`, plus the
//! damping tension's share `T_d l / L` with `T_d = c (l_dot - l L_dot / L) / L`; the dashpot
//! dissipates `T_d (l_dot - l L_dot / L) = c L (strain rate)^2`.

use super::effect::{plain_segment, winch_pull};
use super::props::RopeProps;
use crate::math::Vec3;

#[test]
fn winch_pull_and_dissipation_of_one_segment_are_the_hand_formulas() {
    let props = RopeProps::steel_40mm();
    let (ea, c) = (props.ea, props.axial_damping);
    let rest = 2.0;
    for (stretch, l_dot, rest_rate) in [
        (1.002, 0.3, 0.1),
        (1.002, 0.3, -0.4),
        (1.0005, -0.01, 0.25),
        (1.0, 0.0, 0.0),
    ] {
        let l = stretch * rest;
        let seg = plain_segment(
            &Vec3::zeros(),
            &Vec3::new(0.0, 0.0, l),
            &Vec3::zeros(),
            &Vec3::new(0.0, 0.0, l_dot),
            rest,
            rest_rate,
            &props,
            false,
        );
        let e = (l - rest) / rest;
        let strain_rate = (l_dot - l * rest_rate / rest) / rest;
        let (pull, dissipation) = if l > rest {
            let t_d = c * strain_rate;
            (
                ea * (e + 0.5 * e * e) + t_d * l / rest,
                c * rest * strain_rate * strain_rate,
            )
        } else {
            (0.0, 0.0)
        };
        let got = winch_pull(ea, &seg, rest);
        let got_dissipation = (seg.law.t - seg.elastic) * seg.dashpot_rate;
        let scale = ea * e.abs() + c * strain_rate.abs() + 1.0;
        assert!(
            (got - pull).abs() <= 1e-12 * scale,
            "stretch {stretch}, l_dot {l_dot}, L_dot {rest_rate}: pull {got} against {pull}"
        );
        assert!(
            (got_dissipation - dissipation).abs() <= 1e-12 * scale * (l_dot.abs() + 1.0),
            "dissipation {got_dissipation} against {dissipation}"
        );
        assert!(got_dissipation >= 0.0);
    }
}
