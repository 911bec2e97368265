//! Checks of a plot written by [`super::svg`] or [`super::loglog`], read back from its SVG text:
//! the legend lies outside the data area and holds all its text, covers no mark (the rings of
//! located peaks and linearized frequencies) and no label, every curve stays inside the data
//! area, no two curves share a colour or a dash pattern, and no text runs off the canvas.
//! Text extents use the same width estimate as the layout
//! ([`super::plot_style::text_width`]). Lengths are px.
//!
//! Plots drawn by matplotlib (tools/mbstudy) cannot be read back this way; they carry their
//! layout as measured by matplotlib's renderer in a `<g class="layout">` group of empty `rect`s
//! (`axes`, `legend-box`, `mark`, `label`), which [`parse_layout`] reads and [`check_layout`]
//! checks: no legend over a mark or a label, all of them on the canvas.

use super::plot_style::text_width;
use quick_xml::XmlVersion;
use quick_xml::events::{BytesStart, Event};
use quick_xml::reader::Reader;

/// An axis-aligned box [px]: left, top, right, bottom.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Bounds {
    fn inside(&self, o: &Bounds, tol: f64) -> bool {
        self.x0 >= o.x0 - tol
            && self.x1 <= o.x1 + tol
            && self.y0 >= o.y0 - tol
            && self.y1 <= o.y1 + tol
    }
    fn overlaps(&self, o: &Bounds) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
}

/// One curve read back: its legend name, stroke colour, dash pattern, pixel points and the
/// same points in data coordinates (log axes give log10-free values, i.e. the data itself).
#[derive(Debug, Clone)]
pub struct PlotSeries {
    pub name: String,
    pub color: String,
    pub dash: String,
    pub pixels: Vec<(f64, f64)>,
    pub points: Vec<(f64, f64)>,
}

/// One text element: its content, estimated box and whether it sits in the legend.
#[derive(Debug, Clone)]
pub struct PlotText {
    pub text: String,
    pub bounds: Bounds,
    pub in_legend: bool,
}

/// A plot read back from its SVG.
#[derive(Debug, Clone)]
pub struct Plot {
    pub canvas: Bounds,
    pub data: Bounds,
    pub legend: Bounds,
    pub series: Vec<PlotSeries>,
    pub texts: Vec<PlotText>,
    /// Boxes of the marks drawn over the curves (`circle class="marker"`).
    pub marks: Vec<Bounds>,
}

fn attr(e: &BytesStart, name: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == name)
        .and_then(|a| a.normalized_value(XmlVersion::Implicit1_0).ok())
        .map(|v| v.into_owned())
}

fn num(e: &BytesStart, name: &str) -> Result<f64, String> {
    attr(e, name)
        .ok_or(format!("no attribute {name}"))?
        .parse()
        .map_err(|_| format!("attribute {name} is not a number"))
}

fn rect_bounds(e: &BytesStart) -> Result<Bounds, String> {
    let (x, y) = (num(e, "x")?, num(e, "y")?);
    Ok(Bounds {
        x0: x,
        y0: y,
        x1: x + num(e, "width")?,
        y1: y + num(e, "height")?,
    })
}

/// An open `<text>`: position, anchor, font size, rotation and whether inside the legend.
struct OpenText {
    x: f64,
    y: f64,
    anchor: String,
    size: f64,
    rotated: bool,
    in_legend: bool,
    text: String,
}

impl OpenText {
    /// Estimated box: glyphs rise 0.8 em above the baseline and drop 0.25 em below it; a text
    /// rotated by -90 degrees about its anchor point turns that box on its side.
    fn bounds(&self) -> Bounds {
        let w = text_width(&self.text, self.size);
        let start = match self.anchor.as_str() {
            "middle" => -0.5 * w,
            "end" => -w,
            _ => 0.0,
        };
        if self.rotated {
            Bounds {
                x0: self.x - 0.8 * self.size,
                x1: self.x + 0.25 * self.size,
                y0: self.y - start - w,
                y1: self.y - start,
            }
        } else {
            Bounds {
                x0: self.x + start,
                x1: self.x + start + w,
                y0: self.y - 0.8 * self.size,
                y1: self.y + 0.25 * self.size,
            }
        }
    }
}

/// Data coordinate of pixel `p` on an axis from pixel `a` (value `v0`) to pixel `b` (`v1`).
fn invert(p: f64, a: f64, b: f64, v0: f64, v1: f64, log: bool) -> f64 {
    let v = v0 + (p - a) / (b - a) * (v1 - v0);
    if log { 10f64.powf(v) } else { v }
}

/// Reads the plot back from `svg`.
pub fn parse(svg: &str) -> Result<Plot, String> {
    let mut reader = Reader::from_str(svg);
    let (mut canvas, mut data, mut legend) = (None, None, None);
    let mut ranges = (0.0, 1.0, 0.0, 1.0, false);
    let mut raw_series = Vec::new();
    let mut texts = Vec::new();
    let mut marks = Vec::new();
    let mut open: Option<OpenText> = None;
    let (mut font, mut legend_depth, mut depth) = (12.0, None, 0usize);
    loop {
        let ev = reader.read_event().map_err(|e| e.to_string())?;
        let (e, empty) = match &ev {
            Event::Start(e) => (Some(e.clone()), false),
            Event::Empty(e) => (Some(e.clone()), true),
            Event::Text(t) => {
                if let Some(o) = open.as_mut() {
                    o.text.push_str(&t.xml10_content());
                }
                (None, false)
            }
            Event::GeneralRef(_) => {
                // an entity (&amp; and the like) is one character
                if let Some(o) = open.as_mut() {
                    o.text.push('?');
                }
                (None, false)
            }
            Event::End(end) => {
                if end.name().as_ref() == "text"
                    && let Some(o) = open.take()
                {
                    texts.push(PlotText {
                        bounds: o.bounds(),
                        in_legend: o.in_legend,
                        text: o.text,
                    });
                }
                if legend_depth == Some(depth) {
                    legend_depth = None;
                }
                depth = depth.saturating_sub(1);
                (None, false)
            }
            Event::Eof => break,
            _ => (None, false),
        };
        let Some(e) = e else { continue };
        if !empty {
            depth += 1;
        }
        let class = attr(&e, "class").unwrap_or_default();
        match e.name().as_ref() {
            "svg" => {
                canvas = Some(Bounds {
                    x0: 0.0,
                    y0: 0.0,
                    x1: num(&e, "width")?,
                    y1: num(&e, "height")?,
                });
                font = num(&e, "font-size").unwrap_or(12.0);
            }
            "g" if class == "legend" && !empty => legend_depth = Some(depth),
            "rect" if class == "data" => {
                data = Some(rect_bounds(&e)?);
                ranges = (
                    num(&e, "data-x0")?,
                    num(&e, "data-x1")?,
                    num(&e, "data-y0")?,
                    num(&e, "data-y1")?,
                    attr(&e, "data-scale").as_deref() == Some("log"),
                );
            }
            "rect" if class == "legend-box" => legend = Some(rect_bounds(&e)?),
            "circle" if class == "marker" => {
                let (x, y, r) = (num(&e, "cx")?, num(&e, "cy")?, num(&e, "r")?);
                marks.push(Bounds {
                    x0: x - r,
                    y0: y - r,
                    x1: x + r,
                    y1: y + r,
                });
            }
            "polyline" if class == "series" => {
                let pixels: Result<Vec<(f64, f64)>, String> = attr(&e, "points")
                    .unwrap_or_default()
                    .split_whitespace()
                    .map(|p| {
                        let (x, y) = p.split_once(',').ok_or("bad point")?;
                        Ok((
                            x.parse().map_err(|_| "bad x")?,
                            y.parse().map_err(|_| "bad y")?,
                        ))
                    })
                    .collect();
                raw_series.push((
                    attr(&e, "data-name").unwrap_or_default(),
                    attr(&e, "stroke").unwrap_or_default(),
                    attr(&e, "stroke-dasharray").unwrap_or_default(),
                    pixels?,
                ));
            }
            "text" if !empty => {
                open = Some(OpenText {
                    x: num(&e, "x")?,
                    y: num(&e, "y")?,
                    anchor: attr(&e, "text-anchor").unwrap_or_default(),
                    size: num(&e, "font-size").unwrap_or(font),
                    rotated: attr(&e, "transform").is_some_and(|t| t.starts_with("rotate(-90")),
                    in_legend: legend_depth.is_some(),
                    text: String::new(),
                });
            }
            _ => {}
        }
    }
    let data = data.ok_or("no data area (rect of class data)")?;
    let (x0, x1, y0, y1, log) = ranges;
    let series = raw_series
        .into_iter()
        .map(|(name, color, dash, pixels)| PlotSeries {
            points: pixels
                .iter()
                .map(|&(px, py)| {
                    (
                        invert(px, data.x0, data.x1, x0, x1, log),
                        invert(py, data.y1, data.y0, y0, y1, log),
                    )
                })
                .collect(),
            name,
            color,
            dash,
            pixels,
        })
        .collect();
    Ok(Plot {
        canvas: canvas.ok_or("no svg element")?,
        data,
        legend: legend.ok_or("no legend box (rect of class legend-box)")?,
        series,
        texts,
        marks,
    })
}

/// Checks the layout rules of the module doc; the first broken rule is the error.
pub fn check(p: &Plot) -> Result<(), String> {
    if p.legend.overlaps(&p.data) {
        return Err(format!(
            "legend {:?} overlaps the data area {:?}",
            p.legend, p.data
        ));
    }
    if !p.legend.inside(&p.canvas, 0.0) {
        return Err(format!(
            "legend {:?} is cut off by the canvas {:?}",
            p.legend, p.canvas
        ));
    }
    for (i, s) in p.series.iter().enumerate() {
        let pt = |b: &(f64, f64)| Bounds {
            x0: b.0,
            y0: b.1,
            x1: b.0,
            y1: b.1,
        };
        if let Some(q) = s.pixels.iter().find(|q| !pt(q).inside(&p.data, 0.6)) {
            return Err(format!("curve {:?} leaves the data area at {q:?}", s.name));
        }
        for o in &p.series[..i] {
            if o.color == s.color {
                return Err(format!(
                    "curves {:?} and {:?} share colour {}",
                    o.name, s.name, s.color
                ));
            }
            if o.dash == s.dash {
                return Err(format!(
                    "curves {:?} and {:?} share dash pattern {:?}",
                    o.name, s.name, s.dash
                ));
            }
        }
    }
    for t in &p.texts {
        if !t.bounds.inside(&p.canvas, 0.5) {
            return Err(format!(
                "text {:?} runs off the canvas: {:?}",
                t.text, t.bounds
            ));
        }
        if t.in_legend && !t.bounds.inside(&p.legend, 0.5) {
            return Err(format!(
                "legend text {:?} runs out of the legend box",
                t.text
            ));
        }
        if !t.in_legend && t.bounds.overlaps(&p.legend) {
            return Err(format!("text {:?} overlaps the legend", t.text));
        }
    }
    if let Some(m) = p.marks.iter().find(|m| m.overlaps(&p.legend)) {
        return Err(format!("the legend covers the mark at {m:?}"));
    }
    let legend_texts = p.texts.iter().filter(|t| t.in_legend).count();
    if legend_texts < p.series.len() {
        return Err(format!(
            "{} curves but {legend_texts} legend entries",
            p.series.len()
        ));
    }
    Ok(())
}

/// The layout of a matplotlib plot as its renderer measured it (see the module doc) [px of the
/// SVG's own units].
#[derive(Debug, Clone)]
pub struct Layout {
    pub canvas: Bounds,
    pub axes: Vec<Bounds>,
    pub legends: Vec<Bounds>,
    pub marks: Vec<Bounds>,
    pub labels: Vec<Bounds>,
}

/// A length attribute in SVG units (`504pt` and `504` alike: matplotlib's `viewBox` is in pt).
fn length(e: &BytesStart, name: &str) -> Result<f64, String> {
    let v = attr(e, name).ok_or(format!("no attribute {name}"))?;
    v.trim_end_matches("pt")
        .parse()
        .map_err(|_| format!("attribute {name} = {v:?} is not a length"))
}

/// Reads the `<g class="layout">` group of a matplotlib plot; fails when there is none (a plot
/// the checks cannot read).
pub fn parse_layout(svg: &str) -> Result<Layout, String> {
    let mut reader = Reader::from_str(svg);
    let mut canvas = None;
    let mut found = false;
    let (mut axes, mut legends, mut marks, mut labels) = (vec![], vec![], vec![], vec![]);
    loop {
        let ev = reader.read_event().map_err(|e| e.to_string())?;
        let e = match &ev {
            Event::Start(e) | Event::Empty(e) => e.clone(),
            Event::Eof => break,
            _ => continue,
        };
        let class = attr(&e, "class").unwrap_or_default();
        match (e.name().as_ref(), class.as_str()) {
            ("svg", _) if canvas.is_none() => {
                canvas = Some(Bounds {
                    x0: 0.0,
                    y0: 0.0,
                    x1: length(&e, "width")?,
                    y1: length(&e, "height")?,
                });
            }
            ("g", "layout") => found = true,
            ("rect", "axes") => axes.push(rect_bounds(&e)?),
            ("rect", "legend-box") => legends.push(rect_bounds(&e)?),
            ("rect", "mark") => marks.push(rect_bounds(&e)?),
            ("rect", "label") => labels.push(rect_bounds(&e)?),
            _ => {}
        }
    }
    if !found {
        return Err(
            "no layout group (g class=\"layout\"): a plot the checks cannot read".to_string(),
        );
    }
    Ok(Layout {
        canvas: canvas.ok_or("no svg element")?,
        axes,
        legends,
        marks,
        labels,
    })
}

/// Checks a matplotlib plot's layout: no legend covers a mark or a label, and the axes, legends,
/// marks and labels lie on the canvas.
pub fn check_layout(l: &Layout) -> Result<(), String> {
    if l.axes.is_empty() {
        return Err("the layout has no axes".into());
    }
    for (what, boxes) in [
        ("axes", &l.axes),
        ("legend", &l.legends),
        ("mark", &l.marks),
        ("label", &l.labels),
    ] {
        if let Some(b) = boxes.iter().find(|b| !b.inside(&l.canvas, 0.5)) {
            return Err(format!("{what} {b:?} runs off the canvas {:?}", l.canvas));
        }
    }
    for g in &l.legends {
        if let Some(m) = l.marks.iter().find(|m| m.overlaps(g)) {
            return Err(format!("the legend {g:?} covers the mark at {m:?}"));
        }
        if let Some(t) = l.labels.iter().find(|t| t.overlaps(g)) {
            return Err(format!("the legend {g:?} covers the label at {t:?}"));
        }
    }
    Ok(())
}

/// Checks a plot the project writes, whichever way it was drawn: [`check`] for our own SVGs (a
/// `rect class="data"`), [`check_layout`] for matplotlib's.
pub fn check_any(svg: &str) -> Result<(), String> {
    if svg.contains(r#"class="data""#) {
        check(&parse(svg)?)
    } else {
        check_layout(&parse_layout(svg)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r##"<svg width="300" height="200" font-size="12"><rect class="data" x="40" y="20" width="150" height="150" data-x0="0" data-x1="10" data-y0="0" data-y1="100"/><polyline class="series" data-name="a" stroke="#111" points="40,170 190,20"/><polyline class="series" data-name="b" stroke="#222" stroke-dasharray="2 2" points="40,20 190,170"/><g class="legend"><rect class="legend-box" x="200" y="20" width="90" height="44"/><text x="210" y="36">a</text><text x="210" y="54">b</text></g></svg>"##;

    #[test]
    fn a_good_plot_passes_and_reads_back_its_data() {
        let p = parse(GOOD).unwrap();
        check(&p).unwrap();
        assert_eq!(p.series[0].points, vec![(0.0, 0.0), (10.0, 100.0)]);
        assert_eq!(p.series[1].dash, "2 2");
    }

    #[test]
    fn each_broken_rule_is_caught() {
        for (from, to, what) in [
            (
                r#"x="200" y="20" width="90""#,
                r#"x="150" y="20" width="90""#,
                "overlaps the data",
            ),
            (
                r#"width="90" height="44""#,
                r#"width="190" height="44""#,
                "cut off",
            ),
            ("#222", "#111", "share colour"),
            (r#" stroke-dasharray="2 2""#, "", "share dash"),
            ("190,170", "250,170", "leaves the data area"),
            (">b</text>", ">a long entry</text>", "out of the legend box"),
            (r#"<text x="210" y="54">b</text>"#, "", "legend entries"),
            (
                "</g></svg>",
                r#"</g><circle class="marker" cx="198" cy="30" r="4"/></svg>"#,
                "covers the mark",
            ),
        ] {
            let bad = GOOD.replacen(from, to, 1);
            let Err(err) = check(&parse(&bad).unwrap()) else {
                panic!("{what}: not caught");
            };
            assert!(err.contains(what), "{what}: {err}");
        }
    }

    const LAYOUT: &str = r#"<svg width="504pt" height="324pt" viewBox="0 0 504 324"><path d="M0 0"/><g class="layout"><rect class="axes" x="50" y="30" width="300" height="250"/><rect class="legend-box" x="360" y="30" width="120" height="60"/><rect class="mark" x="300" y="200" width="12" height="12"/><rect class="label" x="310" y="210" width="30" height="10"/></g></svg>"#;

    #[test]
    fn a_matplotlib_layout_passes_and_each_broken_rule_is_caught() {
        check_any(LAYOUT).unwrap();
        for (from, to, what) in [
            (
                r#"class="mark" x="300" y="200""#,
                r#"class="mark" x="365" y="40""#,
                "covers the mark",
            ),
            (
                r#"class="label" x="310" y="210""#,
                r#"class="label" x="400" y="50""#,
                "covers the label",
            ),
            (r#"width="120""#, r#"width="160""#, "runs off the canvas"),
            (r#"<g class="layout">"#, "<g>", "no layout group"),
        ] {
            let bad = LAYOUT.replacen(from, to, 1);
            let Err(err) = check_any(&bad) else {
                panic!("{what}: not caught");
            };
            assert!(err.contains(what), "{what}: {err}");
        }
    }
}
