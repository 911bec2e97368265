//! A log-log SVG scatter plot for work-precision diagrams: several series of markers joined by
//! lines, failures drawn as crosses on the top edge, and one annotation per series (e.g. the
//! observed order).

use std::fmt::Write;

/// One series: points `(x, y)` (both > 0), failed runs at `x` (drawn as crosses), a note.
pub struct LogSeries {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub failures: Vec<f64>,
    pub note: String,
}

const COLORS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2",
];

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

/// An SVG document (820 x 420 px): log10 axes with a grid line per decade, `series` as markers
/// and lines, failures as crosses at the top, the notes in the legend.
pub fn loglog_plot(title: &str, x_label: &str, y_label: &str, series: &[LogSeries]) -> String {
    let (w, h, l, r, t, b) = (820.0, 420.0, 70.0, 230.0, 30.0, 45.0);
    let (x0, x1) = decades(series.iter().flat_map(|s| {
        s.points
            .iter()
            .map(|p| p.0)
            .chain(s.failures.iter().copied())
    }));
    let (y0, y1) = decades(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    let sx = |x: f64| l + (x.log10() - x0) / (x1 - x0) * (w - l - r);
    let sy = |y: f64| h - b - (y.log10() - y0) / (y1 - y0) * (h - t - b);
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/>"#
    );
    let _ = write!(
        s,
        r#"<text x="{}" y="18" text-anchor="middle" font-size="14">{}</text>"#,
        (l + w - r) / 2.0,
        escape(title)
    );
    let _ = write!(
        s,
        r#"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="black"/>"#,
        w - l - r,
        h - t - b
    );
    let mut d = x0;
    while d <= x1 + 1e-9 {
        let x = sx(10f64.powf(d));
        let _ = write!(
            s,
            r##"<line x1="{x:.1}" y1="{t}" x2="{x:.1}" y2="{}" stroke="#ddd"/><text x="{x:.1}" y="{}" text-anchor="middle">1e{d:.0}</text>"##,
            h - b,
            h - b + 16.0
        );
        d += 1.0;
    }
    let mut d = y0;
    while d <= y1 + 1e-9 {
        let y = sy(10f64.powf(d));
        let _ = write!(
            s,
            r##"<line x1="{l}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">1e{d:.0}</text>"##,
            w - r,
            l - 6.0,
            y + 4.0
        );
        d += 1.0;
    }
    let _ = write!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        (l + w - r) / 2.0,
        h - 8.0,
        escape(x_label)
    );
    let _ = write!(
        s,
        r#"<text x="16" y="{0}" text-anchor="middle" transform="rotate(-90 16 {0})">{1}</text>"#,
        (t + h - b) / 2.0,
        escape(y_label)
    );
    for (i, se) in series.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
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
            r#"<polyline fill="none" stroke="{c}" stroke-width="1.2" points="{}"/>"#,
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
        let ly = t + 14.0 + 30.0 * i as f64;
        let _ = write!(
            s,
            r##"<circle cx="{}" cy="{}" r="4" fill="{c}"/><text x="{}" y="{}" fill="{c}">{}</text><text x="{}" y="{}" fill="#444" font-size="11">{}</text>"##,
            w - r + 14.0,
            ly - 4.0,
            w - r + 24.0,
            ly,
            escape(&se.name),
            w - r + 24.0,
            ly + 13.0,
            escape(&se.note)
        );
    }
    let _ = write!(
        s,
        r##"<text x="{}" y="{}" fill="#444" font-size="11">x on top: run failed</text>"##,
        w - r + 14.0,
        h - b
    );
    s.push_str("</svg>\n");
    s
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
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
    }
}
