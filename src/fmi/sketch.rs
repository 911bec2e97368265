//! Schematic SVG sketch of each model for `documentation/index.html` (issue #23): the mechanism,
//! its frames and the names of the main ports, placed on the drawing. Every port name drawn is
//! taken from [`port_labels`], which a test checks against the model's variable table, so the
//! sketch cannot name a port the model does not have.

use std::fmt::Write;

use super::documentation::escape;

/// A port label: the port's name and where it is drawn (x, y in the 640 x 360 canvas).
type Label = (&'static str, f64, f64);

/// The port names a model's sketch draws, with their positions.
pub fn port_labels(identifier: &str) -> &'static [Label] {
    match identifier {
        "PanelLock" => &[
            ("root_motor_torque", 40.0, 330.0),
            ("hinge0_angle", 150.0, 250.0),
            ("hinge1_angle", 232.0, 203.0),
            ("hinge1_contact_force", 140.0, 135.0),
            ("hinge1_latched", 140.0, 120.0),
            ("tip_normal_velocity", 470.0, 40.0),
            ("root_force_x", 40.0, 345.0),
        ],
        "RopeBlock" => &[
            ("hook0_vz", 330.0, 30.0),
            ("hook0_load", 330.0, 45.0),
            ("sling0_tension_hook", 150.0, 110.0),
            ("contact0_normal", 120.0, 215.0),
            ("block_z", 330.0, 275.0),
            ("ground_normal", 430.0, 345.0),
        ],
        "PidController" => &[
            ("setpoint", 20.0, 150.0),
            ("measurement", 20.0, 250.0),
            ("error", 200.0, 165.0),
            ("kp", 330.0, 105.0),
            ("ki", 330.0, 175.0),
            ("kd", 330.0, 245.0),
            ("u_max", 480.0, 130.0),
            ("u", 590.0, 195.0),
        ],
        "SpringMassDamper" => &[
            ("k", 95.0, 150.0),
            ("c", 95.0, 250.0),
            ("m", 300.0, 205.0),
            ("F", 470.0, 185.0),
            ("x", 300.0, 320.0),
            ("spring_force", 160.0, 115.0),
        ],
        _ => &[],
    }
}

const HEAD: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"360\" viewBox=\"0 0 640 360\" font-family=\"sans-serif\" font-size=\"12\">\n\
<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"black\"/></marker></defs>\n\
<rect width=\"640\" height=\"360\" fill=\"white\"/>\n";

fn arrow(out: &mut String, x1: f64, y1: f64, x2: f64, y2: f64, colour: &str) {
    let _ = writeln!(
        out,
        "<line x1=\"{x1}\" y1=\"{y1}\" x2=\"{x2}\" y2=\"{y2}\" stroke=\"{colour}\" stroke-width=\"1.5\" marker-end=\"url(#arrow)\"/>"
    );
}

fn text(out: &mut String, x: f64, y: f64, s: &str, extra: &str) {
    let _ = writeln!(out, "<text x=\"{x}\" y=\"{y}\"{extra}>{}</text>", escape(s));
}

/// World frame axes at (x, y): x right, second axis up, labelled.
fn frame(out: &mut String, x: f64, y: f64, name: &str, up: &str) {
    arrow(out, x, y, x + 40.0, y, "black");
    arrow(out, x, y, x, y - 40.0, "black");
    text(out, x + 43.0, y + 4.0, "x", "");
    text(out, x - 4.0, y - 44.0, up, "");
    text(out, x + 4.0, y + 14.0, name, " font-style=\"italic\"");
}

fn panel_lock(out: &mut String) {
    // satellite wall, root hinge, yoke, hinge bodies, panels (seen along the hinge axes z)
    out.push_str(
        "<rect x=\"20\" y=\"200\" width=\"60\" height=\"100\" fill=\"#ddd\" stroke=\"black\"/>\n",
    );
    text(out, 26.0, 220.0, "satellite", "");
    frame(out, 30.0, 290.0, "world (z: hinge axes)", "y");
    let pts = [(80.0, 250.0), (200.0, 190.0), (380.0, 130.0), (560.0, 70.0)];
    let names = ["yoke", "panel 1", "panel 2"];
    for (k, w) in pts.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let _ = writeln!(
            out,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#36c\" stroke-width=\"{}\"/>",
            a.0,
            a.1,
            b.0,
            b.1,
            if k == 0 { 4 } else { 8 }
        );
        text(
            out,
            (a.0 + b.0) / 2.0 + 6.0,
            (a.1 + b.1) / 2.0 + 18.0,
            names[k],
            " fill=\"#36c\"",
        );
    }
    for (k, p) in pts[..3].iter().enumerate() {
        // hinge body with its torsion spring (coil) and latch (cam with groove, pin)
        let _ = writeln!(
            out,
            "<circle cx=\"{}\" cy=\"{}\" r=\"9\" fill=\"#fc6\" stroke=\"black\"/>\n\
<path d=\"M{} {} a14 14 0 1 1 -6 -12\" fill=\"none\" stroke=\"#a50\" stroke-width=\"1.5\"/>\n\
<circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"black\"/>",
            p.0,
            p.1,
            p.0 + 10.0,
            p.1 + 10.0,
            p.0 + 5.0,
            p.1 - 5.0
        );
        text(
            out,
            p.0 - 10.0,
            p.1 + 30.0,
            &format!("hinge {k}"),
            " fill=\"#a50\"",
        );
    }
    text(
        out,
        340.0,
        250.0,
        "hinge body (yellow), torsion spring (brown coil),",
        "",
    );
    text(
        out,
        340.0,
        265.0,
        "latch: pin (dot) drops into the cam groove",
        "",
    );
    text(out, 340.0, 280.0, "at the lock angle", "");
    // deployment angle of the root hinge
    out.push_str("<path d=\"M120 250 A40 40 0 0 0 116 232\" fill=\"none\" stroke=\"black\"/>\n<line x1=\"80\" y1=\"250\" x2=\"140\" y2=\"250\" stroke=\"black\" stroke-dasharray=\"3 3\"/>\n");
    text(out, 124.0, 244.0, "angle", " font-size=\"10\"");
    arrow(out, 540.0, 60.0, 528.0, 36.0, "#c00");
}

fn rope_block(out: &mut String) {
    frame(out, 30.0, 330.0, "world", "z");
    // ground, block with lugs, slings to the hook
    out.push_str(
        "<line x1=\"20\" y1=\"340\" x2=\"620\" y2=\"340\" stroke=\"#963\" stroke-width=\"2\"/>\n",
    );
    out.push_str(
        "<rect x=\"150\" y=\"200\" width=\"340\" height=\"90\" fill=\"#ccd\" stroke=\"black\"/>\n",
    );
    text(
        out,
        160.0,
        305.0,
        "block (design frame: x along, z up from the bottom)",
        "",
    );
    let _ = writeln!(
        out,
        "<circle cx=\"320\" cy=\"245\" r=\"3\" fill=\"black\"/>"
    );
    arrow(out, 320.0, 245.0, 360.0, 245.0, "#444");
    arrow(out, 320.0, 245.0, 320.0, 215.0, "#444");
    for (lx, ex) in [(200.0, 150.0), (440.0, 490.0)] {
        let _ = writeln!(
            out,
            "<rect x=\"{}\" y=\"283\" width=\"10\" height=\"10\" fill=\"#666\"/>\n\
<polyline points=\"320,60 {ex},200 {},288\" fill=\"none\" stroke=\"#a33\" stroke-width=\"2\"/>\n\
<circle cx=\"{ex}\" cy=\"200\" r=\"5\" fill=\"none\" stroke=\"#a33\" stroke-width=\"2\"/>",
            lx - 5.0,
            lx
        );
    }
    text(
        out,
        160.0,
        195.0,
        "contact node on the edge",
        " font-size=\"10\"",
    );
    text(out, 190.0, 280.0, "lug", " font-size=\"10\"");
    out.push_str("<path d=\"M315 50 q5 -12 10 0 q0 10 -6 10\" fill=\"none\" stroke=\"black\" stroke-width=\"2\"/>\n");
    text(out, 250.0, 55.0, "hook 0", "");
    arrow(out, 320.0, 48.0, 320.0, 18.0, "#c00");
}

fn pid(out: &mut String) {
    let bx = |out: &mut String, x: f64, y: f64, w: f64, label: &str| {
        let _ = writeln!(
            out,
            "<rect x=\"{x}\" y=\"{y}\" width=\"{w}\" height=\"30\" fill=\"#eef\" stroke=\"black\"/>"
        );
        text(out, x + 6.0, y + 19.0, label, "");
    };
    out.push_str("<circle cx=\"170\" cy=\"195\" r=\"12\" fill=\"none\" stroke=\"black\"/>\n");
    text(out, 158.0, 190.0, "+", "");
    text(out, 164.0, 218.0, "-", "");
    arrow(out, 20.0, 160.0, 158.0, 190.0, "black");
    arrow(out, 20.0, 240.0, 160.0, 204.0, "black");
    bx(out, 250.0, 110.0, 90.0, "P");
    bx(out, 250.0, 180.0, 90.0, "I (tracking Tt)");
    bx(out, 250.0, 250.0, 90.0, "D (filter Tf)");
    for y in [125.0, 195.0, 265.0] {
        arrow(out, 182.0, 195.0, 248.0, y, "black");
        arrow(out, 342.0, y, 418.0, 195.0, "black");
    }
    out.push_str("<circle cx=\"430\" cy=\"195\" r=\"12\" fill=\"none\" stroke=\"black\"/>\n");
    text(out, 425.0, 199.0, "+", "");
    bx(out, 470.0, 180.0, 80.0, "clamp");
    arrow(out, 442.0, 195.0, 468.0, 195.0, "black");
    arrow(out, 550.0, 195.0, 630.0, 195.0, "black");
    text(out, 20.0, 30.0, "sampled at each communication point", "");
}

fn spring_mass_damper(out: &mut String) {
    out.push_str(
        "<line x1=\"40\" y1=\"120\" x2=\"40\" y2=\"280\" stroke=\"black\" stroke-width=\"3\"/>\n",
    );
    out.push_str("<polyline points=\"40,160 80,160 90,145 110,175 130,145 150,175 170,145 180,160 250,160\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>\n");
    out.push_str("<path d=\"M40 240 H120 M120 225 V255 M110 225 H150 V255 H110 M135 240 H250\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>\n");
    out.push_str(
        "<rect x=\"250\" y=\"130\" width=\"120\" height=\"140\" fill=\"#eef\" stroke=\"black\"/>\n",
    );
    arrow(out, 370.0, 200.0, 460.0, 200.0, "#c00");
    arrow(out, 250.0, 300.0, 350.0, 300.0, "black");
    text(out, 20.0, 30.0, "m x'' + c x' + k x = F", "");
}

/// The sketch of a registered model; `None` for a model without one.
pub fn svg(identifier: &str) -> Option<String> {
    let draw: fn(&mut String) = match identifier {
        "PanelLock" => panel_lock,
        "RopeBlock" => rope_block,
        "PidController" => pid,
        "SpringMassDamper" => spring_mass_damper,
        _ => return None,
    };
    let mut out = String::from(HEAD);
    draw(&mut out);
    for (name, x, y) in port_labels(identifier) {
        text(
            &mut out,
            *x,
            *y,
            name,
            " fill=\"#c00\" font-family=\"monospace\"",
        );
    }
    out.push_str("</svg>\n");
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::registry;

    #[test]
    fn every_drawn_port_exists_in_the_variable_table() {
        for entry in registry() {
            let info = (entry.info)();
            let svg =
                svg(info.identifier).unwrap_or_else(|| panic!("{} has no sketch", info.identifier));
            assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
            assert!(!port_labels(info.identifier).is_empty());
            for (name, _, _) in port_labels(info.identifier) {
                assert!(
                    info.port_by_name(name).is_some(),
                    "{}: the sketch draws `{name}`, which the table does not have",
                    info.identifier
                );
                assert!(svg.contains(&format!(">{name}</text>")));
            }
        }
    }
}
