//! One verdict per answer: a ray–triangle answer is judged by one rule (`HitTruth::judge`: its
//! triangle and, for a hit, its `t` within `T_ULPS` ulps) wherever it is judged — the family's verdict
//! (stress rows, the kit, found cases) and the verdict lines of `hit` and `judge` agree on every
//! answer, and a stress row counts a right triangle at a wrong `t` as wrong.

use tetwalk::backend::CPU;
use tetwalk::exact::hit::T_ULPS;
use tetwalk::family::triangle::{HitTally, Hits};
use tetwalk::family::{Family, Triangle, Verdict};
use tetwalk::report::lines::Lines;

/// Every ray–triangle method's answers on a triangle stress row, and each answer with its `t` moved
/// far (1%) and a little (2 ulps): the family's verdict and the verdict line say the same.
#[test]
fn the_family_verdict_and_the_verdict_lines_agree_on_every_answer() {
    let rows = <Triangle as Family>::Rows::default();
    let mut checked = 0;
    let (mut t_wrong, mut t_right) = (0, 0);
    for row in Triangle::rows(&rows).into_iter().step_by(7) {
        let cases: Vec<_> = (0..40)
            .filter_map(|i| Triangle::case(&rows, row, 1, i))
            .collect();
        let asked: Vec<_> = cases.iter().map(|(c, _)| *c).collect();
        for m in Triangle::methods() {
            let answers = Triangle::answers(&CPU, m, &asked).unwrap();
            for ((case, truth), a) in cases.iter().zip(&answers) {
                let moved = |k: f32| {
                    Hits::of(
                        &a.nearest()
                            .map(|(i, t)| (i, t * k))
                            .into_iter()
                            .collect::<Vec<_>>(),
                    )
                };
                for answer in [*a, moved(1.01), moved(1.0 + 2.0 * f32::EPSILON)] {
                    let verdict = Triangle::verdict(case, truth, &answer);
                    let said = Triangle::said(case, truth, &answer, T_ULPS);
                    let line = Triangle::verdict_line(case, truth, &answer, &said);
                    let right = verdict == Verdict::Right;
                    assert_eq!(said.correct, Some(right), "{line:?} against {verdict:?}");
                    assert_eq!(line["correct"], right);
                    // The stress tally counts it as the verdict does.
                    let mut t = HitTally::default();
                    Triangle::tally(&mut t, case, truth, &answer);
                    assert_eq!(Triangle::wrong(&t), !right as u64, "{line:?}");
                    if truth.right(answer.nearest().map(|(i, _)| i)) && answer.nearest().is_some() {
                        if right {
                            t_right += 1
                        } else {
                            t_wrong += 1;
                            assert_eq!(t.wrong_t, 1);
                        }
                    }
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 5000, "{checked}");
    assert!(
        t_wrong > 100 && t_right > 100,
        "t wrong {t_wrong}, t right {t_right}"
    );
}
