//! three.js as embedded by the build script (build.rs) from tools/replay/node_modules, the
//! version pinned in tools/replay/package-lock.json.

/// The three.js sources a replay page inlines.
pub struct ThreeJs {
    /// The `three` package version, e.g. `0.187.0`.
    pub version: &'static str,
    /// `build/three.core.js`: the core classes (ES module).
    pub core: &'static str,
    /// `build/three.module.js`: the WebGL renderer; imports `./three.core.js`.
    pub module: &'static str,
    /// `examples/jsm/controls/OrbitControls.js`: camera control; imports `three`.
    pub orbit_controls: &'static str,
}

/// The embedded three.js, or why this build has none.
const THREE: Result<ThreeJs, &str> = include!(concat!(env!("OUT_DIR"), "/replay_three.rs"));

/// The embedded three.js; `Err` says why there is none and what to run.
pub fn three() -> Result<&'static ThreeJs, String> {
    match &THREE {
        Ok(t) => Ok(t),
        Err(why) => Err(format!(
            "--replay needs three.js, which this mbcosim was built without ({why}): in the source tree run `npm ci --prefix tools/replay` (needs npm; tests/setup_env.sh does it), then rebuild mbcosim (`cargo build --release --bin mbcosim`)"
        )),
    }
}
