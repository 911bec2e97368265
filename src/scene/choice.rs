//! Choice parameters for importers that cannot set Enumerations.
//!
//! A choice (`integrator`, `contact_law`, `load_frame`, `hook_command`) is declared as an
//! Enumeration, which keeps its named items for importers that read them (fmpy, the CLI, scene
//! files). libcosim and Ecos skip Enumeration variables, so every choice also has a plain Integer
//! twin, `<name>_number`, with its own value reference: 0 (its start value) leaves the choice to
//! the Enumeration, 1..=n picks item n and overrides the Enumeration, whatever order the two were
//! set in. Why a twin and not an alias: docs/choice_parameters.md.

use super::port::{Causality, PortSpec, PortType, ValueRef, Variability};

/// Suffix of the Integer twin's name.
pub const NUMBER_SUFFIX: &str = "_number";

/// The item number in effect: the twin's when it is not 0, else the Enumeration's.
pub fn effective(enumeration: i32, number: i32) -> i32 {
    if number != 0 { number } else { enumeration }
}

/// The Integer twin of the Enumeration parameter `name` with `items`, at Integer value reference
/// `vr`: `<name>_number`, fixed, start 0, range 0..=items, its description listing the items.
pub fn number_twin(name: &str, items: &[(&str, &str)], vr: ValueRef) -> PortSpec {
    let list: Vec<String> = items
        .iter()
        .enumerate()
        .map(|(k, (item, _))| format!("{} {item}", k + 1))
        .collect();
    PortSpec {
        name: format!("{name}{NUMBER_SUFFIX}"),
        vr,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        ty: PortType::Integer {
            start: Some(0),
            min: Some(0),
            max: Some(items.len() as i32),
        },
        unit: None,
        description: format!(
            "`{name}` as a plain Integer, for importers that cannot set Enumerations (libcosim, Ecos): {}; 0: `{name}` decides; 1 or more overrides `{name}`.",
            list.join(", "),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static ITEMS: &[(&str, &str)] = &[("a", "first"), ("b", "second")];

    #[test]
    fn the_twin_overrides_only_when_not_zero() {
        assert_eq!(effective(2, 0), 2);
        assert_eq!(effective(2, 1), 1);
        assert_eq!(effective(1, 2), 2);
    }

    #[test]
    fn the_twin_is_an_integer_parameter_over_the_items() {
        let t = number_twin("law", ITEMS, 9);
        assert_eq!(t.name, "law_number");
        assert_eq!(t.vr, 9);
        assert_eq!(
            t.ty,
            PortType::Integer {
                start: Some(0),
                min: Some(0),
                max: Some(2)
            }
        );
        assert!(t.description.contains("1 a, 2 b"), "{}", t.description);
    }
}
