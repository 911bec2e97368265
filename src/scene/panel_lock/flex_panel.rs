//! Flexible panels of PanelLock: the plate FE model, its reduction, and a cache of the result.
//!
//! A panel is a rectangular plate (x along its length, y along its width = the hinge axis, z
//! normal) meshed with `panel_mesh` ACM elements. Attachment nodes: mid-width of the inboard
//! edge (x = 0) and of the outboard edge (x = length). Inner panels carry both (their outboard
//! node holds the next hinge's shaft), the outer panel only the inboard one; the tip velocity is
//! read at the outboard mid-width node of the outer panel, which every panel has.
//!
//! Cache: the FE assembly, eigen-solve and reduction depend only on the panel description, the
//! mesh, `n_modes`, the damping ratio, the reduction and whether the panel is inner or outer.
//! They are memoized in a process-wide map keyed by those values (bit-exact floats), so repeated
//! instantiations of an FMU with the same panels (parameter studies, co-simulation restarts)
//! pay for them once. Measured cost of one inner + one outer panel at the default 8 x 4 mesh,
//! 10 modes: see `examples/bench_flex_panel.rs` (a few ms; the cache matters for finer meshes,
//! about 0.1-1 s at 20 x 10).

use super::params::{PanelLockParams, Reduction};
use crate::flex::{ModalBodyData, PanelSpec, PlateModel};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Modal data of one panel and its attachment nodes.
#[derive(Debug, Clone)]
pub struct FlexPanel {
    pub data: Arc<ModalBodyData>,
    /// Inboard (frame) hinge node and outboard edge mid-width node.
    pub inboard_node: usize,
    pub outboard_node: usize,
}

type Key = (Vec<u64>, usize, usize, usize, Reduction, bool);

fn cache() -> &'static Mutex<HashMap<Key, FlexPanel>> {
    static CACHE: OnceLock<Mutex<HashMap<Key, FlexPanel>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The plate description of the panels of `p`.
pub fn panel_spec(p: &PanelLockParams) -> PanelSpec {
    PanelSpec {
        a: p.panel_length,
        b: p.panel_width,
        thickness: p.panel_thickness,
        youngs_modulus: p.panel_youngs_modulus,
        poisson: p.panel_poisson,
        density: p.panel_structural_density(),
        non_structural_mass: p.panel_nonstructural_mass,
    }
}

/// Builds (or fetches from the cache) the modal data of a panel; `outer` is the outermost
/// panel (no outboard hinge).
pub fn flex_panel(p: &PanelLockParams, outer: bool) -> Result<FlexPanel, String> {
    let spec = panel_spec(p);
    let [nx, ny] = p.panel_mesh;
    let key: Key = (
        [
            spec.a,
            spec.b,
            spec.thickness,
            spec.youngs_modulus,
            spec.poisson,
            spec.density,
            spec.non_structural_mass,
            p.modal_damping_ratio,
        ]
        .iter()
        .map(|x| x.to_bits())
        .collect(),
        nx,
        ny,
        p.n_modes,
        p.reduction,
        outer,
    );
    if let Some(hit) = cache().lock().map_err(|e| e.to_string())?.get(&key) {
        return Ok(hit.clone());
    }
    let panel = compute(
        &spec,
        nx,
        ny,
        p.n_modes,
        p.modal_damping_ratio,
        p.reduction,
        outer,
    )?;
    let mut c = cache().lock().map_err(|e| e.to_string())?;
    if c.len() > 64 {
        c.clear();
    }
    c.insert(key, panel.clone());
    Ok(panel)
}

/// The uncached FE model and reduction.
pub fn compute(
    spec: &PanelSpec,
    nx: usize,
    ny: usize,
    n_modes: usize,
    zeta: f64,
    reduction: Reduction,
    outer: bool,
) -> Result<FlexPanel, String> {
    // the panel parameters the plate model is made of, so that a failure names what to change
    let err = |e: crate::flex::FlexError| {
        format!(
            "flexible panel ({}x{} elements, n_modes = {n_modes}; panel_length {} m, panel_width {} m, panel_thickness {} m, panel_youngs_modulus {} Pa, panel_poisson {}): {e}",
            nx, ny, spec.a, spec.b, spec.thickness, spec.youngs_modulus, spec.poisson
        )
    };
    let plate = PlateModel::new(spec, nx, ny).map_err(err)?;
    let inboard_node = plate.node_index(0, ny / 2).map_err(err)?;
    let outboard_node = plate.node_index(nx, ny / 2).map_err(err)?;
    let attach: Vec<usize> = if outer {
        vec![inboard_node]
    } else {
        vec![inboard_node, outboard_node]
    };
    let data = match reduction {
        Reduction::CraigBampton => {
            ModalBodyData::from_craig_bampton(&plate, inboard_node, &attach, n_modes, zeta)
        }
        Reduction::FreeInterface => {
            ModalBodyData::from_free_interface(&plate, n_modes, zeta, &attach)
        }
    }
    .map_err(err)?;
    Ok(FlexPanel {
        data: Arc::new(data),
        inboard_node,
        outboard_node,
    })
}
