//! Round-trip and malformed-input tests of the modal text format.

use super::body::{ModalBodyData, ModalBodyParts};
use super::error::FlexError;
use super::plate::{PanelSpec, PlateModel};
use super::reduce::modal_damping;
use super::text_format::{from_text, read_file, to_text, write_file};

fn body() -> ModalBodyData {
    let s = PanelSpec {
        a: 1.6,
        b: 0.8,
        thickness: 0.02,
        youngs_modulus: 2e9,
        poisson: 0.3,
        density: 50.0,
        non_structural_mass: 1.0,
    };
    let p = PlateModel::new(&s, 4, 2).unwrap();
    let h0 = p.node_index(0, 0).unwrap();
    let h1 = p.node_index(0, 2).unwrap();
    ModalBodyData::from_craig_bampton(&p, h0, &[h0, h1], 3, 0.01).unwrap()
}

#[test]
fn text_round_trip_is_exact() {
    let b = body();
    let text = to_text(&b);
    let back = from_text(&text).unwrap();
    assert_eq!(back, b);
    // And through a file.
    let path = std::env::temp_dir().join(format!("mbcosim_flex_rt_{}.txt", std::process::id()));
    write_file(&b, &path).unwrap();
    let from_file = read_file(&path);
    let _ = std::fs::remove_file(&path);
    assert_eq!(from_file.unwrap(), b);
}

/// Lines of the text from the first line starting with `from` up to (excluding) the first
/// later line starting with `to`, removed.
fn cut(text: &str, from: &str, to: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let a = lines.iter().position(|l| l.starts_with(from)).unwrap();
    let b = a
        + 1
        + lines[a + 1..]
            .iter()
            .position(|l| l.starts_with(to))
            .unwrap();
    [&lines[..a], &lines[b..]].concat().join("\n")
}

#[test]
fn optional_blocks_default_to_node_sums_and_modal_damping() {
    let b = body();
    let text = to_text(&b);
    // Without INVARIANTS the invariants are node sums, which need a consistent MASS_MATRIX:
    // the plate's consistent reduced mass is not the lumped node sum, so this is refused.
    let e = from_text(&cut(&text, "INVARIANTS", "END")).unwrap_err();
    assert!(e.to_string().contains("node sums"), "{e}");
    // A point-mass body (modal mass = node sums) loads without the block.
    let lumped = b.node_sum_invariants().unwrap();
    let pm = ModalBodyData::new(ModalBodyParts {
        positions: b.positions().to_vec(),
        node_masses: b.node_masses().to_vec(),
        translational_shapes: b.translational_shapes().to_vec(),
        rotational_shapes: b.rotational_shapes().to_vec(),
        mass: lumped.modal_mass.clone(),
        stiffness: b.stiffness().clone(),
        damping: b.damping().clone(),
        attachment_nodes: b.attachment_nodes().to_vec(),
        invariants: None,
    })
    .unwrap();
    let no_inv = from_text(&cut(&to_text(&pm), "INVARIANTS", "END")).unwrap();
    assert_eq!(no_inv.invariants(), &lumped);
    assert_eq!(no_inv, pm);
    // DAMPING_RATIO instead of the matrix.
    let ratio =
        cut(&text, "DAMPING_MATRIX", "NODES").replace("\nNODES", "\nDAMPING_RATIO 0.05\nNODES");
    let damped = from_text(&ratio).unwrap();
    let d = modal_damping(b.stiffness(), b.mass(), 0.05).unwrap();
    assert!((damped.damping() - &d).amax() < 1e-12 * d.amax());
}

/// Replaces the first line starting with `prefix` by `f(line)`; returns the text and the
/// 1-based number of that line.
fn mutate(text: &str, prefix: &str, f: impl Fn(&str) -> String) -> (String, usize) {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = lines
        .iter()
        .position(|l| l.trim_start().starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starts with {prefix}"));
    lines[i] = f(&lines[i]);
    (lines.join("\n"), i + 1)
}

/// A rewrite of one line of a file.
type Mutation = Box<dyn Fn(&str) -> String>;

/// The line with whitespace-separated token `i` replaced by `v`.
fn set_token(line: &str, i: usize, v: &str) -> String {
    let mut t: Vec<&str> = line.split_whitespace().collect();
    t[i] = v;
    t.join(" ")
}

fn expect_parse_error(text: &str, line: usize, needle: &str) {
    match from_text(text) {
        Err(FlexError::Parse { line: l, message }) => {
            assert_eq!(l, line, "wrong line for '{message}'");
            assert!(message.contains(needle), "'{message}' lacks '{needle}'");
        }
        other => panic!("expected a parse error containing '{needle}', got {other:?}"),
    }
}

#[test]
fn malformed_files_give_line_and_expectation() {
    let text = to_text(&body());
    let drop_last = |l: &str| l.rsplit_once(' ').unwrap().0.to_string();
    let cases: Vec<(&str, Mutation, &str)> = vec![
        (
            "MBCOSIM_MODAL_BODY",
            Box::new(|_| "MODAL 1".into()),
            "expected 'MBCOSIM_MODAL_BODY 1'",
        ),
        (
            "MBCOSIM_MODAL_BODY",
            Box::new(|_| "MBCOSIM_MODAL_BODY 2".into()),
            "unsupported version '2'",
        ),
        (
            "UNITS",
            Box::new(|_| "UNITS mm".into()),
            "expected 'UNITS SI'",
        ),
        (
            "MODE_COUNT",
            Box::new(|_| "MODE_COUNT -3".into()),
            "not a non-negative integer",
        ),
        (
            "FREQUENCIES_HZ",
            Box::new(drop_last),
            "expected 6 numbers for FREQUENCIES_HZ, found 5",
        ),
        (
            "STIFFNESS_MATRIX",
            Box::new(|_| "STIFNESS_MATRIX".into()),
            "expected 'STIFFNESS_MATRIX'",
        ),
        (
            "3 ",
            Box::new(|l| set_token(l, 2, "abc")),
            "'abc' is not a finite number (x y z mass of node 3)",
        ),
        (
            "5 x",
            Box::new(|l| l.replacen("5 x", "5 q", 1)),
            "expected '5 x' and 6 numbers",
        ),
        (
            "Q 2",
            Box::new(|l| l.replace("Q 2", "Q 2 NaN")),
            "expected 9 numbers for Q_2, found 10",
        ),
        (
            "ATTACHMENT_NODES",
            Box::new(|_| "ATTACHMENT_NODES 0 99".into()),
            "attachment node 99 out of range",
        ),
        (
            "ATTACHMENT_NODES",
            Box::new(|_| "ATTACHMENT_NODES 0".into()),
            "expected 2 attachment nodes",
        ),
        (
            "END",
            Box::new(|_| "END\nEXTRA 1".into()),
            "unexpected content after END",
        ),
    ];
    for (prefix, f, needle) in cases {
        let (bad, line) = mutate(&text, prefix, f);
        // "END\nEXTRA" puts the offending record one line further down.
        let line = if needle.contains("after END") {
            line + 1
        } else {
            line
        };
        expect_parse_error(&bad, line, needle);
    }
    // A row of the mass matrix with a missing value.
    let lines: Vec<&str> = text.lines().collect();
    let m = lines.iter().position(|l| *l == "MASS_MATRIX").unwrap();
    let (bad, line) = mutate(&text, lines[m + 2].trim_start(), drop_last);
    assert_eq!(line, m + 3);
    expect_parse_error(
        &bad,
        line,
        "expected 6 numbers for row 1 of MASS_MATRIX, found 5",
    );
    // Truncated file: end of file reported one past the last line.
    let truncated: String = lines[..m + 4].join("\n");
    expect_parse_error(
        &truncated,
        m + 5,
        "unexpected end of file, expected 6 numbers for row 3",
    );
    // Frequencies in rad/s instead of Hz.
    let (bad, line) = mutate(&text, "FREQUENCIES_HZ", |l| {
        let v: Vec<String> = l
            .split_whitespace()
            .skip(1)
            .map(|x| format!("{:e}", x.parse::<f64>().unwrap() * std::f64::consts::TAU))
            .collect();
        format!("FREQUENCIES_HZ {}", v.join(" "))
    });
    expect_parse_error(&bad, line, "frequency 1 is");
}

#[test]
fn semantic_errors_after_parsing_are_reported() {
    let text = to_text(&body());
    // Negative node mass is caught with its line.
    let (bad, line) = mutate(&text, "4 ", |l| {
        let mut t: Vec<String> = l.split_whitespace().map(str::to_string).collect();
        t[4] = "-1".into();
        t.join(" ")
    });
    expect_parse_error(&bad, line, "node 4: mass must be >= 0");
    // A mass matrix that is not positive definite: reported by the body constructor.
    let lines: Vec<&str> = text.lines().collect();
    let m = lines.iter().position(|l| *l == "MASS_MATRIX").unwrap();
    let (bad, _) = mutate(&text, lines[m + 1].trim_start(), |l| {
        let mut t: Vec<String> = l.split_whitespace().map(str::to_string).collect();
        t[0] = "-5".into();
        t.join(" ")
    });
    let e = from_text(&bad).unwrap_err();
    assert!(
        e.to_string().contains("not symmetric") || e.to_string().contains("positive definite"),
        "{e}"
    );
}

#[test]
fn counts_past_their_caps_are_refused_before_anything_is_sized_by_them() {
    use super::text_format::{MAX_MODES, MAX_NODES};
    let head = |nodes: usize, modes: usize| {
        format!(
            "MBCOSIM_MODAL_BODY 1\nUNITS SI\nNODE_COUNT {nodes}\nMODE_COUNT {modes}\nATTACHMENT_COUNT 0\n"
        )
    };
    // a NODE_COUNT of 2^60 used to size a vector before one node was read (an abort, not an Err)
    let e = from_text(&head(1 << 60, 1)).unwrap_err().to_string();
    assert!(e.contains("MAX_NODES") && e.contains("line 3"), "{e}");
    let e = from_text(&head(MAX_NODES + 1, 1)).unwrap_err().to_string();
    assert!(e.contains(&format!("cap of {MAX_NODES} nodes")), "{e}");
    let e = from_text(&head(1, MAX_MODES + 1)).unwrap_err().to_string();
    assert!(e.contains("MAX_MODES") && e.contains("line 4"), "{e}");
}

#[test]
fn a_modal_file_that_is_a_device_is_refused_by_the_bounded_reader() {
    let e = read_file(std::path::Path::new("/dev/zero"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("modal body file /dev/zero") && e.contains("character device"),
        "{e}"
    );
}
