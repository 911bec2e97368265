//! The geometric stiffness of joint constraints: the derivative of a joint's generalized reaction
//! `G^T lambda` with respect to the positions of its two bodies, for the Newton matrices of the
//! implicit integrators. Without it their iteration converges only linearly where joints carry
//! large forces on levers (a long hanging chain: rate 0.25 per iteration at 1000 bodies and a
//! 1 ms step, 10 iterations per step instead of 3).
//!
//! Conventions as [`super::constraint`]: per body a translation increment (world) and a rotation
//! increment `dtheta` (body frame, `R -> R (I + [dtheta]x)`). For a row term `c . (R s)` with
//! `c` fixed in the world the rotation gradient is `s x R^T c`, whose derivative is
//! `[s]x [R^T c]x dtheta`; the other derivatives follow from the primitives' world covectors
//! (derived in the comments below). Frames on flexible-body nodes and angle drives are left out
//! (their rows keep the linear convergence).

use crate::math::{Mat3, Matrix6, Vec3, skew};
use crate::model::kinematics::{BodyKin, kin_of};
use crate::model::{Joint, JointKind};

/// Which 3x3 parts of a 6x6 block are formed: translation-translation, translation-rotation,
/// rotation-translation, rotation-rotation (rows: the side's reaction entries, columns: the other
/// side's increments).
pub type Parts = [bool; 4];

/// `sum_r lambda_r d(g_r)/dx` of one joint: `blocks[a][b]` holds side `a`'s six reaction entries
/// against side `b`'s six position increments, `parts[a][b]` which of its 3x3 parts the joint's
/// kind forms (a structural property: the same for every evaluation).
#[derive(Debug, Clone, Copy)]
pub struct JointStiffness {
    pub blocks: [[Matrix6<f64>; 2]; 2],
    pub parts: [[Parts; 2]; 2],
}

impl JointStiffness {
    fn zero() -> Self {
        JointStiffness {
            blocks: [[Matrix6::zeros(); 2]; 2],
            parts: [[[false; 4]; 2]; 2],
        }
    }

    /// Adds `m` to the 3x3 part `part` (0 tt, 1 t-theta, 2 theta-t, 3 theta-theta) of block
    /// `(a, b)`.
    fn add(&mut self, a: usize, b: usize, part: usize, m: &Mat3) {
        let (r0, c0) = PART_ORIGIN[part];
        let blk = &mut self.blocks[a][b];
        for r in 0..3 {
            for c in 0..3 {
                blk[(r0 + r, c0 + c)] += m[(r, c)];
            }
        }
        self.parts[a][b][part] = true;
    }

    /// Calls `f(a, b, row, column, value)` for every entry of the formed parts: side `a`'s
    /// reaction entry `row` (0-2 translation, 3-5 rotation) against side `b`'s increment
    /// `column`.
    pub fn for_each_entry(&self, mut f: impl FnMut(usize, usize, usize, usize, f64)) {
        for a in 0..2 {
            for b in 0..2 {
                for (part, &(r0, c0)) in PART_ORIGIN.iter().enumerate() {
                    if !self.parts[a][b][part] {
                        continue;
                    }
                    for r in r0..r0 + 3 {
                        for c in c0..c0 + 3 {
                            f(a, b, r, c, self.blocks[a][b][(r, c)]);
                        }
                    }
                }
            }
        }
    }
}

/// Row and column where each 3x3 part of a 6x6 block starts.
const PART_ORIGIN: [(usize, usize); 4] = [(0, 0), (0, 3), (3, 0), (3, 3)];

/// One side of a joint: rotation and the frame's body vectors.
struct Side<'a> {
    k: &'a BodyKin,
    origin: Vec3,
    axes: Mat3,
}

impl Side<'_> {
    fn axis(&self, c: usize) -> Vec3 {
        self.axes.column(c).into()
    }
}

/// Point coincidence rows with world multipliers `l` (side j enters with `-c`): only the
/// rotation of each side's own lever, `[o]x [R^T l]x` (side i) and `-[o]x [R^T l]x` (side j).
fn point(si: &Side, sj: &Side, l: &Vec3, out: &mut JointStiffness) {
    let hi = skew(&si.origin) * skew(&(si.k.rot.transpose() * l));
    let hj = skew(&sj.origin) * skew(&(sj.k.rot.transpose() * l));
    out.add(0, 0, 3, &hi);
    out.add(1, 1, 3, &(-hj));
}

/// `u_i . u_j` (axis `ci` of i, `cj` of j) with multiplier `lam`. Gradients `a_i x R_i^T u_j`
/// and `a_j x R_j^T u_i`; `u_j` moves with side j as `-R_j [a_j]x dtheta_j`.
fn dot1(si: &Side, ci: usize, sj: &Side, cj: usize, lam: f64, out: &mut JointStiffness) {
    let (ai, aj) = (si.axis(ci), sj.axis(cj));
    let (ui, uj) = (si.k.rot * ai, sj.k.rot * aj);
    let (ri, rj) = (si.k.rot, sj.k.rot);
    out.add(0, 0, 3, &(lam * skew(&ai) * skew(&(ri.transpose() * uj))));
    out.add(
        0,
        1,
        3,
        &(-lam * skew(&ai) * ri.transpose() * rj * skew(&aj)),
    );
    out.add(1, 1, 3, &(lam * skew(&aj) * skew(&(rj.transpose() * ui))));
    out.add(
        1,
        0,
        3,
        &(-lam * skew(&aj) * rj.transpose() * ri * skew(&ai)),
    );
}

/// `u_i . (p_j - p_i)` (axis `ci` of i) with multiplier `lam`. Gradients: translation `-u_i`
/// (i) and `u_i` (j); rotation `a_i x R_i^T d - o_i x a_i` (i) and `o_j x R_j^T u_i` (j), with
/// `d = p_j - p_i`, whose image `R_i^T d` moves by `[R_i^T d + o_i]x dtheta_i` with side i's
/// rotation, by `-R_i^T dr_i` and `R_i^T dr_j` with the translations and by
/// `-R_i^T R_j [o_j]x dtheta_j` with side j's rotation.
fn dot2(si: &Side, ci: usize, sj: &Side, lam: f64, out: &mut JointStiffness) {
    let ai = si.axis(ci);
    let (ri, rj) = (si.k.rot, sj.k.rot);
    let ui = ri * ai;
    let (oi, oj) = (si.origin, sj.origin);
    let d = sj.k.r + rj * oj - si.k.r - ri * oi;
    let du_i = ri * skew(&ai); // -d(u_i)/d(theta_i)
    out.add(0, 0, 1, &(lam * du_i));
    out.add(1, 0, 1, &(-lam * du_i));
    let sai = skew(&ai);
    out.add(0, 0, 3, &(lam * sai * skew(&(ri.transpose() * d + oi))));
    out.add(0, 0, 2, &(-lam * sai * ri.transpose()));
    out.add(0, 1, 2, &(lam * sai * ri.transpose()));
    out.add(0, 1, 3, &(-lam * sai * ri.transpose() * rj * skew(&oj)));
    let soj = skew(&oj);
    out.add(1, 1, 3, &(lam * soj * skew(&(rj.transpose() * ui))));
    out.add(1, 0, 3, &(-lam * soj * rj.transpose() * ri * sai));
}

/// The geometric stiffness of `joint` for its multipliers `lambda` (one per row of the joint's
/// kind, in [`super::constraint::joint_rows`]' order; 0 for a row left out as redundant), or
/// `None` where it is not formed (a frame on a flexible-body node, angle drives).
pub fn joint_stiffness(joint: &Joint, kins: &[BodyKin], lambda: &[f64]) -> Option<JointStiffness> {
    let (fi, fj) = (&joint.frame_i, &joint.frame_j);
    if fi.node.is_some() || fj.node.is_some() {
        return None;
    }
    let si = Side {
        k: kin_of(kins, fi.body),
        origin: fi.origin,
        axes: fi.axes,
    };
    let sj = Side {
        k: kin_of(kins, fj.body),
        origin: fj.origin,
        axes: fj.axes,
    };
    let mut out = JointStiffness::zero();
    let l3 = |k: usize| Vec3::new(lambda[k], lambda[k + 1], lambda[k + 2]);
    let (x, y, z) = (0, 1, 2);
    match joint.kind {
        JointKind::Spherical => point(&si, &sj, &l3(0), &mut out),
        JointKind::PointOnLine => {
            dot2(&si, x, &sj, lambda[0], &mut out);
            dot2(&si, y, &sj, lambda[1], &mut out);
        }
        JointKind::Revolute => {
            point(&si, &sj, &l3(0), &mut out);
            dot1(&si, z, &sj, x, lambda[3], &mut out);
            dot1(&si, z, &sj, y, lambda[4], &mut out);
        }
        JointKind::Fixed => {
            point(&si, &sj, &l3(0), &mut out);
            dot1(&si, z, &sj, x, lambda[3], &mut out);
            dot1(&si, z, &sj, y, lambda[4], &mut out);
            dot1(&si, x, &sj, y, lambda[5], &mut out);
        }
        JointKind::Prismatic => {
            dot1(&si, z, &sj, x, lambda[0], &mut out);
            dot1(&si, z, &sj, y, lambda[1], &mut out);
            dot1(&si, x, &sj, y, lambda[2], &mut out);
            dot2(&si, x, &sj, lambda[3], &mut out);
            dot2(&si, y, &sj, lambda[4], &mut out);
        }
        JointKind::TranslationDrive(_) => dot2(&si, z, &sj, lambda[0], &mut out),
        JointKind::AngleDrive(_) => return None,
    }
    Some(out)
}
