//! Build script: links every artifact to one libm, and embeds three.js into `mbcosim` for the replay pages of
//! `mbcosim simulate --replay` (docs/replay.md), when `npm ci --prefix tools/replay` has
//! installed the version pinned in tools/replay/package-lock.json. Without it (or with another
//! version installed) the build still succeeds, and `--replay` says what to run.
//!
//! Writes `$OUT_DIR/replay_three.rs`: one expression of type `Result<ThreeJs, &str>` that the
//! command line includes (`src/bin/mbcosim/replay/three.rs`). The library does not use it.
//!
//! libm: on x86_64 Linux, x86_64 Windows and aarch64 Linux, every link of this package (the
//! FMUs' library, the executables, tests, examples) gets `-Wl,-wrap,NAME` for each C math
//! function of src/fmi/c_math_symbols.rs, so that every call of `sin`, `pow`, ... in any object
//! file (ours, std's, nalgebra's, ...) goes to `__wrap_NAME` of src/fmi/c_math.rs, the `libm`
//! crate, instead of the C runtime's (docs/platforms.md, "One libm in every artifact").

use std::path::{Path, PathBuf};

// WRAPPED, WRAPPED_WINDOWS: the C math symbols src/fmi/c_math.rs defines `__wrap_<name>` for.
include!("src/fmi/c_math_symbols.rs");

/// The linker arguments that send every reference to a wrapped C math symbol to
/// `__wrap_<name>`, for the target cargo builds for (empty where src/fmi/c_math.rs defines no
/// trampolines). `-u __wrap_<name>` makes GNU ld take the definition from the library's rlib
/// while it reads it, before the rlibs of std and the dependencies that call it. The one-dash
/// spellings `-wrap` and `-u` are the ones that GNU ld, mingw-w64's ld and zig's `cc` (which
/// rejects `--wrap` and `--undefined`) all accept.
fn libm_link_args(arch: &str, os: &str) -> Vec<String> {
    let supported = matches!(
        (arch, os),
        ("x86_64", "linux" | "windows") | ("aarch64", "linux")
    );
    if !supported {
        return Vec::new();
    }
    let windows: &[&str] = if os == "windows" {
        &WRAPPED_WINDOWS
    } else {
        &[]
    };
    WRAPPED
        .iter()
        .chain(windows)
        .flat_map(|name| [format!("-Wl,-wrap,{name}"), format!("-Wl,-u,__wrap_{name}")])
        .collect()
}

/// The files of the `three` package the page needs, relative to its folder.
const FILES: [&str; 3] = [
    "build/three.core.js",
    "build/three.module.js",
    "examples/jsm/controls/OrbitControls.js",
];

/// The `"version"` of the first `"key"` object found after `after` in a JSON text (enough for
/// package.json and package-lock.json, which npm writes itself).
fn version_after(text: &str, after: &str) -> Option<String> {
    let start = text.find(after)? + after.len();
    let rest = &text[start..];
    let v = rest.find("\"version\"")? + "\"version\"".len();
    let rest = rest[v..].trim_start().strip_prefix(':')?.trim_start();
    let rest = rest.strip_prefix('"')?;
    Some(rest[..rest.find('"')?].to_string())
}

fn embed(root: &Path) -> Result<String, String> {
    let tools = root.join("tools/replay");
    let lock = std::fs::read_to_string(tools.join("package-lock.json"))
        .map_err(|e| format!("cannot read tools/replay/package-lock.json: {e}"))?;
    let pinned = version_after(&lock, "\"node_modules/three\"")
        .ok_or("tools/replay/package-lock.json pins no version of three")?;
    let dir = tools.join("node_modules/three");
    let installed = std::fs::read_to_string(dir.join("package.json"))
        .ok()
        .and_then(|t| version_after(&t, "{"))
        .ok_or("three.js is not installed (no tools/replay/node_modules/three/package.json)")?;
    if installed != pinned {
        return Err(format!(
            "tools/replay/node_modules holds three {installed}, the lock file pins {pinned}"
        ));
    }
    let mut paths = Vec::new();
    for f in FILES {
        let p = dir.join(f);
        if !p.is_file() {
            return Err(format!("three {installed} has no {f}"));
        }
        paths.push(p);
    }
    Ok(format!(
        "Ok(ThreeJs {{ version: {installed:?}, core: include_str!({:?}), module: include_str!({:?}), orbit_controls: include_str!({:?}) }})",
        paths[0], paths[1], paths[2]
    ))
}

fn main() {
    let root = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=src/fmi/c_math_symbols.rs");
    let var = |k: &str| std::env::var(k).unwrap_or_default();
    for arg in libm_link_args(&var("CARGO_CFG_TARGET_ARCH"), &var("CARGO_CFG_TARGET_OS")) {
        println!("cargo::rustc-link-arg={arg}");
    }
    println!("cargo::rerun-if-changed=tools/replay/package-lock.json");
    // only paths that exist: cargo reruns a build script (and rebuilds the crate) on every
    // build while a watched path is missing. Without three.js, watch the folder `npm ci` fills.
    let three = root.join("tools/replay/node_modules/three");
    if three.join("package.json").is_file() {
        println!("cargo::rerun-if-changed=tools/replay/node_modules/three/package.json");
        for f in FILES.iter().filter(|f| three.join(f).is_file()) {
            println!("cargo::rerun-if-changed=tools/replay/node_modules/three/{f}");
        }
    } else {
        println!("cargo::rerun-if-changed=tools/replay");
    }
    let code = match embed(&root) {
        Ok(code) => code,
        Err(why) => format!("Err({why:?})"),
    };
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    if let Err(e) = std::fs::write(out.join("replay_three.rs"), code) {
        println!("cargo::warning=cannot write replay_three.rs to OUT_DIR: {e}");
    }
}
