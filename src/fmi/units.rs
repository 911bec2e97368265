//! Unit symbols to SI base-unit exponents, for `UnitDefinitions` in `modelDescription.xml`.
//!
//! A symbol is a product of atoms, optionally divided by another product: `N`, `N.m`, `kg.m2`,
//! `m/s2`, `rad/s`, `1/s`, `N.m/rad`, `kg*m^2`. Products use `.` or `*`; an atom may carry an
//! integer exponent written directly (`m2`, `s-2`) or after `^`. Unknown atoms are an error, so a
//! misspelt unit cannot reach an FMU.

/// Exponents of the FMI `BaseUnit` attributes, in order `kg, m, s, A, K, mol, cd, rad`.
pub const BASE_NAMES: [&str; 8] = ["kg", "m", "s", "A", "K", "mol", "cd", "rad"];

/// A unit as SI base exponents and a factor (value in SI = factor * value in this unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SiUnit {
    /// Exponents of kg, m, s, A, K, mol, cd, rad.
    pub exponents: [i32; 8],
    /// Scale to SI (1 for coherent SI units; pi/180 for `deg`).
    pub factor: f64,
}

/// Atoms: symbol, factor, exponents (kg, m, s, A, K, mol, cd, rad).
const ATOMS: &[(&str, f64, [i32; 8])] = &[
    ("kg", 1.0, [1, 0, 0, 0, 0, 0, 0, 0]),
    ("g", 1e-3, [1, 0, 0, 0, 0, 0, 0, 0]),
    ("m", 1.0, [0, 1, 0, 0, 0, 0, 0, 0]),
    ("mm", 1e-3, [0, 1, 0, 0, 0, 0, 0, 0]),
    ("s", 1.0, [0, 0, 1, 0, 0, 0, 0, 0]),
    ("ms", 1e-3, [0, 0, 1, 0, 0, 0, 0, 0]),
    ("A", 1.0, [0, 0, 0, 1, 0, 0, 0, 0]),
    ("K", 1.0, [0, 0, 0, 0, 1, 0, 0, 0]),
    ("mol", 1.0, [0, 0, 0, 0, 0, 1, 0, 0]),
    ("cd", 1.0, [0, 0, 0, 0, 0, 0, 1, 0]),
    ("rad", 1.0, [0, 0, 0, 0, 0, 0, 0, 1]),
    (
        "deg",
        std::f64::consts::PI / 180.0,
        [0, 0, 0, 0, 0, 0, 0, 1],
    ),
    ("N", 1.0, [1, 1, -2, 0, 0, 0, 0, 0]),
    ("kN", 1e3, [1, 1, -2, 0, 0, 0, 0, 0]),
    ("J", 1.0, [1, 2, -2, 0, 0, 0, 0, 0]),
    ("W", 1.0, [1, 2, -3, 0, 0, 0, 0, 0]),
    ("Pa", 1.0, [1, -1, -2, 0, 0, 0, 0, 0]),
    ("MPa", 1e6, [1, -1, -2, 0, 0, 0, 0, 0]),
    ("GPa", 1e9, [1, -1, -2, 0, 0, 0, 0, 0]),
    ("Hz", 1.0, [0, 0, -1, 0, 0, 0, 0, 0]),
    ("V", 1.0, [1, 2, -3, -1, 0, 0, 0, 0]),
    ("C", 1.0, [0, 0, 1, 1, 0, 0, 0, 0]),
];

fn atom(token: &str) -> Result<(f64, [i32; 8], i32), String> {
    let split = token
        .find(|c: char| c == '^' || c == '-' || c.is_ascii_digit())
        .unwrap_or(token.len());
    let (name, exp) = token.split_at(split);
    let exp = exp.strip_prefix('^').unwrap_or(exp);
    let power = if exp.is_empty() {
        1
    } else {
        exp.parse::<i32>()
            .map_err(|_| format!("bad exponent `{exp}` in `{token}`"))?
    };
    let (_, factor, e) = ATOMS.iter().find(|(n, _, _)| *n == name).ok_or_else(|| {
        format!(
            "unknown unit `{name}` (known: {})",
            ATOMS.iter().map(|a| a.0).collect::<Vec<_>>().join(" ")
        )
    })?;
    Ok((*factor, *e, power))
}

fn product(text: &str, sign: i32, unit: &mut SiUnit) -> Result<(), String> {
    let text = text.trim_start_matches('(').trim_end_matches(')');
    if text == "1" {
        return Ok(());
    }
    for token in text.split(['.', '*']) {
        if token.is_empty() {
            return Err("empty factor".into());
        }
        let (factor, e, power) = atom(token)?;
        let p = sign * power;
        unit.factor *= factor.powi(p);
        for (u, x) in unit.exponents.iter_mut().zip(e) {
            *u += x * p;
        }
    }
    Ok(())
}

/// Parses a unit symbol into SI base exponents and a factor.
pub fn parse(symbol: &str) -> Result<SiUnit, String> {
    let mut unit = SiUnit {
        exponents: [0; 8],
        factor: 1.0,
    };
    let mut parts = symbol.split('/');
    let num = parts.next().unwrap_or("");
    let den = parts.next();
    if parts.next().is_some() || num.is_empty() || symbol.contains(char::is_whitespace) {
        return Err(format!(
            "unit `{symbol}`: use one `/` at most and no spaces"
        ));
    }
    product(num, 1, &mut unit).map_err(|e| format!("unit `{symbol}`: {e}"))?;
    if let Some(den) = den {
        product(den, -1, &mut unit).map_err(|e| format!("unit `{symbol}`: {e}"))?;
    }
    Ok(unit)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exps(s: &str) -> [i32; 8] {
        parse(s).unwrap().exponents
    }

    #[test]
    fn derived_units_reduce_to_base_units() {
        assert_eq!(exps("N"), [1, 1, -2, 0, 0, 0, 0, 0]);
        assert_eq!(exps("N.m"), [1, 2, -2, 0, 0, 0, 0, 0]);
        assert_eq!(exps("N.m/rad"), [1, 2, -2, 0, 0, 0, 0, -1]);
        assert_eq!(exps("kg.m2"), [1, 2, 0, 0, 0, 0, 0, 0]);
        assert_eq!(exps("kg*m^2"), [1, 2, 0, 0, 0, 0, 0, 0]);
        assert_eq!(exps("m/s2"), [0, 1, -2, 0, 0, 0, 0, 0]);
        assert_eq!(exps("m.s-2"), [0, 1, -2, 0, 0, 0, 0, 0]);
        assert_eq!(exps("1/s"), [0, 0, -1, 0, 0, 0, 0, 0]);
        assert_eq!(exps("N.s/m"), [1, 0, -1, 0, 0, 0, 0, 0]);
        assert_eq!(exps("Pa"), exps("N/m2"));
        assert!((parse("deg").unwrap().factor - 0.017453292519943295).abs() < 1e-18);
        assert!((parse("mm/ms").unwrap().factor - 1.0).abs() < 1e-15);
    }

    #[test]
    fn bad_symbols_are_refused() {
        for bad in ["", "furlong", "m/s/s", "m s", "m..s", "m^x", "/s"] {
            assert!(parse(bad).is_err(), "{bad}");
        }
    }
}
