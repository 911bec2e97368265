//! Assembles the PanelLock multibody model from [`PanelLockParams`].
//!
//! The array folds like an accordion in the world x-y plane; every hinge axis is parallel to the
//! world z axis. Hinge `k` (0 = root) has deployment angle `theta_k`, from its stowed angle to its
//! lock angle; its joint frames have `z = s_k e_z` with `s_k = +1, -1, +1, ...` alternating the
//! fold direction, so `theta_k = lock_k + raw_k` with `raw_k` the relative angle of the frames
//! (zero when deployed straight). Chain: satellite -> root hinge body -> yoke -> hinge body ->
//! panel 1 -> ... Each hinge body turns on a revolute joint against its inboard neighbour (the
//! hinge shaft: deployment spring, damping, latch and motor act across it) and is bolted to its
//! outboard neighbour by a fixed joint (whose multipliers are the hinge-to-panel loads).

use super::flex_outputs::FlexPanelRef;
use super::flex_panel::flex_panel;
use super::params::PanelLockParams;
use crate::contact::ContactLaw;
use crate::contact::latch::{LatchGeometry, LatchParams};
use crate::effect::angle_stop::{AngleStop, AngleStops};
use crate::effect::body_load::{InputLoad, InputLoads};
use crate::effect::cable_loop::{CableLoop, CableLoops};
use crate::effect::hinge_friction::{DEFAULT_SLIP_RATE, HingeFriction, HingeFrictions};
use crate::effect::latch::{Latch, Latches};
use crate::flex::ModalBodyData;
use crate::math::{Mat3, Quat, Vec3};
use crate::model::*;
use std::sync::Arc;

/// Where things are in the assembled model.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The satellite (ground when it is fixed).
    pub satellite: BodyId,
    /// Yoke then panels, inboard to outboard.
    pub plates: Vec<BodyId>,
    /// Plate lengths [m].
    pub plate_lengths: Vec<f64>,
    /// Hinge bodies, root first.
    pub hinges: Vec<BodyId>,
    /// Frames of each hinge shaft as force effects and outputs use them: (inboard side, hinge
    /// body side); on a flexible inboard panel the inboard one rides on the panel's outboard node
    /// body ([`ModelBuilder::force_frame`]).
    pub hinge_frames: Vec<(Frame, Frame)>,
    /// Lock angle of each hinge [rad].
    pub lock_angles: Vec<f64>,
    /// Index of the root hinge's revolute joint in `model.joints`.
    pub root_joint: usize,
    /// Model input index of the root-hinge motor torque [N m].
    pub motor_input: usize,
    /// Model input indices of the satellite force x, y, z [N] and torque x, y, z [N m] (in
    /// `load_frame`, at the satellite's centre of mass); `None` with a fixed satellite (no
    /// inputs, no load effect).
    pub satellite_inputs: Option<[usize; 6]>,
    /// The latches (for evaluating wall forces in outputs), if enabled.
    pub latches: Option<Arc<Latches>>,
    /// Flexible panels: the modal data of the outer panel and its tip node (outboard edge,
    /// mid-width); `None` with rigid panels.
    pub flex_tip: Option<(Arc<ModalBodyData>, usize)>,
    /// Flexible panels, inboard to outboard, for their deflection outputs; empty when rigid.
    pub flex_panels: Vec<FlexPanelRef>,
}

/// Names of the satellite's model inputs: force x, y, z [N], torque x, y, z [N m].
pub const SATELLITE_INPUTS: [&str; 6] = [
    "satellite_force_x",
    "satellite_force_y",
    "satellite_force_z",
    "satellite_torque_x",
    "satellite_torque_y",
    "satellite_torque_z",
];

fn plate_inertia(m: f64, length: f64, width: f64, thick: f64) -> Mat3 {
    Mat3::from_diagonal(&Vec3::new(
        m * (width * width + thick * thick) / 12.0,
        m * (length * length + width * width) / 12.0,
        m * (length * length + thick * thick) / 12.0,
    ))
}

/// Builds the model and its layout; `Err` explains a bad parameter.
pub fn build(p: &PanelLockParams) -> Result<(Model, Layout), String> {
    build_posed(p, None)
}

/// [`build`] with the bodies placed at the hinges' deployment angles `pose` [rad] (one per
/// hinge) instead of their stowed angles: the same bodies, joints and effects in the same order,
/// only the initial positions differ (the locked array's start for its linearization,
/// [`super::locked_frequency`]).
pub(super) fn build_posed(
    p: &PanelLockParams,
    pose: Option<&[f64]>,
) -> Result<(Model, Layout), String> {
    p.validate()?;
    let mut b = ModelBuilder::new();
    let motor_input = b.add_input("root_motor_torque");
    if let Some(g) = p.gravity {
        b.set_gravity(Some(Vec3::new(0.0, 0.0, -g)))?;
    }
    let ez = Vec3::z();
    let rot = |phi: f64| Quat::from_axis_angle(&Vec3::z_axis(), phi);
    // satellite and the root attach point (in the satellite frame): the body frame at the
    // centre of mass, parallel to the world at t = 0, the attach point at the world origin
    let cg = Vec3::from(p.satellite_cg);
    let (satellite, attach_local) = if p.free_satellite {
        let [a, bb, c] = p.satellite_inertia;
        let id = b.add_rigid_body(
            "satellite",
            p.satellite_mass,
            Mat3::from_diagonal(&Vec3::new(a, bb, c)),
            BodyInit::at(cg),
        )?;
        (id, -cg)
    } else {
        (BodyId::GROUND, Vec3::zeros())
    };
    let satellite_inputs = p
        .free_satellite
        .then(|| SATELLITE_INPUTS.map(|name| b.add_input(name)));
    if let Some(idx) = satellite_inputs {
        b.add_force_effect(Arc::new(InputLoads {
            elements: vec![InputLoad {
                name: "satellite load".into(),
                body: satellite,
                force_inputs: [idx[0], idx[1], idx[2]],
                torque_inputs: [idx[3], idx[4], idx[5]],
                frame: p.load_frame,
            }],
        }));
    }
    let n = p.n_hinges();
    let mut layout = Layout {
        satellite,
        plates: Vec::new(),
        plate_lengths: Vec::new(),
        hinges: Vec::new(),
        hinge_frames: Vec::new(),
        lock_angles: Vec::new(),
        root_joint: 0,
        motor_input,
        satellite_inputs,
        latches: None,
        flex_tip: None,
        flex_panels: Vec::new(),
    };
    // plate frame of a flexible panel (x length, y width, z normal) in the rigid panel frame
    // (x length, y normal, z width = hinge axis): a quarter turn about x
    let plate_turn = Quat::from_axis_angle(&Vec3::x_axis(), std::f64::consts::FRAC_PI_2);
    let mut frictions = Vec::new();
    let mut latches = Vec::new();
    let mut stops = Vec::new();
    let (mut phi, mut pos) = (0.0, Vec3::zeros());
    let (mut inboard, mut inboard_tip) = (satellite, attach_local);
    let mut inboard_node: Option<usize> = None;
    for k in 0..n {
        let s = if k == 0 {
            1.0
        } else if k % 2 == 1 {
            -1.0
        } else {
            1.0
        };
        let hv = p.hinge(k);
        let (lock, stow) = (hv.lock_angle, hv.stowed_angle);
        phi += s * (pose.map_or(stow, |a| a[k]) - lock);
        let pv = p.panel(k);
        let (len, mass, name) = if k == 0 {
            (p.yoke_length, p.yoke_mass, "yoke".to_string())
        } else {
            (pv.length, pv.mass(), format!("panel{k}"))
        };
        let dir = rot(phi) * Vec3::x();
        let hinge_inertia = Mat3::identity() * (p.hinge_mass * p.hinge_gyration_radius.powi(2));
        let hinge = b.add_rigid_body(
            &format!("hinge{k}"),
            p.hinge_mass,
            hinge_inertia,
            BodyInit::at(pos).oriented(rot(phi)),
        )?;
        let flex = if k > 0 && p.flexible_panels {
            Some(flex_panel(&p.with_panel(k), k == n - 1)?)
        } else {
            None
        };
        let plate = match &flex {
            None => b.add_rigid_body(
                &name,
                mass,
                plate_inertia(mass, len, pv.width, pv.thickness),
                BodyInit::at(pos + 0.5 * len * dir).oriented(rot(phi)),
            )?,
            Some(f) => {
                let zeros = vec![0.0; f.data.n_modes()];
                b.add_modal_body(
                    &name,
                    f.data.clone(),
                    BodyInit::at(pos - 0.5 * pv.width * ez).oriented(rot(phi) * plate_turn),
                    &zeros,
                    &zeros,
                )?
            }
        };
        let fi = match inboard_node {
            None => Frame::with_z(inboard, inboard_tip, s * ez),
            // the hinge axis (world z) is the plate's y axis
            Some(node) => Frame::with_z(inboard, Vec3::zeros(), s * Vec3::y()).on_node(node),
        };
        let fj = Frame::with_z(hinge, Vec3::zeros(), s * ez);
        if k == 0 {
            layout.root_joint = 0;
        }
        b.add_joint(&format!("hinge{k} shaft"), JointKind::Revolute, fi, fj)?;
        // The shaft's inboard frame as force effects see it: on a flexible panel's outboard
        // node it rides on the node body, so that spring, latch, stop, friction, cable loop and
        // the hinge-angle output all act across the same two frames as the shaft joint.
        let fi = b.force_frame(&format!("hinge{k}"), "inboard", &fi, true)?;
        b.add_joint(
            &format!("hinge{k} bolts"),
            JointKind::Fixed,
            Frame::new(hinge, Vec3::zeros()),
            match &flex {
                None => Frame::new(plate, Vec3::new(-0.5 * len, 0.0, 0.0)),
                // node frame axes = the hinge body's (rigid panel) axes
                Some(f) => Frame::at_node(plate, f.inboard_node).with_axes(
                    Vec3::x(),
                    -Vec3::z(),
                    Vec3::y(),
                ),
            },
        )?;
        let (preload, stiffness, damping) = (hv.spring_preload, hv.spring_stiffness, hv.damping);
        if stiffness > 0.0 {
            b.add_torsion_spring(TorsionSpring {
                name: format!("hinge{k} spring"),
                frame_i: fi,
                frame_j: fj,
                stiffness,
                damping,
                free_angle: lock + preload / stiffness,
                angle_offset: lock,
            })?;
        } else {
            if preload > 0.0 {
                b.add_joint_torque(JointTorque {
                    name: format!("hinge{k} constant spring"),
                    frame_i: fi,
                    frame_j: fj,
                    torque: Profile::constant(preload),
                })?;
            }
            if damping > 0.0 {
                b.add_torsion_spring(TorsionSpring {
                    name: format!("hinge{k} damper"),
                    frame_i: fi,
                    frame_j: fj,
                    stiffness: 0.0,
                    damping,
                    free_angle: 0.0,
                    angle_offset: lock,
                })?;
            }
        }
        if hv.friction_torque > 0.0 {
            frictions.push(HingeFriction {
                name: format!("hinge{k} friction"),
                frame_i: fi,
                frame_j: fj,
                torque: hv.friction_torque,
                slip_rate: DEFAULT_SLIP_RATE,
            });
        }
        if p.latches {
            let law = ContactLaw::new(
                hv.contact_law,
                hv.contact_stiffness,
                hv.contact_exponent,
                hv.restitution,
            )
            .map_err(|e| format!("latch of hinge {k}: {e}"))?;
            let geometry = LatchGeometry::new(LatchParams {
                cam_radius: p.cam_radius,
                groove_width: p.groove_width,
                groove_depth: p.groove_depth,
                pin_radius: p.pin_radius,
                lock_angle: lock,
            })
            .map_err(|e| format!("latch of hinge {k}: {e}"))?;
            latches.push(Latch {
                name: format!("hinge{k} latch"),
                frame_i: fi,
                frame_j: fj,
                angle_offset: lock,
                geometry,
                law,
            });
        }
        stops.push(AngleStop {
            name: format!("hinge{k} stow stop"),
            frame_i: fi,
            frame_j: fj,
            angle_offset: lock,
            min_angle: stow,
            stiffness: p.stop_stiffness,
            damping: p.stop_damping,
        });
        if let Some(f) = &flex {
            layout.flex_panels.push(FlexPanelRef::new(
                plate,
                f.data.clone(),
                f.outboard_node,
                p.n_modes,
            ));
        }
        layout.plates.push(plate);
        layout.plate_lengths.push(len);
        layout.hinges.push(hinge);
        layout.hinge_frames.push((fi, fj));
        layout.lock_angles.push(lock);
        pos += len * dir;
        inboard = plate;
        inboard_tip = Vec3::new(0.5 * len, 0.0, 0.0);
        inboard_node = flex.as_ref().map(|f| f.outboard_node);
        if k == n - 1 {
            layout.flex_tip = flex.map(|f| (f.data, f.outboard_node));
        }
    }
    let (fi, fj) = layout.hinge_frames[0];
    b.add_joint_torque(JointTorque {
        name: "root motor".into(),
        frame_i: fi,
        frame_j: fj,
        torque: Profile::Input {
            index: motor_input,
            gain: 1.0,
        },
    })?;
    b.add_force_effect(Arc::new(AngleStops { elements: stops }));
    if !latches.is_empty() {
        let l = Arc::new(Latches { elements: latches });
        layout.latches = Some(l.clone());
        b.add_force_effect(l);
    }
    if !frictions.is_empty() {
        b.add_force_effect(Arc::new(HingeFrictions {
            elements: frictions,
        }));
    }
    if p.cable_loop {
        let span = |k: usize| {
            let h = p.hinge(k);
            h.lock_angle - h.stowed_angle
        };
        let loops = (0..n - 1)
            .map(|k| CableLoop {
                name: format!("cable loop {k}-{}", k + 1),
                a: [layout.hinge_frames[k].0, layout.hinge_frames[k].1],
                b: [layout.hinge_frames[k + 1].0, layout.hinge_frames[k + 1].1],
                c_a: 1.0,
                c_b: -span(k) / span(k + 1),
                s0: 0.0,
                stiffness: p.cable_stiffness,
                damping: p.cable_damping,
            })
            .collect();
        b.add_force_effect(Arc::new(CableLoops { elements: loops }));
    }
    Ok((b.build()?, layout))
}
