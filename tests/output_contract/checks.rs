//! Which test checks each output, and against what (see `main.rs`).
//!
//! An entry names outputs by pattern: `#` stands for a decimal index (`hinge#_angle` covers
//! `hinge0_angle` ... `hinge6_angle`). Every output matches exactly one entry. A check is
//! `path::function` from the repository root: a Rust test (`tests/...rs`) or a pytest function
//! (`tests/python/...py`).

/// Which value of the continuous solution an output reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// The value at the communication point.
    Instant,
    /// The largest value since the start, over every internal step.
    Peak,
    /// An integral since the start (work, dissipated energy).
    Cumulative,
    /// The time of an event, fixed once it happened.
    Event,
    /// A running count since the start.
    Count,
    /// A discrete state at the communication point.
    Flag,
}

impl Sampling {
    /// The word the document uses.
    pub fn word(self) -> &'static str {
        match self {
            Sampling::Instant => "instant",
            Sampling::Peak => "peak",
            Sampling::Cumulative => "cumulative",
            Sampling::Event => "event",
            Sampling::Count => "count",
            Sampling::Flag => "flag",
        }
    }
}

/// One entry of the output contract.
#[derive(Debug, Clone, Copy)]
pub struct Check {
    /// Model identifier.
    pub model: &'static str,
    /// Output name patterns (`#`: a decimal index).
    pub outputs: &'static [&'static str],
    /// Which value the outputs report.
    pub sampling: Sampling,
    /// The tests that check them, `path::function`.
    pub tests: &'static [&'static str],
    /// What those tests compare with, and to what tolerance.
    pub against: &'static str,
}

impl Check {
    /// True when one of the entry's patterns matches `name`.
    pub fn covers(&self, name: &str) -> bool {
        self.outputs.iter().any(|p| matches(p, name))
    }
}

/// True when `name` matches `pattern`, in which each `#` stands for one or more decimal digits.
pub fn matches(pattern: &str, name: &str) -> bool {
    match pattern.split_once('#') {
        None => pattern == name,
        Some((head, tail)) => {
            let Some(rest) = name.strip_prefix(head) else {
                return false;
            };
            let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
            digits > 0 && matches(tail, &rest[digits..])
        }
    }
}

use Sampling::*;

const PANEL_LOCK: &str = "PanelLock";
const ROPE_BLOCK: &str = "RopeBlock";
const PID: &str = "PidController";

/// The contract, model by model.
pub const CHECKS: &[Check] = &[
    // ---------------------------------------------------------------- PanelLock
    Check {
        model: PANEL_LOCK,
        outputs: &["hinge#_angle"],
        sampling: Instant,
        tests: &[
            "tests/panel_lock_array.rs::coulomb_friction_takes_4_tf_over_k_of_amplitude_per_cycle",
            "tests/python/test_panel_lock.py::test_joint_coordinate_dopri5_follows_the_maximal_one",
        ],
        against: "one hinge with spring and Coulomb friction: half period pi sqrt(I/k) (1e-4) and amplitude loss 2 T_f/k per half cycle by hand (2e-4); the default array in joint coordinates against maximal coordinates with constraints, 1e-8 rad",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["hinge#_rate"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::rates_and_tip_velocity_are_the_derivatives_of_angles_and_tip_position",
        ],
        against: "central difference of the reported angles over 1 ms samples of the deployment, 1e-5 of the largest rate",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["hinge#_contact_force"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::settled_latch_force_carries_the_spring_torque_over_its_arm",
            "tests/panel_lock.rs::locked_latch_settles_at_the_contact_law_equilibrium",
        ],
        against: "locked one-panel array at rest: force = spring torque by hand / the latch geometry's moment arm, 1e-6 (the contact law not used); the penetration against the law's static solution, 1e-3",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["hinge#_peak_force"],
        sampling: Peak,
        tests: &[
            "tests/panel_lock.rs::peak_lock_force_and_lock_time_converge_with_the_tolerance",
            "tests/panel_lock.rs::every_integrator_gives_the_same_lock_up",
            "tests/panel_lock_default_accuracy.rs::rigid_default_scene_within_one_percent_of_a_tight_bdf_run",
            "tests/panel_lock_peaks_step.rs::lock_up_peaks_of_hinges_0_2_3_hold_at_every_communication_step",
            "tests/panel_lock_peaks_step.rs::rattle_peak_of_hinge_1_holds_one_percent_by_default_and_its_band_on_gen_alpha",
        ],
        against: "root hinge's first lock-up against BDF rtol 1e-10 (error shrinks, < 1e-4 at rtol 1e-8) and every integrator against BDF (1e-3); per hinge at communication steps 1 ms-0.1 s: hinges 0, 2, 3 at the default (auto: dopri5_tree 1e-9) within 0.1 % of BDF 1e-10 and DOPRI5 1e-11 (which agree to 1.5e-5), gen_alpha 1e-4 within 1 %. Hinge 1's peak comes from a chaotic rattle 6 s after its lock-up: against the median of tight dopri5_tree runs the default holds 1 %, gen_alpha 1e-4 only 10 % (measured up to 9.1 %; docs/auto_integrator.md)",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["hinge#_lock_time"],
        sampling: Event,
        tests: &[
            "tests/output_checks/panel_lock.rs::lock_time_and_latched_flag_follow_the_engagement_angle_crossing",
            "tests/panel_lock.rs::peak_lock_force_and_lock_time_converge_with_the_tolerance",
        ],
        against: "the time the reported angle (2 ms samples, linear interpolation) crosses the latch geometry's engagement angle, 5e-6 s, all four hinges; root lock time against BDF rtol 1e-10",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["hinge#_latched"],
        sampling: Flag,
        tests: &[
            "tests/output_checks/panel_lock.rs::lock_time_and_latched_flag_follow_the_engagement_angle_crossing",
            "tests/python/test_panel_lock.py::test_every_integrator_through_fmpy_equals_the_native_run",
        ],
        against: "off at every 2 ms sample before the reported angle reaches the latch geometry's engagement angle, on from the first sample past it, all four hinges",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["root_force_x", "root_force_y", "root_force_z"],
        sampling: Instant,
        tests: &[
            "tests/panel_lock_interface.rs::interface_wrench_equals_the_arrays_momentum_balance",
            "tests/panel_lock_interface.rs::interface_wrench_accelerates_a_free_satellite",
            "tests/panel_lock.rs::gravity_along_the_hinge_axes_is_carried_by_the_root_shaft",
        ],
        against: "minus the array's momentum rate sum m (a - g) from the index-1 accelerations over a 16 s deployment with gravity, motor and every lock-up, 1e-6 of the terms' scale (measured 1.5e-13 DOPRI5, 9.7e-12 gen-alpha); a free satellite's m a, 1e-6 (2.1e-15); the array's weight by hand at t = 0, 1e-9",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["root_torque_x", "root_torque_y", "root_torque_z"],
        sampling: Instant,
        tests: &[
            "tests/panel_lock_interface.rs::interface_wrench_equals_the_arrays_momentum_balance",
            "tests/panel_lock_interface.rs::interface_wrench_accelerates_a_free_satellite",
            "tests/panel_lock_interface.rs::interface_torque_about_the_axes_carries_the_spring_and_motor_at_rest",
        ],
        against: "minus the array's angular momentum rate about the attachment point, sum (r - O) x m (a - g) + A (J w_dot + w x J w), 1e-6 of the terms' scale; a free satellite's own; at rest the root spring preload plus the motor torque (1e-9)",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["root_peak_force", "root_peak_torque"],
        sampling: Peak,
        tests: &[
            "tests/panel_lock_interface.rs::tracked_peaks_bound_the_samples_and_do_not_miss_the_impacts",
            "tests/python/test_panel_lock.py::test_root_interface_outputs_carry_the_deployment_and_bound_their_samples",
        ],
        against: "tracked at a 0.1 s communication step against the largest of the magnitudes sampled every 1 ms (a finer sampling of the momentum-checked wrench), 1 % (measured 0.3 % force, 0.4 % torque); never below a sampled magnitude, never falling",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["tip_normal_velocity"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::rates_and_tip_velocity_are_the_derivatives_of_angles_and_tip_position",
            "tests/panel_lock_flex.rs::post_lock_frequency_matches_the_linearized_locked_system",
        ],
        against: "central difference of the outer panel's tip position (from the body state) along its normal, 1e-5 of the largest (rigid panels); flexible: its post-lock frequency against the linearized locked system's eigenvalue",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["kinetic_energy"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::kinetic_and_potential_energy_against_the_bodies_and_springs_by_hand",
        ],
        against: "the default array deploying: sum of m v^2/2 + w.I w/2 over the rigid bodies' positions and velocities in the state, 1e-9 of the energy released",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["potential_energy"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::kinetic_and_potential_energy_against_the_bodies_and_springs_by_hand",
        ],
        against: "the default array deploying (no latch contact, orbit): its change = the change of the hinge springs' k (theta_free - theta)^2/2 and the stow stops' k_stop p^2/2 at the reported angles, 1e-9 of the energy released",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["energy_dissipated"],
        sampling: Cumulative,
        tests: &[
            "tests/panel_lock_array.rs::coulomb_friction_takes_4_tf_over_k_of_amplitude_per_cycle",
            "tests/panel_lock.rs::hinges_lock_in_the_designed_order_and_the_energy_balance_closes",
        ],
        against: "one Coulomb hinge: dissipated = friction torque x angle travelled and = spring energy lost between extremes, 2e-4; the default array's balance kinetic + potential + dissipated - input closes to 5e-5 of the spring energy released",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["root_power"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock_bonds.rs::a_fixed_satellite_s_bond_carries_no_power",
            "tests/output_checks/panel_lock_bonds.rs::root_work_is_the_satellite_s_kinetic_energy_lost_and_closes_the_array_s_balance",
        ],
        against: "fixed satellite: exactly 0 while the wrench is not; free satellite: its integral (root_work) is the satellite's kinetic energy lost, by hand from mass, inertia and motion, 1e-6 (weak as an instantaneous check: the power itself is checked only through its integral)",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["locked_frequency"],
        sampling: Event,
        tests: &[
            "tests/panel_lock_locked_frequency.rs::locked_frequency_of_one_rigid_panel_by_hand",
            "tests/panel_lock_locked_frequency.rs::locked_frequency_is_the_small_amplitude_free_vibration",
            "tests/python/test_panel_lock.py::test_locked_frequency_through_fmpy_equals_the_table1_column",
        ],
        against: "one rigid panel locked: the two-hinge planar model by hand (the bodies' masses on the line, each seated latch's contact stiffness at the spring preload plus the spring), 1e-6 (measured 3.7e-7); the free vibration after lock-up, cycle frequencies from the tip velocity's zero crossings below 1e-3 m/s late in a 280 s ring-down, 5e-4 (measured 9.9e-5); 0 until every hinge latched; the packed FMU through fmpy equals the table1 study's column, 1e-9 (its CSV's 10 digits)",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["root_work"],
        sampling: Cumulative,
        tests: &[
            "tests/output_checks/panel_lock_bonds.rs::root_work_is_the_satellite_s_kinetic_energy_lost_and_closes_the_array_s_balance",
        ],
        against: "free satellite, motor and springs deploying through every lock-up: minus the change of the satellite's m v^2/2 + sum I w^2/2 by hand, and with input_work the array's kinetic + potential + dissipated change, 1e-6 of the energy moved",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["input_work"],
        sampling: Cumulative,
        tests: &[
            "tests/output_checks/panel_lock.rs::input_work_is_the_motor_torque_times_the_root_travel",
        ],
        against: "sum of the held motor torque x the reported root-angle travel over two torque levels, 1e-9",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &[
            "satellite_qw",
            "satellite_qx",
            "satellite_qy",
            "satellite_qz",
            "satellite_wx",
            "satellite_wy",
            "satellite_wz",
        ],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::satellite_velocity_and_rate_are_the_derivatives_of_position_and_attitude",
            "tests/panel_lock_satellite.rs::body_frame_loads_turn_with_the_satellite",
        ],
        against: "free deployment: body rate = vector part of 2 conj(q) dq/dt by central differences over 1 ms, 1e-5 of the largest rate, |q| = 1 to 1e-12; body-frame loads rotated by the reported attitude give the momentum change, 1e-5",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &[
            "satellite_x",
            "satellite_y",
            "satellite_z",
            "satellite_vx",
            "satellite_vy",
            "satellite_vz",
        ],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::satellite_velocity_and_rate_are_the_derivatives_of_position_and_attitude",
            "tests/panel_lock_satellite.rs::world_frame_loads_change_the_momentum_by_their_impulse",
        ],
        against: "velocity = central difference of the position over 1 ms, 1e-5 of the largest; the force's moment about the centre of mass taken at the reported position gives the angular impulse, 1e-6",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &[
            "angular_momentum_x",
            "angular_momentum_y",
            "angular_momentum_z",
        ],
        sampling: Instant,
        tests: &[
            "tests/panel_lock_satellite.rs::free_deployment_conserves_linear_and_angular_momentum",
            "tests/panel_lock_satellite.rs::world_frame_loads_change_the_momentum_by_their_impulse",
        ],
        against: "conservation through the four lock-ups (1e-8 of the satellite's own momentum at rtol 1e-9); with loads, the angular impulse integrated from the loads, 1e-6",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["panel#_tip_deflection", "panel#_mode#"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/panel_lock.rs::panel_deflections_scale_with_the_inverse_of_the_stiffness",
            "tests/panel_lock_satellite.rs::flexible_panels_conserve_momentum_and_report_their_deflection",
        ],
        against: "partly weak: deflections and modal amplitudes are compliance x load, so at 100x and 1000x the default modulus (quasi-static) each excited one's ratio is 10 within 8 % (measured 0.08 % outer panel, up to 5 % on the inner panels' mode 2), the unexcited ones at round-off; ranges (1e-7 ... 0.05 m) and 0 for rigid panels; no absolute value against an independent deflection",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &[
            "solver_steps",
            "solver_rejected_steps",
            "solver_newton_iterations",
            "solver_factorizations",
        ],
        sampling: Count,
        tests: &[
            "tests/output_checks/panel_lock.rs::solver_counters_are_the_integrator_statistics",
            "tests/python/test_fmi3_early_return.py::test_intermediate_update_is_called_at_every_internal_step",
        ],
        against: "the native scene's integrator statistics at the same points, exactly, never decreasing; steps also against the count of intermediate-update callbacks through FMI 3.0",
    },
    Check {
        model: PANEL_LOCK,
        outputs: &["solver_integrator"],
        sampling: Count,
        tests: &[
            "tests/output_checks/panel_lock.rs::solver_integrator_is_the_integrator_the_run_uses",
        ],
        against: "the integrator kind of the simulation the same parameters build natively, for `auto` on rigid, flexible and free-satellite scenes and for explicit choices",
    },
    // ---------------------------------------------------------------- PidController
    Check {
        model: PID,
        outputs: &["u"],
        sampling: Instant,
        tests: &[
            "src/scene/pid_tests.rs::constant_error_gives_exact_ramp_for_any_step_sequence",
            "src/scene/pid_tests.rs::filtered_derivative_of_a_ramp_matches_the_discrete_and_continuous_solutions",
            "src/scene/pid_tests.rs::back_calculation_prevents_windup",
            "src/scene/pid_tests.rs::pi_loop_on_a_first_order_plant_settles_at_the_setpoint",
        ],
        against: "kp e + ki e t for any step sequence (1e-12), the filtered derivative's discrete and continuous solutions, the first unsaturated output after windup by hand, a PI loop on an exact first-order plant settling (1e-6)",
    },
    Check {
        model: PID,
        outputs: &["error"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/pid.rs::error_is_setpoint_minus_measurement_of_the_last_sample",
        ],
        against: "setpoint - measurement of the inputs held over the step, by hand, 1e-15, for eight samples",
    },
    Check {
        model: PID,
        outputs: &["saturated"],
        sampling: Flag,
        tests: &[
            "tests/output_checks/pid.rs::error_is_setpoint_minus_measurement_of_the_last_sample",
            "src/scene/pid_tests.rs::back_calculation_prevents_windup",
        ],
        against: "on exactly when the proportional output kp e by hand exceeds a limit, off otherwise; with anti-windup, on while the output sits at u_max and off in the step after the error reverses",
    },
    // ---------------------------------------------------------------- RopeBlock
    Check {
        model: ROPE_BLOCK,
        outputs: &["hook#_x", "hook#_y", "hook#_z"],
        sampling: Instant,
        tests: &[
            "tests/rope_hook_position.rs::the_hook_follows_the_cubic_move_by_hand",
            "tests/rope_hook_ramp.rs::the_hook_follows_the_commanded_ramp",
            "tests/rope_hook_position.rs::a_four_hook_rig_is_driven_and_observed_through_its_variables",
        ],
        against: "position commands: the cubic move by hand, also retargeted mid-move, 1e-9 m; velocity commands: the integral of the ramped profile by hand; four hooks at their rigged positions and moved by 0.3 m, 1e-12 m",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["hook#_load", "hook#_fz"],
        sampling: Instant,
        tests: &[
            "tests/python/test_rope_block.py::test_hook_load_at_rest_equals_the_total_weight",
            "tests/rope_hook_position.rs::a_four_hook_rig_is_driven_and_observed_through_its_variables",
            "tests/rope/slings.rs::sling_legs_carry_weight_over_n_cos_beta",
        ],
        against: "at rest: block + slings weight from the rig geometry (shortest sling paths), 1e-3; four vertical slings: a quarter of the block + the sling's weight, fz = -load, 1e-6; two spreader hooks' fz sum = weight, 1e-4",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &[
            "sling#_tension_hook",
            "sling#_tension_lug",
            "sling#_utilisation",
            "sling#_angle",
        ],
        sampling: Instant,
        tests: &[
            "tests/rope_rig.rs::symmetric_four_point_lift_matches_the_closed_form",
            "tests/rope_rig.rs::asymmetric_four_point_lift_matches_the_closed_form",
            "tests/rope_rig.rs::indeterminate_four_point_lift_matches_an_independent_elastic_solution",
            "tests/rope/slings.rs::sling_legs_carry_weight_over_n_cos_beta",
        ],
        against: "statically determinate four-point lifts: tensions, utilisation = tension / breaking load and angles by hand, 1e-6; an indeterminate lift against an independent elastic Newton solution; legs over frictionless edges W / (n cos beta), 1e-4",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["contact#_normal", "contact#_friction"],
        sampling: Instant,
        tests: &[
            "tests/rope/reported_cone.rs::lift_reports_contact_forces_inside_the_cone",
            "tests/rope/reported_cone.rs::turnover_reports_contact_forces_inside_the_cone",
            "tests/rope/reported_cone.rs::friction_off_reports_exactly_zero_friction_and_no_slip",
            "tests/rope/cone.rs::tilted_strand_friction_inside_one_cone",
            "tests/python/test_rope_block.py::test_lift_contact_outputs_inside_the_coulomb_cone",
        ],
        against: "Coulomb's law on the reported values at every communication point: friction <= mu N (1 + 1e-9), and >= mu N (1 - 1e-9) where the slip flag says sliding (default lift plain and ramped, turn-over, tilted strand 0-20 deg at 9.81 and 981 kN); friction off: exactly 0, and N against |T_prev e_prev + T_next e_next| from the reported segment tensions",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["contact#_slip"],
        sampling: Flag,
        tests: &[
            "tests/rope/reported_cone.rs::lift_reports_contact_forces_inside_the_cone",
            "tests/rope/reported_cone.rs::friction_off_reports_exactly_zero_friction_and_no_slip",
            "tests/python/test_rope_block.py::test_friction_off_reports_exactly_zero_friction_and_no_slip",
        ],
        against: "where the flag says sliding, the reported friction is on the cone (mu N within 1e-9); with friction off it reads 0 on every row",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["contact#_x", "contact#_y", "contact#_z", "contact#_sling"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/rope_block.rs::each_contact_slot_reports_its_sling_s_node_on_the_shortest_path_over_the_edge",
            "tests/rope_hook_position.rs::a_sling_swung_over_the_deck_edge_and_back_wraps_the_edge_and_leaves_it",
        ],
        against: "the default lift at rest: each slot's node where its sling's straight legs hook -> deck edge -> lug are shortest, by hand from the rig (golden section), 1e-6 m, the four slings once each, empty slots -1; a sling swung over the edge: node at the edge, 1e-9 m",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["contact_count"],
        sampling: Instant,
        tests: &[
            "tests/python/test_rope_block.py::test_hook_load_at_rest_equals_the_total_weight",
            "tests/rope_hook_position.rs::a_sling_swung_over_the_deck_edge_and_back_wraps_the_edge_and_leaves_it",
            "tests/output_checks/rope_block.rs::each_contact_slot_reports_its_sling_s_node_on_the_shortest_path_over_the_edge",
        ],
        against: "one node per sling over a deck edge (4) by the rig geometry; a sling swung over the edge and back: 0, 1, 0",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["contact_rebuilds"],
        sampling: Count,
        tests: &[
            "tests/output_checks/rope_block.rs::contact_rebuilds_and_event_energy_follow_the_contact_node_changes",
            "tests/rope_block_cosim.rs::clones_and_bytes_continue_bit_for_bit_across_contact_changes",
        ],
        against: "a sling swung over the deck edge and back: 0 at the start and while it hangs clear, never falls, grows in every step in which contact_count changes (0, 1, 0); a lower bound only: rebuilds for nodes moved along an edge are not counted by hand",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["block_x", "block_y", "block_z"],
        sampling: Instant,
        tests: &[
            "tests/rope_rig.rs::symmetric_four_point_lift_matches_the_closed_form",
            "tests/rope_hook_position.rs::the_block_follows_a_hoisted_hook_to_its_static_equilibrium",
        ],
        against: "at rest: centre of gravity under the hook at its design height, 1e-6 m; a hook hoisted 2 m lifts the block 2 m, 1e-5 m",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &[
            "block_qw", "block_qx", "block_qy", "block_qz", "block_wx", "block_wy", "block_wz",
            "block_vx", "block_vy", "block_vz",
        ],
        sampling: Instant,
        tests: &[
            "tests/output_checks/rope_block.rs::block_position_and_attitude_are_the_integrals_of_its_velocities",
            "tests/rope_hook_position.rs::a_four_hook_rig_is_driven_and_observed_through_its_variables",
        ],
        against: "turn-over swing: the velocity integrated (trapezoidal, 2 ms) stays on the position, the body angular velocity integrated (q exp(w dt/2)) on the attitude, 1e-5 of the path and of the angle turned, |q| = 1 to 1e-12; roll from two hooks raised 0.3 m against atan(0.3 / 12.6), 5 %",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["hook#_fx", "hook#_fy"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/rope_bonds.rs::hook_forces_at_rest_carry_the_weight_of_block_and_slings",
            "tests/output_checks/rope_bonds.rs::port_powers_add_up_to_the_rope_effect_s_input_power",
        ],
        against: "at rest, lift and turn-over: the hooks' forces add up to (0, 0, -weight of block and slings), 1e-8; swinging: the bond force's z and length equal hook#_fz and hook#_load from the segment tensions, 1e-9",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["hook#_power", "hook#_winch_force", "hook#_winch_power"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/rope_bonds.rs::port_powers_add_up_to_the_rope_effect_s_input_power",
            "tests/output_checks/rope_bonds.rs::hook_power_is_the_force_outputs_against_the_commanded_velocity",
            "src/rope/winch_pull_tests.rs::winch_pull_and_dissipation_of_one_segment_are_the_hand_formulas",
            "tests/python/test_osp_ports.py::test_the_joined_winch_is_passive",
        ],
        against: "hook moving sideways and up while paying out: hook + winch power = the rope effect's own input power (its sum, what the integrator books), 1e-9 of the port power; hook power = -(fx, fy, fz) . commanded velocity through the FMU variables, fz from the tensions, 1e-9; winch power = -winch force x rate, 1e-12; the winch pull on one segment against EA (e + e^2/2) + c (strain rate) l / L by hand, 1e-12; the winch joined to a mass-spring-damper through its port decays (passivity: drum speed below 5 % of its first second's after 4 s)",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["hook#_work", "hook#_winch_work"],
        sampling: Cumulative,
        tests: &[
            "tests/output_checks/rope_bonds.rs::port_work_closes_the_energy_balance",
            "tests/output_checks/rope_bonds.rs::port_work_does_not_move_with_the_communication_step",
        ],
        against: "driven lift: hook + winch work = change of kinetic + potential + dissipated - events, 1e-6 of the work done, and = energy_input; the same at 1 ms and 0.1 s communication steps, 1e-4",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["energy_kinetic"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/rope_block.rs::hook_work_lifted_weight_and_kinetic_energy_by_hand",
        ],
        against: "1 m hoist: within 2 % of the block's m v^2/2 from the block outputs (measured 0.65 %; the rest: slings and the block's turn), 0 at rest",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["energy_potential"],
        sampling: Instant,
        tests: &[
            "tests/output_checks/rope_block.rs::hook_work_lifted_weight_and_kinetic_energy_by_hand",
        ],
        against: "1 m hoist, damped to rest: up by the hook load at rest (block and slings) x 1 m, 1e-4",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["energy_input"],
        sampling: Cumulative,
        tests: &[
            "tests/output_checks/rope_block.rs::hook_work_lifted_weight_and_kinetic_energy_by_hand",
        ],
        against: "1 m hoist: the integral of the slings' pull on the hook against its travel, -fz dz from the hook outputs (trapezoidal, 5 ms), 1e-4",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["energy_dissipated"],
        sampling: Cumulative,
        tests: &[
            "tests/output_checks/rope_block.rs::ground_friction_dissipates_its_force_times_the_sliding_speed",
            "tests/rope_ground.rs::block_dragged_along_the_ground_slides_at_the_friction_limit",
            "tests/output_checks/rope_block.rs::hook_work_lifted_weight_and_kinetic_energy_by_hand",
        ],
        against: "block dragged 2 m on the ground: the integral of ground_friction x the block's horizontal speed (5e-3; measured 1.6e-3, the rope's damping adding little); as the closing term of kinetic + potential + dissipated - input - events = constant (1e-2 of the dissipated while dragged, 1e-4 of the weight x 1 m in a damped hoist)",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["energy_events"],
        sampling: Cumulative,
        tests: &[
            "tests/output_checks/rope_block.rs::contact_rebuilds_and_event_energy_follow_the_contact_node_changes",
        ],
        against: "a sling swung over the deck edge and back: changes only in steps with a rebuild, and there by what kinetic + potential + dissipated - input jump (-1.15 J, 44.6 J, 243 J; within 0.5 J + 2e-3)",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["ground_normal", "ground_friction"],
        sampling: Instant,
        tests: &[
            "tests/rope_ground.rs::block_partly_set_down_balances_hook_and_ground",
            "tests/rope_ground.rs::block_dragged_along_the_ground_slides_at_the_friction_limit",
            "tests/python/test_rope_block.py::test_ground_contact_carries_what_the_hook_does_not",
            "tests/output_checks/rope_block.rs::ground_friction_dissipates_its_force_times_the_sliding_speed",
        ],
        against: "ground normal + hook load = weight at rest, 2e-3; sliding: friction / normal = mu (1e-2) and the hook's mean pull = mean friction (3e-2); friction x sliding speed integrates to the energy dissipated (5e-3); 0 when the ground is off",
    },
    Check {
        model: ROPE_BLOCK,
        outputs: &["daf"],
        sampling: Instant,
        tests: &[
            "tests/rope_rig.rs::symmetric_four_point_lift_matches_the_closed_form",
            "tests/rope_rig_examples.rs::every_example_scene_hangs_at_rest",
            "tests/output_checks/rope_block.rs::hook_work_lifted_weight_and_kinetic_energy_by_hand",
        ],
        against: "1 at rest, 1e-6, for the rigs and example scenes; during a hoist = -hook fz / the hook load at rest, 1e-5",
    },
    // ---------------------------------------------------------------- SpringMassDamper
    Check {
        model: "SpringMassDamper",
        outputs: &["x", "v"],
        sampling: Instant,
        tests: &[
            "src/scene/spring_mass_damper/tests.rs::free_damped_oscillation_matches_the_closed_form",
            "src/scene/spring_mass_damper/tests.rs::step_force_matches_the_closed_form",
            "tests/python/test_spring_mass_damper.py::test_matches_the_closed_form",
        ],
        against: "the closed-form damped oscillation about F/k (free, step force, an input step at 1 s through fmpy), 1e-6 of the amplitude (measured 6e-12)",
    },
    Check {
        model: "SpringMassDamper",
        outputs: &["a", "spring_force"],
        sampling: Instant,
        tests: &[
            "src/scene/spring_mass_damper/tests.rs::free_damped_oscillation_matches_the_closed_form",
            "tests/python/test_spring_mass_damper.py::test_matches_the_closed_form",
        ],
        against: "-k x - c v and (F - k x - c v) / m by hand from the reported x and v, 1e-12",
    },
];
