use super::*;
use crate::scene::panel_lock::PanelLockModel;
use crate::scene::port::ValueRef;
use crate::scene::registry;

fn vr(m: &dyn CoSimModel, name: &str) -> ValueRef {
    m.info().port_by_name(name).unwrap().vr
}

#[test]
fn rendered_defaults_parse_and_apply_to_every_model_without_changing_anything() {
    for entry in registry() {
        let info = (entry.info)();
        let text = render(info);
        let file = parse(&text, "defaults").unwrap();
        let n_params = info
            .ports
            .iter()
            .filter(|p| p.causality == Causality::Parameter)
            .count();
        assert_eq!(file.entries.len(), n_params, "{}", info.identifier);
        assert_eq!(file.model.as_deref(), Some(info.identifier));
        let mut fresh = (entry.create)();
        let mut applied = (entry.create)();
        assert_eq!(apply(applied.as_mut(), &file, "defaults"), Ok(n_params));
        for p in info
            .ports
            .iter()
            .filter(|p| p.causality == Causality::Parameter)
        {
            let same = match &p.ty {
                PortType::Real { .. } => {
                    fresh.get_real(p.vr).unwrap().to_bits()
                        == applied.get_real(p.vr).unwrap().to_bits()
                }
                PortType::Integer { .. } | PortType::Enumeration { .. } => {
                    fresh.get_integer(p.vr) == applied.get_integer(p.vr)
                }
                PortType::Boolean { .. } => fresh.get_boolean(p.vr) == applied.get_boolean(p.vr),
                PortType::String { .. } => fresh.get_string(p.vr) == applied.get_string(p.vr),
            };
            assert!(
                same,
                "{}: {} changed by its own defaults",
                info.identifier, p.name
            );
        }
        // the rendered defaults also initialize
        fresh.reset();
        applied.initialize(0.0).unwrap();
    }
}

#[test]
fn a_variant_scene_sets_values_by_name_type_and_item() {
    let text = r#"
# a lighter variant
model = "PanelLock"   # checked

[parameters]
n_panels = 2                  # integer
contact_stiffness = 1e8       # real
hinge_damping = 2             # integer literal for a real
latches = false               # boolean
integrator = "DOPRI5"         # enumeration by item name
contact_law = 1               # enumeration by number
"#;
    let mut m = PanelLockModel::new();
    let file = parse(text, "variant.toml").unwrap();
    assert_eq!(apply(&mut m, &file, "variant.toml"), Ok(6));
    assert_eq!(m.get_integer(vr(&m, "n_panels")), Ok(2));
    assert_eq!(m.get_real(vr(&m, "contact_stiffness")), Ok(1e8));
    assert_eq!(m.get_real(vr(&m, "hinge_damping")), Ok(2.0));
    assert_eq!(m.get_boolean(vr(&m, "latches")), Ok(false));
    let items = match &m.info().port_by_name("integrator").unwrap().ty {
        PortType::Enumeration { items, .. } => items.to_vec(),
        _ => unreachable!(),
    };
    let dopri = items.iter().position(|(n, _)| *n == "dopri5").unwrap() as i32 + 1;
    assert_eq!(m.get_integer(vr(&m, "integrator")), Ok(dopri));
    assert_eq!(m.get_integer(vr(&m, "contact_law")), Ok(1));
}

#[test]
fn bad_scene_files_are_refused_with_file_line_and_cause() {
    let cases: &[(&str, &str)] = &[
        (
            "[parameters]\nno_such_thing = 1\n",
            "s.toml:2: `PanelLock` has no parameter named `no_such_thing`",
        ),
        (
            "[parameters]\nn_panels = 1.5\n",
            "s.toml:2: `n_panels` needs an integer, got a real",
        ),
        (
            "[parameters]\nlatches = 1\n",
            "s.toml:2: `latches` needs true or false, got an integer",
        ),
        (
            "[parameters]\ncontact_stiffness = nan\n",
            "s.toml:2: `contact_stiffness`: `nan` refused: values must be finite",
        ),
        (
            "[parameters]\ncontact_stiffness = 1e999\n",
            "s.toml:2: `contact_stiffness`: `1e999` refused: values must be finite",
        ),
        (
            "[parameters]\ncontact_stiffness = -5.0\n",
            "below its minimum",
        ),
        (
            "[parameters]\nn_panels = 2\n\nn_panels = 3\n",
            "s.toml:4: `n_panels` is set twice (first on line 2)",
        ),
        ("[settings]\n", "s.toml:1: unknown table `[settings]`"),
        (
            "n_panels = 2\n",
            "s.toml:1: `n_panels` is outside `[parameters]`",
        ),
        (
            "model = \"RopeBlock\"\n",
            "s.toml: the scene is for model `RopeBlock`, not `PanelLock`",
        ),
        (
            "[parameters]\nintegrator = \"RK4\"\n",
            "s.toml:2: `integrator` = \"RK4\" is not one of",
        ),
        // TOML syntax errors: the crate's wording, with the line (and column)
        (
            "[parameters]\nn_panels 2\n",
            "s.toml:2: key with no value, expected `=`",
        ),
        (
            "[parameters]\n\"n_panels = 2\n",
            "invalid basic string, expected `\"`",
        ),
        (
            "[parameters]\nn_panels = 99999999999\n",
            "does not fit in 32 bits",
        ),
    ];
    for (text, want) in cases {
        let mut m = PanelLockModel::new();
        let r = parse(text, "s.toml").and_then(|f| apply(&mut m, &f, "s.toml"));
        let e = r.expect_err(text);
        assert!(e.contains(want), "{text:?}: got `{e}`, want `{want}`");
    }
    // an output cannot be set from a scene
    let out = PanelLockModel::new()
        .info()
        .ports
        .iter()
        .find(|p| p.causality == Causality::Output)
        .unwrap()
        .name
        .clone();
    let text = format!("[parameters]\n\"{out}\" = 1.0\n");
    let e = parse(&text, "s.toml")
        .and_then(|f| apply(&mut PanelLockModel::new(), &f, "s.toml"))
        .unwrap_err();
    assert!(e.contains("has causality output"), "{e}");
}

#[test]
fn comments_strings_and_quoted_keys_round_trip() {
    let text =
        "[parameters]\n\"a.b[1]\" = \"x # not a comment \\\"q\\\"\" # comment\nk-1 = 1_000\n";
    let f = parse(text, "t").unwrap();
    assert_eq!(f.entries[0].name, "a.b[1]");
    assert_eq!(
        f.entries[0].value,
        SceneValue::String("x # not a comment \"q\"".into())
    );
    assert_eq!(f.entries[1].value, SceneValue::Integer(1000));
    assert_eq!(key_text("a.b[1]"), "\"a.b[1]\"");
    assert_eq!(key_text("rtol"), "rtol");
}

#[test]
fn toml_forms_the_old_subset_parser_could_not_read() {
    let text = r#"[parameters]   # a comment after the header
"a" = "tab\there \u00e9 \U0001F600"
b = 'C:\no\escapes'
c = """
two
lines"""
d = 1_000.0
e = 0x1F
f = +1.5
g = 0o17
h = 0b101
"#;
    let f = parse(text, "t").unwrap();
    let got: Vec<(&str, &SceneValue, usize)> = f
        .entries
        .iter()
        .map(|e| (e.name.as_str(), &e.value, e.line))
        .collect();
    let s = |v: &str| SceneValue::String(v.into());
    assert_eq!(
        got,
        [
            ("a", &s("tab\there \u{e9} \u{1F600}"), 2),
            ("b", &s("C:\\no\\escapes"), 3),
            ("c", &s("two\nlines"), 4),
            ("d", &SceneValue::Real(1000.0), 7),
            ("e", &SceneValue::Integer(31), 8),
            ("f", &SceneValue::Real(1.5), 9),
            ("g", &SceneValue::Integer(15), 10),
            ("h", &SceneValue::Integer(5), 11),
        ]
    );
    // the table in its inline and dotted forms is the same table, lines per key
    let inline = parse(
        "model = \"PanelLock\"\nparameters = { n_panels = 2, latches = false }\n",
        "t",
    )
    .unwrap();
    let dotted = parse("parameters.n_panels = 2\nparameters.latches = false\n", "t").unwrap();
    assert_eq!(inline.model_line, 1);
    let names = |f: &SceneFile| {
        f.entries
            .iter()
            .map(|e| (e.name.clone(), e.line))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        names(&inline),
        [("n_panels".to_string(), 2), ("latches".to_string(), 2)]
    );
    assert_eq!(
        names(&dotted),
        [("n_panels".to_string(), 1), ("latches".to_string(), 2)]
    );
    // file order, not the tree's name order: apply sets values in the order written
    let f = parse("[parameters]\nz = 1\na = 2\n", "t").unwrap();
    assert_eq!(f.entries[0].name, "z");
    // control characters are escaped by the renderer, so names and strings round-trip
    let q = quote("a\u{1}b\u{7f}\"\\");
    let f = parse(&format!("[parameters]\nk = {q}\n"), "t").unwrap();
    assert_eq!(f.entries[0].value, s("a\u{1}b\u{7f}\"\\"));
}

#[test]
fn what_is_no_parameter_value_is_refused_with_file_line_and_cause() {
    let cases: &[(&str, &str)] = &[
        (
            "[parameters]\n\ncontact_stiffness = +inf\n",
            "s.toml:3: `contact_stiffness`: `+inf` refused: values must be finite",
        ),
        (
            "[parameters]\ncontact_stiffness = -inf\n",
            "s.toml:2: `contact_stiffness`: `-inf` refused: values must be finite",
        ),
        (
            "[parameters]\ncontact_stiffness = 1_0e9_99\n",
            "s.toml:2: `contact_stiffness`: `1_0e9_99` refused: values must be finite",
        ),
        (
            "[parameters]\nn_panels = 2\nbody.mass = 1.0\n",
            "s.toml:3: `body.mass` is a dotted key, which TOML reads as tables; quote a parameter name that holds `.`: `\"body.mass\" = ...`",
        ),
        (
            "[parameters]\n[parameters.sub]\nx = 1\n",
            "s.toml:2: unknown table `[parameters.sub]`: a scene file has only `[parameters]`",
        ),
        (
            "[parameters]\n[parameters.a.b]\n",
            "s.toml:2: unknown table `[parameters.a.b]`",
        ),
        (
            "[[parameters]]\nn_panels = 2\n",
            "s.toml:1: `[[parameters]]` is an array of tables: a scene file has one `[parameters]` table",
        ),
        ("[[runs]]\n", "s.toml:1: unknown table `[[runs]]`"),
        ("[a.b]\n", "s.toml:1: unknown table `[a.b]`"),
        (
            "x.y = 1\n",
            "s.toml:1: `x.y` is outside `[parameters]` (only `model` may stand there); it is a dotted key",
        ),
        (
            "[parameters]\nn_panels = { value = 2 }\n",
            "s.toml:2: `n_panels`: cannot read an inline table `{ value = 2 }` (expected a number, true/false or a \"string\")",
        ),
        (
            "[parameters]\nn_panels = [\n  2,\n  3,\n]\n",
            "s.toml:2: `n_panels`: cannot read an array `[ ...`",
        ),
        (
            "[parameters]\nn_panels = 1979-05-27\n",
            "s.toml:2: `n_panels`: cannot read a date-time `1979-05-27`",
        ),
        (
            "[parameters]\nn_panels = 99999999999999999999\n",
            "s.toml:2: `n_panels`: `99999999999999999999` does not fit in a 64-bit integer",
        ),
        (
            "[parameters]\n\ncontact_stiffness = \"\"\"\n1e7\"\"\"\n",
            "s.toml:3: `contact_stiffness` needs a number, got a string",
        ),
        (
            "model = \"PanelLock\"\nmodel = \"PanelLock\"\n",
            "s.toml:2: `model` is set twice (first on line 1): duplicate key",
        ),
        (
            "model = 3\n",
            "s.toml:1: `model` must be given once, as a string",
        ),
        (
            "parameters = 3\n",
            "s.toml:1: `parameters` must be the table `[parameters]`, not an integer",
        ),
        (
            "[parameters]\nn_panels = 2\n[parameters]\n",
            "s.toml:3: `[parameters]` appears twice (first on line 1): duplicate key",
        ),
        (
            "[parameters]\n\"n_panels\" = 2\n'n_panels' = 3\n",
            "s.toml:3: `n_panels` is set twice (first on line 2): duplicate key",
        ),
        (
            "[parameters]\na.b = 1\na.b = 2\n",
            "s.toml:3: `a.b` is set twice (first on line 2): duplicate key",
        ),
        (
            "model = \"RopeBlock\"\n",
            "s.toml: the scene is for model `RopeBlock`, not `PanelLock` (line 1)",
        ),
        // syntax the old parser let through, which TOML refuses: the crate says why
        (
            "[parameters]\nn_panels = 01\n",
            "s.toml:2: unexpected leading zero",
        ),
        ("[parameters]\nx = 1.\n", "s.toml:2: invalid fraction"),
        (
            "[parameters]\nlatches = yes\n",
            "s.toml:2: string values must be quoted",
        ),
        (
            "[parameters]\nx = \"\\q\"\n",
            "s.toml:2: missing escaped value",
        ),
        ("[parameters]]\n", "s.toml:1: "),
    ];
    for (text, want) in cases {
        let mut m = PanelLockModel::new();
        let r = parse(text, "s.toml").and_then(|f| apply(&mut m, &f, "s.toml"));
        let e = r.expect_err(text);
        assert!(e.contains(want), "{text:?}: got `{e}`, want `{want}`");
    }
}

/// A small deterministic generator (xorshift64*), so the garbage below is the same every run.
struct Garbage(u64);

impl Garbage {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

#[test]
fn garbage_is_refused_with_a_message_never_a_panic() {
    const PIECES: &[&str] = &[
        "[",
        "]",
        "[[",
        "]]",
        "{",
        "}",
        "=",
        ".",
        ",",
        "\"",
        "'",
        "\"\"\"",
        "'''",
        "\\",
        "\\u",
        "\\U0010FFFF",
        "#",
        "\n",
        "\r\n",
        " ",
        "\t",
        "\0",
        "\u{7f}",
        "é",
        "\u{FEFF}",
        "model",
        "parameters",
        "n_panels",
        "contact_stiffness",
        "integrator",
        "latches",
        "\"bdf\"",
        "1",
        "-0",
        "+1",
        "0x",
        "0o7",
        "0b2",
        "1e",
        "1e999",
        "1_",
        "_1",
        "1.5",
        "nan",
        "+inf",
        "-inf",
        "true",
        "false",
        "1979-05-27T07:32:00Z",
        "07:32",
        "a.b",
        "\"a.b\"",
    ];
    let rendered = render(PanelLockModel::new().info());
    let mut g = Garbage(0x9e37_79b9_7f4a_7c15);
    let mut model = PanelLockModel::new();
    let mut refused = 0;
    for round in 0..6000 {
        let text = match round % 3 {
            // random bytes (as a file that is read as UTF-8 would hold them)
            0 => {
                let bytes: Vec<u8> = (0..g.below(80)).map(|_| g.next() as u8).collect();
                String::from_utf8_lossy(&bytes).into_owned()
            }
            // TOML-ish pieces in random order
            1 => (0..g.below(30))
                .map(|_| PIECES[g.below(PIECES.len())])
                .collect(),
            // the default scene with a few bytes changed, dropped or a piece put in
            _ => {
                let mut t = rendered.clone().into_bytes();
                for _ in 0..1 + g.below(4) {
                    let at = g.below(t.len());
                    match g.below(3) {
                        0 => t[at] = g.next() as u8,
                        1 => {
                            t.remove(at);
                        }
                        _ => {
                            let p = PIECES[g.below(PIECES.len())].as_bytes();
                            t.splice(at..at, p.iter().copied());
                        }
                    }
                }
                String::from_utf8_lossy(&t).into_owned()
            }
        };
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            parse(&text, "g.toml").and_then(|f| apply(&mut model, &f, "g.toml"))
        }));
        match r {
            Ok(Ok(_)) => {}
            Ok(Err(e)) => {
                assert!(
                    e.starts_with("g.toml"),
                    "{text:?}: message without the file: {e}"
                );
                refused += 1;
            }
            Err(_) => panic!("the scene parser panicked on {text:?}"),
        }
    }
    assert!(refused > 4000, "only {refused} of 6000 refused");
}
