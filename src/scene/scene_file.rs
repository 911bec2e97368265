//! Scene files: a model's parameters as data, so a variant needs no recompiling.
//!
//! A scene file is a TOML document (TOML 1.1, read by the `toml` crate), read when an FMU is
//! instantiated (`resources/scene.toml` inside the FMU) and by `mbcosim simulate --scene FILE`:
//!
//! ```toml
//! # comments run to the end of the line
//! model = "PanelLock"          # optional; when present it must name the model
//!
//! [parameters]
//! n_panels = 3                 # integers (also 0x1F, 0o17, 0b11, 1_000)
//! contact_stiffness = 1.0e7    # reals (an integer literal is accepted for a real)
//! latches = true               # booleans
//! integrator = "bdf"           # enumerations: item name, any case (or its number)
//! "some.dotted[name]" = 0.5    # names outside [A-Za-z0-9_-] are quoted
//! ```
//!
//! Any TOML syntax is read: basic and literal strings with all their escapes, multi-line
//! strings, `_` between digits, `parameters = { .. }` or `parameters.name = ..` for the table.
//! A RopeBlock scene may also describe its rig in the tables `[block]`, `[[lug]]`, `[[sling]]`,
//! `[[hook]]`, a PanelLock scene its array in `[[hinge]]` and `[[panel]]` ([`TABLES`]; arrays of
//! numbers allowed there), read by the model ([`CoSimModel::set_tables`],
//! `docs/rope_block_rig.md`, `docs/panel_lock_array.md`).
//! What is not a parameter value is refused with the file and line: arrays, inline tables and
//! date-times as values, other tables (`[settings]`, `[parameters.sub]`, `[[parameters]]`),
//! keys other than `model` outside `[parameters]`, and dotted keys inside it (`a.b = 1` is a
//! table `a` in TOML: a name that holds `.` is quoted, `"a.b" = 1`).
//!
//! Every key of `[parameters]` is a parameter of the model's variable table (the names in
//! `modelDescription.xml`); units are those of the table (SI). Unknown names, outputs, wrong types,
//! out-of-range values, NaN/Inf (`nan`, `inf`, `+inf`, and reals that overflow as `1e999`),
//! integers beyond 64 bits and duplicate keys are refused with the file and line; TOML syntax
//! errors keep the crate's wording, with the file, line and column. The default scene of each
//! model is rendered from its variable table by [`render`] (the files under `resources/scenes/`
//! of the repository, checked against the table by a test), so the defaults exist once, in the
//! table.

use toml::Spanned;
use toml::de::{DeString, DeTable, DeValue};

use super::CoSimModel;
use super::port::{Causality, ModelInfo, PortSpec, PortType};
use crate::bounded_file::{self, FileKind};

/// Name of the scene file inside an FMU's `resources/` folder.
pub const FMU_SCENE: &str = "scene.toml";

/// Largest scene file read: the default scenes are 3-7 kB and a rig of 64 slings about 20 kB;
/// 4 MiB leaves room for comments and generated files, and parses in well under a second
/// (docs/bounded_inputs.md).
pub const SCENE_FILE_BYTES: u64 = 4 * 1024 * 1024;

/// A scene file, for [`bounded_file`].
pub const SCENE_FILE: FileKind = FileKind {
    what: "scene file",
    max_bytes: SCENE_FILE_BYTES,
    cap_name: "SCENE_FILE_BYTES",
};

/// Most keys and array values a scene file may hold, counted over every table: a model has at
/// most a few hundred parameters and a rig of 64 slings some 1,000 keys (docs/bounded_inputs.md).
pub const MAX_SCENE_KEYS: usize = 10_000;

/// Most tables (`[block]`, each `[[lug]]`, `[[sling]]`, ...) a scene file may hold: a rig has at
/// most 4 hooks, 64 slings and 256 lugs, a panel array 6 panels and 7 hinges.
pub const MAX_SCENE_TABLES: usize = 1_000;

/// A value written in a scene file.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneValue {
    /// An integer literal.
    Integer(i64),
    /// A floating-point literal.
    Real(f64),
    /// `true` or `false`.
    Boolean(bool),
    /// A basic string.
    String(String),
    /// An array of numbers (only in the tables of [`TABLES`]: positions, an inertia tensor).
    Reals(Vec<f64>),
}

/// Tables a scene file may hold besides `[parameters]`: a RopeBlock rig, as `[block]` and the
/// arrays of tables `[[lug]]`, `[[sling]]`, `[[hook]]` (see `docs/rope_block_rig.md`), and a
/// PanelLock array, `[[hinge]]` and `[[panel]]` (`docs/panel_lock_array.md`). Which of them a
/// model takes is the model's to say: [`CoSimModel::set_tables`] reads their keys and refuses
/// the tables of another model (a model without tables refuses them all).
pub const TABLES: [&str; 6] = ["block", "lug", "sling", "hook", "hinge", "panel"];

/// One `[name]` table or one `[[name]]` element of a scene file (a name of [`TABLES`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneTable {
    /// Table name (`block`, `lug`, ...).
    pub name: String,
    /// Position in its array of tables (0 for a plain table).
    pub index: usize,
    /// Line of the header (1-based), for messages.
    pub line: usize,
    /// Its `key = value` lines in file order.
    pub entries: Vec<SceneEntry>,
}

/// One `name = value` line of the `[parameters]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneEntry {
    /// Variable name.
    pub name: String,
    /// Value as written.
    pub value: SceneValue,
    /// Line number (1-based), for messages.
    pub line: usize,
}

/// A parsed scene file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneFile {
    /// The `model` key, when given.
    pub model: Option<String>,
    /// The line of the `model` key (0 when it is absent), for messages.
    pub model_line: usize,
    /// The parameter values in file order.
    pub entries: Vec<SceneEntry>,
    /// The tables of [`TABLES`] in file order.
    pub tables: Vec<SceneTable>,
}

/// Parses `text`; `origin` (a file name) prefixes every message.
///
/// The text is read by the `toml` crate into its spanned document tree (every key and value
/// keeps its byte range), which gives each message its line. TOML syntax errors come first, with
/// the crate's wording; then the document is checked against the scene layout, in file order.
/// No input makes this panic: it runs inside `fmi2Instantiate`.
pub fn parse(text: &str, origin: &str) -> Result<SceneFile, String> {
    let src = Source::new(text, origin);
    if text.len() as u64 > SCENE_FILE_BYTES {
        return Err(format!(
            "{origin}: the scene has {} bytes, over the cap of {} on a scene file (SCENE_FILE_BYTES; docs/bounded_inputs.md)",
            text.len(),
            bounded_file::human_bytes(SCENE_FILE_BYTES)
        ));
    }
    check_lexical_counts(text, origin)?;
    let (doc, errors) = DeTable::parse_recoverable(text);
    if !errors.is_empty() {
        return Err(src.syntax_error(doc.get_ref(), &errors));
    }
    check_counts(doc.get_ref(), origin)?;
    let mut file = SceneFile::default();
    for (key, value) in in_file_order(doc.get_ref()) {
        let pos = key.span().start;
        match key.get_ref().as_ref() {
            "model" => match value.get_ref() {
                DeValue::String(m) => {
                    file.model = Some(m.to_string());
                    file.model_line = src.line(pos);
                }
                _ => return Err(src.at(pos, "`model` must be given once, as a string")),
            },
            "parameters" => match value.get_ref() {
                // `[parameters]`, `parameters = { .. }` and `parameters.name = ..` are one table
                DeValue::Table(table) => {
                    for (k, v) in in_file_order(table) {
                        file.entries.push(src.entry(k, v)?);
                    }
                }
                DeValue::Array(_) if form(key, value) == Form::Header => {
                    return Err(src.at(
                        pos,
                        "`[[parameters]]` is an array of tables: a scene file has one `[parameters]` table",
                    ));
                }
                other => {
                    return Err(src.at(
                        pos,
                        format!(
                            "`parameters` must be the table `[parameters]`, not {}",
                            a_type(other)
                        ),
                    ));
                }
            },
            name if TABLES.contains(&name) => {
                let tables: Vec<&Val<'_>> = match (value.get_ref(), form(key, value)) {
                    (DeValue::Table(_), Form::Header) => vec![value],
                    (DeValue::Array(a), Form::Header) => a.iter().collect(),
                    _ => {
                        return Err(src.at(
                            pos,
                            format!("`{name}` must be written as a table header (`[{name}]` or `[[{name}]]`)"),
                        ));
                    }
                };
                for (index, t) in tables.into_iter().enumerate() {
                    let DeValue::Table(table) = t.get_ref() else {
                        return Err(
                            src.at(t.span().start, format!("`[[{name}]]` must hold tables"))
                        );
                    };
                    let mut entries = Vec::new();
                    for (k, v) in in_file_order(table) {
                        entries.push(src.table_entry(name, k, v)?);
                    }
                    file.tables.push(SceneTable {
                        name: name.to_string(),
                        index,
                        line: src.line(t.span().start),
                        entries,
                    });
                }
            }
            name => return Err(src.outside(name, key, value)),
        }
    }
    file.tables.sort_by_key(|t| t.line);
    Ok(file)
}

/// The caps of [`check_counts`] on upper bounds read from the text before the TOML parse, so
/// that a file under the byte cap cannot make the parser build a large tree (100,000 `[[lug]]`
/// tables in 3.7 MB grew the resident memory by 230 MB before the counts refused them). Every
/// table header is a line starting with `[` and every key or array value needs a `=` or a `,`
/// (the last value of an array aside); lines of multi-line arrays and characters inside strings
/// are counted too, so these bounds only over-count, by at most one value per array.
fn check_lexical_counts(text: &str, origin: &str) -> Result<(), String> {
    let headers = text
        .lines()
        .filter(|l| {
            let l = l.trim_start();
            l.starts_with('[')
                && !l.contains(',')
                && !l.contains('=')
                && l.trim_end().ends_with(']')
        })
        .count();
    if headers > MAX_SCENE_TABLES {
        return Err(format!(
            "{origin}: the scene has {headers} table headers, over the cap of {MAX_SCENE_TABLES} tables in a scene file (MAX_SCENE_TABLES; docs/bounded_inputs.md)"
        ));
    }
    let separators = text.bytes().filter(|b| matches!(b, b'=' | b',')).count();
    if separators > 2 * MAX_SCENE_KEYS {
        return Err(format!(
            "{origin}: the scene has {separators} `=` and `,`, more than {} keys and array values can need, over the cap of {MAX_SCENE_KEYS} in a scene file (MAX_SCENE_KEYS; docs/bounded_inputs.md)",
            2 * MAX_SCENE_KEYS
        ));
    }
    Ok(())
}

/// `Err` naming the cap when `doc` holds more tables than [`MAX_SCENE_TABLES`] or more keys
/// (array values included) than [`MAX_SCENE_KEYS`]; counted before anything else
/// looks at the keys, so the work after the TOML parse is bounded.
fn check_counts(doc: &DeTable<'_>, origin: &str) -> Result<(), String> {
    let (mut keys, mut tables) = (doc.len(), 0usize);
    let mut stack: Vec<&DeValue<'_>> = doc.values().map(|v| v.get_ref()).collect();
    while let Some(v) = stack.pop() {
        match v {
            DeValue::Table(t) => {
                tables += 1;
                keys += t.len();
                stack.extend(t.values().map(|v| v.get_ref()));
            }
            DeValue::Array(a) => {
                keys += a.len();
                stack.extend(a.iter().map(|v| v.get_ref()));
            }
            _ => {}
        }
    }
    if tables > MAX_SCENE_TABLES {
        return Err(format!(
            "{origin}: the scene has {tables} tables, over the cap of {MAX_SCENE_TABLES} in a scene file (MAX_SCENE_TABLES; docs/bounded_inputs.md)"
        ));
    }
    if keys > MAX_SCENE_KEYS {
        return Err(format!(
            "{origin}: the scene has {keys} keys and array values, over the cap of {MAX_SCENE_KEYS} in a scene file (MAX_SCENE_KEYS; docs/bounded_inputs.md)"
        ));
    }
    Ok(())
}

type Key<'i> = Spanned<DeString<'i>>;
type Val<'i> = Spanned<DeValue<'i>>;

/// How a table or array came to be in the document.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Form {
    /// `[name]` or `[[name]]`: the value's span is the header, which holds the key.
    Header,
    /// Made on the way to a deeper key: `a` of the dotted key `a.b = 1` or of the header `[a.b]`
    /// (the value's span is the key's).
    Implicit,
    /// Written after `=`: a scalar, an inline table `{ .. }` or an array `[ .. ]`.
    Value,
}

fn form(key: &Key<'_>, value: &Val<'_>) -> Form {
    let (k, v) = (key.span(), value.span());
    if k == v {
        Form::Implicit
    } else if v.start <= k.start && k.end <= v.end {
        Form::Header
    } else {
        Form::Value
    }
}

/// The entries of `table` in the order of the file (the tree keeps them sorted by name).
fn in_file_order<'t, 'i>(table: &'t DeTable<'i>) -> Vec<(&'t Key<'i>, &'t Val<'i>)> {
    let mut v: Vec<_> = table.iter().collect();
    v.sort_by_key(|(k, _)| k.span().start);
    v
}

/// "an array", "a date-time", ... for messages.
fn a_type(v: &DeValue<'_>) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a real",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "an inline table",
    }
}

/// The text being parsed and its name, for messages; every position is a byte offset that may
/// come from the parser, so each use is clamped or checked rather than indexed.
struct Source<'a> {
    text: &'a str,
    origin: &'a str,
    /// Byte offsets of the newlines, so a line number costs a binary search (counting the
    /// newlines before each key made 80,000 keys quadratic: minutes inside `fmi2Instantiate`).
    newlines: Vec<usize>,
}

impl<'a> Source<'a> {
    fn new(text: &'a str, origin: &'a str) -> Self {
        let newlines = text
            .bytes()
            .enumerate()
            .filter(|&(_, c)| c == b'\n')
            .map(|(i, _)| i)
            .collect();
        Source {
            text,
            origin,
            newlines,
        }
    }

    /// The 1-based line of byte offset `pos`.
    fn line(&self, pos: usize) -> usize {
        self.newlines.partition_point(|&n| n < pos) + 1
    }

    /// Byte range of the line holding `pos`, without its newline.
    fn line_range(&self, pos: usize) -> std::ops::Range<usize> {
        let bytes = self.text.as_bytes();
        let pos = pos.min(bytes.len());
        let start = bytes
            .get(..pos)
            .and_then(|b| b.iter().rposition(|&c| c == b'\n'))
            .map_or(0, |i| i + 1);
        let end = bytes
            .get(pos..)
            .and_then(|b| b.iter().position(|&c| c == b'\n'))
            .map_or(bytes.len(), |i| pos + i);
        start..end
    }

    /// The 1-based column (in characters) of `pos`.
    fn column(&self, pos: usize) -> usize {
        let start = self.line_range(pos).start;
        let pos = pos.min(self.text.len()).max(start);
        self.text
            .get(start..pos)
            .map_or(pos - start, |s| s.chars().count())
            + 1
    }

    fn at(&self, pos: usize, msg: impl std::fmt::Display) -> String {
        format!("{}:{}: {msg}", self.origin, self.line(pos))
    }

    /// The source text of `span` (empty if the span does not fit the text).
    fn slice(&self, span: std::ops::Range<usize>) -> &str {
        self.text.get(span).unwrap_or("")
    }

    /// The first line of the source text of `value`, shortened for a message.
    fn snippet(&self, value: &Val<'_>) -> String {
        let raw = self.slice(value.span());
        let first = raw.lines().next().unwrap_or("").trim();
        let mut out: String = first.chars().take(40).collect();
        if out.len() < raw.trim().len() {
            out.push_str(" ...");
        }
        out
    }

    /// The table header (`[a.b]`, `[[a]]`) of the line holding `pos`, if that line is one.
    fn header_at(&self, pos: usize) -> Option<&str> {
        header_of(self.slice(self.line_range(pos)))
    }

    /// `name = value` of `[parameters]` as a scene entry.
    fn entry(&self, key: &Key<'_>, value: &Val<'_>) -> Result<SceneEntry, String> {
        let name = key.get_ref();
        let pos = key.span().start;
        let raw = self.slice(value.span());
        let cannot_read = |what: &str| {
            self.at(
                pos,
                format!(
                    "`{name}`: cannot read {what} `{}` (expected a number, true/false or a \"string\")",
                    self.snippet(value)
                ),
            )
        };
        let v = match value.get_ref() {
            DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
                Ok(i) => SceneValue::Integer(i),
                Err(_) => {
                    return Err(self.at(
                        pos,
                        format!(
                            "`{name}`: `{raw}` does not fit in a 64-bit integer (a real is written with `.` or an exponent)"
                        ),
                    ));
                }
            },
            DeValue::Float(f) => {
                // the crate has checked the syntax: what Rust cannot read is a nan or inf form
                let x = f.as_str().parse::<f64>().unwrap_or(f64::NAN);
                if !x.is_finite() {
                    return Err(self.at(
                        pos,
                        format!("`{name}`: `{raw}` refused: values must be finite"),
                    ));
                }
                SceneValue::Real(x)
            }
            DeValue::Boolean(b) => SceneValue::Boolean(*b),
            DeValue::String(s) => SceneValue::String(s.to_string()),
            DeValue::Datetime(_) => return Err(cannot_read("a date-time")),
            DeValue::Array(_) | DeValue::Table(_) => match form(key, value) {
                Form::Value => return Err(cannot_read(a_type(value.get_ref()))),
                Form::Implicit if self.header_at(pos).is_none() => {
                    let (path, leaf) = dotted_path(key, value);
                    return Err(self.at(
                        leaf,
                        format!(
                            "`{path}` is a dotted key, which TOML reads as tables; quote a parameter name that holds `.`: `\"{}\" = ...`",
                            path.replace('"', "")
                        ),
                    ));
                }
                Form::Header | Form::Implicit => {
                    let header = self.header_at(pos).unwrap_or("[parameters.?]");
                    return Err(self.at(
                        pos,
                        format!("unknown table `{header}`: a scene file has only `[parameters]`"),
                    ));
                }
            },
        };
        Ok(SceneEntry {
            name: name.to_string(),
            value: v,
            line: self.line(pos),
        })
    }

    /// `key = value` of a table of [`TABLES`]: a scalar as in `[parameters]`, or an array of
    /// numbers.
    fn table_entry(
        &self,
        table: &str,
        key: &Key<'_>,
        value: &Val<'_>,
    ) -> Result<SceneEntry, String> {
        let pos = key.span().start;
        let name = key.get_ref();
        match (value.get_ref(), form(key, value)) {
            (DeValue::Array(items), Form::Value) => {
                let mut v = Vec::with_capacity(items.len());
                for item in items.iter() {
                    let x = match item.get_ref() {
                        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
                            .map(|i| i as f64)
                            .unwrap_or(f64::NAN),
                        DeValue::Float(f) => f.as_str().parse::<f64>().unwrap_or(f64::NAN),
                        _ => {
                            return Err(self.at(
                                pos,
                                format!("`{table}.{name}`: an array here holds numbers only, got `{}`", self.snippet(item)),
                            ));
                        }
                    };
                    if !x.is_finite() {
                        return Err(self.at(
                            pos,
                            format!("`{table}.{name}`: `{}` refused: values must be finite", self.snippet(item)),
                        ));
                    }
                    v.push(x);
                }
                Ok(SceneEntry {
                    name: name.to_string(),
                    value: SceneValue::Reals(v),
                    line: self.line(pos),
                })
            }
            (DeValue::Array(_) | DeValue::Table(_), _) => Err(self.at(
                pos,
                format!(
                    "`{table}.{name}`: a `[{table}]` table holds numbers, strings, booleans and arrays of numbers, not {}",
                    a_type(value.get_ref())
                ),
            )),
            _ => self.entry(key, value),
        }
    }

    /// The message for `name`, a key outside `[parameters]` other than `model`.
    fn outside(&self, name: &str, key: &Key<'_>, value: &Val<'_>) -> String {
        let pos = key.span().start;
        let is_table = matches!(value.get_ref(), DeValue::Table(_) | DeValue::Array(_));
        match (is_table, form(key, value), self.header_at(pos)) {
            (true, Form::Header | Form::Implicit, Some(header)) => self.at(
                pos,
                format!("unknown table `{header}`: a scene file has only `[parameters]`"),
            ),
            (true, Form::Implicit, None) => {
                let (path, leaf) = dotted_path(key, value);
                self.at(
                    leaf,
                    format!(
                        "`{path}` is outside `[parameters]` (only `model` may stand there); it is a dotted key, which TOML reads as tables"
                    ),
                )
            }
            _ => self.at(
                pos,
                format!(
                    "`{}` is outside `[parameters]` (only `model` may stand there)",
                    name
                ),
            ),
        }
    }

    /// The message for the TOML errors of the crate: those on the first line that has one,
    /// with their columns; a duplicate key is named, with the line of its first definition.
    fn syntax_error(&self, doc: &DeTable<'_>, errors: &[toml::de::Error]) -> String {
        let first_line = errors
            .iter()
            .filter_map(|e| e.span())
            .map(|s| self.line(s.start))
            .min();
        let Some(line) = first_line else {
            let all: Vec<&str> = errors.iter().map(|e| e.message()).collect();
            return format!("{}: {}", self.origin, all.join("; "));
        };
        let mut causes: Vec<(usize, String)> = Vec::new();
        for e in errors {
            let Some(span) = e.span() else { continue };
            if self.line(span.start) != line {
                continue;
            }
            let cause = if e.message() == "duplicate key" {
                self.duplicate(doc, span.clone())
            } else {
                format!("{} (column {})", e.message(), self.column(span.start))
            };
            if !causes.iter().any(|(_, c)| *c == cause) {
                causes.push((span.start, cause));
            }
        }
        causes.sort_by_key(|(p, _)| *p);
        let causes: Vec<String> = causes.into_iter().map(|(_, c)| c).collect();
        format!("{}:{line}: {}", self.origin, causes.join("; "))
    }

    /// "`a` is set twice (first on line 2): duplicate key" for the key at `span` (TOML refuses a key or table defined twice).
    fn duplicate(&self, doc: &DeTable<'_>, span: std::ops::Range<usize>) -> String {
        let line = self.line(span.start);
        if let Some(header) = self.header_at(span.start) {
            let first = self
                .text
                .lines()
                .take(line.saturating_sub(1))
                .position(|l| header_of(l).is_some_and(|h| same_header(h, header)))
                .map(|i| format!(" (first on line {})", i + 1))
                .unwrap_or_default();
            return format!("`{header}` appears twice{first}: duplicate key");
        }
        let raw = self.slice(span.clone());
        let name = if raw.starts_with('"') || raw.starts_with('\'') {
            DeValue::parse(raw)
                .ok()
                .and_then(|v| v.get_ref().as_str().map(str::to_string))
                .unwrap_or_else(|| raw.to_string())
        } else {
            raw.to_string()
        };
        // a dotted key is shown as written (`a.b`), a plain one by its name
        let line_start = self.line_range(span.start).start;
        let written = self.slice(line_start..span.end).trim_start();
        let shown = if written == raw {
            name.as_str()
        } else {
            written
        };
        let first = earlier_key(doc, &name, span.start)
            .map(|p| format!(" (first on line {})", self.line(p)))
            .unwrap_or_default();
        format!("`{shown}` is set twice{first}: duplicate key")
    }
}

/// The path of the first leaf under the implicit table `key` (`a.b.c` of `a.b.c = 1`), with
/// the position of the leaf's key.
fn dotted_path(key: &Key<'_>, value: &Val<'_>) -> (String, usize) {
    let mut path = key_text(key.get_ref());
    let mut pos = key.span().start;
    let (mut k, mut v) = (key, value);
    while let (DeValue::Table(t), Form::Implicit) = (v.get_ref(), form(k, v)) {
        let Some(&(next_k, next_v)) = in_file_order(t).first() else {
            break;
        };
        path.push('.');
        path.push_str(&key_text(next_k.get_ref()));
        pos = next_k.span().start;
        (k, v) = (next_k, next_v);
    }
    (path, pos)
}

/// The position of the last key named `name` that starts before `before`, anywhere in `doc`.
fn earlier_key(doc: &DeTable<'_>, name: &str, before: usize) -> Option<usize> {
    let mut best = None;
    let mut consider = |k: &Key<'_>| {
        let p = k.span().start;
        if k.get_ref() == name && p < before && best.is_none_or(|b| p > b) {
            best = Some(p);
        }
    };
    let mut stack: Vec<&DeValue<'_>> = Vec::new();
    for (k, v) in doc.iter() {
        consider(k);
        stack.push(v.get_ref());
    }
    while let Some(v) = stack.pop() {
        match v {
            DeValue::Table(t) => {
                for (k, v) in t.iter() {
                    consider(k);
                    stack.push(v.get_ref());
                }
            }
            DeValue::Array(a) => stack.extend(a.iter().map(|v| v.get_ref())),
            _ => {}
        }
    }
    best
}

/// The table header that `line` starts with (`[a."b.c"]`, `[[a]]`), if it is a header line.
fn header_of(line: &str) -> Option<&str> {
    let s = line.trim_start();
    if !s.starts_with('[') {
        return None;
    }
    let double = s.starts_with("[[");
    let (mut basic, mut literal, mut escaped) = (false, false, false);
    for (i, c) in s.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if basic => escaped = true,
            '"' if !literal => basic = !basic,
            '\'' if !basic => literal = !literal,
            ']' if !basic && !literal => {
                let end = if double && s.get(i + 1..).is_some_and(|r| r.starts_with(']')) {
                    i + 2
                } else {
                    i + 1
                };
                return s.get(..end);
            }
            _ => {}
        }
    }
    None
}

/// Two headers name the same table (whitespace around the names aside).
fn same_header(a: &str, b: &str) -> bool {
    let squeeze = |s: &str| s.chars().filter(|c| !c.is_whitespace()).collect::<String>();
    squeeze(a) == squeeze(b)
}

/// Applies `file` to `model` (before initialization): every entry goes through the model's own
/// setter, so range checks and messages are the same as for an importer's `fmi2Set*`. Returns
/// the number of values set.
pub fn apply(model: &mut dyn CoSimModel, file: &SceneFile, origin: &str) -> Result<usize, String> {
    let info = model.info();
    if let Some(m) = &file.model
        && m != info.identifier
    {
        let line = match file.model_line {
            0 => String::new(),
            n => format!(" (line {n})"),
        };
        return Err(format!(
            "{origin}: the scene is for model `{m}`, not `{}`{line}",
            info.identifier
        ));
    }
    apply_parameters(model, file, origin)?;
    if !file.tables.is_empty() {
        model.set_tables(&file.tables, origin)?;
    }
    Ok(file.entries.len())
}

fn apply_parameters(
    model: &mut dyn CoSimModel,
    file: &SceneFile,
    origin: &str,
) -> Result<(), String> {
    let info = model.info();
    for e in &file.entries {
        let at = |msg: String| format!("{origin}:{}: {msg}", e.line);
        let port = info.port_by_name(&e.name).ok_or_else(|| {
            at(format!(
                "`{}` has no parameter named `{}`",
                info.identifier, e.name
            ))
        })?;
        if port.causality != Causality::Parameter {
            return Err(at(format!(
                "`{}` has causality {}; a scene file sets parameters only",
                e.name,
                port.causality.name()
            )));
        }
        set_one(model, port, &e.value).map_err(at)?;
    }
    Ok(())
}

fn set_one(model: &mut dyn CoSimModel, port: &PortSpec, value: &SceneValue) -> Result<(), String> {
    let wrong = |want: &str| {
        format!(
            "`{}` needs {want}, got {}",
            port.name,
            match value {
                SceneValue::Integer(_) => "an integer",
                SceneValue::Real(_) => "a real",
                SceneValue::Boolean(_) => "a boolean",
                SceneValue::String(_) => "a string",
                SceneValue::Reals(_) => "an array",
            }
        )
    };
    let int32 = |i: i64| {
        i32::try_from(i).map_err(|_| format!("`{}` = {i} does not fit in 32 bits", port.name))
    };
    let r = match (&port.ty, value) {
        (PortType::Real { .. }, SceneValue::Real(v)) => model.set_real(port.vr, *v),
        (PortType::Real { .. }, SceneValue::Integer(i)) => model.set_real(port.vr, *i as f64),
        (PortType::Real { .. }, _) => return Err(wrong("a number")),
        (PortType::Integer { .. }, SceneValue::Integer(i)) => {
            model.set_integer(port.vr, int32(*i)?)
        }
        (PortType::Integer { .. }, _) => return Err(wrong("an integer")),
        (PortType::Boolean { .. }, SceneValue::Boolean(b)) => model.set_boolean(port.vr, *b),
        (PortType::Boolean { .. }, _) => return Err(wrong("true or false")),
        (PortType::String { .. }, SceneValue::String(s)) => model.set_string(port.vr, s),
        (PortType::String { .. }, _) => return Err(wrong("a string")),
        (PortType::Enumeration { items, .. }, SceneValue::String(s)) => {
            let k = items
                .iter()
                .position(|(n, _)| n.eq_ignore_ascii_case(s))
                .ok_or_else(|| {
                    let names: Vec<&str> = items.iter().map(|(n, _)| *n).collect();
                    format!(
                        "`{}` = \"{s}\" is not one of {}",
                        port.name,
                        names.join(", ")
                    )
                })?;
            model.set_integer(port.vr, k as i32 + 1)
        }
        (PortType::Enumeration { .. }, SceneValue::Integer(i)) => {
            model.set_integer(port.vr, int32(*i)?)
        }
        (PortType::Enumeration { .. }, _) => return Err(wrong("an item name")),
    };
    r.map_err(|e| e.to_string())
}

/// The default scene of a model: every parameter at its start value, with its description,
/// unit and (for enumerations) the item names as comments.
pub fn render(info: &ModelInfo) -> String {
    let mut out = format!(
        "# Default scene of {id}: every parameter at its start value.\n\
         # Generated from the variable table by `mbcosim model-descriptions`; copy it, change\n\
         # values and load the copy (`mbcosim simulate {id} --scene FILE`, or replace\n\
         # resources/scene.toml inside the FMU). Units are SI, as in modelDescription.xml.\n\n\
         model = \"{id}\"\n\n[parameters]\n",
        id = info.identifier
    );
    for p in info
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Parameter)
    {
        let unit = p.unit.map(|u| format!(" [{u}]")).unwrap_or_default();
        out.push_str(&format!("\n# {}{unit}\n", p.description));
        let value = match &p.ty {
            PortType::Real { start, .. } => start.map(|v| format!("{v:?}")),
            PortType::Integer { start, .. } => start.map(|v| v.to_string()),
            PortType::Boolean { start } => start.map(|v| v.to_string()),
            PortType::String { start } => start.map(quote),
            PortType::Enumeration { items, start, .. } => {
                let names: Vec<&str> = items.iter().map(|(n, _)| *n).collect();
                out.push_str(&format!("# one of: {}\n", names.join(", ")));
                start.and_then(|k| items.get(k as usize - 1).map(|(n, _)| quote(n)))
            }
        };
        if let Some(v) = value {
            out.push_str(&format!("{} = {v}\n", key_text(&p.name)));
        }
    }
    out
}

fn key_text(name: &str) -> String {
    if !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        name.to_string()
    } else {
        quote(name)
    }
}

fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            // TOML refuses the other control characters in a basic string
            c if c < ' ' || c == '\u{7f}' => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Reads (through [`bounded_file`], capped at [`SCENE_FILE_BYTES`]) and applies the scene file
/// at `path`.
pub fn apply_file(model: &mut dyn CoSimModel, path: &std::path::Path) -> Result<usize, String> {
    let origin = path.display().to_string();
    let text = bounded_file::read_text(path, &SCENE_FILE)?;
    apply(model, &parse(&text, &origin)?, &origin)
}

#[cfg(test)]
#[path = "scene_file_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "scene_file_limits_tests.rs"]
mod limits_tests;
