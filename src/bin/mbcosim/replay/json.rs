//! Small JSON writers for the replay page (numbers, strings, arrays of numbers).

use std::fmt::Write;

/// A finite number in shortest round-trip form (`0.1`, `1e-7`, `2.0`); `null` otherwise
/// (JSON has no NaN or infinity).
pub fn number(out: &mut String, x: f64) {
    if x.is_finite() {
        let _ = write!(out, "{x:?}");
    } else {
        out.push_str("null");
    }
}

/// A finite number rounded to f32 (the precision WebGL draws with; 7 significant digits), in
/// shortest round-trip form of that f32; `null` otherwise.
pub fn number32(out: &mut String, x: f64) {
    let y = x as f32;
    if y.is_finite() {
        let _ = write!(out, "{y:?}");
    } else {
        out.push_str("null");
    }
}

/// `[x0,x1,...]` rounded to f32 ([`number32`]).
pub fn numbers32(out: &mut String, xs: impl IntoIterator<Item = f64>) {
    out.push('[');
    for (i, x) in xs.into_iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        number32(out, x);
    }
    out.push(']');
}

/// `[x0,x1,...]`.
pub fn numbers(out: &mut String, xs: impl IntoIterator<Item = f64>) {
    out.push('[');
    for (i, x) in xs.into_iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        number(out, x);
    }
    out.push(']');
}

/// A JSON string literal of `s` that is also safe inside an HTML `<script>` element: `<` is
/// written `\u003c`, so no `</script>` can end the element early.
pub fn string(out: &mut String, s: &str) {
    out.reserve(s.len() + s.len() / 16 + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            '<' => out.push_str("\\u003c"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip_and_non_finite_is_null() {
        let mut s = String::new();
        numbers(&mut s, [0.1, 1e-7, 2.0, -0.0, f64::NAN, f64::INFINITY]);
        assert_eq!(s, "[0.1,1e-7,2.0,-0.0,null,null]");
        let mut s = String::new();
        numbers32(&mut s, [0.1, 12.345678901, 1e39, 3.0]);
        assert_eq!(s, "[0.1,12.345679,null,3.0]");
    }

    #[test]
    fn strings_escape_quotes_controls_and_script_ends() {
        let mut s = String::new();
        string(&mut s, "a\"b\\c\nd</script>\u{1}");
        assert_eq!(s, "\"a\\\"b\\\\c\\nd\\u003c/script>\\u0001\"");
    }
}
