//! A minimal SVG line plot: one panel, several series on linear axes with ticks, a title and
//! axis labels, and the legend to the right of the data area on a canvas sized to hold it.
//!
//! Every series gets its own colour and dash pattern ([`super::plot_style`]); dense series are
//! thinned per half pixel column keeping each column's lowest and highest point, so no peak is
//! lost. The SVG marks its parts for checks ([`super::svg_check`]): the data area is the `rect`
//! of class `data` (with its axis ranges as `data-x0`, `data-x1`, `data-y0`, `data-y1`), the
//! curves are `polyline`s of class `series`, the legend is the `g` of class `legend`.
//! Lengths are px.

use super::plot_style::{axis_labels, envelope, escape, style, text_width};
use std::fmt::Write;

/// One curve: a name for the legend and its points (x, y) in increasing x.
pub struct Series<'a> {
    pub name: &'a str,
    pub points: Vec<(f64, f64)>,
}

/// Points drawn as rings over the curves (e.g. located peaks), with one legend entry.
pub struct Markers<'a> {
    pub name: &'a str,
    pub points: Vec<(f64, f64)>,
}

/// Font size of labels and legend [px]; of the title [px].
const FONT: f64 = 12.0;
const TITLE_FONT: f64 = 14.0;
/// Size of the data area [px].
const DATA_W: f64 = 640.0;
const DATA_H: f64 = 300.0;
/// Height of one legend row [px] and length of its line sample [px].
const ROW: f64 = 18.0;
const SAMPLE: f64 = 30.0;

/// "Nice" tick spacing for a range.
fn tick_step(span: f64) -> f64 {
    let raw = span / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let n = raw / mag;
    mag * if n < 1.5 {
        1.0
    } else if n < 3.5 {
        2.0
    } else if n < 7.5 {
        5.0
    } else {
        10.0
    }
}

/// Tick values and labels covering `[lo, hi]`.
fn ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    let step = tick_step(hi - lo);
    let mut out = Vec::new();
    let mut v = (lo / step).ceil() * step;
    while v <= hi + 1e-9 * step {
        // a tick at zero reached from below prints as -0: print it as 0
        let tick = if v.abs() < 1e-9 * step { 0.0 } else { v };
        let label = if step >= 1.0 {
            format!("{tick:.0}")
        } else {
            format!("{tick:.*}", (-step.log10().floor()) as usize)
        };
        out.push((tick, label));
        v += step;
    }
    out
}

/// Range `(lo, hi)` of the finite values, widened to a unit span when empty or flat.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi <= lo {
        return (lo, lo + 1.0);
    }
    (lo, hi)
}

/// An SVG document plotting `series` with a title, axis labels (in words, with units) and the
/// legend right of the data area.
pub fn line_plot(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> String {
    line_plot_marked(title, x_label, y_label, series, None)
}

/// [`line_plot`] with `markers` drawn as black rings over the curves and listed last in the
/// legend.
pub fn line_plot_marked(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: Option<&Markers>,
) -> String {
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let all = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .chain(markers.iter().flat_map(|m| m.points.iter()))
            .filter(finite)
    };
    let (x0, x1) = range(all().map(|p| p.0));
    let (y0, y1) = range(all().map(|p| p.1));
    let pad = 0.05 * (y1 - y0);
    let (y0, y1) = (y0 - pad, y1 + pad);
    let y_ticks = ticks(y0, y1);
    let tick_w = y_ticks
        .iter()
        .map(|(_, l)| text_width(l, FONT))
        .fold(0.0, f64::max);
    // margins: left holds the rotated y label and the tick labels, top the title
    let (l, t, b) = (40.0 + tick_w, 36.0, 50.0);
    let mut names: Vec<&str> = series.iter().map(|s| s.name).collect();
    names.extend(markers.map(|m| m.name));
    let legend_text = names
        .iter()
        .map(|n| text_width(n, FONT))
        .fold(0.0, f64::max);
    let (lx, lw) = (l + DATA_W + 16.0, 10.0 + SAMPLE + 8.0 + legend_text + 10.0);
    let lh = 8.0 + ROW * names.len() as f64;
    let w = (lx + lw + 10.0).max(text_width(title, TITLE_FONT) + 20.0);
    let h = t + DATA_H.max(lh) + b;
    let sx = |x: f64| l + (x - x0) / (x1 - x0) * DATA_W;
    let sy = |y: f64| t + DATA_H - (y - y0) / (y1 - y0) * DATA_H;
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="sans-serif" font-size="{FONT}"><rect width="100%" height="100%" fill="white"/>"#
    );
    let _ = write!(
        s,
        r#"<text x="{:.1}" y="22" text-anchor="middle" font-size="{TITLE_FONT}">{}</text>"#,
        w / 2.0,
        escape(title)
    );
    let bottom = t + DATA_H;
    for (v, label) in ticks(x0, x1) {
        let _ = write!(
            s,
            r##"<line x1="{0:.1}" y1="{t}" x2="{0:.1}" y2="{bottom}" stroke="#ddd"/><text x="{0:.1}" y="{1}" text-anchor="middle">{label}</text>"##,
            sx(v),
            bottom + 16.0
        );
    }
    for (v, label) in &y_ticks {
        let _ = write!(
            s,
            r##"<line x1="{l:.1}" y1="{0:.1}" x2="{1:.1}" y2="{0:.1}" stroke="#ddd"/><text x="{2:.1}" y="{3:.1}" text-anchor="end">{label}</text>"##,
            sy(*v),
            l + DATA_W,
            l - 6.0,
            sy(*v) + 4.0
        );
    }
    let _ = write!(
        s,
        r#"<rect class="data" x="{l:.1}" y="{t}" width="{DATA_W}" height="{DATA_H}" fill="none" stroke="black" data-x0="{x0:e}" data-x1="{x1:e}" data-y0="{y0:e}" data-y1="{y1:e}"/>"#
    );
    axis_labels(&mut s, (l, t, DATA_W, DATA_H), h, FONT, x_label, y_label);
    let bucket = 0.5 * (x1 - x0) / DATA_W;
    for (i, se) in series.iter().enumerate() {
        let pts: Vec<(f64, f64)> = se.points.iter().filter(finite).copied().collect();
        let path: Vec<String> = envelope(&pts, x0, bucket)
            .iter()
            .map(|p| format!("{:.1},{:.1}", sx(p.0), sy(p.1)))
            .collect();
        let _ = write!(
            s,
            r#"<polyline class="series" data-name="{}" fill="none" {} stroke-width="1.3" points="{}"/>"#,
            escape(se.name),
            style(i).stroke_attrs(),
            path.join(" ")
        );
    }
    if let Some(m) = markers {
        for p in m.points.iter().filter(finite) {
            let _ = write!(
                s,
                r#"<circle class="marker" cx="{:.1}" cy="{:.1}" r="4" fill="none" stroke="black" stroke-width="1.3"/>"#,
                sx(p.0),
                sy(p.1)
            );
        }
    }
    let _ = write!(
        s,
        r##"<g class="legend"><rect class="legend-box" x="{lx:.1}" y="{t}" width="{lw:.1}" height="{lh:.1}" fill="white" stroke="#999"/>"##
    );
    for (i, name) in names.iter().enumerate() {
        let y = t + 4.0 + ROW * (i as f64 + 0.5);
        let x = lx + 10.0;
        if i < series.len() {
            let _ = write!(
                s,
                r#"<line x1="{x:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" {} stroke-width="2"/>"#,
                x + SAMPLE,
                style(i).stroke_attrs()
            );
        } else {
            let _ = write!(
                s,
                r#"<circle cx="{:.1}" cy="{y:.1}" r="4" fill="none" stroke="black" stroke-width="1.3"/>"#,
                x + SAMPLE / 2.0
            );
        }
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
            x + SAMPLE + 8.0,
            y + 4.0,
            escape(name)
        );
    }
    s.push_str("</g></svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::svg_check::{check, parse};

    #[test]
    fn legend_outside_styles_distinct_and_the_spike_plotted() {
        let names: Vec<String> = (0..8).map(|k| format!("hinge {k} lock force")).collect();
        let series: Vec<Series> = names
            .iter()
            .enumerate()
            .map(|(k, n)| Series {
                name: n,
                points: (0..7000)
                    .map(|i| {
                        let t = 0.01 * i as f64;
                        (
                            t,
                            if i == 3000 + k {
                                16_259.6
                            } else {
                                (t + k as f64).sin()
                            },
                        )
                    })
                    .collect(),
            })
            .collect();
        let svg = line_plot_marked(
            "A title with <markup> & a long tail of words to widen it",
            "time [s]",
            "lock contact force [N]",
            &series,
            Some(&Markers {
                name: "located peak",
                points: vec![(30.0, 16_259.6)],
            }),
        );
        let plot = parse(&svg).unwrap();
        check(&plot).unwrap();
        assert_eq!(plot.series.len(), 8);
        for se in &plot.series {
            let top = se.points.iter().map(|p| p.1).fold(f64::MIN, f64::max);
            assert!((top - 16_259.6).abs() / 16_259.6 < 1e-3, "{top}");
        }
        assert!(svg.contains("&lt;markup&gt; &amp;"));
    }

    #[test]
    fn ticks_print_zero_without_sign() {
        let t = ticks(-1.0e-3, 2.0e-3);
        assert!(t.iter().any(|(v, l)| *v == 0.0 && !l.starts_with('-')));
    }
}
