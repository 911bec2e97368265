//! three.js for the replay pages, read at run time from `tools/replay/node_modules/three` of the
//! source tree (the version pinned in tools/replay/package-lock.json, installed by `npm ci`,
//! which `mbcosim demo` and tests/setup_env.sh run). Reading it at run time rather than embedding
//! it at build time means installing it needs no rebuild (docs/replay.md).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The three.js sources a replay page inlines.
pub struct ThreeJs {
    /// The `three` package version, e.g. `0.187.0`.
    pub version: String,
    /// `build/three.core.js`: the core classes (ES module).
    pub core: String,
    /// `build/three.module.js`: the WebGL renderer; imports `./three.core.js`.
    pub module: String,
    /// `examples/jsm/controls/OrbitControls.js`: camera control; imports `three`.
    pub orbit_controls: String,
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

/// The source trees' `tools/replay` folders to look in, in order: under `MBCOSIM_REPO`, under
/// the current directory or the nearest folder above it that has one, and under the tree this
/// executable was built from.
fn candidates() -> Vec<PathBuf> {
    let has = |d: &Path| d.join("tools/replay/package-lock.json").is_file();
    let mut out = Vec::new();
    if let Some(repo) = std::env::var_os("MBCOSIM_REPO") {
        out.push(PathBuf::from(repo));
    }
    if let Ok(cwd) = std::env::current_dir()
        && let Some(d) = cwd.ancestors().find(|d| has(d))
    {
        out.push(d.to_path_buf());
    }
    out.push(PathBuf::from(env!("CARGO_MANIFEST_DIR")));
    let mut tools: Vec<PathBuf> = Vec::new();
    for d in out.into_iter().filter(|d| has(d)) {
        let t = d.join("tools").join("replay");
        if !tools.contains(&t) {
            tools.push(t);
        }
    }
    tools
}

/// The pinned version of three in `tools` (a `tools/replay` folder).
fn pinned(tools: &Path) -> Result<String, String> {
    let lock = std::fs::read_to_string(tools.join("package-lock.json"))
        .map_err(|e| format!("cannot read {}/package-lock.json: {e}", tools.display()))?;
    version_after(&lock, "\"node_modules/three\"").ok_or_else(|| {
        format!(
            "{}/package-lock.json pins no version of three",
            tools.display()
        )
    })
}

/// The version of three installed in `tools`, if any.
fn installed(tools: &Path) -> Option<String> {
    std::fs::read_to_string(tools.join("node_modules/three/package.json"))
        .ok()
        .and_then(|t| version_after(&t, "{"))
}

/// Reads three.js from `tools` (a `tools/replay` folder) when the pinned version is installed.
fn load(tools: &Path) -> Result<ThreeJs, String> {
    let pinned = pinned(tools)?;
    let dir = tools.join("node_modules/three");
    let version = installed(tools).ok_or_else(|| {
        format!(
            "three.js is not installed (no {}/package.json)",
            dir.display()
        )
    })?;
    if version != pinned {
        return Err(format!(
            "{} holds three {version}, the lock file pins {pinned}",
            dir.display()
        ));
    }
    let read = |f: &str| {
        std::fs::read_to_string(dir.join(f))
            .map_err(|e| format!("three {version}: cannot read {f}: {e}"))
    };
    Ok(ThreeJs {
        core: read(FILES[0])?,
        module: read(FILES[1])?,
        orbit_controls: read(FILES[2])?,
        version,
    })
}

/// The three.js of the first source tree (see [`candidates`]) that has the pinned version
/// installed; `Err` says why there is none and what to run.
fn find() -> Result<ThreeJs, String> {
    let tools = candidates();
    let mut why = Vec::new();
    for t in &tools {
        match load(t) {
            Ok(three) => return Ok(three),
            Err(e) => why.push(e),
        }
    }
    let remedy = match tools.first() {
        Some(t) => format!(
            "run `npm ci --prefix {}` (needs npm; `mbcosim demo` and tests/setup_env.sh do it); no rebuild is needed",
            t.display()
        ),
        None => "run it inside the mbcosim source tree or set MBCOSIM_REPO to it".to_string(),
    };
    let why = if why.is_empty() {
        "no source tree with tools/replay/package-lock.json found".to_string()
    } else {
        why.join("; ")
    };
    Err(format!(
        "--replay needs three.js, read from the source tree's tools/replay/node_modules ({why}): {remedy}"
    ))
}

/// The three.js the replay pages inline, read once per run; `Err` says why there is none and
/// what to run.
pub fn three() -> Result<&'static ThreeJs, String> {
    static THREE: OnceLock<Result<ThreeJs, String>> = OnceLock::new();
    THREE.get_or_init(find).as_ref().map_err(Clone::clone)
}

/// Installs the pinned three.js into `repo`'s tools/replay with `npm ci` unless it is there
/// (for `mbcosim demo`, so that `--replay` works after the quick start's first command).
/// Returns what it did, or why it could not (no npm, npm failed) with the remedy.
pub fn fetch(repo: &Path) -> Result<String, String> {
    let tools = repo.join("tools").join("replay");
    let pinned = pinned(&tools)?;
    if installed(&tools).as_deref() == Some(pinned.as_str()) {
        return Ok(format!("three {pinned} present in {}", tools.display()));
    }
    let status = Command::new("npm")
        .args(["ci", "--ignore-scripts", "--no-audit", "--no-fund", "--prefix"])
        .arg(&tools)
        .stdout(std::process::Stdio::null())
        .status()
        .map_err(|e| {
            format!(
                "cannot run npm ({e}): `--replay` needs three.js; install npm (tests/setup_env.sh does) and run `npm ci --prefix {}`",
                tools.display()
            )
        })?;
    if !status.success() {
        return Err(format!(
            "`npm ci --prefix {}` failed ({status}): `--replay` needs it",
            tools.display()
        ));
    }
    load(&tools).map(|t| format!("installed three {} into {}", t.version, tools.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_versions_as_npm_writes_them() {
        let lock = r#"{"packages": {"": {"version": "0.1.0"}, "node_modules/three": {
            "version": "0.187.0", "resolved": "x"}}}"#;
        assert_eq!(
            version_after(lock, "\"node_modules/three\"").as_deref(),
            Some("0.187.0")
        );
        let package = "{\n  \"name\": \"three\",\n  \"version\" : \"0.186.1\"\n}";
        assert_eq!(version_after(package, "{").as_deref(), Some("0.186.1"));
        assert_eq!(version_after("{\"name\": \"x\"}", "{"), None);
    }

    #[test]
    fn a_missing_or_other_version_is_refused_with_the_reason() {
        let dir = std::env::temp_dir().join(format!("mbcosim-three-{}", std::process::id()));
        let three = dir.join("node_modules/three");
        std::fs::create_dir_all(three.join("build")).unwrap();
        std::fs::write(
            dir.join("package-lock.json"),
            r#"{"packages": {"node_modules/three": {"version": "0.187.0"}}}"#,
        )
        .unwrap();
        std::fs::remove_file(three.join("package.json")).ok();
        assert!(load(&dir).err().unwrap().contains("not installed"));
        std::fs::write(three.join("package.json"), r#"{"version": "0.186.0"}"#).unwrap();
        let e = load(&dir).err().unwrap();
        assert!(e.contains("0.186.0") && e.contains("pins 0.187.0"), "{e}");
        std::fs::write(three.join("package.json"), r#"{"version": "0.187.0"}"#).unwrap();
        assert!(load(&dir).err().unwrap().contains("build/three.core.js"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
