//! The exact oracle: two independent exact formulations agree, and relabelling vertices relabels faces.

mod common;

use common::{any_case, config, lattice_case};
use proptest::prelude::*;
use tetwalk::exact::{FaceSet, classify, clip::classify_by_clipping, perturbed_exit};
use tetwalk::tet::{Ray, Tet};

fn agree(t: &Tet, ray: &Ray) -> Result<(), TestCaseError> {
    let a = classify(t, ray);
    let b = classify_by_clipping(t, ray);
    prop_assert_eq!(
        a,
        b,
        "side-product and clipping oracles disagree on {:?} {:?}",
        t,
        ray
    );
    if let Ok(c) = a {
        prop_assert_eq!(
            c.exit.is_empty(),
            c.entry.is_empty(),
            "a line that meets enters and leaves"
        );
        let (f, _) = perturbed_exit(t, ray).unwrap();
        if let Some(f) = f {
            prop_assert!(
                c.exit.contains(f),
                "perturbed exit {} not exact {:?}",
                f,
                c.exit
            );
        }
    }
    Ok(())
}

fn permuted(s: FaceSet, perm: &[usize; 4]) -> FaceSet {
    // Face i of the permuted tetrahedron is face perm[i] of the original.
    let mut out = FaceSet::default();
    (0..4)
        .filter(|&i| s.contains(perm[i]))
        .for_each(|i| out.insert(i));
    out
}

proptest! {
    #![proptest_config(config("oracle_agree", 1500))]
    #[test]
    fn formulations_agree(case in any_case()) {
        agree(&case.0, &case.1)?;
    }
}

proptest! {
    #![proptest_config(config("oracle_lattice", 1500))]
    #[test]
    fn formulations_agree_on_lattice(case in lattice_case()) {
        agree(&case.0, &case.1)?;
    }
}

proptest! {
    #![proptest_config(config("oracle_relabel", 600))]
    #[test]
    fn relabelling_vertices_relabels_faces(
        case in prop_oneof![any_case(), lattice_case()],
        perm in Just([0usize, 1, 2, 3]).prop_shuffle(),
    ) {
        let (t, ray) = case;
        let tp: Tet = std::array::from_fn(|i| t[perm[i]]);
        let (a, b) = (classify(&t, &ray).unwrap(), classify(&tp, &ray).unwrap());
        prop_assert_eq!(permuted(a.exit, &perm), b.exit);
        prop_assert_eq!(permuted(a.entry, &perm), b.entry);
        // `Case::relabelled` (how `stress --relabel` asks) renames the entry face the same way.
        let case = tetwalk::tet::Case { tet: t, org: ray.org, dir: ray.dir, entry: a.entry.first().map(|f| f as u8) };
        let moved = case.relabelled(perm);
        prop_assert_eq!(moved.tet, tp);
        prop_assert_eq!(moved.entry.is_some(), case.entry.is_some());
        if let Some(e) = moved.entry {
            prop_assert!(b.entry.contains(e as usize));
        }
        // Reversing the direction swaps entry and exit.
        let back = classify(&t, &Ray { org: ray.org, dir: -ray.dir }).unwrap();
        prop_assert_eq!((back.exit, back.entry), (a.entry, a.exit));
    }
}

#[test]
fn generators_reach_the_exact_stage_and_ties() {
    // The generated cases must exercise what they claim: exact ties, and signs the filter cannot decide.
    let mut ties = 0;
    let before = tetwalk::exact::counts();
    for seed in 0..200 {
        for kind in [
            common::Kind::Through(tetwalk::scenes::tets::Target::Edge),
            common::Kind::Near(tetwalk::scenes::tets::Target::Vertex, 1),
        ] {
            let (t, ray) = common::make(
                tetwalk::scenes::tets::TetShape::Sliver,
                1e-3,
                kind,
                0.0,
                seed,
            )
            .unwrap();
            let c = classify(&t, &ray).unwrap();
            ties += (c.exit.0.count_ones() > 1) as u32;
        }
    }
    let used = tetwalk::exact::counts().since(before);
    println!("ties {ties}, filter {} exact {}", used.filter, used.exact);
    assert!(
        ties >= 100,
        "through-edge rays must give tied exit faces ({ties})"
    );
    assert!(used.exact > 0, "the exact stage must be reached: {used:?}");
}

#[test]
fn any_case_covers_ties() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strat = any_case();
    let (mut ties, mut n) = (0, 0);
    for _ in 0..500 {
        let (t, ray) = strat.new_tree(&mut runner).unwrap().current();
        n += 1;
        ties += classify(&t, &ray).is_ok_and(|c| c.exit.0.count_ones() > 1) as u32;
    }
    println!("{ties} of {n}");
    assert!(ties > 50, "{ties} of {n} cases have tied exit faces");
}
