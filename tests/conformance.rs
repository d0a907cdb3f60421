//! The conformance kit judges like tetwalk's own reports: a registered method run through the kit (as
//! a user's type) fails exactly the stress cases `tetwalk stress` counts for it, and the kit's report
//! holds a case the method answers wrongly. The user-side routes are in `examples/conformance/`.

use tetwalk::backend::CPU;
use tetwalk::choice::Choice;
use tetwalk::conformance::{Accept, Settings, check_exit_faces, check_triangles};
use tetwalk::methods::Model;
use tetwalk::methods::triangle::Mt;
use tetwalk::methods::{Certified, Plucker};
use tetwalk::registry::by_name;
use tetwalk::report::stress::{self, Row};

fn lenient() -> Settings {
    Settings {
        cases: 400,
        rays: 300,
        properties: 400,
        accept: Accept {
            per_million: 1e6,
            ..Accept::default()
        },
        ..Settings::default()
    }
}

#[test]
fn the_kit_counts_what_stress_counts_for_the_same_arithmetic() {
    let s = lenient();
    let passed = check_exit_faces::<Plucker>("plucker", &s).unwrap();
    let st = stress::Settings {
        cases: s.cases,
        rows: Row::ALL.to_vec(),
        seed: s.seed,
        backend: "cpu".into(),
        flatness: 1e-3,
        ulps: 4,
        relabel: [0, 1, 2, 3],
    };
    let report = stress::run(
        &st,
        &[by_name("plucker").unwrap()],
        &CPU,
        &|_| {},
        &mut |_, _, _, _| {},
    )
    .unwrap();
    let mut failed_somewhere = false;
    for row in &report.rows {
        let t = &row.tallies[0];
        let family = format!("stress row {}", row.row.name());
        let (_, judged, failed) = passed
            .families
            .iter()
            .find(|(f, _, _)| *f == family)
            .unwrap();
        assert_eq!(
            (*judged, *failed),
            (t.judged, t.wrong_face + t.no_exit_face),
            "{family}"
        );
        failed_somewhere |= *failed > 0;
    }
    assert!(failed_somewhere, "plucker in f32 fails some stress row");
}

#[test]
fn certified_passes_the_kit_and_mt_is_caught() {
    let strict = Settings {
        cases: 400,
        rays: 300,
        properties: 400,
        ..Settings::default()
    };
    check_exit_faces::<Certified>("certified", &strict).unwrap();
    let failed = check_triangles::<Mt>("mt", &strict).unwrap_err();
    // The report names the method and family and gives the case on one line, judged wrong again.
    let text = failed.to_string();
    assert!(
        text.contains("`mt`") && text.contains(&failed.family),
        "{text}"
    );
    let case = tetwalk::cases::Subject::parse(&failed.case()).unwrap();
    let tetwalk::cases::Subject::Hit(case) = case else {
        panic!("{text}")
    };
    let truth = tetwalk::cases::judge_hit(&case).unwrap();
    let hits = mt_hits(&case);
    assert!(
        !truth.right(tetwalk::methods::triangle::nearest_of(&hits).map(|h| h.0)),
        "{text}"
    );
}

fn mt_hits(case: &tetwalk::cases::HitCase) -> Vec<(u32, f32)> {
    tetwalk::registry::triangle_by_name("mt")
        .unwrap()
        .hits(Model::Plain)(case.tris(), &case.ray())
}

#[test]
fn the_kit_counts_what_octree_stress_counts() {
    use tetwalk::methods::portalez16::{Direction, Portalez16};
    use tetwalk::scenes::cells::{Aim, Place};
    let s = lenient();
    let passed = tetwalk::conformance::check_cells::<Portalez16<Direction>>("p16d", &s).unwrap();
    let st = tetwalk::report::octree::StressSettings {
        cases: s.cases,
        aims: Aim::ALL.to_vec(),
        places: Place::ALL.to_vec(),
        seed: s.seed,
        backend: "cpu".into(),
        ulps: 4,
    };
    let m = tetwalk::registry::octree_by_name("portalez16-direction").unwrap();
    let report = tetwalk::report::octree::stress(&st, &[m], &CPU, &mut |_, _| {}).unwrap();
    let mut failed_somewhere = false;
    for row in &report.rows {
        let family = format!("stress row {}-{}", row.aim.name(), row.place.name());
        let (_, judged, failed) = passed
            .families
            .iter()
            .find(|(f, _, _)| *f == family)
            .unwrap();
        assert_eq!(
            (*judged, *failed),
            (row.tallies[0].judged, row.tallies[0].wrong),
            "{family}"
        );
        failed_somewhere |= *failed > 0;
    }
    assert!(failed_somewhere, "corner rows reach eq. 8's 7");
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
        rays: 100,
        properties: 400,
        accept: Accept {
            touch_only,
            ..Accept::default()
        },
        ..Settings::default()
    };
    check_exit_faces::<WrongWhereTouching>("touching", &with(true)).unwrap();
    // The perturbed line's exit face: none where the line only touches.
    let perturbed = |caught: &tetwalk::conformance::Failed| {
        let case = tetwalk::cases::Subject::parse(&caught.case()).unwrap();
        let tetwalk::cases::Subject::Exit(c) = case else {
            panic!("{caught}")
        };
        let (tet, _, _) = tetwalk::cases::normalized(&c);
        tetwalk::exact::perturbed_exit(&tet, &c.ray()).unwrap().0
    };
    let caught = check_exit_faces::<WrongWhereTouching>("touching", &with(false)).unwrap_err();
    assert_eq!(
        perturbed(&caught),
        None,
        "caught where it touches: {caught}"
    );
    let caught = check_exit_faces::<Plucker>("plucker", &with(true)).unwrap_err();
    assert!(
        perturbed(&caught).is_some(),
        "the case Plücker fails on is crossed, not touched: {caught}"
    );
}
