//! The filter checker: every filtered sign (the oracle's f64 filter, robust's orient3d, certified's
//! f32 stage under each model's bound) equals the exact sign on inputs from every exponent regime,
//! mixed scales inside one case included; and the checker is not vacuous: it refutes a bound without
//! its underflow terms (the bug issue 24 found), and the exact stage is reached in every regime.

use tetwalk::engine::filters::{Filter, Regime, Rounds, check, draw};
use tetwalk::methods::certified::{Bound, GRADUAL, f32_stage};
use tetwalk::tet::Ray;

#[test]
fn every_decided_sign_is_the_exact_sign_in_every_regime() {
    let c = check(5000, 24);
    for r in &c.refuted {
        eprintln!("{r:?}");
    }
    assert_eq!(c.wrong(), 0, "{} decided signs were wrong", c.wrong());
    for (regime, tallies) in &c.tallies {
        for (filter, t) in tallies {
            assert_eq!(t.asked, 5000, "{regime:?} {filter:?}");
        }
        // Certified's f32 stage is asked in every regime, and in the mixed and scaled ones it must
        // hand some signs to the exact stage (otherwise those regimes test nothing hard).
        let stage = |f: Filter| tallies.iter().find(|(g, _)| *g == f).unwrap().1;
        if matches!(regime, Regime::Mixed | Regime::Scaled) {
            assert!(stage(Filter::Certified).exact_stage > 0, "{regime:?}");
        }
        if *regime == Regime::Unit {
            // Away from underflow the f32 stage settles every sign but the near ties (two thirds of
            // the cases are drawn on or along an edge).
            assert!(
                stage(Filter::Certified).exact_stage * 4 < 5000 * 3,
                "{:?}",
                stage(Filter::Certified)
            );
        }
    }
}

#[test]
fn the_checker_refutes_a_bound_without_its_underflow_terms() {
    // The bound as it was before issue 24: no absolute error carried from w into the permanent.
    let old = Bound {
        mu: 0.0,
        c: 2f32.powi(-120),
        ..GRADUAL
    };
    let mut rng = tetwalk::scenes::rng(7);
    let mut refuted = 0;
    for regime in [Regime::Mixed, Regime::Scaled] {
        for _ in 0..20_000 {
            let x = draw(regime, &mut rng);
            let ray = Ray {
                org: x.org,
                dir: x.dir,
            };
            let exact = tetwalk::exact::side(x.a, x.b, &ray);
            if let Some(s) = f32_stage(x.a, x.b, &ray, old, false) {
                refuted += (s != exact) as u32;
            }
            // The real bound is right on the same inputs.
            if let Some(s) = f32_stage(x.a, x.b, &ray, GRADUAL, false) {
                assert_eq!(s, exact, "{x:?}");
            }
        }
    }
    assert!(refuted > 0, "the old bound was not refuted");
}

/// `check-filters`' rounds: seeds `S`, `S + 1`, ... summed (two rounds of one seed each equal
/// `check` of those seeds added), and the table and JSON report every regime and filter once.
#[test]
fn rounds_sum_their_seeds_and_the_report_shows_every_regime_and_filter() {
    let r = Rounds::run(300, 5, 0);
    assert_eq!(r.rounds, 1);
    let one = check(300, 5);
    assert_eq!(
        format!("{:?}", r.campaign.tallies),
        format!("{:?}", one.tallies)
    );
    let mut two = check(300, 5);
    two.add(check(300, 6));
    for ((_, x), (_, y)) in two.tallies.iter().zip(&one.tallies) {
        for ((_, a), (_, b)) in x.iter().zip(y) {
            assert_eq!(a.asked, 2 * b.asked);
        }
    }
    let table = tetwalk::report::filters::table(&r);
    assert!(table.starts_with("1 round from seed 5, 300 cases per regime and round"));
    let rows = Regime::ALL.len() * Filter::ALL.len();
    assert_eq!(
        table.lines().filter(|l| l.starts_with("| ")).count(),
        rows + 1
    );
    let json = serde_json::to_value(tetwalk::report::filters::report(&r)).unwrap();
    assert_eq!(json["rows"].as_array().unwrap().len(), rows);
    assert_eq!(json["cases_per_regime"], 300);
    assert_eq!(json["refuted"].as_array().unwrap().len(), 0);
}
