//! A log-log SVG scatter plot for work-precision diagrams: several series of markers joined by
//! lines, failures drawn as crosses on the top edge, and one annotation per series (e.g. the
//! observed order).

use super::plot_style::{axis_labels, escape, style, text_width};
use std::fmt::Write;

/// One series: points `(x, y)` (both > 0), failed runs at `x` (drawn as crosses), a note.
pub struct LogSeries {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub failures: Vec<f64>,
    pub note: String,
}

/// Decade range `[10^lo, 10^hi]` covering `values` (finite and > 0).
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let (lo, hi) = (lo.floor(), hi.ceil());
    (lo, if hi > lo { hi } else { lo + 1.0 })
}

/// Size of the data area [px]; font sizes of labels, notes and the title [px]; legend row [px].
const DATA_W: f64 = 560.0;
const DATA_H: f64 = 340.0;
const FONT: f64 = 12.0;
const NOTE_FONT: f64 = 11.0;
const TITLE_FONT: f64 = 14.0;
const ROW: f64 = 32.0;
const SAMPLE: f64 = 30.0;

/// An SVG document: log10 axes with a grid line per decade, `series` as markers joined by lines
/// (own colour and dash each), failures as crosses along the top of the data area, and the
/// legend (name and note per series) right of the data area on a canvas sized to hold it. Marks
/// its parts as [`super::svg`] does (`data-scale="log"`, ranges in decades) for
/// [`super::svg_check`].
pub fn loglog_plot(title: &str, x_label: &str, y_label: &str, series: &[LogSeries]) -> String {
    let (x0, x1) = decades(series.iter().flat_map(|s| {
        s.points
            .iter()
            .map(|p| p.0)
            .chain(s.failures.iter().copied())
    }));
    let (y0, y1) = decades(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    let failed_note = "\u{d7} along the top: run failed";
    let legend_text = series
        .iter()
        .map(|s| text_width(&s.name, FONT).max(text_width(&s.note, NOTE_FONT)))
        .fold(text_width(failed_note, NOTE_FONT), f64::max);
    let (l, t, b) = (80.0, 36.0, 50.0);
    let (lx, lw) = (l + DATA_W + 16.0, 10.0 + SAMPLE + 8.0 + legend_text + 10.0);
    let lh = 8.0 + ROW * series.len() as f64 + 20.0;
    let w = (lx + lw + 10.0).max(text_width(title, TITLE_FONT) + 20.0);
    let h = t + DATA_H.max(lh) + b;
    let sx = |x: f64| l + (x.log10() - x0) / (x1 - x0) * DATA_W;
    let sy = |y: f64| t + DATA_H - (y.log10() - y0) / (y1 - y0) * DATA_H;
    let bottom = t + DATA_H;
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
    let mut d = x0;
    while d <= x1 + 1e-9 {
        let x = sx(10f64.powf(d));
        let _ = write!(
            s,
            r##"<line x1="{x:.1}" y1="{t}" x2="{x:.1}" y2="{bottom}" stroke="#ddd"/><text x="{x:.1}" y="{}" text-anchor="middle">1e{d:.0}</text>"##,
            bottom + 16.0
        );
        d += 1.0;
    }
    let mut d = y0;
    while d <= y1 + 1e-9 {
        let y = sy(10f64.powf(d));
        let _ = write!(
            s,
            r##"<line x1="{l}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">1e{d:.0}</text>"##,
            l + DATA_W,
            l - 6.0,
            y + 4.0
        );
        d += 1.0;
    }
    let _ = write!(
        s,
        r#"<rect class="data" x="{l}" y="{t}" width="{DATA_W}" height="{DATA_H}" fill="none" stroke="black" data-scale="log" data-x0="{x0}" data-x1="{x1}" data-y0="{y0}" data-y1="{y1}"/>"#
    );
    axis_labels(&mut s, (l, t, DATA_W, DATA_H), h, FONT, x_label, y_label);
    for (i, se) in series.iter().enumerate() {
        let st = style(i);
        let c = st.color;
        let pts: Vec<(f64, f64)> = se
            .points
            .iter()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
            .map(|p| (sx(p.0), sy(p.1)))
            .collect();
        let path: Vec<String> = pts
            .iter()
            .map(|p| format!("{:.1},{:.1}", p.0, p.1))
            .collect();
        let _ = write!(
            s,
            r#"<polyline class="series" data-name="{}" fill="none" {} stroke-width="1.3" points="{}"/>"#,
            escape(&se.name),
            st.stroke_attrs(),
            path.join(" ")
        );
        for (x, y) in &pts {
            let _ = write!(s, r#"<circle cx="{x:.1}" cy="{y:.1}" r="3" fill="{c}"/>"#);
        }
        for &f in se.failures.iter().filter(|f| f.is_finite() && **f > 0.0) {
            let (x, y) = (sx(f), t + 8.0);
            let _ = write!(
                s,
                r#"<path d="M{:.1},{:.1}L{:.1},{:.1}M{:.1},{:.1}L{:.1},{:.1}" stroke="{c}" stroke-width="2"/>"#,
                x - 4.0,
                y - 4.0,
                x + 4.0,
                y + 4.0,
                x - 4.0,
                y + 4.0,
                x + 4.0,
                y - 4.0
            );
        }
    }
    let _ = write!(
        s,
        r##"<g class="legend"><rect class="legend-box" x="{lx:.1}" y="{t}" width="{lw:.1}" height="{lh:.1}" fill="white" stroke="#999"/>"##
    );
    let tx = lx + 10.0 + SAMPLE + 8.0;
    for (i, se) in series.iter().enumerate() {
        let st = style(i);
        let y = t + 8.0 + ROW * i as f64 + 10.0;
        let _ = write!(
            s,
            r##"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" {} stroke-width="2"/><circle cx="{:.1}" cy="{y:.1}" r="3" fill="{}"/><text x="{tx:.1}" y="{:.1}">{}</text><text x="{tx:.1}" y="{:.1}" fill="#444" font-size="{NOTE_FONT}">{}</text>"##,
            lx + 10.0,
            lx + 10.0 + SAMPLE,
            st.stroke_attrs(),
            lx + 10.0 + SAMPLE / 2.0,
            st.color,
            y + 4.0,
            escape(&se.name),
            y + 17.0,
            escape(&se.note)
        );
    }
    let _ = write!(
        s,
        r##"<text x="{:.1}" y="{:.1}" fill="#444" font-size="{NOTE_FONT}">{}</text></g>"##,
        lx + 10.0,
        t + lh - 8.0,
        failed_note
    );
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_cover_the_data_and_markers_land_inside() {
        assert_eq!(decades([2e-5, 3e-2].into_iter()), (-5.0, -1.0));
        assert_eq!(decades([1.0].into_iter()), (0.0, 1.0));
        let svg = loglog_plot(
            "t <&>",
            "x",
            "y",
            &[LogSeries {
                name: "a".into(),
                points: vec![(1e-3, 1e-2), (1e-2, 1e-6)],
                failures: vec![1e-4],
                note: "order 4.0".into(),
            }],
        );
        assert!(svg.contains("t &lt;&amp;&gt;"));
        assert_eq!(svg.matches("<circle").count(), 3);
        assert!(svg.contains("order 4.0"));
        assert!(svg.contains("<path d=\"M"));
        crate::report::svg_check::check(&crate::report::svg_check::parse(&svg).unwrap()).unwrap();
    }
}
