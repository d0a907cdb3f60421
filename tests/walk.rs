//! Walks: `exact` walks end on the exact first hit on every generated mesh, near and far from the
//! origin; located tetrahedra hold the origin; cycles and step limits are caught.

mod common;

use glam::Vec3;
use tetwalk::exact::hit::{first_hit, line_triangle};
use tetwalk::mesh::{Mesh, load_tetgen};
use tetwalk::methods::Model;
use tetwalk::methods::{ExitMethod, Plain};
use tetwalk::registry::Named;
use tetwalk::registry::by_name;
use tetwalk::scenes::{self, Generated};
use tetwalk::tet::{FACE_VERTICES, Ray, Tet, orientation};
use tetwalk::walk::{Outcome, default_max_steps, locate, walk};

/// Checks every ray's `exact` walk against the brute-force first hit; returns how many were checked.
fn check_exact_walks(mesh: &Mesh, rays: &[Ray]) -> usize {
    let exact = by_name("exact").unwrap();
    let max = default_max_steps(mesh);
    let mut checked = 0;
    let mut start = 0;
    for ray in rays {
        start = locate(mesh, ray.org, start).expect("origin inside the mesh");
        let t = mesh.tet(start);
        for v in FACE_VERTICES {
            assert!(
                orientation(&[t[v[0]], t[v[1]], t[v[2]], ray.org]) >= 0,
                "located tetrahedron must hold {ray:?}"
            );
        }
        let reference = first_hit(mesh, ray);
        let (w, div) = exact.walk_checked(Model::Plain)(mesh, ray, start, max);
        assert_eq!(div, None, "exact walk left the exact exit faces on {ray:?}");
        assert_eq!(
            w,
            exact.walk(Model::Plain)(mesh, ray, start, max),
            "checked and plain walks differ"
        );
        match (w.outcome, reference) {
            (Outcome::LeftMesh { .. }, None) => {}
            (Outcome::Hit { tet, face }, Some((t, faces))) => {
                let tri = mesh
                    .face(tet, face as usize)
                    .map(|i| mesh.points[i as usize]);
                assert!(
                    faces.contains(&(tet, face))
                        || line_triangle(tri, ray).is_some_and(|x| x.t == t),
                    "hit {tet}/{face} is not the first hit ({faces:?}) of {ray:?}"
                );
            }
            (o, r) => panic!("exact walk ended {o:?}, brute force says {r:?} for {ray:?}"),
        }
        checked += 1;
    }
    checked
}

#[test]
fn exact_walks_hit_the_first_constrained_face_on_every_generated_mesh() {
    for (kind, size, offset) in [
        (Generated::Kuhn, 6, 0.0),
        (Generated::Kuhn, 6, 1.0e6),
        (Generated::Jitter, 6, 0.0),
        (Generated::Jitter, 6, 1.0e5),
        (Generated::Fan, 8, 0.0),
        (Generated::Fan, 8, 1.0e6),
    ] {
        let offset = Vec3::splat(offset);
        let mesh = scenes::generated_mesh(kind, size, offset, 3).unwrap();
        let rays = scenes::rays(kind, &mesh, offset, 400, 3);
        let n = check_exact_walks(&mesh, &rays);
        println!("{kind:?} offset {offset}: {n} rays checked");
        assert_eq!(n, rays.len());
    }
}

#[test]
fn tetgen_mesh_loads_and_exact_walks_are_right() {
    let mesh =
        load_tetgen(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/twobox.1").as_ref()).unwrap();
    assert_eq!(mesh.tets.len(), 42);
    assert_eq!(
        mesh.flipped, 42,
        "TetGen writes negative tetrahedra: all are normalised"
    );
    let sides: u32 = mesh.constrained.iter().map(|c| c.count_ones()).sum();
    assert_eq!(
        sides,
        12 * 2 + 12,
        "inner box faces have two sides, outer box faces one"
    );
    let mut r = scenes::rng(9);
    use rand::RngExt;
    let rays: Vec<Ray> = (0..300)
        .map(|_| Ray {
            org: Vec3::from_array(std::array::from_fn(|_| r.random_range(0.1..3.9))),
            dir: Vec3::from_array(std::array::from_fn(|_| r.random_range(-1.0..1.0))),
        })
        .collect();
    assert_eq!(check_exact_walks(&mesh, &rays), 300);
}

/// A broken method that always turns back through the entry face.
struct TurnBack;

impl ExitMethod for TurnBack {
    type RayData = ();
    fn prepare<A: tetwalk::methods::Arith>(_: &Ray) {}
    fn exit_face<A: tetwalk::methods::Arith>(
        _: &Tet,
        _: &(),
        entry: Option<usize>,
    ) -> Option<usize> {
        Some(entry.unwrap_or(3))
    }
}

#[test]
fn cycles_and_step_limits_are_typed_outcomes() {
    let mesh = scenes::generated_mesh(Generated::Kuhn, 4, Vec3::ZERO, 1).unwrap();
    let ray = Ray {
        org: Vec3::new(2.3, 1.6, 2.2),
        dir: Vec3::X,
    };
    let max = default_max_steps(&mesh);
    // Start where face 3 is neither boundary nor constrained, so TurnBack ping-pongs between two tetrahedra.
    let start = (0..mesh.tets.len() as u32)
        .find(|&t| {
            mesh.neighbors[t as usize][3] != tetwalk::mesh::HULL && !mesh.is_constrained(t, 3)
        })
        .unwrap();
    let w = walk::<TurnBack, Plain>(&mesh, &ray, start, max);
    assert!(
        matches!(w.outcome, Outcome::Cycle { period: 2, .. }),
        "{w:?}"
    );
    assert!(w.steps < 10, "Brent's detection is prompt: {w:?}");
    let w = walk::<TurnBack, Plain>(&mesh, &ray, start, 1);
    assert_eq!(w.outcome.kind(), tetwalk::walk::OutcomeKind::StepLimit);
}

#[test]
fn locating_a_mesh_vertex_picks_one_tetrahedron_holding_it() {
    let mesh = scenes::generated_mesh(Generated::Kuhn, 4, Vec3::ZERO, 1).unwrap();
    for p in [
        Vec3::new(2.0, 2.0, 2.0),
        Vec3::new(1.0, 2.0, 1.5),
        Vec3::new(0.0, 0.0, 0.0),
    ] {
        let t = locate(&mesh, p, 0).unwrap();
        assert!(mesh.tet(t).contains(&p) || p.z == 1.5, "{p}: {t}");
        // Starting anywhere else gives the same tetrahedron: the perturbation decides, not the path.
        for s in [0, 17, 200, 383] {
            assert_eq!(locate(&mesh, p, s).unwrap(), t);
        }
    }
    assert!(locate(&mesh, Vec3::splat(-1.0), 5).is_err());
}

/// `certified` walks end where the `exact` walks end, step for step (the same tetrahedra, the same
/// number of steps), on every generated mesh near and far, rays through vertices and edges included;
/// `maria17` does not, and cycles on the Kuhn grid.
#[test]
fn certified_walks_follow_the_exact_walks() {
    let exact = by_name("exact").unwrap();
    let certified = by_name("certified").unwrap();
    let maria17 = by_name("maria17").unwrap();
    let mut maria17_cycles = 0;
    for kind in [Generated::Kuhn, Generated::Jitter, Generated::Fan] {
        for offset in [Vec3::ZERO, Vec3::splat(65536.0)] {
            let mesh = scenes::generated_mesh(kind, 8, offset, 1).unwrap();
            let max = default_max_steps(&mesh);
            for model in Model::ALL {
                for ray in scenes::rays(kind, &mesh, offset, 3000, 7) {
                    let Ok(start) = locate(&mesh, ray.org, 0) else {
                        continue;
                    };
                    let want = exact.walk(Model::Plain)(&mesh, &ray, start, max);
                    let got = certified.walk(model)(&mesh, &ray, start, max);
                    assert_eq!(got, want, "{kind:?} offset {offset} {model:?}: {ray:?}");
                    maria17_cycles += matches!(
                        maria17.walk(Model::Plain)(&mesh, &ray, start, max).outcome,
                        Outcome::Cycle { .. }
                    ) as usize;
                }
            }
        }
    }
    assert!(maria17_cycles > 0, "the same rays make maria17 cycle");
    // The ray: maria17 passes through the vertex (5, 6, 6) and loops with period 6.
    let mesh = scenes::generated_mesh(Generated::Kuhn, 8, Vec3::ZERO, 1).unwrap();
    let ray = Ray {
        org: Vec3::new(4.875, 5.75, 6.25),
        dir: Vec3::new(1.0, 2.0, -2.0),
    };
    let start = locate(&mesh, ray.org, 0).unwrap();
    let max = default_max_steps(&mesh);
    assert!(matches!(
        maria17.walk(Model::Plain)(&mesh, &ray, start, max).outcome,
        Outcome::Cycle { period: 6, .. }
    ));
    assert_eq!(
        certified.walk(Model::Plain)(&mesh, &ray, start, max),
        exact.walk(Model::Plain)(&mesh, &ray, start, max)
    );
}

/// The `exact` walk, which decides only the two signs of Maria et al.'s tree from the entry face,
/// takes the same steps as one that classifies every tetrahedron completely (all ten signs,
/// `perturbed_exit`), on every generated mesh near and far, ties included, and on the bunny.
#[test]
fn the_fast_exact_walk_equals_the_complete_one() {
    struct Complete;
    impl ExitMethod for Complete {
        type RayData = Ray;
        fn prepare<A: tetwalk::methods::Arith>(ray: &Ray) -> Ray {
            *ray
        }
        fn exit_face<A: tetwalk::methods::Arith>(
            tet: &Tet,
            ray: &Ray,
            _entry: Option<usize>,
        ) -> Option<usize> {
            let (face, c) = tetwalk::exact::perturbed_exit(tet, ray).ok()?;
            face.or(c.exit.first())
        }
    }
    let exact = by_name("exact").unwrap();
    let mut meshes: Vec<(Mesh, Vec<Ray>)> = Vec::new();
    for kind in [Generated::Kuhn, Generated::Jitter, Generated::Fan] {
        for offset in [Vec3::ZERO, Vec3::splat(65536.0)] {
            let mesh = scenes::generated_mesh(kind, 8, offset, 1).unwrap();
            let rays = scenes::rays(kind, &mesh, offset, 2000, 9);
            meshes.push((mesh, rays));
        }
    }
    let bunny = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required)
        .unwrap()
        .mesh;
    let (lo, hi) = tetwalk::mesh::bounds(&bunny.points);
    let views = tetwalk::scenes::camera::Views::new(4, 48, 48, 1);
    let rays: Vec<Ray> = (0..4)
        .flat_map(|v| views.rays(&views.camera(lo, hi, v)))
        .collect();
    meshes.push((bunny, rays));
    let mut walked = 0;
    for (mesh, rays) in &meshes {
        let max = default_max_steps(mesh);
        for ray in rays {
            let Ok(start) = locate(mesh, ray.org, 0) else {
                continue;
            };
            assert_eq!(
                exact.walk(Model::Plain)(mesh, ray, start, max),
                walk::<Complete, Plain>(mesh, ray, start, max),
                "{ray:?}"
            );
            walked += 1;
        }
    }
    assert!(walked > 20_000, "{walked}");
}

/// Every method's interleaved walks of a batch of rays from one start (what backends and the count
/// use) end exactly as its walks one at a time, plain and fused, with cycles (maria17 on lattice rays
/// of the Kuhn grid) and step limits among them.
#[test]
fn interleaved_walks_equal_walks_one_at_a_time() {
    let mesh = scenes::generated_mesh(Generated::Kuhn, 8, Vec3::ZERO, 1).unwrap();
    let org = Vec3::new(4.875, 5.75, 6.25);
    let start = locate(&mesh, org, 0).unwrap();
    // Rays from one origin through lattice points (ties) and generic directions.
    let mut rays: Vec<Ray> = scenes::rays(Generated::Kuhn, &mesh, Vec3::ZERO, 600, 3)
        .into_iter()
        .map(|r| Ray { org, dir: r.dir })
        .collect();
    rays.push(Ray {
        org,
        dir: Vec3::new(1.0, 2.0, -2.0),
    });
    let mut kinds = std::collections::BTreeSet::new();
    for m in tetwalk::registry::METHODS {
        for model in Model::ALL {
            for max in [default_max_steps(&mesh), 7] {
                let batch: Vec<(Ray, u32)> = rays.iter().map(|r| (*r, start)).collect();
                let together = m.walks(model)(&mesh, &batch, max);
                for (ray, got) in rays.iter().zip(&together) {
                    assert_eq!(
                        *got,
                        m.walk(model)(&mesh, ray, start, max),
                        "{} {ray:?}",
                        m.name()
                    );
                    kinds.insert(got.outcome.kind());
                }
            }
        }
    }
    for k in [
        tetwalk::walk::OutcomeKind::Cycle,
        tetwalk::walk::OutcomeKind::StepLimit,
        tetwalk::walk::OutcomeKind::Hit,
    ] {
        assert!(kinds.contains(&k), "no walk ended {k:?}: {kinds:?}");
    }
}

/// Relabelling every tetrahedron by an even permutation keeps the mesh (the same tetrahedra,
/// neighbours and constrained faces, positively oriented) and the exact walks' results: where a ray
/// first meets the constrained faces does not depend on labels.
#[test]
fn relabelled_meshes_keep_the_exact_results() {
    let mesh = scenes::generated_mesh(Generated::Jitter, 4, Vec3::ZERO, 3).unwrap();
    let exact = by_name("exact").unwrap();
    let rays = scenes::rays(Generated::Jitter, &mesh, Vec3::ZERO, 300, 9);
    let max = default_max_steps(&mesh);
    for p in tetwalk::tet::EVEN_PERMUTATIONS {
        let r = mesh.relabelled(p).unwrap();
        assert_eq!(r.flipped, 0, "{p:?} keeps the orientation");
        assert_eq!(r.tets.len(), mesh.tets.len());
        let constrained = |m: &Mesh| m.constrained.iter().map(|c| c.count_ones()).sum::<u32>();
        assert_eq!(constrained(&r), constrained(&mesh));
        for (t, v) in r.tets.iter().enumerate() {
            assert_eq!(*v, p.map(|i| mesh.tets[t][i]));
            assert_eq!(r.neighbors[t], p.map(|i| mesh.neighbors[t][i]));
        }
        for ray in &rays {
            let (Ok(a), Ok(b)) = (locate(&mesh, ray.org, 0), locate(&r, ray.org, 0)) else {
                continue;
            };
            let wa = exact.walk(Model::Plain)(&mesh, ray, a, max);
            let mut wb = exact.walk(Model::Plain)(&r, ray, b, max);
            // Back to the original labels: face f of the relabelled tetrahedron is its face p[f].
            wb.outcome = match wb.outcome {
                Outcome::Hit { tet, face } => Outcome::Hit {
                    tet,
                    face: p[face as usize] as u8,
                },
                Outcome::LeftMesh { tet, face } => Outcome::LeftMesh {
                    tet,
                    face: p[face as usize] as u8,
                },
                o => o,
            };
            assert!(
                tetwalk::walk::same_result(&mesh, ray, &wb, &wa),
                "{p:?}: {wa:?} / {wb:?} for {ray:?}"
            );
        }
    }
}

/// The rule every count rests on (`walk::same_result`), as a unit, on walks made up to probe it (the
/// reference need not be the exact walk here): on the 3³ Kuhn grid whose inner cube's faces are
/// constrained, a ray along x crosses the cube's near face (interior), diagonal faces inside it, and
/// its far face. A hit is right only on a face holding the reference's hit point: the same face, the
/// same triangle from the other side, or another face through the same point; not a face crossed
/// earlier or later. Where the reference left the mesh, only a face the ray touches at its boundary
/// (a graze) is right, not one it crosses inside; both leaving is right, and a cycle never is.
#[test]
fn same_result_holds_a_hit_to_the_references_point() {
    use tetwalk::walk::{Outcome, Walk, same_result};
    let mesh = scenes::generated_mesh(Generated::Kuhn, 3, Vec3::ZERO, 1).unwrap();
    let ray = Ray {
        org: Vec3::new(0.5, 1.5, 1.25),
        dir: Vec3::X,
    };
    // Every constrained face the ray crosses, with where (t) and whether on the triangle's boundary.
    let mut crossed: Vec<(u32, u8, rug::Rational, bool)> = Vec::new();
    for t in 0..mesh.tets.len() as u32 {
        for f in 0..4u8 {
            if !mesh.is_constrained(t, f as usize) {
                continue;
            }
            let p = mesh.face(t, f as usize).map(|i| mesh.points[i as usize]);
            if let Some(c) = line_triangle(p, &ray).filter(|c| c.t.cmp0().is_ge()) {
                crossed.push((t, f, c.t, c.on_boundary));
            }
        }
    }
    let hit = |t: u32, f: u8| Walk {
        outcome: Outcome::Hit { tet: t, face: f },
        steps: 1,
    };
    let first_t = crossed.iter().map(|c| c.2.clone()).min().unwrap();
    let last_t = crossed.iter().map(|c| c.2.clone()).max().unwrap();
    assert!(first_t < last_t);
    let at = |t: &rug::Rational| crossed.iter().filter(|c| &c.2 == t).collect::<Vec<_>>();
    let (near, far) = (at(&first_t), at(&last_t));
    let reference = hit(near[0].0, near[0].1);
    // The same point, from either side or another face holding it: right.
    for c in &near {
        assert!(
            same_result(&mesh, &ray, &hit(c.0, c.1), &reference),
            "{c:?}"
        );
    }
    // A later crossing, or an earlier one than a farther reference's: wrong.
    for c in &far {
        assert!(
            !same_result(&mesh, &ray, &hit(c.0, c.1), &reference),
            "{c:?}"
        );
        assert!(
            !same_result(&mesh, &ray, &reference, &hit(c.0, c.1)),
            "earlier than {c:?}"
        );
    }
    // Where the reference left the mesh: a face crossed inside is wrong; a graze is right.
    let left = Walk {
        outcome: Outcome::LeftMesh { tet: 0, face: 0 },
        steps: 1,
    };
    let inside = crossed
        .iter()
        .find(|c| !c.3)
        .expect("a face crossed inside");
    assert!(!same_result(&mesh, &ray, &hit(inside.0, inside.1), &left));
    let graze = Ray {
        org: Vec3::new(0.5, 1.0, 1.0),
        dir: Vec3::X,
    };
    let touched = (0..mesh.tets.len() as u32)
        .flat_map(|t| (0..4u8).map(move |f| (t, f)))
        .find(|&(t, f)| {
            mesh.is_constrained(t, f as usize)
                && line_triangle(
                    mesh.face(t, f as usize).map(|i| mesh.points[i as usize]),
                    &graze,
                )
                .is_some_and(|c| c.on_boundary && c.t.cmp0().is_ge())
        })
        .expect("a constrained face the grazing ray touches at its boundary");
    assert!(same_result(
        &mesh,
        &graze,
        &hit(touched.0, touched.1),
        &left
    ));
    assert!(same_result(&mesh, &ray, &left, &left));
    let cycle = Walk {
        outcome: Outcome::Cycle { tet: 0, period: 3 },
        steps: 9,
    };
    assert!(!same_result(&mesh, &ray, &cycle, &cycle));
    assert!(!same_result(&mesh, &ray, &left, &reference));
}
