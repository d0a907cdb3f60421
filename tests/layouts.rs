//! The compact layouts (seed 003 §3): every tetrahedron decodes to the plain mesh's vertices and
//! neighbours, walks over each layout visit the same tetrahedra as the plain `aman20` walk, and Hilbert
//! reordering keeps what every walk finds.

use glam::Vec3;
use tetwalk::exact::edge_margin;
use tetwalk::mesh::layout::{Layout, STOP, rank, xor_sum};
use tetwalk::mesh::reorder::{hilbert_sorted, regions};
use tetwalk::mesh::{Mesh, load_tetgen};
use tetwalk::methods::Model;
use tetwalk::methods::aman20::Frame;
use tetwalk::methods::{Aman20, Aman20Scaled, Arith, ExitMethod, Fused, Plain};
use tetwalk::registry::by_name;
use tetwalk::scenes::{self, Generated};
use tetwalk::tet::Ray;
use tetwalk::walk::layouts::{LayoutKind, Source, encoded_neighbor, walk_layout};
use tetwalk::walk::{default_max_steps, locate, walk_traced};

/// Test meshes with rays, and the offset they were moved by (exactly, so margins are measured without it).
fn meshes() -> Vec<(String, Mesh, Vec<Ray>, Vec3)> {
    let mut out = Vec::new();
    for (kind, offset) in [
        (Generated::Kuhn, 0.0),
        (Generated::Jitter, 0.0),
        (Generated::Jitter, 1.0e5),
        (Generated::Fan, 0.0),
    ] {
        let off = Vec3::splat(offset);
        let mesh = scenes::generated_mesh(kind, 6, off, 5).unwrap();
        let rays = scenes::rays(kind, &mesh, off, 300, 5);
        out.push((format!("{kind:?} {offset}"), mesh, rays, off));
    }
    let twobox =
        load_tetgen(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/twobox.1").as_ref()).unwrap();
    let rays = (0..100)
        .map(|i| {
            let f = i as f32;
            Ray {
                org: Vec3::new(0.3 + f * 0.03, 0.7, 0.2 + f * 0.01),
                dir: Vec3::new((f * 0.7).sin(), (f * 1.3).cos(), 0.4),
            }
        })
        .collect();
    out.push(("twobox".into(), twobox, rays, Vec3::ZERO));
    let sorted: Vec<_> = out
        .iter()
        .map(|(n, m, r, o)| (format!("{n} hilbert"), hilbert_sorted(m), r.clone(), *o))
        .collect();
    out.extend(sorted);
    out
}

#[test]
fn every_tetrahedron_decodes_to_the_plain_mesh() {
    for (name, mesh, _, _) in meshes() {
        let layout = Layout::build(&mesh);
        for (t, v) in mesh.tets.iter().enumerate() {
            let t32 = &layout.tet32[t];
            assert_eq!(
                [
                    t32.v[0],
                    t32.v[1],
                    t32.v[2],
                    t32.v[0] ^ t32.v[1] ^ t32.v[2] ^ t32.vx
                ],
                *v,
                "{name} {t}"
            );
            let enc: [u32; 4] =
                std::array::from_fn(|f| encoded_neighbor(&mesh, &layout, t as u32, f));
            assert_eq!(t32.n, enc, "{name} {t}");
            assert_eq!(layout.tet20[t].vx, xor_sum(v));
            assert_eq!(layout.tet16[t].vx, xor_sum(v));
            for f in 0..4 {
                assert_eq!(
                    layout.tet20[t].n[rank(v, v[f])],
                    enc[f],
                    "{name} tet20 {t}/{f}"
                );
                // Tet16: from any real neighbour, every other neighbour decodes.
                if enc[f] & STOP == 0 {
                    for g in 0..4 {
                        let got = tetwalk::mesh::layout::next_tet16(
                            &layout.tet16[t],
                            enc[f],
                            rank(v, v[f]),
                            rank(v, v[g]),
                        );
                        assert_eq!(got, enc[g], "{name} tet16 {t}: from {f} to {g}");
                    }
                }
                if enc[f] & STOP != 0 && enc[f] != STOP | tetwalk::mesh::layout::BOUNDARY {
                    assert!(layout.constrained[(enc[f] & !STOP) as usize].contains(&(t as u32)));
                }
            }
        }
    }
}

/// Walks `M` over every layout and compares with the plain walk; returns (rays compared, rays that differ).
fn compare_walks<M, A>(mesh: &Mesh, rays: &[Ray], offset: Vec3) -> (usize, usize)
where
    M: ExitMethod,
    M::RayData: Frame,
    A: Arith,
{
    let layout = Layout::build(mesh);
    let max = default_max_steps(mesh);
    let (mut n, mut differ, mut compared) = (0, 0, 0);
    for ray in rays {
        let Ok(start) = locate(mesh, ray.org, 0) else {
            continue;
        };
        let (plain, visited) = walk_traced::<M, A>(mesh, ray, start, max);
        // Where the ray passes exactly through an edge or vertex, lies in a face's plane, or comes so close
        // that f32 may get a determinant's sign wrong, Algorithm 1's answer may depend on the order in
        // which the walk carries the entry face's vertices; every other ray must agree exactly.
        let home = Ray {
            org: ray.org - offset,
            dir: ray.dir,
        };
        let clean = visited
            .iter()
            .all(|&t| edge_margin(&mesh.tet(t).map(|v| v - offset), &home) > 1e-6);
        for kind in [LayoutKind::Tet32, LayoutKind::Tet20, LayoutKind::Tet16] {
            let mut seen = vec![start];
            let mut prev = start;
            let (end, steps) = walk_layout::<M, A>(
                kind,
                &layout,
                &mesh.points,
                ray,
                &Source::new(&layout, start),
                max,
                |d| {
                    let v = mesh.tets[d.tet as usize];
                    assert!(
                        v.contains(&d.fourth) && !mesh.tets[prev as usize].contains(&d.fourth),
                        "{kind:?}: wrong fourth vertex"
                    );
                    let f = v.iter().position(|&x| x == d.across).unwrap();
                    assert_eq!(
                        d.next,
                        encoded_neighbor(mesh, &layout, d.tet, f),
                        "{kind:?}: wrong neighbour"
                    );
                    seen.push(d.tet);
                    prev = d.tet;
                },
            );
            let same =
                end.to_outcome(mesh) == plain.outcome && steps == plain.steps && seen == visited;
            if clean {
                compared += 1;
                assert!(
                    same,
                    "{kind:?}: {end:?} after {steps} vs {plain:?} for {ray:?}"
                );
            }
            differ += !same as usize;
        }
        n += 1;
    }
    assert!(
        compared >= n,
        "a third of the walks at least must be compared exactly ({compared} of {n} × 3)"
    );
    (n, differ)
}

#[test]
fn layout_walks_visit_the_same_tetrahedra() {
    for (name, mesh, rays, offset) in meshes() {
        for (method, (n, differ)) in [
            (
                "aman20",
                compare_walks::<Aman20, Plain>(&mesh, &rays, offset),
            ),
            (
                "aman20 fma",
                compare_walks::<Aman20, Fused>(&mesh, &rays, offset),
            ),
            (
                "aman20-scaled",
                compare_walks::<Aman20Scaled, Plain>(&mesh, &rays, offset),
            ),
        ] {
            println!(
                "{name} {method}: {n} rays, {differ} layout walks differ (only on degenerate rays)"
            );
            assert!(n >= rays.len() * 9 / 10, "{name}: too few rays located");
        }
    }
}

#[test]
fn hilbert_order_keeps_regions_together_and_walks_unchanged() {
    let mesh =
        load_tetgen(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/twobox.1").as_ref()).unwrap();
    let sorted = hilbert_sorted(&mesh);
    let r = regions(&sorted);
    assert_eq!(
        r.iter().max(),
        Some(&1),
        "the inner box and the space around it"
    );
    assert!(
        r.windows(2).filter(|w| w[0] != w[1]).count() == 1,
        "each region is contiguous: {r:?}"
    );
    let kuhn = scenes::generated_mesh(Generated::Jitter, 6, Vec3::ZERO, 2).unwrap();
    let sorted = hilbert_sorted(&kuhn);
    assert_ne!(sorted.tets, kuhn.tets);
    let exact = by_name("exact").unwrap();
    for ray in scenes::rays(Generated::Jitter, &kuhn, Vec3::ZERO, 200, 2) {
        let (Ok(a), Ok(b)) = (locate(&kuhn, ray.org, 0), locate(&sorted, ray.org, 0)) else {
            continue;
        };
        let wa = exact.walk(Model::Plain)(&kuhn, &ray, a, 100_000);
        let wb = exact.walk(Model::Plain)(&sorted, &ray, b, 100_000);
        let hit = |m: &Mesh, o: &tetwalk::walk::Outcome| match *o {
            tetwalk::walk::Outcome::Hit { tet, face } => Some(
                m.face(tet, face as usize)
                    .map(|i| m.points[i as usize].to_array()),
            ),
            _ => None,
        };
        let (ha, hb) = (hit(&kuhn, &wa.outcome), hit(&sorted, &wb.outcome));
        assert_eq!(
            ha.map(|mut f| {
                f.sort_by(|x, y| x.partial_cmp(y).unwrap());
                f
            }),
            hb.map(|mut f| {
                f.sort_by(|x, y| x.partial_cmp(y).unwrap());
                f
            })
        );
        assert_eq!(wa.steps, wb.steps);
    }
}
