//! `documentation/index.html` of an FMU, generated from the variable table.
//!
//! Lists parameters (with variability, start value, limits and unit), inputs, outputs and
//! internal values, the FMI capabilities and the log categories, so the documentation can never
//! disagree with `modelDescription.xml`.

use std::fmt::Write;

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

fn table(out: &mut String, title: &str, ports: &[&PortSpec], with_start: bool) {
    if ports.is_empty() {
        return;
    }
    let _ = writeln!(out, "<h2>{}</h2>\n<table>", escape(title));
    let head = if with_start {
        "<th>start</th><th>range</th>"
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "<tr><th>name</th><th>type</th><th>variability</th>{head}<th>unit</th><th>description</th></tr>"
    );
    for p in ports {
        let extra = if with_start {
            format!(
                "<td>{}</td><td>{}</td>",
                escape(&start(p)),
                escape(&range(p))
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td>{extra}<td>{}</td><td>{}</td></tr>",
            escape(&p.name),
            escape(&type_name(p)),
            p.variability.name(),
            escape(unit(p)),
            escape(&p.description)
        );
    }
    out.push_str("</table>\n");
}

/// The HTML page for one model.
pub fn index_html(info: &ModelInfo) -> String {
    let of = |c: Causality| {
        info.ports
            .iter()
            .filter(|p| p.causality == c)
            .collect::<Vec<_>>()
    };
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
    table(&mut out, "Parameters", &of(Causality::Parameter), true);
    table(
        &mut out,
        "Calculated parameters",
        &of(Causality::CalculatedParameter),
        false,
    );
    table(&mut out, "Inputs", &of(Causality::Input), true);
    table(&mut out, "Outputs", &of(Causality::Output), false);
    table(&mut out, "Internal values", &of(Causality::Local), false);
    let _ = write!(
        out,
        "<h2>Usage and limits</h2>\n<ul>\n\
<li>FMI 2.0 Co-Simulation, GUID <code>{guid}</code>, binary for <code>linux64</code>.</li>\n\
<li>Fixed parameters can be set until <code>fmi2ExitInitializationMode</code>; tunable parameters and inputs also between steps. Values outside their range, NaN and infinities are refused with <code>fmi2Error</code>.</li>\n\
<li>Inputs are held constant over a communication step; outputs change only in <code>fmi2DoStep</code>. Variable step sizes are accepted; communication points are matched to the model time with a relative tolerance of 1e-9.</li>\n\
<li>FMU states can be saved, restored and serialized (also across processes); <code>fmi2Reset</code> is supported; instances are independent and may run on different threads.</li>\n\
<li>Default experiment: stop time {stop} s, step {step} s.</li>\n</ul>\n<h2>Log categories</h2>\n<ul>\n",
        guid = escape(info.guid),
        stop = fmt_real(info.default_stop_time),
        step = fmt_real(info.default_step)
    );
    for (_, name, desc) in CATEGORIES {
        let _ = writeln!(
            out,
            "<li><code>{}</code>: {}</li>",
            name.to_string_lossy(),
            escape(desc)
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
        let html = index_html(pid::info());
        for p in &pid::info().ports {
            assert!(
                html.contains(&format!("<code>{}</code>", p.name)),
                "{}",
                p.name
            );
        }
        assert!(html.contains("<h2>Outputs</h2>") && html.contains("1/s"));
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
