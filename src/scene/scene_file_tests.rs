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
        (
            "[parameters]\nn_panels 2\n",
            "s.toml:2: expected `name = value`",
        ),
        ("[parameters]\n\"n_panels = 2\n", "unterminated string"),
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
