//! The user's `cargo test`: each method judged by tetwalk's conformance kit, one call each.

use tetwalk::cases::Subject;
use tetwalk::conformance::{self, Accept, Settings};
use tetwalk::found::Answer;
use tetwalk::methods::triangle::SingleRay;
use tetwalk::methods::{CellMethod, ExitMethod, Plain};
use tetwalk_conformance_example::{
    ExactEdges, ExactPlucker, ExactSlabs, F32MollerTrumbore, F32Plucker, F32Slabs,
};

#[test]
fn exact_plucker_passes_every_family() {
    let passed = conformance::exit_faces::<ExactPlucker>(&Settings::default());
    // Every stress row, every lattice-tie scene and the property campaign were judged.
    assert_eq!(
        passed.families.len(),
        10 + conformance::WALK_SCENES.len() + 1
    );
    assert!(
        passed
            .families
            .iter()
            .all(|(_, judged, failed)| *judged > 0 && *failed == 0)
    );
}

#[test]
fn f32_plucker_is_caught_with_a_case_that_fails_again() {
    let failed = conformance::check_exit_faces::<F32Plucker>("f32-plucker", &Settings::default())
        .expect_err("rounded side products must be caught");
    let report = failed.to_string();
    println!("{report}");
    assert!(report.contains("f32-plucker") && report.contains(&failed.family));
    // The report's case line, read back, makes the method answer as recorded, and wrongly.
    let line = report
        .lines()
        .find_map(|l| l.trim_start().strip_prefix("case:"))
        .unwrap();
    let Subject::Exit(case) = Subject::parse(line.trim()).unwrap() else {
        panic!("the stress rows judge single tetrahedra first: {line}");
    };
    let Some(Answer::Face(face)) = failed.record.failure.map(|f| f.answer) else {
        panic!("{report}");
    };
    let (tet, entry, map) = tetwalk::cases::normalized(&case);
    let again =
        F32Plucker::exit_face::<Plain>(&tet, &F32Plucker::prepare::<Plain>(&case.ray()), entry);
    assert_eq!(again.map(|f| map[f] as u8), face);
    let exact = tetwalk::cases::classify(&case).unwrap();
    assert!(!face.is_some_and(|f| exact.exit.contains(f as usize)));
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
    let passed = conformance::check_exit_faces::<F32Plucker>("f32-plucker", &lenient).unwrap();
    assert!(passed.families.iter().any(|(_, _, failed)| *failed > 0));
}

/// The watertight claim: only leaks count.
fn watertight() -> Settings {
    Settings {
        accept: Accept {
            leaks_only: true,
            ..Accept::default()
        },
        ..Settings::default()
    }
}

#[test]
fn exact_edges_never_leak() {
    conformance::triangles::<ExactEdges>(&watertight());
}

#[test]
fn f32_moller_trumbore_leaks_and_is_caught() {
    let failed = conformance::check_triangles::<F32MollerTrumbore>("f32-mt", &watertight())
        .expect_err("f32 Möller-Trumbore leaks through shared edges");
    println!("{failed}");
    let Subject::Hit(case) = failed.record.subject else {
        panic!("a triangle family judges triangle cases")
    };
    // The ray passes through the closed surface and the method hits none of its triangles.
    let truth = tetwalk::cases::judge_hit(&case).unwrap();
    let hits: Vec<u32> = (0..case.tris().len() as u32)
        .filter(|&i| {
            F32MollerTrumbore::test::<Plain>(&case.tris()[i as usize], &case.ray())
                .is_some_and(|t| t > 0.0 && t.is_finite())
        })
        .collect();
    assert!(truth.leaks(&hits), "{failed}");
}

#[test]
fn exact_slabs_pass_every_octree_row() {
    let passed = conformance::cells::<ExactSlabs>(&Settings::default());
    assert!(
        passed
            .families
            .iter()
            .all(|(_, judged, failed)| *judged > 0 && *failed == 0)
    );
}

#[test]
fn f32_slabs_are_caught_on_an_octree_row() {
    let failed = conformance::check_cells::<F32Slabs>("f32-slabs", &Settings::default())
        .expect_err("rounded exit points leave edges and centre lines");
    println!("{failed}");
    let Subject::Box(case) = failed.record.subject else {
        panic!("an octree family judges cells")
    };
    let got = F32Slabs::exit::<Plain>(case.lo, case.hi, &case.ray());
    let exact = tetwalk::exact::boxes::box_exit(case.lo, case.hi, &case.ray()).unwrap();
    let signs = got.map(|(f, q)| (f, tetwalk::octree::cell::quarter_signs(q)));
    assert_eq!(exact.right(signs), Some(false), "{failed}");
}
