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

#[test]
fn only_the_fmi_module_knows_fmi_and_uses_unsafe() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut bad = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let in_fmi = rel.starts_with("fmi/");
        let in_bin = rel.starts_with("bin/");
        let text = std::fs::read_to_string(f).unwrap();
        for (line, code) in code_lines(&text) {
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
    assert!(files.len() > 10, "scanned only {} files", files.len());
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
