//! The rope effect's memory, as typed records: the one place that knows its slot layout.
//!
//! The memory of a [`super::RopeEffect`] (its part of the system's memory, see
//! [`crate::effect::ForceEffect::n_memory`]) is first one [`HookRecord`] of [`HOOK_MEM`] values
//! per hook, then one [`ContactRecord`] of [`CONTACT_MEM`] values per contact node (index =
//! contact slot). Every reader and writer of those values goes through the records below, by
//! field name; the serialized RopeBlock state stores the memory as these values in this order
//! (docs/state_serialization.md, docs/rope_memory.md), so the indices are part of the state
//! format: `tests/rope/memory.rs` pins each field to its index.
//!
//! A hook record holds the command a hook follows since its last change at `t0` (see
//! [`HookInit`]). A contact record holds the node's state after the last accepted step:
//! `sigma` [m] and the slip state along the rope, the friction share `mu_rope` [-] with which the
//! rope slides through the node, for the friction along the edge ([`super::edge_hold`]) the
//! anchor `u0` [m], the capacity `cap` [N] and the sliding state (0 sticking: the hold's spring
//! acts; `+-1` sliding along the edge: the constant force `+-cap`, see
//! [`super::RopeEffect::edge_slide_force`]), and the coefficient `mu` [-] of the node's Coulomb
//! cone ([`super::friction`]). A sticking node's `sigma` freezes the split of rope between its
//! two segments; a slipping node's `sigma` is recomputed after every accepted step (it is not
//! used while slipping).
//!
//! The records are views over a slice (`&[f64]` to read, `&mut [f64]` to read and write): they
//! copy nothing and own nothing; the memory itself stays the system's and the state's.

use super::layout::{HookInit, HookMode, SlipMode};
use crate::math::Vec3;

/// Memory values per hook.
pub const HOOK_MEM: usize = 18;
/// Memory values per contact node.
pub const CONTACT_MEM: usize = 7;

// Hook record: the index of each field (a vector takes three values from its index on).
const HOOK_POSITION: usize = 0;
const HOOK_VELOCITY: usize = 3;
const HOOK_TARGET_VELOCITY: usize = 6;
const HOOK_T0: usize = 9;
const HOOK_PAYOUT: usize = 10;
const HOOK_PAYOUT_RATE: usize = 11;
const HOOK_TARGET_PAYOUT_RATE: usize = 12;
const HOOK_RAMP: usize = 13;
const HOOK_TARGET_POSITION: usize = 14;
const HOOK_MODE: usize = 17;

// Contact record: the index of each field.
const CONTACT_SIGMA: usize = 0;
const CONTACT_MODE: usize = 1;
const CONTACT_SHARE: usize = 2;
const CONTACT_ANCHOR: usize = 3;
const CONTACT_CAP: usize = 4;
const CONTACT_EDGE_SLIDE: usize = 5;
const CONTACT_MU: usize = 6;

/// The whole memory of a rope effect: `M` is `&[f64]` (read) or `&mut [f64]` (read and write),
/// the effect's part of the memory from its first value on (what follows it is not touched).
#[derive(Debug)]
pub struct RopeMemory<M> {
    mem: M,
    hooks: usize,
}

impl<M> RopeMemory<M> {
    /// The memory `mem` of a rope effect with `hooks` hooks.
    pub fn new(mem: M, hooks: usize) -> Self {
        RopeMemory { mem, hooks }
    }

    /// Number of memory values of an effect with `hooks` hooks and `contacts` contact nodes.
    pub fn len(hooks: usize, contacts: usize) -> usize {
        HOOK_MEM * hooks + CONTACT_MEM * contacts
    }

    fn hook_range(k: usize) -> std::ops::Range<usize> {
        HOOK_MEM * k..HOOK_MEM * (k + 1)
    }

    fn contact_range(&self, c: usize) -> std::ops::Range<usize> {
        let o = HOOK_MEM * self.hooks + CONTACT_MEM * c;
        o..o + CONTACT_MEM
    }
}

impl<'a> RopeMemory<&'a [f64]> {
    /// Hook `k`'s record.
    pub fn hook(&self, k: usize) -> HookRecord<&'a [f64]> {
        HookRecord(&self.mem[Self::hook_range(k)])
    }

    /// Contact slot `c`'s record.
    pub fn contact(&self, c: usize) -> ContactRecord<&'a [f64]> {
        ContactRecord(&self.mem[self.contact_range(c)])
    }
}

impl<'a> RopeMemory<&'a mut [f64]> {
    /// Hook `k`'s record, writable.
    pub fn hook_mut(&mut self, k: usize) -> HookRecord<&mut [f64]> {
        HookRecord(&mut self.mem[Self::hook_range(k)])
    }

    /// Contact slot `c`'s record, writable.
    pub fn contact_mut(&mut self, c: usize) -> ContactRecord<&mut [f64]> {
        let r = self.contact_range(c);
        ContactRecord(&mut self.mem[r])
    }

    /// Contact slot `c`'s record, writable, for as long as the memory is borrowed.
    pub fn into_contact(self, c: usize) -> ContactRecord<&'a mut [f64]> {
        let r = self.contact_range(c);
        ContactRecord(&mut self.mem[r])
    }

    /// Contact slot `c`'s record, writable, if the memory holds it (`None` if it is shorter).
    pub fn try_into_contact(self, c: usize) -> Option<ContactRecord<&'a mut [f64]>> {
        let r = self.contact_range(c);
        self.mem.get_mut(r).map(ContactRecord)
    }
}

/// One hook's record ([`HOOK_MEM`] values): the command it follows since `t0` (see
/// [`HookInit`] for what each field means).
#[derive(Debug)]
pub struct HookRecord<M>(M);

impl<M: AsRef<[f64]>> HookRecord<M> {
    fn vec3(&self, i: usize) -> Vec3 {
        let m = self.0.as_ref();
        Vec3::new(m[i], m[i + 1], m[i + 2])
    }

    /// Position [m] (world) at `t0`.
    pub fn position(&self) -> Vec3 {
        self.vec3(HOOK_POSITION)
    }

    /// Velocity [m/s] (world) at `t0`.
    pub fn velocity(&self) -> Vec3 {
        self.vec3(HOOK_VELOCITY)
    }

    /// Target velocity [m/s] (world; [`HookMode::Velocity`]).
    pub fn target_velocity(&self) -> Vec3 {
        self.vec3(HOOK_TARGET_VELOCITY)
    }

    /// Time [s] of the last command change.
    pub fn t0(&self) -> f64 {
        self.0.as_ref()[HOOK_T0]
    }

    /// Pay-out [m] at `t0`.
    pub fn payout(&self) -> f64 {
        self.0.as_ref()[HOOK_PAYOUT]
    }

    /// Pay-out rate [m/s] at `t0`.
    pub fn payout_rate(&self) -> f64 {
        self.0.as_ref()[HOOK_PAYOUT_RATE]
    }

    /// Target pay-out rate [m/s].
    pub fn target_payout_rate(&self) -> f64 {
        self.0.as_ref()[HOOK_TARGET_PAYOUT_RATE]
    }

    /// Ramp time [s] from `t0`.
    pub fn ramp(&self) -> f64 {
        self.0.as_ref()[HOOK_RAMP]
    }

    /// Target position [m] (world; [`HookMode::Position`]).
    pub fn target_position(&self) -> Vec3 {
        self.vec3(HOOK_TARGET_POSITION)
    }

    /// Command mode (stored as [`HookMode::code`]).
    pub fn mode(&self) -> HookMode {
        HookMode::from_code(self.0.as_ref()[HOOK_MODE])
    }

    /// The whole record as the hook description it was written from.
    pub fn get(&self) -> HookInit {
        HookInit {
            position: self.position(),
            velocity: self.velocity(),
            target_velocity: self.target_velocity(),
            t0: self.t0(),
            payout: self.payout(),
            payout_rate: self.payout_rate(),
            target_payout_rate: self.target_payout_rate(),
            ramp: self.ramp(),
            mode: self.mode(),
            target_position: self.target_position(),
        }
    }
}

impl<M: AsMut<[f64]>> HookRecord<M> {
    fn set_vec3(&mut self, i: usize, v: &Vec3) {
        self.0.as_mut()[i..i + 3].copy_from_slice(v.as_slice());
    }

    /// Writes every field from `h`.
    pub fn set(&mut self, h: &HookInit) {
        self.set_vec3(HOOK_POSITION, &h.position);
        self.set_vec3(HOOK_VELOCITY, &h.velocity);
        self.set_vec3(HOOK_TARGET_VELOCITY, &h.target_velocity);
        let m = self.0.as_mut();
        m[HOOK_T0] = h.t0;
        m[HOOK_PAYOUT] = h.payout;
        m[HOOK_PAYOUT_RATE] = h.payout_rate;
        m[HOOK_TARGET_PAYOUT_RATE] = h.target_payout_rate;
        m[HOOK_RAMP] = h.ramp;
        self.set_vec3(HOOK_TARGET_POSITION, &h.target_position);
        self.0.as_mut()[HOOK_MODE] = h.mode.code();
    }
}

/// One contact node's record ([`CONTACT_MEM`] values), see the module documentation.
#[derive(Debug)]
pub struct ContactRecord<M>(M);

impl<M: AsRef<[f64]>> ContactRecord<M> {
    /// Material coordinate [m] of the node after the last accepted step.
    pub fn sigma(&self) -> f64 {
        self.0.as_ref()[CONTACT_SIGMA]
    }

    /// Slip state along the rope.
    pub fn mode(&self) -> SlipMode {
        SlipMode::from_code(self.mode_code())
    }

    /// The stored code of the slip state ([`SlipMode::code`]), as stored.
    pub fn mode_code(&self) -> f64 {
        self.0.as_ref()[CONTACT_MODE]
    }

    /// Friction share `mu_rope` [-] with which the rope slides through the node.
    pub fn share(&self) -> f64 {
        self.0.as_ref()[CONTACT_SHARE]
    }

    /// Anchor `u0` [m] of the hold along the edge (from the edge's point; 0 without a hold).
    pub fn anchor(&self) -> f64 {
        self.0.as_ref()[CONTACT_ANCHOR]
    }

    /// Friction capacity `cap` [N] along the edge.
    pub fn cap(&self) -> f64 {
        self.0.as_ref()[CONTACT_CAP]
    }

    /// Sliding state along the edge [-]: 0 sticking, `+-1` sliding (the sign of the friction
    /// force `+-cap` on the node's coordinate along the edge).
    pub fn edge_slide(&self) -> f64 {
        self.0.as_ref()[CONTACT_EDGE_SLIDE]
    }

    /// Coefficient `mu` [-] of the node's Coulomb cone.
    pub fn mu(&self) -> f64 {
        self.0.as_ref()[CONTACT_MU]
    }
}

impl<M: AsMut<[f64]>> ContactRecord<M> {
    /// Sets the material coordinate [m].
    pub fn set_sigma(&mut self, sigma: f64) {
        self.0.as_mut()[CONTACT_SIGMA] = sigma;
    }

    /// Sets the slip state along the rope.
    pub fn set_mode(&mut self, mode: SlipMode) {
        self.0.as_mut()[CONTACT_MODE] = mode.code();
    }

    /// Sets the friction share `mu_rope` [-].
    pub fn set_share(&mut self, share: f64) {
        self.0.as_mut()[CONTACT_SHARE] = share;
    }

    /// Sets the anchor `u0` [m] along the edge.
    pub fn set_anchor(&mut self, u0: f64) {
        self.0.as_mut()[CONTACT_ANCHOR] = u0;
    }

    /// Sets the capacity `cap` [N] along the edge.
    pub fn set_cap(&mut self, cap: f64) {
        self.0.as_mut()[CONTACT_CAP] = cap;
    }

    /// Sets the sliding state along the edge [-] (0, or the sign of the friction force).
    pub fn set_edge_slide(&mut self, state: f64) {
        self.0.as_mut()[CONTACT_EDGE_SLIDE] = state;
    }

    /// Sets the cone's coefficient `mu` [-].
    pub fn set_mu(&mut self, mu: f64) {
        self.0.as_mut()[CONTACT_MU] = mu;
    }
}
