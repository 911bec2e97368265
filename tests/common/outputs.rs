//! Reading the rows of a scene's outputs.

/// Kinetic + potential + dissipated - input (hook work) - events [J] from an output row, for
/// the output names `names` (the `energy.*` outputs of the scenes).
pub fn energy_balance(names: &[String]) -> impl Fn(&[f64]) -> f64 {
    let e: Vec<usize> = ["kinetic", "potential", "dissipated", "input", "events"]
        .iter()
        .map(|c| {
            let name = format!("energy.{c}");
            names.iter().position(|x| *x == name).unwrap()
        })
        .collect();
    move |o: &[f64]| o[e[0]] + o[e[1]] + o[e[2]] - o[e[3]] - o[e[4]]
}
