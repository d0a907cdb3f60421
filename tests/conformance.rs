//! The conformance kit judges like tetwalk's own reports: a registered method run through the kit (as
//! a user's type) fails exactly the stress cases `tetwalk stress` counts for it, and the kit's report
//! holds a case the method answers wrongly, which read back fails again. The user-side routes are in
//! `examples/conformance/`.

use tetwalk::backend::CPU;
use tetwalk::engine::found::Found;
use tetwalk::engine::stress::{self, StressSettings};
use tetwalk::family::{ExitFace, Family, OctreeCells, Triangle};
use tetwalk::kit::{self, Accept, Failed, Passed, Settings};
use tetwalk::methods::Model;
use tetwalk::methods::triangle::Mt;
use tetwalk::methods::{Certified, Plucker};
use tetwalk::registry::Named;

fn lenient() -> Settings {
    Settings {
        cases: 400,
        properties: 400,
        accept: Accept {
            per_million: 1e6,
            ..Accept::default()
        },
        ..Settings::default()
    }
}

/// Each stress row of family `F` of `tetwalk stress` for registered method `name`, beside the kit's
/// group of the same row for the same method run as a user's type: the same cases judged, the same
/// failures; some row fails.
fn kit_counts_as_stress_does<F: Family>(passed: &Passed, name: &str, s: &Settings) {
    let st = StressSettings::<F> {
        contract: Default::default(),
        cases: F::kit_row_cases(s.cases),
        rows: Default::default(),
        seed: s.seed,
        backend: CPU.ran(),
        scale: Default::default(),
    };
    let m = tetwalk::family::by_name::<F>(name).unwrap();
    let report = stress::run(&st, &[stress::Who::Method(m)], &CPU, &|_| {}, &mut |_| {}).unwrap();
    let mut failed_somewhere = false;
    for row in &report.rows {
        let t = &row.tallies[0].counts;
        let group = format!("stress row {}", F::row_name(&row.row));
        let g = passed.groups.iter().find(|g| g.name == group).unwrap();
        assert_eq!(
            (g.judged, g.failed),
            (F::judged(&row.facts, t), F::wrong(t)),
            "{group}"
        );
        failed_somewhere |= g.failed > 0;
    }
    assert!(failed_somewhere, "{name} fails some stress row");
}

#[test]
fn the_kit_counts_what_stress_counts_for_the_same_arithmetic() {
    let s = lenient();
    let passed = kit::exit_faces::<Plucker>(&s).unwrap();
    kit_counts_as_stress_does::<ExitFace>(&passed, "plucker", &s);
}

#[test]
fn the_kit_counts_what_octree_stress_counts() {
    use tetwalk::methods::portalez16::{Direction, Portalez16};
    let s = lenient();
    let passed = kit::cells::<Portalez16<Direction>>(&s).unwrap();
    kit_counts_as_stress_does::<OctreeCells>(&passed, "portalez16-direction", &s);
}

#[test]
fn certified_passes_the_kit_and_mt_is_caught() {
    let strict = Settings {
        cases: 400,
        properties: 400,
        ..Settings::default()
    };
    kit::exit_faces::<Certified>(&strict).unwrap();
    let failed = kit::triangles::<Mt>(&strict).unwrap_err();
    // The report names the method and group and gives the case on one line, judged wrong again.
    let text = failed.to_string();
    assert!(
        text.contains("`Mt`") && text.contains(&failed.group),
        "{text}"
    );
    assert!(failed.reproduced, "{text}");
    let case = Found::<Triangle>::parse(&failed.case).unwrap().case;
    let truth = Triangle::truth(&case).unwrap();
    let hits = tetwalk::family::by_name::<Triangle>("mt")
        .unwrap()
        .hits(Model::Plain)(case.tris(), &case.ray());
    assert!(
        !truth.right(tetwalk::methods::triangle::nearest_of(&hits).map(|h| h.0)),
        "{text}"
    );
}

/// Wrong exactly where the line only touches the tetrahedron (the perturbed line misses it): a face
/// that is not an exact exit face; elsewhere the perturbed exit face, always right.
struct WrongWhereTouching;

impl tetwalk::methods::ExitMethod for WrongWhereTouching {
    type RayData = tetwalk::tet::Ray;

    fn prepare<A: tetwalk::methods::Arith>(ray: &tetwalk::tet::Ray) -> tetwalk::tet::Ray {
        *ray
    }

    fn exit_face<A: tetwalk::methods::Arith>(
        tet: &tetwalk::tet::Tet,
        ray: &tetwalk::tet::Ray,
        _entry: Option<usize>,
    ) -> Option<usize> {
        let (face, x) = tetwalk::exact::perturbed_exit(tet, ray).ok()?;
        match face {
            Some(f) => Some(f),
            None => (0..4).find(|&f| !x.exit.contains(f)),
        }
    }
}

/// `Accept::touch_only` lets through wrong faces on touching lines, and nothing else: the method wrong
/// only there passes with it and is caught without it; f32 Plücker, wrong on crossing lines too, is
/// caught with it.
#[test]
fn touch_only_accepts_touching_lines_alone() {
    let with = |touch_only: bool| Settings {
        cases: 400,
        properties: 400,
        accept: Accept {
            touch_only,
            ..Accept::default()
        },
        ..Settings::default()
    };
    kit::exit_faces::<WrongWhereTouching>(&with(true)).unwrap();
    // The perturbed line's exit face: none where the line only touches.
    let perturbed = |caught: &Failed| {
        let c = Found::<ExitFace>::parse(&caught.case).unwrap().case;
        let (tet, _, _) = tetwalk::cases::normalized(&c);
        tetwalk::exact::perturbed_exit(&tet, &c.ray()).unwrap().0
    };
    let caught = kit::exit_faces::<WrongWhereTouching>(&with(false)).unwrap_err();
    assert_eq!(
        perturbed(&caught),
        None,
        "caught where it touches: {caught}"
    );
    let caught = kit::exit_faces::<Plucker>(&with(true)).unwrap_err();
    assert!(
        perturbed(&caught).is_some(),
        "the case Plücker fails on is crossed, not touched: {caught}"
    );
    assert!(caught.reproduced, "{caught}");
    // The kit names a method by its type, without module paths.
    assert_eq!(caught.method, "Plucker");
}

#[test]
fn a_registered_method_through_the_kit_is_named_as_registered() {
    let passed = kit::run::registered::<ExitFace>("certified", &lenient())
        .unwrap()
        .unwrap();
    assert!(passed.groups.iter().all(|g| g.failed == 0 && g.judged > 0));
    let m = tetwalk::family::by_name::<ExitFace>("certified").unwrap();
    assert_eq!(m.name(), "certified");
}

/// The kit holds a method to its contract: f32 Plücker judged with origins strictly inside the
/// tetrahedron still fails, and its failure, shrunk, keeps the origin strictly inside (checked here
/// exactly); the well-shaped row it passes is judged in full.
#[test]
fn the_kit_keeps_every_case_and_shrink_inside_the_contract() {
    use tetwalk::kit::prelude::{Contract, Origin};
    let s = Settings {
        cases: 400,
        properties: 400,
        contract: Contract {
            origin: Origin::Inside.into(),
            unit_direction: true,
            ..Contract::default()
        },
        ..Settings::default()
    };
    let failed = tetwalk::kit::run::registered::<ExitFace>("plucker", &s)
        .unwrap()
        .expect_err("f32 Plücker fails near edges whatever the origin");
    for line in [&failed.case, &failed.original] {
        let c = tetwalk::engine::found::Found::<ExitFace>::parse(line)
            .unwrap()
            .case;
        let side = |f: usize| {
            let [a, b, d] = tetwalk::tet::FACE_VERTICES[f].map(|i| c.tet[i]);
            tetwalk::tet::orientation(&[a, b, d, c.org])
                * tetwalk::tet::orientation(&[a, b, d, c.tet[f]])
        };
        assert!((0..4).all(|f| side(f) > 0), "{line}");
        assert!((c.dir.as_dvec3().length() - 1.0).abs() < 1e-6, "{line}");
    }
}

/// The kit runs a method in any arithmetic model of the list (`Settings::model`), not only plain and
/// fused: `certified` passes in each, and f32 Plücker fails in each.
#[test]
fn the_kit_runs_every_arithmetic_model() {
    use tetwalk::kit::prelude::Model;
    for model in Model::ALL {
        let s = Settings {
            cases: 200,
            properties: 200,
            model,
            ..Settings::default()
        };
        tetwalk::kit::run::registered::<ExitFace>("certified", &s)
            .unwrap()
            .unwrap_or_else(|f| panic!("{model:?}: {f}"));
        assert!(
            tetwalk::kit::run::registered::<ExitFace>("plucker", &s)
                .unwrap()
                .is_err(),
            "{model:?}"
        );
    }
}

/// Exact exit faces numbered otherwise: its face i is tetwalk's face `RENUMBER[i]` (an involution).
struct RenumberedCertified;
const RENUMBER: [usize; 4] = [2, 3, 0, 1];

impl tetwalk::methods::ExitMethod for RenumberedCertified {
    type RayData = <Certified as tetwalk::methods::ExitMethod>::RayData;
    fn prepare<A: tetwalk::methods::Arith>(ray: &tetwalk::tet::Ray) -> Self::RayData {
        <Certified as tetwalk::methods::ExitMethod>::prepare::<A>(ray)
    }
    fn exit_face<A: tetwalk::methods::Arith>(
        tet: &tetwalk::tet::Tet,
        ray: &Self::RayData,
        entry: Option<usize>,
    ) -> Option<usize> {
        let e = entry.map(|e| RENUMBER[e]);
        <Certified as tetwalk::methods::ExitMethod>::exit_face::<A>(tet, ray, e)
            .map(|f| RENUMBER[f])
    }
}

/// f32 Plücker written for negatively oriented tetrahedra: it mirrors what it is handed (vertices 0
/// and 1 swapped) before its side products, and answers in the handed one's numbering.
struct NegativePlucker;

impl tetwalk::methods::ExitMethod for NegativePlucker {
    type RayData = <Plucker as tetwalk::methods::ExitMethod>::RayData;
    fn prepare<A: tetwalk::methods::Arith>(ray: &tetwalk::tet::Ray) -> Self::RayData {
        <Plucker as tetwalk::methods::ExitMethod>::prepare::<A>(ray)
    }
    fn exit_face<A: tetwalk::methods::Arith>(
        tet: &tetwalk::tet::Tet,
        ray: &Self::RayData,
        entry: Option<usize>,
    ) -> Option<usize> {
        let mut t = *tet;
        t.swap(0, 1);
        let swap = tetwalk::tet::SWAP01;
        <Plucker as tetwalk::methods::ExitMethod>::exit_face::<A>(&t, ray, entry.map(|e| swap[e]))
            .map(|f| swap[f])
    }
}

/// The convention check runs first and says what it found: a method numbering faces otherwise is
/// stopped with the numbering its answers fit, one written for negatively oriented tetrahedra with
/// the orientation; neither is reported as a stress row wrong on every case. A method in tetwalk's
/// convention passes it (the other tests here).
#[test]
fn the_convention_check_names_another_face_numbering_or_orientation() {
    let s = lenient();
    let f = kit::exit_faces::<RenumberedCertified>(&s).unwrap_err();
    println!("{f}");
    assert_eq!((f.group.as_str(), f.judged), ("convention check", 0), "{f}");
    let note = f.note.clone().unwrap();
    assert!(note.contains("tetwalk's face [2, 3, 0, 1][i]"), "{note}");
    assert!(
        f.to_string().contains("not judged in `convention check`"),
        "{f}"
    );
    let f = kit::exit_faces::<NegativePlucker>(&s).unwrap_err();
    println!("{f}");
    let note = f.note.clone().unwrap();
    assert_eq!(f.group, "convention check", "{f}");
    assert!(
        note.contains("negatively oriented") && !note.contains("[i]"),
        "{note}"
    );
}

/// `every_group` runs every group and reports each failing one; without it the first stops the run.
#[test]
fn every_group_reports_each_failing_group() {
    let s = Settings {
        cases: 400,
        properties: 400,
        ..Settings::default()
    };
    let first = kit::exit_faces::<Plucker>(&s).unwrap_err();
    assert!(first.also.is_empty());
    let all = kit::exit_faces::<Plucker>(&Settings {
        every_group: true,
        ..s
    })
    .unwrap_err();
    assert_eq!(all.group, first.group);
    let mut groups: Vec<&str> = std::iter::once(&*all)
        .chain(&all.also)
        .map(|f| f.group.as_str())
        .collect();
    assert!(groups.len() > 1, "{groups:?}");
    // Walks' groups too (the exit-face family's failures do not stop them), each once.
    assert!(
        groups
            .iter()
            .any(|g| g.contains("walk") || g.contains("lattice")),
        "{groups:?}"
    );
    let n = groups.len();
    groups.dedup();
    assert_eq!(groups.len(), n);
    let text = all.to_string();
    assert!(
        all.also
            .iter()
            .all(|f| text.contains(&f.found) && !f.found.is_empty()),
        "{text}"
    );
}

/// A reported case line read back into a case ([`kit::KitCase::from_line`]) for each family, as a
/// regression test would: the same case, its line the same, judged one at a time with the one-case
/// entry points — the failing method fails it again, the exact one passes it.
#[test]
fn a_reported_case_line_reads_back_into_a_regression_test() {
    use tetwalk::kit::prelude::*;
    let s = Settings {
        cases: 400,
        properties: 400,
        ..Settings::default()
    };
    let f = exit_faces::<Plucker>(&s).unwrap_err();
    for line in [&f.case, &f.original, &f.found] {
        let c = Case::from_line(line).unwrap();
        assert!(judge_exit_face::<Plucker>(&c, &s).is_err(), "{line}");
        judge_exit_face::<Certified>(&c, &s).unwrap();
    }
    assert_eq!(Case::from_line(&f.case).unwrap().to_line(), f.case);
    let f = triangles::<Mt>(&s).unwrap_err();
    let c = HitCase::from_line(&f.case).unwrap();
    assert!(judge_triangle::<Mt>(&c, &s).is_err(), "{}", f.case);
    assert_eq!(c.to_line(), f.case);
    // A line of another family, or not a case, is refused with the reason.
    let e = Case::from_line(&f.case).unwrap_err().to_string();
    assert!(e.contains("field"), "{e}");
    assert!(Case::from_line("{\"tet\": 1}").is_err());
}

/// Every family's case type decodes fuzzer bytes as its fuzz target does (`arbitrary::Arbitrary`),
/// reads back from its own line, is made to hold a contract, and is drawn from a stress row by name.
#[test]
fn each_familys_cases_are_generated_read_and_written() {
    use tetwalk::kit::prelude::*;
    fn family<C: KitCase + for<'a> arbitrary::Arbitrary<'a>>() {
        let mut rng = 0x1234_5678u64;
        let mut made = 0;
        for _ in 0..200 {
            let bytes: Vec<u8> = (0..120)
                .map(|_| {
                    rng = rng
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    (rng >> 56) as u8
                })
                .collect();
            let via_trait = C::arbitrary(&mut arbitrary::Unstructured::new(&bytes)).ok();
            assert_eq!(via_trait, C::from_bytes(&bytes));
            if let Some(c) = via_trait {
                made += 1;
                assert_eq!(C::from_line(&c.to_line()).unwrap(), c, "{}", C::FAMILY);
                let unit = Contract {
                    unit_direction: true,
                    ..Contract::default()
                };
                if let Some(u) = c.within(&unit, 1) {
                    let line = u.to_line();
                    assert_eq!(C::from_line(&line).unwrap(), u);
                }
            }
        }
        assert!(made > 50, "{}: {made} of 200 inputs made a case", C::FAMILY);
        let rows = C::rows();
        assert!(!rows.is_empty());
        let drawn = (0..20)
            .filter_map(|i| C::row_case(&rows[0], 7, i).unwrap())
            .count();
        assert!(drawn > 0, "{}", C::FAMILY);
        assert_eq!(
            C::row_case(&rows[0], 7, 3).unwrap(),
            C::row_case(&rows[0], 7, 3).unwrap()
        );
        let e = C::row_case("no-such-row", 7, 0).unwrap_err().to_string();
        assert!(e.contains(&rows[0]), "{e}");
    }
    family::<Case>();
    family::<WalkCase>();
    family::<HitCase>();
    family::<BoxCase>();
}
