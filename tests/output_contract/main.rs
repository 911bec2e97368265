//! The output contract: every output of every registered model is listed in [`checks::CHECKS`]
//! with what it reports (sampling: instant, peak, cumulative, ...) and the test that checks its
//! value against something independent of the code that computes it (a hand calculation, a
//! conservation law, a finer solution, the same quantity through another path).
//!
//! `docs/output_checks.md` is generated from the variable tables and that list. Regenerate it
//! after changing either: `MBCOSIM_WRITE_OUTPUT_CHECKS=1 cargo test --release --test output_contract`.
//!
//! The tests here fail when an output has no entry, when an entry names no output, when a named
//! check does not exist or is not a test, and when the generated document differs from the
//! checked-in one. How to add an output and why: `docs/output_contract.md`.

mod checks;
mod document;

use std::path::{Path, PathBuf};

use checks::{CHECKS, Check};
use mbcosim::scene::port::{Causality, ModelInfo};
use mbcosim::scene::registry;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every registered model's table, by identifier.
fn models() -> Vec<&'static ModelInfo> {
    registry().iter().map(|e| (e.info)()).collect()
}

/// The output ports of `info`, in table order.
fn outputs(info: &ModelInfo) -> Vec<&str> {
    info.ports
        .iter()
        .filter(|p| p.causality == Causality::Output)
        .map(|p| p.name.as_str())
        .collect()
}

#[test]
fn every_output_has_exactly_one_check() {
    let mut problems = Vec::new();
    for info in models() {
        for name in outputs(info) {
            let hits: Vec<&Check> = CHECKS
                .iter()
                .filter(|c| c.model == info.identifier && c.covers(name))
                .collect();
            match hits.len() {
                1 => {}
                0 => problems.push(format!(
                    "{}: output `{name}` has no entry in tests/output_contract/checks.rs",
                    info.identifier
                )),
                n => problems.push(format!(
                    "{}: output `{name}` matches {n} entries (one each)",
                    info.identifier
                )),
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_entry_names_outputs_that_exist() {
    let infos = models();
    let mut problems = Vec::new();
    for c in CHECKS {
        let Some(info) = infos.iter().find(|i| i.identifier == c.model) else {
            problems.push(format!("entry for unknown model `{}`", c.model));
            continue;
        };
        let names = outputs(info);
        for pattern in c.outputs {
            if !names.iter().any(|n| checks::matches(pattern, n)) {
                problems.push(format!("{}: `{pattern}` matches no output", c.model));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A check named `path::function` exists and is a test: the file is in the repository and
/// defines the function as a test (`fn name(` under `#[test]` in Rust, `def test_...(` in
/// Python), so that a helper cannot stand in for a check.
fn check_exists(root: &Path, reference: &str) -> Result<(), String> {
    let (path, function) = reference
        .rsplit_once("::")
        .ok_or_else(|| format!("`{reference}` is not `path::function`"))?;
    let text = std::fs::read_to_string(root.join(path))
        .map_err(|e| format!("`{reference}`: cannot read {path}: {e}"))?;
    if path.ends_with(".py") {
        let wanted = format!("def {function}(");
        return if !function.starts_with("test_") {
            Err(format!("`{reference}`: not a pytest test (test_...)"))
        } else if text.lines().any(|l| l.trim_start().starts_with(&wanted)) {
            Ok(())
        } else {
            Err(format!("`{reference}`: {path} defines no `{wanted}`"))
        };
    }
    let wanted = format!("fn {function}(");
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let Some(at) = lines.iter().position(|l| l.starts_with(&wanted)) else {
        return Err(format!("`{reference}`: {path} defines no `{wanted}`"));
    };
    // the attributes and comments right above the function
    let above = lines[..at]
        .iter()
        .rev()
        .take_while(|l| l.starts_with("#[") || l.starts_with("//"));
    if above.clone().any(|l| *l == "#[test]") {
        Ok(())
    } else {
        Err(format!(
            "`{reference}`: `{function}` in {path} is not a #[test]"
        ))
    }
}

#[test]
fn every_named_check_exists() {
    let root = root();
    let mut problems = Vec::new();
    for c in CHECKS {
        if c.tests.is_empty() {
            problems.push(format!("{}: {:?} names no check", c.model, c.outputs));
        }
        if c.against.trim().is_empty() {
            problems.push(format!(
                "{}: {:?} says not what it is checked against",
                c.model, c.outputs
            ));
        }
        for t in c.tests {
            if let Err(e) = check_exists(&root, t) {
                problems.push(e);
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_output_checks_document_is_current() {
    let path = root().join("docs/output_checks.md");
    let text = document::render(&models(), CHECKS);
    if std::env::var_os("MBCOSIM_WRITE_OUTPUT_CHECKS").is_some() {
        std::fs::write(&path, &text).expect("write docs/output_checks.md");
        return;
    }
    let stored = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        stored == text,
        "docs/output_checks.md is not what the tables and tests/output_contract/checks.rs give; \
         regenerate: MBCOSIM_WRITE_OUTPUT_CHECKS=1 cargo test --release --test output_contract"
    );
}

#[test]
fn only_tests_count_as_checks() {
    let root = root();
    let own = "tests/output_checks/panel_lock.rs::";
    assert!(
        check_exists(
            &root,
            &format!("{own}input_work_is_the_motor_torque_times_the_root_travel")
        )
        .is_ok()
    );
    // a helper of the same file, a missing function, a pytest helper
    assert!(check_exists(&root, &format!("{own}tight")).is_err());
    assert!(check_exists(&root, &format!("{own}no_such_test")).is_err());
    assert!(check_exists(&root, "tests/python/conftest.py::native_table").is_err());
    assert!(check_exists(&root, "tests/python/test_rope_block.py::_sim").is_err());
}

#[test]
fn patterns_match_indices_only_where_asked() {
    assert!(checks::matches("hinge#_angle", "hinge0_angle"));
    assert!(checks::matches("hinge#_angle", "hinge12_angle"));
    assert!(!checks::matches("hinge#_angle", "hinge_angle"));
    assert!(!checks::matches("hinge#_angle", "hinge0_angle_rate"));
    assert!(checks::matches("panel#_mode#", "panel2_mode3"));
    assert!(checks::matches("block_x", "block_x"));
    assert!(!checks::matches("block_x", "block_xy"));
}
