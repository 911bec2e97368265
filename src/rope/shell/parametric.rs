//! A built-in parametric ship block: a prism along x whose cross-section is a rectangle with
//! optionally rounded (faceted) bilge corners at the bottom.
//!
//! Design frame: `x` along the block's length (from `-L/2` to `L/2`), `y` across its breadth
//! (from `-B/2` to `B/2`), `z` up from the bottom (`0`) to the top deck (`H`). The box corners are
//! plate edges of 90 degrees; a bilge of radius `R` is a curved shell plate of `n` flat facets, so
//! it contributes `n + 1` plate edges each turning a wrapped rope by `90 / n` degrees.

use super::{DEFAULT_MIN_EDGE_ANGLE, ShellMesh};
use crate::math::Vec3;

/// Dimensions of the parametric block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockShape {
    /// Length along x [m].
    pub length: f64,
    /// Breadth along y [m].
    pub breadth: f64,
    /// Height along z [m].
    pub height: f64,
    /// Radius of the bilge plate(s) at the bottom corners [m]; 0 for a plain box.
    pub bilge_radius: f64,
    /// Number of flat facets of each bilge plate.
    pub bilge_facets: usize,
    /// Round both bottom corners (`true`) or only the one at `y = +B/2`.
    pub both_bilges: bool,
}

impl Default for BlockShape {
    /// A 200 t double-bottom-like block: 18 m x 12 m x 7 m with a 2 m bilge on one side in 8
    /// facets.
    fn default() -> Self {
        BlockShape {
            length: 18.0,
            breadth: 12.0,
            height: 7.0,
            bilge_radius: 2.0,
            bilge_facets: 8,
            both_bilges: false,
        }
    }
}

impl BlockShape {
    /// Checks the dimensions; `Err` names the bad one.
    pub fn validate(&self) -> Result<(), String> {
        for (name, v) in [
            ("length", self.length),
            ("breadth", self.breadth),
            ("height", self.height),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("block {name} must be finite and > 0 m, got {v}"));
            }
        }
        let r = self.bilge_radius;
        let lim = if self.both_bilges {
            0.5 * self.breadth
        } else {
            self.breadth
        }
        .min(self.height);
        if !(r.is_finite() && r >= 0.0 && r < lim) {
            return Err(format!(
                "bilge radius must be in [0, {lim}) m for this breadth and height, got {r}"
            ));
        }
        if r > 0.0 && !(1..=256).contains(&self.bilge_facets) {
            return Err(format!(
                "bilge facets must be in 1..=256, got {}",
                self.bilge_facets
            ));
        }
        Ok(())
    }

    /// The cross-section polygon in (y, z), counter-clockwise seen from +x.
    pub fn section(&self) -> Vec<(f64, f64)> {
        let (b, h, r) = (0.5 * self.breadth, self.height, self.bilge_radius);
        let n = self.bilge_facets.max(1);
        let mut pts = Vec::new();
        let arc = |cy: f64, a0: f64, pts: &mut Vec<(f64, f64)>| {
            for k in 0..=n {
                let a = a0 + 0.5 * std::f64::consts::PI * k as f64 / n as f64;
                pts.push((cy + r * a.cos(), r + r * a.sin()));
            }
        };
        // bottom-left corner
        if r > 0.0 && self.both_bilges {
            arc(-b + r, std::f64::consts::PI, &mut pts);
        } else {
            pts.push((-b, 0.0));
        }
        // bottom-right corner
        if r > 0.0 {
            arc(b - r, -0.5 * std::f64::consts::PI, &mut pts);
        } else {
            pts.push((b, 0.0));
        }
        pts.push((b, h));
        pts.push((-b, h));
        pts
    }

    /// The closed triangle mesh in the design frame.
    pub fn mesh(&self) -> Result<ShellMesh, String> {
        self.validate()?;
        let sec = self.section();
        let n = sec.len();
        let x0 = -0.5 * self.length;
        let x1 = 0.5 * self.length;
        let mut v: Vec<Vec3> = sec.iter().map(|&(y, z)| Vec3::new(x0, y, z)).collect();
        v.extend(sec.iter().map(|&(y, z)| Vec3::new(x1, y, z)));
        let (cy, cz) = sec.iter().fold((0.0, 0.0), |a, p| {
            (a.0 + p.0 / n as f64, a.1 + p.1 / n as f64)
        });
        v.push(Vec3::new(x0, cy, cz));
        v.push(Vec3::new(x1, cy, cz));
        let (c0, c1) = (2 * n as u32, 2 * n as u32 + 1);
        let mut t = Vec::new();
        for k in 0..n as u32 {
            let k1 = (k + 1) % n as u32;
            let (a, b, c, d) = (k, k1, k1 + n as u32, k + n as u32);
            t.push([a, b, c]);
            t.push([a, c, d]);
            t.push([c0, k1, k]);
            t.push([c1, k + n as u32, k1 + n as u32]);
        }
        ShellMesh::new(v, t, DEFAULT_MIN_EDGE_ANGLE)
    }
}
