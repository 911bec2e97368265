//! Plain-text import/export of modal body data, so users can bring modes from their own FE tool.
//!
//! # Format, version 1
//! UTF-8 text, one record per line, whitespace-separated tokens. Blank lines and everything
//! after `#` are ignored. Records come in this order (`n` = modes, `N` = nodes):
//!
//! ```text
//! MBCOSIM_MODAL_BODY 1                 # magic and version
//! UNITS SI                             # m, kg, s, rad; frequencies in Hz
//! NODE_COUNT N                         # N >= 1
//! MODE_COUNT n                         # n >= 0
//! ATTACHMENT_COUNT c
//! FREQUENCIES_HZ f_1 ... f_n           # eigenfrequencies of (K, M), ascending; checked
//! MASS_MATRIX                          # then n lines of n numbers (M_aa, row by row)
//! STIFFNESS_MATRIX                     # then n lines of n numbers (K_aa)
//! DAMPING_MATRIX                       # then n lines of n numbers (D_aa), or instead the
//! DAMPING_RATIO zeta                   #   single record giving every mode the ratio zeta
//! NODES                                # then N lines: k x y z mass   (k = 0 .. N-1 in order;
//!                                      #   position [m] in the body frame, mass [kg] >= 0)
//! TRANSLATIONAL_SHAPES                 # then 3 N lines: k x|y|z phi_1 ... phi_n   [m]
//! ROTATIONAL_SHAPES                    # then 3 N lines: k x|y|z psi_1 ... psi_n   [rad]
//! ATTACHMENT_NODES k_1 ... k_c         # node indices (0-based)
//! INVARIANTS                           # optional block; without it the invariants are the
//! MASS m                               #   point-mass node sums (see `super::invariants`)
//! FIRST_MOMENT S_x S_y S_z
//! INERTIA J_xx J_xy J_xz J_yx J_yy J_yz J_zx J_zy J_zz
//! C_T x|y|z c_1 ... c_n                # three records, rows x, y, z of C_t
//! Q j q_xx q_xy q_xz q_yx ... q_zz     # n records, j = 0 .. n-1 (Q_j row-major)
//! P i j p_xx ... p_zz                  # n^2 records, i-major (P_ij row-major)
//! END
//! ```
//!
//! The modal-mass block of the invariants is `MASS_MATRIX`. For mass-normalized modes write
//! the identity as `MASS_MATRIX` and `(2 pi f_i)^2` on the diagonal of `STIFFNESS_MATRIX`.
//! Give the `INVARIANTS` block when the nodes listed are only some of the FE nodes (e.g. the
//! attachment nodes) or when the FE tool has a consistent mass. The listed frequencies must
//! match the eigenfrequencies of (K, M) to 1e-4 relative (1e-6 Hz absolute near zero): this
//! catches unit mix-ups (rad/s for Hz) and rows in the wrong order.
//!
//! Errors: [`FlexError::Parse`] with the 1-based line number and what was expected there;
//! semantic problems found after parsing (e.g. a mass matrix that is not positive definite)
//! come from [`ModalBodyData::new`].

use std::fmt::Write as _;

use nalgebra::{DMatrix, Matrix3xX};

use super::body::{ModalBodyData, ModalBodyParts};
use super::error::FlexError;
use super::invariants::Invariants;
use super::reduce::modal_damping;
use crate::bounded_file::{self, FileKind};
use crate::math::{Mat3, Vec3};

/// Magic word of the first record.
pub const MAGIC: &str = "MBCOSIM_MODAL_BODY";
/// Format version written and accepted.
pub const VERSION: u32 = 1;

const AXES: [&str; 3] = ["x", "y", "z"];

/// Serializes `body` (all values with round-trip precision, invariants included).
pub fn to_text(body: &ModalBodyData) -> String {
    let n = body.n_modes();
    let mut s = String::new();
    let nums = |v: &mut String, it: &mut dyn Iterator<Item = f64>| {
        for x in it {
            let _ = write!(v, " {x:e}");
        }
        v.push('\n');
    };
    let _ = writeln!(
        s,
        "# modal body data for mbcosim (format: src/flex/text_format.rs)"
    );
    let _ = writeln!(s, "{MAGIC} {VERSION}\nUNITS SI");
    let _ = writeln!(s, "NODE_COUNT {}", body.n_nodes());
    let _ = writeln!(s, "MODE_COUNT {n}");
    let _ = writeln!(s, "ATTACHMENT_COUNT {}", body.attachment_nodes().len());
    s.push_str("FREQUENCIES_HZ");
    let freqs = body.frequencies_hz().unwrap_or_else(|_| vec![0.0; n]);
    nums(&mut s, &mut freqs.into_iter());
    for (name, m) in [
        ("MASS_MATRIX", body.mass()),
        ("STIFFNESS_MATRIX", body.stiffness()),
        ("DAMPING_MATRIX", body.damping()),
    ] {
        let _ = writeln!(s, "{name}");
        for r in 0..n {
            let row = m.row(r);
            s.push_str("  ");
            nums(&mut s, &mut row.iter().copied());
        }
    }
    s.push_str("NODES  # k x y z mass\n");
    for (k, (p, m)) in body.positions().iter().zip(body.node_masses()).enumerate() {
        let _ = writeln!(s, "  {k} {:e} {:e} {:e} {m:e}", p.x, p.y, p.z);
    }
    for (name, shapes) in [
        ("TRANSLATIONAL_SHAPES", body.translational_shapes()),
        ("ROTATIONAL_SHAPES", body.rotational_shapes()),
    ] {
        let _ = writeln!(s, "{name}");
        for (k, sh) in shapes.iter().enumerate() {
            for (r, axis) in AXES.iter().enumerate() {
                let _ = write!(s, "  {k} {axis}");
                nums(&mut s, &mut sh.row(r).iter().copied());
            }
        }
    }
    s.push_str("ATTACHMENT_NODES");
    for a in body.attachment_nodes() {
        let _ = write!(s, " {a}");
    }
    s.push('\n');
    let inv = body.invariants();
    let _ = writeln!(s, "INVARIANTS\nMASS {:e}", inv.mass);
    s.push_str("FIRST_MOMENT");
    nums(&mut s, &mut inv.first_moment.iter().copied());
    s.push_str("INERTIA");
    nums(&mut s, &mut row_major(&inv.inertia).into_iter());
    for (r, axis) in AXES.iter().enumerate() {
        let _ = write!(s, "C_T {axis}");
        nums(&mut s, &mut inv.c_t.row(r).iter().copied());
    }
    for (j, q) in inv.q.iter().enumerate() {
        let _ = write!(s, "Q {j}");
        nums(&mut s, &mut row_major(q).into_iter());
    }
    for i in 0..n {
        for j in 0..n {
            let _ = write!(s, "P {i} {j}");
            nums(&mut s, &mut row_major(&inv.p[i * n + j]).into_iter());
        }
    }
    s.push_str("END\n");
    s
}

fn row_major(m: &Mat3) -> [f64; 9] {
    std::array::from_fn(|i| m[(i / 3, i % 3)])
}

/// Writes `body` to the file `path` in the text format.
pub fn write_file(body: &ModalBodyData, path: &std::path::Path) -> Result<(), FlexError> {
    std::fs::write(path, to_text(body))
        .map_err(|e| FlexError::InvalidInput(format!("cannot write {}: {e}", path.display())))
}

/// Largest modal-body file read: 256 MiB holds 1,000 modes with their invariants (the `P`
/// block alone is 1,000,000 records) or 100,000 nodes of 20 modes (docs/bounded_inputs.md).
pub const MODAL_FILE_BYTES: u64 = 256 * 1024 * 1024;

/// A modal-body file, for [`bounded_file`].
pub const MODAL_FILE: FileKind = FileKind {
    what: "modal body file",
    max_bytes: MODAL_FILE_BYTES,
    cap_name: "MODAL_FILE_BYTES",
};

/// Most modes a body may have: `MODE_COUNT` sizes the matrices before their rows are read.
pub const MAX_MODES: usize = 1_000;

/// Most nodes a body may have: `NODE_COUNT` sizes the node tables before they are read.
pub const MAX_NODES: usize = 1_000_000;

/// Reads a body from the file `path` (see [`from_text`]), through [`bounded_file`] (a regular
/// file of at most [`MODAL_FILE_BYTES`]).
pub fn read_file(path: &std::path::Path) -> Result<ModalBodyData, FlexError> {
    let text = bounded_file::read_text(path, &MODAL_FILE)
        .map_err(|e| FlexError::InvalidInput(e.message))?;
    from_text(&text)
}

/// One significant line: 1-based number and its tokens.
struct Record<'a> {
    line: usize,
    tokens: Vec<&'a str>,
}

/// Significant lines of the text, with line numbers for error messages.
struct Reader<'a> {
    records: Vec<Record<'a>>,
    pos: usize,
    /// Line number reported at end of file (one past the last line).
    eof_line: usize,
}

fn parse_err<T>(line: usize, message: impl Into<String>) -> Result<T, FlexError> {
    Err(FlexError::Parse {
        line,
        message: message.into(),
    })
}

impl<'a> Reader<'a> {
    fn new(text: &'a str) -> Self {
        let mut records = Vec::new();
        let mut last = 0;
        for (i, raw) in text.lines().enumerate() {
            last = i + 1;
            let content = raw.split('#').next().unwrap_or("");
            let tokens: Vec<&str> = content.split_whitespace().collect();
            if !tokens.is_empty() {
                records.push(Record {
                    line: i + 1,
                    tokens,
                });
            }
        }
        Self {
            records,
            pos: 0,
            eof_line: last + 1,
        }
    }

    /// Next record, or an end-of-file error saying what was expected.
    fn next(&mut self, expected: &str) -> Result<&Record<'a>, FlexError> {
        match self.records.get(self.pos) {
            Some(r) => {
                self.pos += 1;
                Ok(r)
            }
            None => parse_err(
                self.eof_line,
                format!("unexpected end of file, expected {expected}"),
            ),
        }
    }

    fn peek_keyword(&self) -> Option<&'a str> {
        self.records.get(self.pos).map(|r| r.tokens[0])
    }

    /// Next record must start with `keyword`; returns its line and remaining tokens.
    fn keyword(&mut self, keyword: &str, usage: &str) -> Result<(usize, Vec<&'a str>), FlexError> {
        let r = self.next(&format!("'{usage}'"))?;
        if r.tokens[0] != keyword {
            return parse_err(
                r.line,
                format!("expected '{usage}', found '{}'", r.tokens.join(" ")),
            );
        }
        Ok((r.line, r.tokens[1..].to_vec()))
    }

    /// `KEYWORD <count>` record.
    fn count(&mut self, keyword: &str) -> Result<usize, FlexError> {
        let (line, rest) = self.keyword(keyword, &format!("{keyword} <count>"))?;
        if rest.len() != 1 {
            return parse_err(line, format!("expected one count after {keyword}"));
        }
        parse_usize(line, rest[0], keyword)
    }

    /// A record of exactly `n` numbers (no keyword), `what` naming it.
    fn numbers(&mut self, n: usize, what: &str) -> Result<Vec<f64>, FlexError> {
        let r = self.next(&format!("{n} numbers for {what}"))?;
        let line = r.line;
        let tokens = r.tokens.clone();
        numbers(line, &tokens, n, what)
    }

    /// `n` records of `n` numbers after a `keyword` record.
    fn matrix(&mut self, keyword: &str, n: usize) -> Result<DMatrix<f64>, FlexError> {
        let (line, rest) = self.keyword(keyword, keyword)?;
        if !rest.is_empty() {
            return parse_err(line, format!("{keyword} takes no values on its own line"));
        }
        let mut m = DMatrix::zeros(n, n);
        for r in 0..n {
            let row = self.numbers(n, &format!("row {r} of {keyword}"))?;
            for (c, v) in row.into_iter().enumerate() {
                m[(r, c)] = v;
            }
        }
        Ok(m)
    }

    /// 3 N records `k axis v_1..v_n` after a `keyword` record.
    fn shapes(
        &mut self,
        keyword: &str,
        nodes: usize,
        n: usize,
    ) -> Result<Vec<Matrix3xX<f64>>, FlexError> {
        let (line, rest) = self.keyword(keyword, keyword)?;
        if !rest.is_empty() {
            return parse_err(line, format!("{keyword} takes no values on its own line"));
        }
        let mut out = Vec::with_capacity(nodes);
        for k in 0..nodes {
            let mut sh = Matrix3xX::zeros(n);
            for (r, axis) in AXES.iter().enumerate() {
                let usage = format!("'{k} {axis}' and {n} numbers ({keyword})");
                let rec = self.next(&usage)?;
                let (line, t) = (rec.line, rec.tokens.clone());
                if t.len() < 2 || t[0] != k.to_string() || t[1] != *axis {
                    return parse_err(line, format!("expected {usage}, found '{}'", t.join(" ")));
                }
                let v = numbers(line, &t[2..], n, &format!("{keyword} of node {k}, {axis}"))?;
                for (c, x) in v.into_iter().enumerate() {
                    sh[(r, c)] = x;
                }
            }
            out.push(sh);
        }
        Ok(out)
    }
}

fn parse_usize(line: usize, token: &str, what: &str) -> Result<usize, FlexError> {
    token.parse::<usize>().or_else(|_| {
        parse_err(
            line,
            format!("'{token}' is not a non-negative integer ({what})"),
        )
    })
}

/// Exactly `n` finite numbers from `tokens`.
fn numbers(line: usize, tokens: &[&str], n: usize, what: &str) -> Result<Vec<f64>, FlexError> {
    if tokens.len() != n {
        return parse_err(
            line,
            format!("expected {n} numbers for {what}, found {}", tokens.len()),
        );
    }
    tokens
        .iter()
        .map(|t| match t.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => parse_err(line, format!("'{t}' is not a finite number ({what})")),
        })
        .collect()
}

/// Parses the text format (module doc) into a validated [`ModalBodyData`].
pub fn from_text(text: &str) -> Result<ModalBodyData, FlexError> {
    let mut rd = Reader::new(text);
    let (line, rest) = rd.keyword(MAGIC, &format!("{MAGIC} {VERSION}"))?;
    if rest != [VERSION.to_string().as_str()] {
        return parse_err(
            line,
            format!(
                "unsupported version '{}', this reader accepts {VERSION}",
                rest.join(" ")
            ),
        );
    }
    let (line, rest) = rd.keyword("UNITS", "UNITS SI")?;
    if rest != ["SI"] {
        return parse_err(
            line,
            format!("expected 'UNITS SI', found 'UNITS {}'", rest.join(" ")),
        );
    }
    let nodes = rd.count("NODE_COUNT")?;
    let count_line = rd.records[rd.pos - 1].line;
    if nodes == 0 {
        return parse_err(count_line, "NODE_COUNT must be at least 1");
    }
    if nodes > MAX_NODES {
        return parse_err(
            count_line,
            format!(
                "NODE_COUNT {nodes} is over the cap of {MAX_NODES} nodes (MAX_NODES; docs/bounded_inputs.md)"
            ),
        );
    }
    let n = rd.count("MODE_COUNT")?;
    if n > MAX_MODES {
        return parse_err(
            rd.records[rd.pos - 1].line,
            format!(
                "MODE_COUNT {n} is over the cap of {MAX_MODES} modes (MAX_MODES; docs/bounded_inputs.md)"
            ),
        );
    }
    let n_att = rd.count("ATTACHMENT_COUNT")?;
    let (freq_line, rest) = rd.keyword("FREQUENCIES_HZ", "FREQUENCIES_HZ f_1 ... f_n")?;
    let freqs = numbers(freq_line, &rest, n, "FREQUENCIES_HZ")?;
    let mass = rd.matrix("MASS_MATRIX", n)?;
    let stiffness = rd.matrix("STIFFNESS_MATRIX", n)?;
    let damping = match rd.peek_keyword() {
        Some("DAMPING_RATIO") => {
            let (line, rest) = rd.keyword("DAMPING_RATIO", "DAMPING_RATIO zeta")?;
            let z = numbers(line, &rest, 1, "DAMPING_RATIO")?[0];
            modal_damping(&stiffness, &mass, z).map_err(|e| FlexError::Parse {
                line,
                message: e.to_string(),
            })?
        }
        _ => rd.matrix("DAMPING_MATRIX", n)?,
    };
    let (line, rest) = rd.keyword("NODES", "NODES")?;
    if !rest.is_empty() {
        return parse_err(line, "NODES takes no values on its own line");
    }
    let mut positions = Vec::with_capacity(nodes);
    let mut node_masses = Vec::with_capacity(nodes);
    for k in 0..nodes {
        let rec = rd.next(&format!("node record '{k} x y z mass'"))?;
        let (line, t) = (rec.line, rec.tokens.clone());
        if t[0] != k.to_string() {
            return parse_err(line, format!("expected node index {k}, found '{}'", t[0]));
        }
        let v = numbers(line, &t[1..], 4, &format!("x y z mass of node {k}"))?;
        if v[3] < 0.0 {
            return parse_err(line, format!("node {k}: mass must be >= 0, got {}", v[3]));
        }
        positions.push(Vec3::new(v[0], v[1], v[2]));
        node_masses.push(v[3]);
    }
    let translational_shapes = rd.shapes("TRANSLATIONAL_SHAPES", nodes, n)?;
    let rotational_shapes = rd.shapes("ROTATIONAL_SHAPES", nodes, n)?;
    let (line, rest) = rd.keyword("ATTACHMENT_NODES", "ATTACHMENT_NODES k_1 ... k_c")?;
    if rest.len() != n_att {
        return parse_err(
            line,
            format!(
                "expected {n_att} attachment nodes (ATTACHMENT_COUNT), found {}",
                rest.len()
            ),
        );
    }
    let mut attachment_nodes = Vec::with_capacity(n_att);
    for t in rest {
        let k = parse_usize(line, t, "attachment node")?;
        if k >= nodes {
            return parse_err(
                line,
                format!("attachment node {k} out of range (0..{nodes})"),
            );
        }
        attachment_nodes.push(k);
    }
    let invariants = if rd.peek_keyword() == Some("INVARIANTS") {
        rd.next("INVARIANTS")?;
        Some(read_invariants(&mut rd, n, &mass)?)
    } else {
        None
    };
    let (line, rest) = rd.keyword("END", "END")?;
    if !rest.is_empty() {
        return parse_err(line, "END takes no values");
    }
    if let Some(extra) = rd.records.get(rd.pos) {
        return parse_err(extra.line, "unexpected content after END");
    }
    let body = ModalBodyData::new(ModalBodyParts {
        positions,
        node_masses,
        translational_shapes,
        rotational_shapes,
        mass,
        stiffness,
        damping,
        attachment_nodes,
        invariants,
    })?;
    let computed = body.frequencies_hz()?;
    for (i, (f, c)) in freqs.iter().zip(&computed).enumerate() {
        if (f - c).abs() > 1e-4 * c.abs() + 1e-6 {
            return parse_err(
                freq_line,
                format!(
                    "frequency {} is {f} Hz but MASS_MATRIX/STIFFNESS_MATRIX give {c} Hz \
                     (frequencies in Hz, ascending)",
                    i + 1
                ),
            );
        }
    }
    Ok(body)
}

/// The records of an `INVARIANTS` block after its keyword.
fn read_invariants(
    rd: &mut Reader,
    n: usize,
    mass: &DMatrix<f64>,
) -> Result<Invariants, FlexError> {
    let (line, rest) = rd.keyword("MASS", "MASS m")?;
    let m = numbers(line, &rest, 1, "MASS")?[0];
    let (line, rest) = rd.keyword("FIRST_MOMENT", "FIRST_MOMENT S_x S_y S_z")?;
    let s = numbers(line, &rest, 3, "FIRST_MOMENT")?;
    let (line, rest) = rd.keyword("INERTIA", "INERTIA and 9 numbers (row-major)")?;
    let inertia = Mat3::from_row_slice(&numbers(line, &rest, 9, "INERTIA")?);
    let mut c_t = Matrix3xX::zeros(n);
    for (r, axis) in AXES.iter().enumerate() {
        let usage = format!("C_T {axis} and {n} numbers");
        let (line, rest) = rd.keyword("C_T", &usage)?;
        if rest.first() != Some(axis) {
            return parse_err(line, format!("expected '{usage}'"));
        }
        for (c, v) in numbers(line, &rest[1..], n, &format!("C_T row {axis}"))?
            .into_iter()
            .enumerate()
        {
            c_t[(r, c)] = v;
        }
    }
    let mut q = Vec::with_capacity(n);
    for j in 0..n {
        let usage = format!("Q {j} and 9 numbers");
        let (line, rest) = rd.keyword("Q", &usage)?;
        if rest.first().copied() != Some(j.to_string().as_str()) {
            return parse_err(line, format!("expected '{usage}'"));
        }
        q.push(Mat3::from_row_slice(&numbers(
            line,
            &rest[1..],
            9,
            &format!("Q_{j}"),
        )?));
    }
    let mut p = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let usage = format!("P {i} {j} and 9 numbers");
            let (line, rest) = rd.keyword("P", &usage)?;
            if rest.len() < 2 || rest[0] != i.to_string() || rest[1] != j.to_string() {
                return parse_err(line, format!("expected '{usage}'"));
            }
            p.push(Mat3::from_row_slice(&numbers(
                line,
                &rest[2..],
                9,
                &format!("P_{i}{j}"),
            )?));
        }
    }
    Ok(Invariants {
        mass: m,
        first_moment: Vec3::new(s[0], s[1], s[2]),
        inertia,
        c_t,
        q,
        p,
        modal_mass: mass.clone(),
    })
}
