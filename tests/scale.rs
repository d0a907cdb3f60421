//! Stress rows at power-of-two scales (`stress --scale`): a case scaled by 2^E is the same geometry,
//! so where nothing underflows or overflows every f32 method answers it as it answers the case itself;
//! where products do underflow or overflow, claims can stop holding (`woop-watertight` at 2^60), and
//! `certified` and `exact` never do.

mod common;

use tetwalk::backend::CPU;
use tetwalk::engine::stress::{StressReport, StressSettings, run};
use tetwalk::family::{self, ExitFace, Family, OctreeCells, Scale, Triangle, Walks};

fn stress<F: Family>(cases: usize, scale: Scale, methods: &[&str]) -> StressReport<F> {
    let s = StressSettings::<F> {
        contract: Default::default(),
        cases,
        rows: F::Rows::default(),
        seed: 3,
        backend: CPU.ran(),
        scale,
    };
    let methods: Vec<&F::Method> = methods
        .iter()
        .map(|m| family::by_name::<F>(m).unwrap())
        .collect();
    run(
        &s,
        &tetwalk::engine::stress::Who::methods(&methods),
        &CPU,
        &|_| {},
        &mut |_| {},
    )
    .unwrap()
}

/// Each method's wrong answers, row by row.
fn wrong<F: Family>(r: &StressReport<F>) -> Vec<u64> {
    r.rows
        .iter()
        .flat_map(|row| row.tallies.iter().map(|t| F::wrong(&t.counts)))
        .collect()
}

/// Scaled by 2^20 or 2^-20 (the rows' coordinates stay far from underflow and overflow), every f32
/// method of every family answers exactly as at scale 1: the same wrong answers, row by row (walks
/// through the generated meshes scaled too).
#[test]
fn a_scale_in_range_changes_no_answer() {
    let tets = [
        "ray-plane",
        "plucker",
        "maria17",
        "aman20-scaled",
        "certified",
    ];
    let base = wrong(&stress::<ExitFace>(300, Scale::default(), &tets));
    assert!(base.iter().sum::<u64>() > 0);
    for e in [20, -20] {
        assert_eq!(
            wrong(&stress::<ExitFace>(300, Scale::uniform(e), &tets)),
            base
        );
    }
    let tris = ["mt", "woop-watertight"];
    let base = wrong(&stress::<Triangle>(20, Scale::default(), &tris));
    assert_eq!(
        wrong(&stress::<Triangle>(20, Scale::uniform(20), &tris)),
        base
    );
    let walks = ["maria17", "ray-plane"];
    let base = wrong(&stress::<Walks>(100, Scale::default(), &walks));
    assert!(base.iter().sum::<u64>() > 0);
    assert_eq!(
        wrong(&stress::<Walks>(100, Scale::uniform(20), &walks)),
        base
    );
    let cells = ["portalez16", "portalez16-direction"];
    let base = wrong(&stress::<OctreeCells>(200, Scale::default(), &cells));
    assert_eq!(
        wrong(&stress::<OctreeCells>(200, Scale::uniform(-20), &cells)),
        base
    );
}

/// Far from 1, `woop-watertight`'s products overflow and its claim stops holding: it leaks through
/// edges at 2^60 and at 2^-70, and not at 1.
#[test]
fn woop_watertight_leaks_where_its_products_overflow_or_underflow() {
    let leaks = |e: i32| {
        let r = stress::<Triangle>(20, Scale::uniform(e), &["woop-watertight"]);
        r.rows
            .iter()
            .map(|row| Triangle::refuted(&row.tallies[0].counts))
            .sum::<u64>()
    };
    assert_eq!(leaks(0), 0);
    assert!(leaks(60) > 0);
    assert!(leaks(-70) > 0);
}

/// `certified` and `exact` are right at every scale, the direction's own scale apart from the points'
/// too, where products underflow and overflow.
#[test]
fn certified_and_exact_are_right_at_every_scale() {
    for s in [
        Scale::uniform(-140),
        Scale::uniform(110),
        Scale {
            points: 0,
            direction: -120,
        },
        Scale {
            points: -60,
            direction: 60,
        },
    ] {
        let r = stress::<ExitFace>(200, s, &["certified", "exact"]);
        assert!(judged(&r) > 1000, "{s}: {}", judged(&r));
        assert_eq!(wrong(&r).iter().sum::<u64>(), 0, "{s}");
        let r = stress::<Walks>(40, s, &["certified", "exact"]);
        assert!(judged(&r) >= 80, "walks at {s}: {}", judged(&r));
        assert_eq!(wrong(&r).iter().sum::<u64>(), 0, "walks at {s}");
    }
    // Where its products underflow, maria17 walks go wrong on nearly every ray.
    let r = stress::<Walks>(40, Scale::uniform(-100), &["maria17"]);
    assert!(wrong(&r).iter().sum::<u64>() * 10 > judged(&r) * 9, "{r:?}");
}

/// Cases judged over the rows.
fn judged<F: Family>(r: &StressReport<F>) -> u64 {
    r.rows
        .iter()
        .map(|row| F::judged(&row.facts, &row.tallies[0].counts))
        .sum()
}

/// `--scale` is refused for an exponent out of range; the report says the scale, for walks too (their
/// generated meshes scaled with the rays).
#[test]
fn the_command_line_scales_what_scales() {
    let (code, out, err) = common::run_tetwalk(
        &[
            "stress", "--family", "walk", "--scale", "-10", "--cases", "20", "--scenes", "fan",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("every case scaled by 2^-10"), "{out}");
    let (code, _, err) = common::run_tetwalk(&["stress", "--scale", "400"], b"");
    assert_eq!(code, 2);
    assert!(err.contains("400"), "{err}");
    let (code, out, err) = common::run_tetwalk(
        &[
            "stress",
            "--cases",
            "20",
            "--rows",
            "well",
            "--scale=-30/40",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("every case scaled by 2^-30, direction 2^40"),
        "{out}"
    );
}
