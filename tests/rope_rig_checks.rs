//! Rigs read from scene files (issue #21): a user mesh with lugs that match it gets its contact
//! nodes, the built-in lugs on a bigger mesh are refused instead of silently passing through the
//! deck, every bad rig is refused at instantiation (when the scene file is applied) with its named
//! error and the file's line, and a sling passing through the block is warned about.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::rope_block::RopeBlockModel;
use mbcosim::scene::scene_file::{apply, parse};
use std::path::{Path, PathBuf};

/// A folder of its own for this test's files.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("mbcosim_rig_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An OBJ box `[-l/2, l/2] x [-b/2, b/2] x [0, h]` [m]; `drop` triangles left out (an open mesh).
fn write_box(dir: &Path, l: f64, b: f64, h: f64, drop: usize) -> PathBuf {
    let mut s = String::new();
    for &z in &[0.0, h] {
        for &(x, y) in &[(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            s.push_str(&format!("v {} {} {z}\n", x * l / 2.0, y * b / 2.0));
        }
    }
    // outward-facing quads (1-based): bottom, top, four sides
    let quads = [
        [1, 4, 3, 2],
        [5, 6, 7, 8],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 4, 8, 7],
        [4, 1, 5, 8],
    ];
    let mut tris = Vec::new();
    for q in quads {
        tris.push([q[0], q[1], q[2]]);
        tris.push([q[0], q[2], q[3]]);
    }
    for t in &tris[..tris.len() - drop] {
        s.push_str(&format!("f {} {} {}\n", t[0], t[1], t[2]));
    }
    let p = dir.join(format!("box_{drop}.obj"));
    std::fs::write(&p, s).unwrap();
    p
}

/// The 20 m x 14 m x 8 m block of the issue with lugs 1 m below the deck edge, 0.3 m off the side
/// shell, slings over the deck edges to one hook 19 m above the deck.
fn user_lift(mesh: &str, extra_block: &str, slings: &str) -> String {
    let mut s = format!(
        "model = \"RopeBlock\"\n[parameters]\nsegments = 40\n\n[block]\nmesh = \"{mesh}\"\nmass = 250e3\n{extra_block}\n"
    );
    for (x, y) in [(7.5, 7.3), (-7.5, 7.3), (-7.5, -7.3), (7.5, -7.3)] {
        s.push_str(&format!("[[lug]]\nposition = [{x}, {y}, 7.0]\n\n"));
    }
    s.push_str(slings);
    s.push_str("[[hook]]\nposition = [0.0, 0.0, 27.0]\ncrane = 1\n");
    s
}

fn four_slings(extra: &str) -> String {
    (0..4)
        .map(|k| format!("[[sling]]\nlug = {k}\nhook = 0\n{extra}\n"))
        .collect()
}

/// Applies scene text `text` (file `dir/scene.toml`) to a new model; the model or the message.
fn instantiate(dir: &Path, text: &str) -> Result<RopeBlockModel, String> {
    let origin = dir.join("scene.toml").display().to_string();
    let mut m = RopeBlockModel::new();
    let file = parse(text, &origin)?;
    apply(&mut m, &file, &origin)?;
    Ok(m)
}

#[test]
fn a_user_mesh_with_matching_lugs_gets_its_contact_nodes() {
    let dir = folder("contact");
    write_box(&dir, 20.0, 14.0, 8.0, 0);
    let text = user_lift("box_0.obj", "", &four_slings(""));
    let mut m = instantiate(&dir, &text).expect("the rig is accepted");
    m.initialize(0.0).expect("the rig hangs");
    let info = m.info();
    let count = m
        .get_integer(info.port_by_name("contact_count").unwrap().vr)
        .unwrap();
    let tension = m
        .get_real(info.port_by_name("sling0_tension_hook").unwrap().vr)
        .unwrap();
    let daf = m.get_real(info.port_by_name("daf").unwrap().vr).unwrap();
    println!(
        "20 x 14 x 8 m user mesh: {count} contact nodes, sling 0 {tension:.0} N, daf {daf:.9}"
    );
    assert_eq!(count, 4, "one contact node per sling over its deck edge");
    assert!((daf - 1.0).abs() < 1e-6);
}

#[test]
fn the_built_in_lugs_on_a_bigger_mesh_are_refused() {
    // the case: mesh_file alone keeps the built-in lugs, which lie inside this block
    let dir = folder("builtin_lugs");
    let mesh = write_box(&dir, 20.0, 14.0, 8.0, 0);
    let text = format!("[parameters]\nmesh_file = \"{}\"\n", mesh.display());
    let mut m = instantiate(&dir, &text).unwrap();
    let e = m.initialize(0.0).unwrap_err().to_string();
    println!("{e}");
    assert!(e.contains("lug_off_block: lug 0 is 0.700 m"), "{e}");
}

/// The message of refusing `text` at instantiation.
fn refused(name: &str, text: &str) -> String {
    let dir = folder(name);
    write_box(&dir, 20.0, 14.0, 8.0, 0);
    write_box(&dir, 20.0, 14.0, 8.0, 1);
    let e = instantiate(&dir, text).expect_err("refused");
    println!("{name}: {e}");
    e
}

#[test]
fn a_sling_shorter_than_its_straight_path_is_refused() {
    let mut slings = four_slings("");
    slings = slings.replacen("hook = 0\n", "hook = 0\nlength = 20.0\n", 2);
    let e = refused("short", &user_lift("box_0.obj", "", &slings));
    assert!(
        e.contains("rig refused: sling_too_short: sling 0 (20.000 m unstretched)"),
        "{e}"
    );
}

#[test]
fn a_sling_that_cannot_reach_its_hook_over_the_edge_is_refused() {
    // 3 m below the deck: just long enough straight, too short over the deck edge for its
    // 500 kN breaking load
    let mut text = user_lift("box_0.obj", "", &four_slings(""));
    text = text.replace("position = [7.5, 7.3, 7.0]", "position = [7.5, 7.3, 5.0]");
    let straight = (7.5f64.powi(2) + 7.3f64.powi(2) + 22.0f64.powi(2)).sqrt();
    text = text.replacen(
        "lug = 0\nhook = 0\n",
        &format!("lug = 0\nhook = 0\nlength = {straight}\nbreaking_load = 5e5\n"),
        1,
    );
    let e = refused("reach", &text);
    assert!(e.contains("sling_cannot_reach: sling 0"), "{e}");
}

#[test]
fn a_lug_off_the_block_is_refused() {
    let text = user_lift("box_0.obj", "", &four_slings("")).replace(
        "position = [-7.5, -7.3, 7.0]",
        "position = [-7.5, -9.0, 7.0]",
    );
    let e = refused("lug", &text);
    assert!(e.contains("lug_off_block: lug 2 is 2.000 m"), "{e}");
}

#[test]
fn a_mesh_that_is_not_closed_is_refused() {
    let e = refused("open", &user_lift("box_1.obj", "", &four_slings("")));
    assert!(
        e.contains("mesh_not_closed: the block mesh has 3 edges"),
        "{e}"
    );
}

#[test]
fn scene_file_mistakes_name_the_line() {
    let cases = [
        ("[[sling]]\nlug = 0\n", ":1: [[sling]] 0 needs `hook`"),
        (
            "[[hook]]\nposition = [1.0, 2.0]\n",
            ":2: [[hook]] 0 `position` must be an array of 3 numbers",
        ),
        (
            "[[lug]]\nposition = [0, 0, 8]\ncolour = \"red\"\n",
            ":3: [[lug]] 0 has no key `colour`",
        ),
        (
            "[block]\nbox = [20.0, 14.0, 8.0]\nmesh = \"a.obj\"\n",
            ":3: [block] give either `box` or `mesh`",
        ),
        (
            "[[sling]]\nlug = 0\nhook = 0\nea = -1.0\n",
            ":4: [[sling]] 0 `ea` must be > 0 [N]",
        ),
        (
            "[[hook]]\nposition = [0, 0, \"up\"]\n",
            ":2: `hook.position`: an array here holds numbers only",
        ),
    ];
    let dir = folder("lines");
    for (text, want) in cases {
        let e = instantiate(&dir, text).expect_err("refused");
        println!("{e}");
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
    // a model without a rig refuses the tables
    let mut panel = mbcosim::scene::panel_lock::create();
    let file = parse("[[hook]]\nposition = [0, 0, 1]\n", "p.toml").unwrap();
    let e = apply(panel.as_mut(), &file, "p.toml").unwrap_err();
    assert!(e.contains("p.toml:1: unknown table `[hook]`"), "{e}");
}

#[test]
fn a_sling_through_the_block_is_warned_about() {
    // contact on, but a straight route from a lug under the bottom plate: through the block
    let dir = folder("warn");
    write_box(&dir, 20.0, 14.0, 8.0, 0);
    let text = user_lift("box_0.obj", "", &four_slings("route = \"straight\""))
        .replace("position = [7.5, 7.3, 7.0]", "position = [7.5, 5.0, -0.2]");
    let mut m = instantiate(&dir, &text).expect("accepted with a warning");
    let log = m.take_log();
    let warned = log
        .iter()
        .any(|r| r.message.contains("sling 0 passes through the block"));
    assert!(warned, "{log:?}");
}

#[test]
fn random_rigs_are_answered_without_panics() {
    // numbers from 1e-300 to 1e300 of either sign, wrong indices, any counts: every rig gets a
    // model or a message at instantiation (the reader runs inside fmi2Instantiate)
    let dir = folder("fuzz");
    write_box(&dir, 20.0, 14.0, 8.0, 0);
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let num = |next: &mut dyn FnMut() -> u64| -> String {
        let r = next();
        let x = match r % 4 {
            0 => (r % 41) as f64 - 20.0,
            1 => ((r >> 8) % 1000) as f64 * 0.05,
            2 => 10f64.powi(((r >> 16) % 601) as i32 - 300),
            _ => -10f64.powi(((r >> 16) % 601) as i32 - 300),
        };
        format!("{x:e}")
    };
    let (mut accepted, mut refused) = (0, 0);
    for _ in 0..300 {
        let mut text = String::from("[block]\n");
        if next() % 2 == 0 {
            text.push_str(&format!(
                "box = [{}, {}, {}]\n",
                num(&mut next),
                num(&mut next),
                num(&mut next)
            ));
        } else {
            text.push_str("mesh = \"box_0.obj\"\n");
        }
        for key in ["mass", "cog", "inertia", "plate_thickness"] {
            if next() % 3 == 0 {
                let v = match key {
                    "cog" => format!(
                        "[{}, {}, {}]",
                        num(&mut next),
                        num(&mut next),
                        num(&mut next)
                    ),
                    "inertia" => format!(
                        "[{}, {}, {}, {}, {}, {}]",
                        num(&mut next),
                        num(&mut next),
                        num(&mut next),
                        num(&mut next),
                        num(&mut next),
                        num(&mut next)
                    ),
                    _ => num(&mut next),
                };
                text.push_str(&format!("{key} = {v}\n"));
            }
        }
        for _ in 0..(next() % 5) {
            text.push_str(&format!(
                "[[lug]]\nposition = [{}, {}, {}]\n",
                num(&mut next),
                num(&mut next),
                num(&mut next)
            ));
        }
        for _ in 0..(next() % 5) {
            text.push_str(&format!(
                "[[sling]]\nlug = {}\nhook = {}\n",
                next() % 5,
                next() % 5
            ));
            if next() % 2 == 0 {
                text.push_str(&format!(
                    "length = {}\nea = {}\n",
                    num(&mut next),
                    num(&mut next)
                ));
            }
        }
        for _ in 0..(next() % 6) {
            text.push_str(&format!(
                "[[hook]]\nposition = [{}, {}, {}]\n",
                num(&mut next),
                num(&mut next),
                num(&mut next)
            ));
        }
        match std::panic::catch_unwind(|| instantiate(&dir, &text).map(|_| ())) {
            Ok(Ok(())) => accepted += 1,
            Ok(Err(e)) => {
                assert!(!e.is_empty());
                refused += 1
            }
            Err(_) => panic!("panicked on\n{text}"),
        }
    }
    // the good rig with one number replaced: deeper into the checks
    let good = user_lift(
        "box_0.obj",
        "cog = [0.0, 0.0, 3.5]\n",
        &four_slings("length = 23.0"),
    );
    let spots: Vec<usize> = good
        .char_indices()
        .filter(|&(i, c)| {
            c.is_ascii_digit()
                && !good[..i].ends_with(|p: char| {
                    p.is_ascii_alphanumeric() || p == '.' || p == '_' || p == '-'
                })
        })
        .map(|(i, _)| i)
        .collect();
    for _ in 0..300 {
        let at = spots[(next() as usize) % spots.len()];
        let end = at
            + good[at..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '.'))
                .unwrap_or(0);
        let text = format!("{}{}{}", &good[..at], num(&mut next), &good[end..]);
        match std::panic::catch_unwind(|| instantiate(&dir, &text).map(|_| ())) {
            Ok(Ok(())) => accepted += 1,
            Ok(Err(_)) => refused += 1,
            Err(_) => panic!("panicked on\n{text}"),
        }
    }
    println!("random rigs: {accepted} accepted, {refused} refused, no panic");
}
