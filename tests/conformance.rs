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
