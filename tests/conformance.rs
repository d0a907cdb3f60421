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
