//! Methods against the oracle: `exact` always right; every method right on well-shaped tetrahedra with
//! rays at a measured margin from every edge; failures on degenerate families measured and printed.

mod common;

use common::{Kind, any_case, config, judge, lattice_case, make, model};
use proptest::prelude::*;
use tetwalk::exact::{classify, edge_margin};
use tetwalk::methods::Model;
use tetwalk::registry::Named;
use tetwalk::registry::{METHODS, by_name};
use tetwalk::scenes::rng;
use tetwalk::scenes::tets::{Target, TetShape, stabbing_ray, tet};
use tetwalk::tet::Case;
use tetwalk::tet::{Ray, Tet};

/// Margin (see [`edge_margin`]) far above f32 rounding (2^-24 ≈ 6e-8) times any operation count.
const SAFE_MARGIN: f64 = 1e-4;

fn case_of(t: Tet, ray: Ray, with_entry: bool) -> (Case, tetwalk::exact::Classification) {
    let c = classify(&t, &ray).unwrap();
    let entry = if with_entry {
        c.entry.first().map(|f| f as u8)
    } else {
        None
    };
    (
        Case {
            tet: t,
            org: ray.org,
            dir: ray.dir,
            entry,
        },
        c,
    )
}

proptest! {
    #![proptest_config(config("exact_correct", 2000))]
    #[test]
    fn exact_is_correct_on_every_case(case in prop_oneof![any_case(), lattice_case()], with_entry: bool, model in model()) {
        let (case, c) = case_of(case.0, case.1, with_entry);
        let j = judge(&case, &c, by_name("exact").unwrap(), model);
        prop_assert_ne!(j.correct, Some(false), "exact answered {:?}, exact exits {:?}", j.face, j.exact_exit);
        prop_assert_eq!(j.face.is_some(), c.meets());
    }
}

proptest! {
    #![proptest_config(config("methods_margin", 3000))]
    #[test]
    fn every_method_is_right_with_margin(seed: u64, with_entry: bool, model in model()) {
        let mut r = rng(seed);
        let t = tet(TetShape::Well, 1.0, &mut r);
        let ray = stabbing_ray(&t, &mut r);
        prop_assume!(edge_margin(&t, &ray) >= SAFE_MARGIN);
        let (case, c) = case_of(t, ray, with_entry);
        prop_assert_eq!(c.exit.0.count_ones(), 1);
        for m in METHODS {
            let j = judge(&case, &c, m, model);
            prop_assert_eq!(j.correct, Some(true), "{} ({:?}) answered {:?}, exact {:?}", m.name(), model, j.face, j.exact_exit);
        }
    }
}

proptest! {
    #![proptest_config(config("methods_some_exit", 2000))]
    #[test]
    fn no_method_finds_no_exit_far_from_edges(
        family in common::family(),
        flatness in prop_oneof![Just(1.0f32), Just(0.1), Just(0.01)],
        seed: u64, with_entry: bool, model in model(),
    ) {
        let (t, ray) = make(family, flatness, Kind::Stab, 0.0, seed).unwrap();
        prop_assume!(edge_margin(&t, &ray) >= SAFE_MARGIN);
        let (case, c) = case_of(t, ray, with_entry);
        for m in METHODS {
            prop_assert!(judge(&case, &c, m, model).face.is_some(), "{} found no exit face", m.name());
        }
    }
}

/// Every method's wrong answers over the degenerate families, flatness and ray kinds, pinned in
/// `golden/degenerate_families_table.snap`: a change in any method's arithmetic or face tables changes
/// a count. Beside it: tetwalk's own methods (`exact`, `certified`) are never wrong, and every published
/// method fails somewhere.
#[test]
fn degenerate_families_failures_are_measured() {
    let kinds = [
        ("stab", Kind::Stab),
        ("near-edge", Kind::Near(Target::Edge, 4)),
        ("near-vertex", Kind::Near(Target::Vertex, 4)),
        ("edge", Kind::Through(Target::Edge)),
        ("vertex", Kind::Through(Target::Vertex)),
    ];
    let mut table =
        String::from("| method | fma | family | flatness | rays | cases | wrong | misses |\n");
    for m in METHODS {
        let mut wrong_anywhere = 0;
        for model in [Model::Plain, Model::Fused] {
            let fma = model == Model::Fused;
            for family in TetShape::ALL {
                for flatness in [1e-2f32, 1e-4] {
                    for (name, kind) in kinds {
                        let (mut wrong, mut n, mut misses) = (0, 0, 0);
                        for seed in 0..300 {
                            let Some((t, ray)) = make(family, flatness, kind, 0.0, seed) else {
                                continue;
                            };
                            let (case, c) = case_of(t, ray, seed % 2 == 0);
                            match judge(&case, &c, m, model).correct {
                                Some(false) => wrong += 1,
                                None => misses += 1,
                                Some(true) => {}
                            }
                            n += 1;
                        }
                        assert!(
                            n >= 250,
                            "the generator must produce cases ({family:?} {name}: {n})"
                        );
                        if m.name() == "exact" {
                            assert_eq!(wrong, 0, "exact was wrong on {family:?} {flatness} {name}");
                        }
                        wrong_anywhere += wrong;
                        if wrong > 0 {
                            table += &format!(
                                "| {} | {fma} | {family:?} | {flatness} | {name} | {n} | {wrong} | {misses} |\n",
                                m.name()
                            );
                        }
                    }
                }
            }
        }
        if m.info.published {
            assert!(wrong_anywhere > 0, "{} never failed here", m.name());
        } else {
            assert_eq!(wrong_anywhere, 0, "{} is never wrong", m.name());
        }
    }
    print!("{table}");
    common::settings().bind(|| insta::assert_snapshot!("degenerate_families_table", table));
}

proptest! {
    #![proptest_config(config("certified_correct", 3000))]
    /// `certified` is right on every case of every family, lattice ties included, from every exact entry
    /// face (not only the one the tie-breaking picks) and from none, plain and as a GPU compiles it.
    #[test]
    fn certified_is_correct_on_every_case(case in prop_oneof![any_case(), lattice_case()], model in model()) {
        let (t, ray) = case;
        let c = classify(&t, &ray).unwrap();
        let m = by_name("certified").unwrap();
        let entries: Vec<Option<u8>> =
            std::iter::once(None).chain(c.entry.iter().map(|f| Some(f as u8))).collect();
        for entry in entries {
            let case = Case { tet: t, org: ray.org, dir: ray.dir, entry };
            let j = judge(&case, &c, m, model);
            prop_assert_ne!(j.correct, Some(false), "entry {:?}: answered {:?}, exact exits {:?}", entry, j.face, j.exact_exit);
        }
    }
}
