//! What the SVG plots share: one style (colour and dash pattern) per series, neither repeated
//! within a plot of up to [`MAX_DISTINCT`] series; a text-width estimate to size the canvas
//! around titles and legends; XML escaping; and a peak-keeping thinning of dense series.
//!
//! All lengths are SVG user units (px at 96 dpi); font sizes are px.

/// Colour of a series: ten hues that stay apart in print and for the common colour-vision
/// deficiencies (no light yellow or grey on white).
const COLORS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2",
    "#000000", "#7a7a00",
];

/// SVG `stroke-dasharray` of a series ("" = solid), lengths in px.
const DASHES: [&str; 10] = [
    "",
    "7 3",
    "2 2",
    "9 3 2 3",
    "4 4",
    "12 3",
    "1 3",
    "7 2 2 2 2 2",
    "3 3 9 3",
    "14 4 2 4",
];

/// Series a plot can hold with every colour and every dash pattern distinct.
pub const MAX_DISTINCT: usize = COLORS.len();

/// Stroke colour and dash pattern of series `i` of a plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Style {
    pub color: &'static str,
    /// `stroke-dasharray` value; empty for a solid line.
    pub dash: &'static str,
}

impl Style {
    /// The `stroke` and (when dashed) `stroke-dasharray` attributes.
    pub fn stroke_attrs(&self) -> String {
        if self.dash.is_empty() {
            format!(r#"stroke="{}""#, self.color)
        } else {
            format!(
                r#"stroke="{}" stroke-dasharray="{}""#,
                self.color, self.dash
            )
        }
    }
}

/// Style of series `i`: colour and dash pattern `i mod 10`, so the first ten differ in both.
pub fn style(i: usize) -> Style {
    Style {
        color: COLORS[i % COLORS.len()],
        dash: DASHES[i % DASHES.len()],
    }
}

/// Upper estimate of the width [px] of `text` in a sans-serif font of `size` px: 0.62 em per
/// character (DejaVu Sans and Liberation Sans average below 0.6 em on labels like these).
pub fn text_width(text: &str, size: f64) -> f64 {
    0.62 * size * text.chars().count() as f64
}

/// Font size [px] at most `size` at which `text` fits in `room` px (by [`text_width`]).
pub fn fitting_size(text: &str, size: f64, room: f64) -> f64 {
    let w = text_width(text, size);
    if w <= room { size } else { size * room / w }
}

/// `s` with `&`, `<` and `>` escaped for SVG text and attributes.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Thins `points` (in increasing x) to at most four per bucket of `bucket` x units: the first,
/// the lowest, the highest and the last point of each bucket, in x order. The extremes are kept
/// exactly, so a plot drawn from the result shows every peak of the input at its true height.
pub fn envelope(points: &[(f64, f64)], x0: f64, bucket: f64) -> Vec<(f64, f64)> {
    if bucket.is_nan() || bucket <= 0.0 || points.len() < 8 {
        return points.to_vec();
    }
    let mut out = Vec::new();
    let mut i = 0;
    while i < points.len() {
        let key = ((points[i].0 - x0) / bucket).floor();
        let mut j = i;
        let (mut lo, mut hi) = (i, i);
        while j < points.len() && ((points[j].0 - x0) / bucket).floor() == key {
            if points[j].1 < points[lo].1 {
                lo = j;
            }
            if points[j].1 > points[hi].1 {
                hi = j;
            }
            j += 1;
        }
        let mut keep = [i, lo, hi, j - 1];
        keep.sort_unstable();
        let mut last = usize::MAX;
        for k in keep {
            if k != last {
                out.push(points[k]);
                last = k;
            }
        }
        i = j;
    }
    out
}

/// The two axis labels of a plot whose data area spans `left`..`left + width` and
/// `top`..`top + height` on a canvas `canvas_h` high [px], in font size `font` [px]: the x
/// label 38 px below the data area, the y label rotated, centred on the data area and shrunk
/// to stay on the canvas.
pub fn axis_labels(
    s: &mut String,
    (left, top, width, height): (f64, f64, f64, f64),
    canvas_h: f64,
    font: f64,
    x_label: &str,
    y_label: &str,
) {
    use std::fmt::Write;
    let _ = write!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + width / 2.0,
        top + height + 38.0,
        escape(x_label)
    );
    let mid = top + height / 2.0;
    let _ = write!(
        s,
        r#"<text x="16" y="{0:.1}" text-anchor="middle" font-size="{2:.1}" transform="rotate(-90 16 {0:.1})">{1}</text>"#,
        mid,
        escape(y_label),
        fitting_size(y_label, font, 2.0 * mid.min(canvas_h - mid) - 8.0)
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn styles_are_distinct_up_to_max_distinct() {
        let styles: Vec<Style> = (0..MAX_DISTINCT).map(style).collect();
        for a in 0..styles.len() {
            for b in a + 1..styles.len() {
                assert_ne!(styles[a].color, styles[b].color);
                assert_ne!(styles[a].dash, styles[b].dash);
            }
        }
        assert_eq!(style(0).stroke_attrs(), r##"stroke="#1f77b4""##);
        assert!(style(1).stroke_attrs().contains("stroke-dasharray"));
    }

    #[test]
    fn envelope_keeps_the_extremes_and_the_ends() {
        // a spike of one sample among 10,000 in one bucket survives the thinning
        let mut p: Vec<(f64, f64)> = (0..10_000).map(|i| (i as f64 * 1e-3, 0.0)).collect();
        p[5_432].1 = 16_259.6;
        p[7_000].1 = -3.0;
        let e = envelope(&p, 0.0, 0.1);
        assert!(e.len() <= 4 * 101);
        assert!(e.contains(&(5.432, 16_259.6)));
        assert!(e.contains(&(7.0, -3.0)));
        assert_eq!(e.first(), p.first());
        assert_eq!(e.last(), p.last());
        assert!(e.windows(2).all(|w| w[0].0 < w[1].0));
    }

    #[test]
    fn escape_covers_markup() {
        assert_eq!(escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
    }
}
