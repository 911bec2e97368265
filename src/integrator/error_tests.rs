//! The solver messages: every cause formats, and every remedy names integrators only by the
//! spellings the FMUs' `integrator` parameter accepts (issue #44 item 7: messages said "choose
//! gen-alpha" while the parameter takes `gen_alpha`).

use super::*;
use crate::scene::panel_lock::ports::INTEGRATORS as PANEL_LOCK;
use crate::scene::rope_block::ports::INTEGRATORS as ROPE_BLOCK;

const KINDS: [IntegratorKind; 6] = [
    IntegratorKind::GenAlpha,
    IntegratorKind::Bdf,
    IntegratorKind::Dopri5,
    IntegratorKind::Dopri5Tree,
    IntegratorKind::Verner65Tree,
    IntegratorKind::Verner87Tree,
];

fn newton(cause: NewtonCause) -> NewtonFailure {
    NewtonFailure { t: 1.25, cause }
}

/// One failure of every kind of [`Cause`], [`Collapse`], [`Passage`] and [`NewtonCause`].
fn every_cause() -> Vec<Cause> {
    let newton_causes = [
        NewtonCause::SingularMatrix("Newton matrix is singular (pivot 3 of 9 vanishes)".into()),
        NewtonCause::NonFinite("Newton residual"),
        NewtonCause::Diverged(Some(0.96)),
        NewtonCause::Diverged(None),
        NewtonCause::NoConvergence(12),
        NewtonCause::SlipModes,
    ];
    let mut causes = Vec::new();
    for c in &newton_causes {
        causes.push(Cause::FixedStepTooLarge {
            h: 1e-3,
            newton: newton(c.clone()),
        });
        causes.push(Cause::StepCollapse {
            h: 1e-15,
            why: Collapse::Newton {
                newton: newton(c.clone()),
                singular: None,
            },
        });
    }
    causes.push(Cause::StepCollapse {
        h: 1e-15,
        why: Collapse::Newton {
            newton: newton(NewtonCause::Diverged(None)),
            singular: Some(SingularPassage {
                joints: "'A', 'B'".into(),
                ratio: 1e-9,
                rtol: 1e-6,
            }),
        },
    });
    causes.push(Cause::StepCollapse {
        h: 1e-15,
        why: Collapse::EnergyGain { gain: 3.5 },
    });
    causes.push(Cause::StepCollapse {
        h: 1e-15,
        why: Collapse::ErrorEstimate,
    });
    causes.push(Cause::NonFinite { h: 1e-3 });
    causes.push(Cause::Stiffness {
        steps: 40,
        h_lambda: 3.3,
        h: 1e-6,
        more: 2e6,
        t_end: 2.0,
    });
    causes.push(Cause::StepBudget { max_steps: 200_000 });
    causes.push(Cause::Tolerance {
        rtol: 1e-10,
        atol: 1e-10,
        h: 1e-7,
        share: 0.13,
    });
    for how in [
        Passage::Branch {
            degrees: 170.0,
            until: 1.5,
        },
        Passage::Energy {
            change: 0.2,
            allowed: 1e-4,
            until: 1.5,
        },
        Passage::StepCollapse { h: 1e-15 },
    ] {
        causes.push(Cause::SingularConfiguration {
            joints: "'B'".into(),
            how,
        });
    }
    causes.push(Cause::Other("projection onto the joints failed".into()));
    // a new kind of cause must be added above: this match has no wildcard
    for c in &causes {
        match c {
            Cause::FixedStepTooLarge { .. }
            | Cause::StepCollapse { .. }
            | Cause::NonFinite { .. }
            | Cause::Stiffness { .. }
            | Cause::StepBudget { .. }
            | Cause::Tolerance { .. }
            | Cause::SingularConfiguration { .. }
            | Cause::Other(_) => {}
        }
    }
    causes
}

/// Every failure of [`every_cause`] as each integrator and outside one.
fn every_failure() -> Vec<Failure> {
    let kinds = KINDS.iter().map(|k| Some(*k)).chain([None]);
    kinds
        .flat_map(|kind| {
            every_cause().into_iter().map(move |cause| Failure {
                kind,
                t: Some(1.0),
                cause,
            })
        })
        .collect()
}

/// The words of `text` that name an integrator (any spelling: `gen-alpha`, `BDF`, `dopri5_tree`,
/// `Verner65`, ...).
fn integrator_words(text: &str) -> Vec<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'))
        .map(|w| w.trim_matches('-'))
        .filter(|w| {
            let l = w.to_ascii_lowercase();
            ["alpha", "bdf", "dopri", "verner", "runge", "kutta"]
                .iter()
                .any(|n| l.contains(n))
        })
        .map(str::to_string)
        .collect()
}

/// The spellings both FMUs' `integrator` parameter accepts.
fn accepted_by_both() -> Vec<&'static str> {
    PANEL_LOCK
        .iter()
        .map(|(name, _)| *name)
        .filter(|name| ROPE_BLOCK.iter().any(|(n, _)| n == name))
        .collect()
}

#[test]
fn the_word_scan_finds_integrator_names_in_any_spelling() {
    let words = integrator_words(
        "choose gen-alpha, BDF or dopri5-tree (or dopri5's projection, verner65_tree) when \
         ill-conditioned",
    );
    assert_eq!(
        words,
        ["gen-alpha", "BDF", "dopri5-tree", "dopri5", "verner65_tree"]
    );
    let accepted = accepted_by_both();
    assert!(!accepted.contains(&"gen-alpha") && accepted.contains(&"gen_alpha"));
}

#[test]
fn parameter_names_are_the_items_of_the_integrator_parameter() {
    // PanelLock's items are ALL in order, then Dopri5Tree and `auto` (no integrator of its own:
    // it resolves to one of the others); RopeBlock's are ALL
    let panel: Vec<&str> = PANEL_LOCK.iter().map(|(n, _)| *n).collect();
    let rope: Vec<&str> = ROPE_BLOCK.iter().map(|(n, _)| *n).collect();
    let all: Vec<&str> = IntegratorKind::ALL
        .iter()
        .map(|k| k.parameter_name().unwrap())
        .collect();
    assert_eq!(rope, all);
    assert_eq!(panel, [&all[..], &["dopri5_tree", "auto"]].concat());
    assert_eq!(
        IntegratorKind::Dopri5Tree.parameter_name(),
        Some("dopri5_tree")
    );
    // the library-only pairs have no spelling, so no remedy can advise them
    assert_eq!(IntegratorKind::Verner65Tree.parameter_name(), None);
    assert_eq!(IntegratorKind::Verner87Tree.parameter_name(), None);
}

#[test]
fn every_remedy_names_integrators_by_spellings_the_parameter_accepts() {
    let accepted = accepted_by_both();
    let mut advised = std::collections::BTreeSet::new();
    for f in every_failure() {
        let Some(remedy) = f.remedy() else {
            assert!(matches!(f.cause, Cause::Other(_)), "{f:?}");
            continue;
        };
        for word in integrator_words(&remedy) {
            assert!(
                accepted.contains(&word.as_str()),
                "the remedy of {f:?} names `{word}`, which the integrator parameter refuses (it takes {accepted:?}): {remedy}"
            );
            advised.insert(word);
        }
    }
    // the scan saw names: every integrator of the shared enumeration is advised somewhere
    assert_eq!(
        advised.into_iter().collect::<Vec<_>>(),
        ["bdf", "dopri5", "gen_alpha"]
    );
}

#[test]
fn messages_join_what_happened_and_the_remedy() {
    for f in every_failure() {
        let e = SolverError::new(f.clone());
        let message = e.to_string();
        match f.remedy() {
            Some(r) => assert_eq!(message, format!("{}; {r}", f.what())),
            None => assert_eq!(message, f.what()),
        }
        assert_eq!(String::from(e.clone()), message);
        assert_eq!(e.cause(), &f.cause);
        assert_eq!(e.failure(), &f);
        assert_eq!(
            format!("{e:?}"),
            format!("SolverError({message:?}, {f:?})"),
            "Debug shows the message"
        );
        assert!(!message.contains("NaN"), "{e}");
    }
}

#[test]
fn a_newton_collapse_is_explained_by_the_type_of_its_failure() {
    let collapse = |cause| {
        SolverError::at(
            IntegratorKind::GenAlpha,
            2.0,
            Cause::StepCollapse {
                h: 8e-15,
                why: Collapse::Newton {
                    newton: newton(cause),
                    singular: None,
                },
            },
        )
        .to_string()
    };
    let singular = collapse(NewtonCause::SingularMatrix(
        "Newton matrix is singular (pivot 3 of 9 vanishes)".into(),
    ));
    assert_eq!(
        singular,
        "step size fell below 8.0e-15 s at t = 2.000000000e0 s: Newton matrix is singular (pivot 3 \
         of 9 vanishes) at t = 1.250000000e0 s; the Newton matrix is singular here: a singular \
         configuration (joints whose constraints lose rank, e.g. a closed loop at a dead point) \
         or a body without mass or inertia"
    );
    let non_finite = collapse(NewtonCause::NonFinite("Newton matrix entries"));
    assert!(
        non_finite.contains("non-finite Newton matrix entries at t = 1.250000000e0 s")
            && non_finite.contains("a force law evaluated outside its range"),
        "{non_finite}"
    );
    let diverged = collapse(NewtonCause::Diverged(Some(0.96)));
    assert!(
        diverged.contains("Newton iteration diverges at t = 1.250000000e0 s (rate 0.96)")
            && diverged.contains("Newton does not converge however small the step"),
        "{diverged}"
    );
    let slip = collapse(NewtonCause::SlipModes);
    assert!(
        slip.contains("slip modes not settled at t = 1.250000000e0 s"),
        "{slip}"
    );
}

#[test]
fn the_stiffness_message_names_the_method_and_the_implicit_alternatives() {
    let e = SolverError::at(
        IntegratorKind::Dopri5,
        0.5,
        Cause::Stiffness {
            steps: 40,
            h_lambda: 3.3,
            h: 1e-6,
            more: 1.5e6,
            t_end: 2.0,
        },
    );
    assert_eq!(
        e.to_string(),
        "dopri5 is stiff here: 40 steps in a row up to t = 5.000000000e-1 s were held at its \
         stability boundary (h |lambda| up to 3.3), not by the tolerance, and at their size \
         (1.00e-6 s) this call needs 1.5e6 more steps to reach t = 2 s; a stiff spring, damper or \
         contact makes explicit steps this small: use integrator = bdf or gen_alpha"
    );
    assert_eq!(e.t(), Some(0.5));
}
