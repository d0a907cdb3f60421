//! The user's `cargo test`: each method judged by tetwalk's conformance kit, one call each.

use tetwalk::kit::prelude::*;
use tetwalk_conformance_example::{
    ExactEdges, ExactPlucker, ExactSlabs, F32MollerTrumbore, F32Plucker, F32Slabs,
};

#[test]
fn exact_plucker_passes_every_group() {
    let passed = exit_faces::<ExactPlucker>(&Settings::default()).unwrap();
    // Every stress row of tetrahedra (11) and its property campaign, every lattice-tie scene (5) and
    // its property campaign were judged.
    assert_eq!(passed.groups.len(), 11 + 1 + 5 + 1);
    assert!(passed.groups.iter().all(|g| g.judged > 0 && g.failed == 0));
}

#[test]
fn f32_plucker_is_caught_with_a_case_that_fails_again() {
    let failed = exit_faces::<F32Plucker>(&Settings::default())
        .expect_err("rounded side products must be caught");
    println!("{failed}");
    let report = failed.to_string();
    assert!(report.contains("F32Plucker") && report.contains(&failed.group));
    // The report's case line, read back, makes the method answer as recorded, and wrongly.
    assert!(failed.reproduced, "{report}");
    assert!(report.contains(&failed.found));
    // The found line holds the shrunk case and, as "original", the case as the group found it, each
    // printed once.
    use tetwalk::kit::prelude::*;
    let found: serde_json::Value = serde_json::from_str(&failed.found).unwrap();
    assert_eq!(
        Case::from_line(&failed.found).unwrap(),
        Case::from_line(&failed.case).unwrap()
    );
    assert_eq!(
        Case::from_line(&found["original"].to_string()).unwrap(),
        Case::from_line(&failed.original).unwrap()
    );
    assert_eq!(report.matches("\"tet\"").count(), 2, "{report}");
}

#[test]
fn f32_plucker_passes_when_its_failures_are_within_budget() {
    let lenient = Settings {
        accept: Accept {
            per_million: 1e6,
            ..Accept::default()
        },
        ..Settings::default()
    };
    let passed = exit_faces::<F32Plucker>(&lenient).unwrap();
    assert!(passed.groups.iter().any(|g| g.failed > 0));
}

/// The watertight claim: only leaks count.
fn watertight() -> Settings {
    Settings {
        accept: Accept {
            claim_only: true,
            ..Accept::default()
        },
        ..Settings::default()
    }
}

#[test]
fn exact_edges_never_leak() {
    triangles::<ExactEdges>(&watertight()).unwrap();
}

#[test]
fn f32_moller_trumbore_leaks_and_is_caught() {
    let failed = triangles::<F32MollerTrumbore>(&watertight())
        .expect_err("f32 Möller-Trumbore leaks through shared edges");
    println!("{failed}");
    // The ray passes through the closed surface and the method hits none of its triangles, again
    // when the case is read back from its line.
    assert_eq!(failed.family, "triangle");
    assert!(failed.reproduced, "{failed}");
}

#[test]
fn exact_slabs_pass_every_octree_row() {
    let passed = cells::<ExactSlabs>(&Settings::default()).unwrap();
    assert!(passed.groups.iter().all(|g| g.judged > 0 && g.failed == 0));
}

#[test]
fn f32_slabs_are_caught_on_an_octree_row() {
    let failed = cells::<F32Slabs>(&Settings::default())
        .expect_err("rounded exit points leave edges and centre lines");
    println!("{failed}");
    assert_eq!(failed.family, "octree");
    assert!(failed.reproduced, "{failed}");
}
