//! Architecture rules checked on the source text.
//!
//! - Nothing outside `src/fmi/` (and the `src/bin/` application, which packs FMUs) names
//!   `crate::fmi`, `mbcosim::fmi` or an `fmi2` symbol in code: models stay FMI-agnostic.
//! - No `unsafe` outside `src/fmi/`.
//! - The command line's crates (`clap`, `indicatif`) only in the `src/bin/` application.

use std::path::{Path, PathBuf};

// Linked although unused: build.rs sends the C math symbols of every link of this package to
// the library's libm (docs/platforms.md, "One libm in every artifact").
extern crate mbcosim as _;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Source lines without `//` comments (doc comments included).
fn code_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.split("//").next().unwrap_or("")))
        .filter(|(_, l)| !l.trim().is_empty())
}

/// Source of `src/` as `(path relative to src, code lines)`: every file whole, or with
/// `library_only` the non-test source (no `*_tests.rs`, `tests.rs` or `src/bin/` files, and each
/// file cut at its `#[cfg(test)] mod tests`).
fn source_code(library_only: bool) -> Vec<(String, Vec<(usize, String)>)> {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut out = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let test_file =
            rel.ends_with("_tests.rs") || rel.ends_with("/tests.rs") || rel.starts_with("bin/");
        if library_only && test_file {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        let end = match library_only {
            true => text.find("#[cfg(test)]\nmod tests").unwrap_or(text.len()),
            false => text.len(),
        };
        let lines = code_lines(&text[..end])
            .map(|(k, l)| (k, l.to_string()))
            .collect();
        out.push((rel, lines));
    }
    assert!(out.len() > 10, "scanned only {} files", out.len());
    out
}

/// Non-test source of `src/` (see [`source_code`]).
fn library_code() -> Vec<(String, Vec<(usize, String)>)> {
    source_code(true)
}

#[test]
fn only_the_fmi_module_knows_fmi_and_uses_unsafe() {
    let mut bad = Vec::new();
    for (rel, lines) in source_code(false) {
        let in_fmi = rel.starts_with("fmi/");
        let in_bin = rel.starts_with("bin/");
        for (line, code) in &lines {
            if !in_fmi
                && !in_bin
                && rel != "lib.rs"
                && (code.contains("fmi::") || code.contains("fmi2"))
            {
                bad.push(format!("src/{rel}:{line}: names FMI: {}", code.trim()));
            }
            if !in_bin && (code.contains("clap::") || code.contains("indicatif")) {
                bad.push(format!(
                    "src/{rel}:{line}: command-line crate outside src/bin: {}",
                    code.trim()
                ));
            }
            if !in_fmi && code.contains("unsafe") && !code.contains("unsafe_code") {
                bad.push(format!(
                    "src/{rel}:{line}: unsafe outside src/fmi: {}",
                    code.trim()
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// One panic boundary per exported call: `catch_unwind` only in the FMI boundary's guard and in
/// the exports that run without it (instantiation, freeing, refusing an interface). A model or
/// a lower floor that caught panics would put a second boundary under the guard.
#[test]
fn panics_are_caught_at_the_fmi_boundary_only() {
    const ALLOWED: [&str; 3] = [
        "fmi/boundary.rs",
        "fmi/exports/common.rs",
        "fmi/exports3/common.rs",
    ];
    let mut bad = Vec::new();
    for (rel, lines) in library_code() {
        for (line, code) in &lines {
            if code.contains("catch_unwind(") && !ALLOWED.contains(&rel.as_str()) {
                bad.push(format!("src/{rel}:{line}: {}", code.trim()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "panic boundaries below the guard:\n{}",
        bad.join("\n")
    );
    // the guard's own boundary wraps the whole body, once
    let boundary = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/fmi/boundary.rs"),
    )
    .unwrap();
    let fn_guard = &boundary[boundary.find("pub unsafe fn guard(").unwrap()..];
    let fn_guard = &fn_guard[..fn_guard.find("\n}\n").unwrap()];
    assert_eq!(
        fn_guard.matches("catch_unwind(").count(),
        2,
        "the body's and the fatal log's"
    );
}

/// The request check once per step: `check_step` is called only by the trait's
/// `step_request` (which adds the lifecycle guard), and `step_request` only by the FMI wrapper's
/// step and by the trait's `do_step` for direct callers (a model's clock takes the checked
/// `StepRequest`).
#[test]
fn step_requests_are_checked_in_two_places_only() {
    let sites = |name: &str| {
        let mut calls = Vec::new();
        for (rel, lines) in library_code() {
            for (line, code) in &lines {
                if code.contains(&format!("{name}(")) && !code.contains(&format!("fn {name}(")) {
                    calls.push(format!("src/{rel}:{line}"));
                }
            }
        }
        let mut places: Vec<String> = calls
            .iter()
            .map(|c| c.rsplit_once(':').unwrap().0.to_string())
            .collect();
        places.sort();
        (places, calls)
    };
    let (places, calls) = sites("check_step");
    assert_eq!(places, ["src/scene/mod.rs"], "{calls:?}");
    let (places, calls) = sites("step_request");
    assert_eq!(
        places,
        ["src/fmi/instance.rs", "src/scene/mod.rs"],
        "{calls:?}"
    );
}

/// The floors of `src/lib.rs`'s map, bottom first: a module may import its own floor's
/// modules only if they do not import it back, and any module of a lower floor.
const FLOORS: &[&[&str]] = &[
    &["math", "bounded_file"],
    &["contact", "flex", "state"],
    &["model"],
    &["effect"],
    &["rope"],
    &["dae"],
    &["tree"],
    &["integrator"],
    &["sim"],
    &["report"],
    &["scene"],
    &["fmi"],
];

/// Upward arrows the code has today, each with its reason (docs/architecture.md, "Exceptions").
/// The test fails when one disappears, so the list stays true.
const EXCEPTIONS: &[(&str, &str)] = &[
    // the builder assembles the force effects' groups and `Model` holds them as
    // `Arc<dyn ForceEffect>`; moving assembly up into `dae` splits the two (issue #43 item 5)
    ("model", "effect"),
    // the work-precision report and the README figures run the models: a studies floor above
    // `scene` (issue #43 item 5) removes it
    ("report", "scene"),
];

fn floor_of(module: &str) -> Option<usize> {
    FLOORS.iter().position(|f| f.contains(&module))
}

/// The top-level modules a code line names through `crate::` (also inside `crate::{a, b::c}`).
fn crate_refs(code: &str) -> Vec<String> {
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for (k, _) in code.match_indices("crate::") {
        let rest = &code[k + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let (mut depth, mut start) = (0usize, 0usize);
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        out.push(ident(&group[start..i]));
                        break;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.push(ident(&group[start..i]));
                        start = i + 1;
                    }
                    _ => {}
                }
            }
        } else {
            out.push(ident(rest));
        }
    }
    out.retain(|m| !m.is_empty());
    out
}

/// Every arrow of the map: library code (test modules aside) imports only down the floors,
/// except the listed exceptions; no two modules of one floor import each other; every module
/// has a floor.
#[test]
fn imports_follow_the_floors_of_the_map() {
    let mut arrows: std::collections::BTreeMap<(String, String), String> = Default::default();
    for (rel, lines) in library_code() {
        let from = rel.split('/').next().unwrap().trim_end_matches(".rs");
        if from == "lib" {
            continue;
        }
        assert!(
            floor_of(from).is_some(),
            "src/{rel}: module `{from}` has no floor in FLOORS"
        );
        for (line, code) in &lines {
            for to in crate_refs(code) {
                if to != from && floor_of(&to).is_some() {
                    arrows
                        .entry((from.to_string(), to))
                        .or_insert_with(|| format!("src/{rel}:{line}"));
                }
            }
        }
    }
    let mut bad = Vec::new();
    for ((from, to), at) in &arrows {
        let (f, t) = (floor_of(from).unwrap(), floor_of(to).unwrap());
        let excepted = EXCEPTIONS.contains(&(from.as_str(), to.as_str()));
        if (t > f || (t == f && arrows.contains_key(&(to.clone(), from.clone())))) && !excepted {
            bad.push(format!(
                "{at}: `{from}` imports `{to}`, on a higher floor or in a circle"
            ));
        }
    }
    for (from, to) in EXCEPTIONS {
        if !arrows.contains_key(&(from.to_string(), to.to_string())) {
            bad.push(format!(
                "the exception `{from}` -> `{to}` is gone: remove it from EXCEPTIONS and docs/architecture.md"
            ));
        }
    }
    assert!(arrows.len() > 20, "found only {} arrows", arrows.len());
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn crate_references_are_read_from_paths_and_groups() {
    assert_eq!(crate_refs("use crate::dae::System;"), ["dae"]);
    assert_eq!(
        crate_refs("use crate::{math::Vec3, scene::{a, b}, sim};"),
        ["math", "scene", "sim"]
    );
    assert_eq!(
        crate_refs("let q = crate::integrator::init::x(crate::sim::Y);"),
        ["integrator", "sim"]
    );
    assert!(crate_refs("use super::x;").is_empty());
}
