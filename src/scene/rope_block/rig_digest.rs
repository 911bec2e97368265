//! Digests of a rig's values (block, lugs, slings, hooks), kept in serialized FMU states so that a
//! state refuses to restore into an instance whose scene file gives another rig.
//!
//! Each part is written as bytes (every number as its IEEE bits, little endian, with a tag for
//! each enumeration case and for every value left to the scene-wide default) and hashed with
//! [`checksum64`]. File paths are not part of the digest: a mesh block contributes its scale, its
//! bytes are the state's separate mesh digest.

use super::params::Route;
use super::rig::{BlockGeometry, Rig};
use crate::math::Vec3;
use crate::scene::bytes::checksum64;

/// Names of the parts, in the order of [`RigDigest::parts`].
pub const RIG_PARTS: [&str; 4] = ["[block]", "[[lug]]", "[[sling]]", "[[hook]]"];

/// The digests of a rig's four parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RigDigest {
    /// Block, lugs, slings, hooks (see [`RIG_PARTS`]).
    pub parts: [u64; 4],
}

/// Bytes of the values of one part.
#[derive(Default)]
struct Bytes(Vec<u8>);

impl Bytes {
    fn tag(&mut self, t: u8) {
        self.0.push(t);
    }
    fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn vec3(&mut self, v: &Vec3) {
        v.iter().for_each(|x| self.f64(*x));
    }
    fn opt(&mut self, x: Option<f64>) {
        match x {
            None => self.tag(0),
            Some(v) => {
                self.tag(1);
                self.f64(v);
            }
        }
    }
    fn digest(&self) -> u64 {
        checksum64(&self.0)
    }
}

impl RigDigest {
    /// The digest of `rig`'s values.
    pub fn of(rig: &Rig) -> Self {
        let mut block = Bytes::default();
        let b = &rig.block;
        match &b.geometry {
            BlockGeometry::Shape(s) => {
                block.tag(0);
                for x in [s.length, s.breadth, s.height, s.bilge_radius] {
                    block.f64(x);
                }
                block.u64(s.bilge_facets as u64);
                block.tag(u8::from(s.both_bilges));
            }
            BlockGeometry::Mesh { scale, .. } => {
                block.tag(1);
                block.f64(*scale);
            }
        }
        block.opt(b.mass);
        block.opt(b.plate.map(|p| p.thickness));
        block.opt(b.plate.map(|p| p.density));
        match b.cog {
            None => block.tag(0),
            Some(c) => {
                block.tag(1);
                block.vec3(&c);
            }
        }
        match b.inertia {
            None => block.tag(0),
            Some(i) => {
                block.tag(1);
                i.iter().for_each(|x| block.f64(*x));
            }
        }
        match b.pose {
            None => block.tag(0),
            Some(pose) => {
                block.tag(1);
                block.vec3(&pose.position);
                pose.orientation.coords.iter().for_each(|x| block.f64(*x));
            }
        }
        let mut lugs = Bytes::default();
        lugs.u64(rig.lugs.len() as u64);
        rig.lugs.iter().for_each(|l| lugs.vec3(&l.position));
        let mut slings = Bytes::default();
        slings.u64(rig.slings.len() as u64);
        for s in &rig.slings {
            slings.u64(s.lug as u64);
            slings.u64(s.hook as u64);
            slings.opt(s.length);
            slings.f64(s.length_factor);
            for x in [
                s.ea,
                s.mass_per_length,
                s.diameter,
                s.damping,
                s.breaking_load,
            ] {
                slings.opt(x);
            }
            match s.route {
                Route::Straight => slings.tag(0),
                Route::OverEdge => slings.tag(1),
                Route::Via(p) => {
                    slings.tag(2);
                    slings.vec3(&p);
                }
            }
        }
        let mut hooks = Bytes::default();
        hooks.u64(rig.hooks.len() as u64);
        for h in &rig.hooks {
            hooks.vec3(&h.position);
            hooks.u64(u64::from(h.crane));
        }
        RigDigest {
            parts: [
                block.digest(),
                lugs.digest(),
                slings.digest(),
                hooks.digest(),
            ],
        }
    }

    /// `None` when equal, else the names of the parts that differ (`"[[lug]], [[sling]]"`).
    pub fn differences(&self, other: &RigDigest) -> Option<String> {
        let names: Vec<&str> = RIG_PARTS
            .iter()
            .zip(self.parts.iter().zip(&other.parts))
            .filter(|(_, (a, b))| a != b)
            .map(|(n, _)| *n)
            .collect();
        (!names.is_empty()).then(|| names.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_part_is_named_and_only_it() {
        let a = Rig::default();
        assert_eq!(RigDigest::of(&a).differences(&RigDigest::of(&a)), None);
        let mut b = a.clone();
        b.lugs[2].position.x += 1e-9;
        b.hooks[0].crane = 1;
        let d = RigDigest::of(&a).differences(&RigDigest::of(&b));
        assert_eq!(d.as_deref(), Some("[[lug]], [[hook]]"));
        let mut c = a.clone();
        c.slings[0].ea = Some(1.6e8);
        let d = RigDigest::of(&a).differences(&RigDigest::of(&c));
        assert_eq!(d.as_deref(), Some("[[sling]]"));
    }
}
