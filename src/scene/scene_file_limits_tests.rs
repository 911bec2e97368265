//! The scene file's caps (docs/bounded_inputs.md): bytes, keys and tables counted before the
//! keys are looked at, and the RopeBlock rig's caps on lugs, slings and rope segments. Each
//! refusal names its cap.

use super::*;
use crate::scene::rope_block::{self, RopeBlockParams};

fn refused(text: &str) -> String {
    parse(text, "scene.toml").unwrap_err()
}

#[test]
fn a_scene_past_the_byte_cap_is_refused_by_parse_as_well() {
    let text = format!("# {}\n", "x".repeat(SCENE_FILE_BYTES as usize));
    let e = refused(&text);
    assert!(e.contains("SCENE_FILE_BYTES") && e.contains("4 MiB"), "{e}");
}

#[test]
fn fifteen_thousand_unknown_keys_are_refused_by_the_key_cap() {
    // under the text's bound (20,000 `=` and `,`), over the parsed count's cap
    let mut text = String::from("[parameters]\n");
    for k in 0..15_000 {
        text.push_str(&format!("unknown_{k} = 1\n"));
    }
    let e = refused(&text);
    assert!(
        // the 15,000 and `parameters`
        e.contains("15001 keys") && e.contains("MAX_SCENE_KEYS") && e.contains("10000"),
        "{e}"
    );
    // array values count too: one key holding 12,000 numbers
    let big = format!("[block]\nbox = [{}]\n", vec!["1.0"; 12_000].join(", "));
    assert!(refused(&big).contains("12002 keys and array values"));
    // 80,000 keys: refused from the text already
    let many = "unknown = 1\n".repeat(80_000);
    let e = refused(&many);
    assert!(
        e.contains("80000 `=` and `,`") && e.contains("MAX_SCENE_KEYS"),
        "{e}"
    );
}

#[test]
fn keys_under_the_cap_are_refused_at_the_first_unknown_one_with_its_line() {
    let mut text = String::from("[parameters]\n");
    for k in 0..9_000 {
        text.push_str(&format!("unknown_{k} = 1\n"));
    }
    let file = parse(&text, "scene.toml").unwrap();
    assert_eq!(
        file.entries[8_999].line, 9_001,
        "lines from the newline index"
    );
    let mut m = rope_block::create();
    let e = apply(m.as_mut(), &file, "scene.toml").unwrap_err();
    assert!(
        e.contains("scene.toml:2:") && e.contains("no parameter named `unknown_0`"),
        "{e}"
    );
}

#[test]
fn more_tables_than_the_cap_are_refused() {
    let text = "[[lug]]\nposition = [1.0, 2.0, 3.0]\n".repeat(MAX_SCENE_TABLES + 1);
    let e = refused(&text);
    assert!(
        e.contains(&format!("{} table headers", MAX_SCENE_TABLES + 1))
            && e.contains("MAX_SCENE_TABLES"),
        "{e}"
    );
}

#[test]
fn deep_nesting_is_refused_not_a_stack_overflow() {
    let arrays = format!(
        "[parameters]\na = {}1{}\n",
        "[".repeat(100_000),
        "]".repeat(100_000)
    );
    assert!(refused(&arrays).contains("scene.toml:2"));
    let dotted = format!("{} = 1\n", vec!["a"; 100_000].join("."));
    assert!(!refused(&dotted).is_empty());
}

/// A RopeBlock rig of `lugs` lugs and `slings` slings on a 20 x 14 x 8 m box, one hook.
fn rig(lugs: usize, slings: usize) -> String {
    let mut s = String::from("[block]\nbox = [20.0, 14.0, 8.0]\nmass = 250e3\n");
    let at = [[7.0, 7.3], [-7.0, 7.3], [7.0, -7.3], [-7.0, -7.3]];
    for k in 0..lugs {
        let [x, y] = at[k % 4];
        s.push_str(&format!("[[lug]]\nposition = [{x}, {y}, 7.0]\n"));
    }
    s.push_str("[[hook]]\nposition = [0.0, 0.0, 27.0]\n");
    for k in 0..slings {
        s.push_str(&format!("[[sling]]\nlug = {}\nhook = 0\n", k % 4));
    }
    s
}

fn apply_rig(text: &str) -> Result<usize, String> {
    let mut m = rope_block::create();
    apply(m.as_mut(), &parse(text, "scene.toml")?, "scene.toml")
}

#[test]
fn rigs_past_the_sling_and_lug_caps_are_refused_at_the_first_table_too_many() {
    use crate::scene::rope_block::rig::{MAX_RIG_LUGS, MAX_RIG_SLINGS};
    assert_eq!(apply_rig(&rig(MAX_RIG_LUGS, MAX_RIG_SLINGS)), Ok(0));
    let e = apply_rig(&rig(4, MAX_RIG_SLINGS + 1)).unwrap_err();
    assert!(
        e.contains(&format!("[[sling]] {MAX_RIG_SLINGS} is one too many"))
            && e.contains("MAX_RIG_SLINGS"),
        "{e}"
    );
    let e = apply_rig(&rig(MAX_RIG_LUGS + 1, 4)).unwrap_err();
    assert!(e.contains("MAX_RIG_LUGS"), "{e}");
    // 2,000 slings are refused by the table count before the rig is read
    let e = apply_rig(&rig(4, 2_000)).unwrap_err();
    assert!(e.contains("MAX_SCENE_TABLES"), "{e}");
}

#[test]
fn rope_segments_past_the_total_cap_are_refused_naming_it() {
    use crate::scene::rope_block::params::MAX_ROPE_SEGMENTS;
    let mut p = RopeBlockParams::default();
    let slings = p.rig.slings.len();
    p.segments = MAX_ROPE_SEGMENTS / slings;
    assert_eq!(p.validate(), Ok(()));
    p.segments += 1;
    let e = p.validate().unwrap_err();
    assert!(
        e.contains("MAX_ROPE_SEGMENTS") && e.contains(&MAX_ROPE_SEGMENTS.to_string()),
        "{e}"
    );
}

#[test]
fn too_many_tables_or_values_are_refused_before_the_parse() {
    // 100,000 `[[lug]]` tables in 3.7 MB (under the byte cap): refused from the text, before
    // the parser builds its tree (it grew the resident memory by 230 MB)
    let lugs = "[[lug]]\nposition = [7.5, 7.3, 7.0]\n".repeat(100_000);
    let e = refused(&lugs);
    assert!(
        e.contains("100000 table headers") && e.contains("MAX_SCENE_TABLES"),
        "{e}"
    );
    // one array of 30,000 values on one line
    let values = format!("x = [{}]\n", vec!["1"; 30_000].join(","));
    let e = refused(&values);
    assert!(e.contains("MAX_SCENE_KEYS") && e.contains("`,`"), "{e}");
}
