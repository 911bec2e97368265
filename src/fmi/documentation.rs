//! `documentation/index.html` of an FMU, generated from the variable table.
//!
//! Lists parameters (with variability, start value, limits and unit), inputs, outputs and
//! internal values, the FMI capabilities and the log categories, so the documentation can never
//! disagree with `modelDescription.xml`. The FMI 3.0 FMU gets its own page ([`index_html3`]):
//! FMI 3.0 types, value references and arrays, and the FMI 3.0 functions.

use std::fmt::Write;

use super::arrays3::{self, View3};
use super::logger::CATEGORIES;
use super::model_description::fmt_real;
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType};

/// Escapes text for HTML element content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

fn type_name(p: &PortSpec) -> String {
    match &p.ty {
        PortType::Real { .. } => "Real".into(),
        PortType::Integer { .. } => "Integer".into(),
        PortType::Boolean { .. } => "Boolean".into(),
        PortType::String { .. } => "String".into(),
        PortType::Enumeration { type_name, .. } => format!("Enumeration {type_name}"),
    }
}

fn start(p: &PortSpec) -> String {
    match &p.ty {
        PortType::Real { start, .. } => start.map(fmt_real),
        PortType::Integer { start, .. } => start.map(|v| v.to_string()),
        PortType::Boolean { start } => start.map(|v| v.to_string()),
        PortType::String { start } => start.map(|v| format!("\"{v}\"")),
        PortType::Enumeration { items, start, .. } => start.map(|v| {
            let name = usize::try_from(v - 1)
                .ok()
                .and_then(|i| items.get(i))
                .map_or("?", |it| it.0);
            format!("{v} ({name})")
        }),
    }
    .unwrap_or_default()
}

/// The range column: `[lo, hi]` for inclusive bounds; an open bound (the validation refuses
/// it, the declared value is the next float inside) as `(lo` or `hi)`.
pub fn range(p: &PortSpec) -> String {
    let (lo, hi, open) = match &p.ty {
        PortType::Real { min, max, open, .. } => (
            min.map(|v| fmt_real(if open[0] { v.next_down() } else { v })),
            max.map(|v| fmt_real(if open[1] { v.next_up() } else { v })),
            *open,
        ),
        PortType::Integer { min, max, .. } => (
            min.map(|v| v.to_string()),
            max.map(|v| v.to_string()),
            [false; 2],
        ),
        PortType::Enumeration { items, .. } => {
            (Some("1".into()), Some(items.len().to_string()), [false; 2])
        }
        _ => (None, None, [false; 2]),
    };
    match (lo, hi) {
        (None, None) => String::new(),
        (lo, hi) => format!(
            "{}{}, {}{}",
            if open[0] || lo.is_none() { "(" } else { "[" },
            lo.as_deref().unwrap_or("-inf"),
            hi.as_deref().unwrap_or("+inf"),
            if open[1] || hi.is_none() { ")" } else { "]" },
        ),
    }
}

/// The unit column: the declared unit, else the documentation-only note, else `1`.
pub fn unit(p: &PortSpec) -> &'static str {
    match (&p.ty, p.unit) {
        (_, Some(u)) => u,
        (
            PortType::Real {
                unit_note: Some(n), ..
            },
            None,
        ) => n,
        _ => "1",
    }
}

/// One line of a variable table.
struct Row {
    name: String,
    /// FMI 3.0 value reference (the FMI 2.0 page has none).
    vr: Option<u32>,
    ty: String,
    variability: &'static str,
    start: String,
    range: String,
    unit: &'static str,
    description: String,
}

impl Row {
    /// An FMI 2.0 variable: one port.
    fn of_port(p: &PortSpec) -> Row {
        Row {
            name: p.name.to_string(),
            vr: None,
            ty: type_name(p),
            variability: p.variability.name(),
            start: start(p),
            range: range(p),
            unit: unit(p),
            description: p.description.to_string(),
        }
    }

    /// An FMI 3.0 variable: a scalar, or an array (`name[n]`, the start values listed).
    fn of_var(info: &ModelInfo, v: &arrays3::Var3) -> Row {
        let p = v.head(info);
        let ty = match &p.ty {
            PortType::Enumeration { type_name, .. } => format!("Enumeration {type_name}"),
            _ => v.ty.element().to_string(),
        };
        let (name, start) = if v.is_array() {
            let starts: Vec<String> = v.ports.iter().map(|&i| start(&info.ports[i])).collect();
            let start = if starts.iter().all(String::is_empty) {
                String::new()
            } else {
                starts.join(" ")
            };
            (format!("{}[{}]", v.name, v.ports.len()), start)
        } else {
            (v.name.clone(), start(p))
        };
        Row {
            name,
            vr: Some(v.vr),
            ty,
            variability: p.variability.name(),
            start,
            range: range(p),
            unit: unit(p),
            description: arrays3::description(info, v),
        }
    }

    fn vr_cell(&self, with_vr: bool) -> String {
        match (with_vr, self.vr) {
            (true, Some(vr)) => format!("<td>{vr}</td>"),
            (true, None) => "<td></td>".into(),
            (false, _) => String::new(),
        }
    }
}

fn table(out: &mut String, title: &str, rows: &[Row], with_start: bool, with_vr: bool) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(out, "<h2>{}</h2>\n<table>", escape(title));
    let head = if with_start {
        "<th>start</th><th>range</th>"
    } else {
        ""
    };
    let vr_head = if with_vr {
        "<th>value reference</th>"
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "<tr><th>name</th>{vr_head}<th>type</th><th>variability</th>{head}<th>unit</th><th>description</th></tr>"
    );
    for r in rows {
        let extra = if with_start {
            format!("<td>{}</td><td>{}</td>", escape(&r.start), escape(&r.range))
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "<tr><td><code>{}</code></td>{}<td>{}</td><td>{}</td>{extra}<td>{}</td><td>{}</td></tr>",
            escape(&r.name),
            r.vr_cell(with_vr),
            escape(&r.ty),
            r.variability,
            escape(r.unit),
            escape(&r.description)
        );
    }
    out.push_str("</table>\n");
}

/// The platforms of `folders` (names under `binaries/`) as the page lists them.
fn binaries_text(folders: &[&str]) -> String {
    let names: Vec<String> = folders
        .iter()
        .map(|f| format!("<code>{}</code>", escape(f)))
        .collect();
    let noun = if names.len() == 1 {
        "binary"
    } else {
        "binaries"
    };
    format!("{noun} for {}", names.join(", "))
}

/// The HTML page of the FMI 2.0 FMU of one model; `folders` are its binaries' folders under
/// `binaries/`.
pub fn index_html(info: &ModelInfo, folders: &[&str]) -> String {
    let rows = |c: Causality| -> Vec<Row> {
        info.ports
            .iter()
            .filter(|p| p.causality == c)
            .map(Row::of_port)
            .collect()
    };
    let usage = format!(
        "<li>FMI 2.0 Co-Simulation, GUID <code>{guid}</code>, {binaries}.</li>\n\
<li>Fixed parameters can be set until <code>fmi2ExitInitializationMode</code>; tunable parameters and inputs also between steps. Values outside their range, NaN and infinities are refused with <code>fmi2Error</code>.</li>\n\
<li>Inputs are held constant over a communication step; outputs change only in <code>fmi2DoStep</code>. Variable step sizes are accepted; communication points are matched to the model time with a relative tolerance of 1e-9.</li>\n\
<li>FMU states can be saved, restored and serialized (also across processes); <code>fmi2Reset</code> is supported; instances are independent and may run on different threads.</li>\n",
        guid = escape(info.guid),
        binaries = binaries_text(folders),
    );
    page(info, rows, false, &usage)
}

/// The HTML page of the FMI 3.0 FMU of one model: FMI 3.0 names, types and value references,
/// families of outputs as arrays. Empty when the table has no FMI 3.0 view (packing refuses
/// such a table before). `folders` as for [`index_html`].
pub fn index_html3(info: &ModelInfo, folders: &[&str]) -> String {
    let Ok(view) = View3::new(info) else {
        return String::new();
    };
    let rows = |c: Causality| -> Vec<Row> {
        view.vars
            .iter()
            .filter(|v| v.head(info).causality == c)
            .map(|v| Row::of_var(info, v))
            .collect()
    };
    let usage = format!(
        "<li>FMI 3.0 Co-Simulation, instantiationToken <code>{guid}</code>, {binaries}. The independent variable <code>time</code> has value reference {time}.</li>\n\
<li>An array <code>name[n]</code> has one value reference and <code>n</code> values: <code>nValues</code> counts elements.</li>\n\
<li>Fixed parameters can be set until <code>fmi3ExitInitializationMode</code>; tunable parameters and inputs also between steps. Values outside their range, NaN and infinities are refused with <code>fmi3Error</code>.</li>\n\
<li>Inputs are held constant over a communication step; outputs change only in <code>fmi3DoStep</code>. Instantiated with <code>earlyReturnAllowed</code>, <code>fmi3DoStep</code> ends at the model's first event in the step (located in time) with <code>earlyReturn</code> true and <code>lastSuccessfulTime</code> there; an intermediate-update callback is called after every internal integrator step and may ask for an early return. No event mode.</li>\n\
<li>FMU states can be saved, restored and serialized (also across processes); <code>fmi3Reset</code> is supported; instances are independent and may run on different threads.</li>\n",
        guid = escape(info.guid),
        time = super::variables3::TIME_VR,
        binaries = binaries_text(folders),
    );
    page(info, rows, true, &usage)
}

/// The page around the variable tables (`rows` per causality) and the usage notes.
fn page(
    info: &ModelInfo,
    rows: impl Fn(Causality) -> Vec<Row>,
    with_vr: bool,
    usage: &str,
) -> String {
    let mut out = String::new();
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{id}</title>\n\
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto}}table{{border-collapse:collapse}}\
td,th{{border:1px solid #bbb;padding:0.2em 0.5em;text-align:left;vertical-align:top}}</style>\n\
</head>\n<body>\n<h1>{id}</h1>\n<p>{desc}</p>\n",
        id = escape(info.identifier),
        desc = escape(info.description)
    );
    if let Some(svg) = super::sketch::svg(info.identifier) {
        out.push_str("<h2>Sketch</h2>\n<p>Schematic, not to scale; port names in red.</p>\n");
        out.push_str(&svg);
    }
    table(
        &mut out,
        "Parameters",
        &rows(Causality::Parameter),
        true,
        with_vr,
    );
    table(
        &mut out,
        "Calculated parameters",
        &rows(Causality::CalculatedParameter),
        false,
        with_vr,
    );
    table(&mut out, "Inputs", &rows(Causality::Input), true, with_vr);
    table(
        &mut out,
        "Outputs",
        &rows(Causality::Output),
        false,
        with_vr,
    );
    table(
        &mut out,
        "Internal values",
        &rows(Causality::Local),
        false,
        with_vr,
    );
    let _ = write!(
        out,
        "<h2>Usage and limits</h2>\n<ul>\n{usage}<li>Default experiment: stop time {stop} s, step {step} s.</li>\n</ul>\n<h2>Log categories</h2>\n<ul>\n",
        stop = fmt_real(info.default_stop_time),
        step = fmt_real(info.default_step)
    );
    let fmi3 = with_vr;
    for (_, name, desc) in CATEGORIES {
        let desc = if fmi3 {
            desc.replace("fmi2", "fmi3")
        } else {
            desc.to_string()
        };
        let _ = writeln!(
            out,
            "<li><code>{}</code>: {}</li>",
            name.to_string_lossy(),
            escape(&desc)
        );
    }
    out.push_str("</ul>\n</body>\n</html>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::pid;

    #[test]
    fn pid_page_lists_every_port() {
        let html = index_html(pid::info(), &["linux64", "win64"]);
        assert!(
            html.contains("binaries for <code>linux64</code>, <code>win64</code>."),
            "{html}"
        );
        for p in &pid::info().ports {
            assert!(
                html.contains(&format!("<code>{}</code>", p.name)),
                "{}",
                p.name
            );
        }
        assert!(html.contains("<h2>Outputs</h2>") && html.contains("1/s"));
        assert!(!html.contains("value reference") && html.contains("fmi2DoStep"));
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn fmi3_page_shows_arrays_with_their_value_references() {
        let info = crate::scene::rope_block::info();
        let html = index_html3(info, &["x86_64-linux"]);
        assert!(
            html.contains("binary for <code>x86_64-linux</code>."),
            "{html}"
        );
        let view = View3::new(info).unwrap();
        for v in &view.vars {
            let shown = if v.is_array() {
                format!(
                    "<code>{}[{}]</code></td><td>{}</td>",
                    v.name,
                    v.ports.len(),
                    v.vr
                )
            } else {
                format!("<code>{}</code></td><td>{}</td>", v.name, v.vr)
            };
            assert!(html.contains(&shown), "{shown}");
        }
        assert!(html.contains("<code>contact_normal[8]</code>"));
        assert!(!html.contains("<code>contact3_normal</code>"));
        assert!(html.contains("fmi3DoStep") && !html.contains("fmi2DoStep"));
    }
}
