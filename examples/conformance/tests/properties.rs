//! The user's own property tests, drawing cases with the kit's generators (`tetwalk::kit::strategy`,
//! the `proptest` feature: `PROPTEST_CASES` scales them), the fuzz target's body on decoded inputs,
//! and a regression test holding a case line a report printed.

use proptest::prelude::*;
use tetwalk::kit::prelude::*;
use tetwalk::kit::strategy;
use tetwalk_conformance_example::{ExactPlucker, F32Plucker, fuzz_exact_plucker};

/// Unit directions, origins inside the tetrahedron: the contract a walker's step function has.
fn walker() -> Contract {
    Contract {
        origin: Origin::Inside.into(),
        unit_direction: true,
        ..Contract::default()
    }
}

/// A kit failure as proptest's, its report the message.
fn judged(r: Result<(), Box<Failed>>) -> Result<(), TestCaseError> {
    r.map_err(|f| TestCaseError::fail(f.to_string()))
}

proptest! {
    #[test]
    fn exact_plucker_on_fuzzed_cases(case in strategy::cases::<Case>()) {
        judged(judge_exit_face::<ExactPlucker>(&case, &Settings::default()))?;
    }

    #[test]
    fn exact_plucker_near_edges_inside_its_contract(
        case in strategy::row::<Case>("near-edge", walker()).unwrap()
    ) {
        judged(judge_exit_face::<ExactPlucker>(&case, &Settings::default()))?;
    }

    #[test]
    fn exact_plucker_walks_lattice_ties(case in strategy::row::<WalkCase>("kuhn", Contract::default()).unwrap()) {
        judged(judge_walk::<ExactPlucker>(&case, &Settings::default()))?;
    }
}

/// The same property over f32 Plücker fails, and proptest's own shrinking ends on a case the kit
/// reports (its runner run by hand so that the test can expect the failure).
#[test]
fn f32_plucker_fails_the_near_edge_property() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let rows = strategy::row::<Case>("near-edge", walker()).unwrap();
    let result = runner.run(&rows, |case| {
        judged(judge_exit_face::<F32Plucker>(&case, &Settings::default()))
    });
    let Err(proptest::test_runner::TestError::Fail(why, case)) = result else {
        panic!("f32 Plücker passed {result:?}");
    };
    assert!(why.message().contains("F32Plucker"), "{why}");
    assert!(judge_exit_face::<F32Plucker>(&case, &Settings::default()).is_err());
}

/// What the fuzz target runs, on inputs decoded as cargo-fuzz decodes them.
#[test]
fn the_fuzz_targets_body_holds_on_decoded_inputs() {
    use arbitrary::{Arbitrary, Unstructured};
    let mut decoded = 0;
    for seed in 0..300u32 {
        let bytes: Vec<u8> = (0..96u32)
            .map(|i| (seed.wrapping_mul(2654435761) ^ i.wrapping_mul(40503)).to_le_bytes()[1])
            .collect();
        if let Ok(case) = Case::arbitrary_take_rest(Unstructured::new(&bytes)) {
            fuzz_exact_plucker(case);
            decoded += 1;
        }
    }
    assert!(decoded > 100, "{decoded} of 300 inputs decoded");
}

/// A case the kit reported for `F32Plucker` (`Failed::case`, the shrunk case its `found:` line holds), kept as a
/// regression test: f32 Plücker still answers it wrongly, the exact test rightly.
const REPORTED: &str = r#"{"tet":[[0.0,0.0,0.0],[-0.0009765625,0.0,0.0],[0.0,0.0,0.00048828125],[1.1298828,-0.93847656,1.5969238]],"org":[1.0693359,-0.8885498,1.5117798],"dir":[-0.33236694,0.2763672,-0.4699707],"entry":2}"#;

#[test]
fn the_reported_case_is_judged_as_reported() {
    let case = Case::from_line(REPORTED).unwrap();
    assert_eq!(case.to_line(), REPORTED);
    let failed = judge_exit_face::<F32Plucker>(&case, &Settings::default()).unwrap_err();
    assert_eq!(failed.group, "case");
    judge_exit_face::<ExactPlucker>(&case, &Settings::default()).unwrap();
}
