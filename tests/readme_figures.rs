//! The figures README.md embeds are what the code draws now (issue #44 item 7: the embedded
//! contact-force figure showed a hinge-1 peak of 255 N where the demo gave 269 N). Regenerates
//! them into a temporary tree with the same code as `mbcosim readme-figures` and compares them
//! byte for byte with the committed files; fails too when README.md embeds a figure that command
//! does not regenerate.

use mbcosim::report::readme_figures::{embedded, regenerate, regenerated};
use std::path::Path;

#[test]
fn every_readme_figure_is_regenerated_and_up_to_date() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(repo.join("README.md")).unwrap();
    let figures = embedded(&readme);
    assert!(!figures.is_empty(), "README.md embeds no figure");
    let known = regenerated();
    for f in &figures {
        assert!(
            known.contains(f),
            "README.md embeds {f}, which `mbcosim readme-figures` does not regenerate (src/report/readme_figures.rs)"
        );
    }
    let out = std::env::temp_dir().join(format!("mbcosim-readme-figures-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let written = regenerate(repo, &out).unwrap();
    assert!(written.len() >= known.len(), "{written:?}");
    for f in &known {
        assert!(out.join(f).exists(), "{f} was not regenerated");
    }
    let mut stale = Vec::new();
    for fresh_path in &written {
        let rel = fresh_path.strip_prefix(&out).unwrap();
        let fresh = std::fs::read(fresh_path).unwrap();
        let committed = std::fs::read(repo.join(rel)).unwrap_or_default();
        if fresh != committed {
            stale.push(rel.display().to_string());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        stale.is_empty(),
        "stale figures {stale:?}: run `cargo run --release --bin mbcosim -- readme-figures` and commit them"
    );
}
