//! Seed 001's octree: the cell numbering inferred from eqs. 8 and 9 makes both tables right in exact
//! arithmetic (away from exact ties), the box-exit oracle gives every exit face and quarter, the
//! octree keeps the regularity constraint and its links, and the exact octree walk ends where the
//! brute-force exact first hit is.

mod common;

use glam::Vec3;
use rand::RngExt;
use rug::Rational;
use tetwalk::exact::boxes::box_exit;
use tetwalk::family::{OctreeCells, by_name as family_by_name};
use tetwalk::methods::Model;
use tetwalk::methods::portalez16::{
    FACE_TO_NEIGHBOR_INDEX, NO_FACE, OUT_FACES_LOOKUP, exit_vertex,
};
use tetwalk::octree::cell::{FACE_AXIS, FACE_HIGH, FACE_NAMES, face_named, quarter_signs};
use tetwalk::octree::{Octree, Settings};
use tetwalk::registry::Named;
use tetwalk::scenes::rng;
use tetwalk::tet::{Ray, Tri};

/// Eqs. 4–6 evaluated exactly (eq. 1 with `Q - P = d`): the table index at `p`.
fn exact_index(ray: &Ray, p: Vec3) -> usize {
    let q = |x: f32| Rational::from_f32(x).unwrap();
    let (o, d) = (ray.org.to_array().map(q), ray.dir.to_array().map(q));
    let pi = [
        Rational::from(&d[0] * &o[1]) - Rational::from(&o[0] * &d[1]),
        Rational::from(&d[0] * &o[2]) - Rational::from(&o[0] * &d[2]),
        d[0].clone(),
        Rational::from(&d[1] * &o[2]) - Rational::from(&o[1] * &d[2]),
        d[2].clone(),
        Rational::from(-&d[1]),
    ];
    let p = p.to_array().map(q);
    let o = [
        Rational::from(&pi[4] * &p[1]) + Rational::from(&pi[5] * &p[2]) + &pi[3],
        Rational::from(&pi[2] * &p[2]) - &pi[1] - Rational::from(&pi[4] * &p[0]),
        pi[0].clone() - Rational::from(&pi[2] * &p[1]) - Rational::from(&pi[5] * &p[0]),
    ];
    (0..3).map(|k| (o[k].cmp0().is_lt() as usize) << k).sum()
}

#[test]
fn eqs_8_and_9_are_right_in_exact_arithmetic_under_the_inferred_numbering() {
    let mut r = rng(3);
    let mut judged = 0;
    for _ in 0..20_000 {
        let lo = Vec3::from_array([0; 3].map(|_| r.random_range(-4..4) as f32));
        let hi = lo + Vec3::splat(2f32.powi(r.random_range(-2..3)));
        let inside =
            lo + (hi - lo) * Vec3::from_array([0; 3].map(|_| r.random_range(0.01..0.99f32)));
        let dir = Vec3::from_array([0; 3].map(|_| r.random_range(-1.0..1.0f32)));
        let ray = Ray {
            org: inside - dir * r.random_range(0.0..3.0f32),
            dir,
        };
        let x = box_exit(lo, hi, &ray).unwrap();
        if !x.crosses {
            continue;
        }
        judged += 1;
        let v = exit_vertex(dir);
        let corner =
            Vec3::from_array([0, 1, 2].map(|a| if v >> a & 1 == 1 { hi[a] } else { lo[a] }));
        let f = OUT_FACES_LOOKUP[v][exact_index(&ray, corner)];
        assert_ne!(f, NO_FACE, "{ray:?} in {lo}..{hi}");
        let f = f as usize;
        let mut centre = (lo + hi) * 0.5;
        centre[FACE_AXIS[f]] = if FACE_HIGH[f] {
            hi[FACE_AXIS[f]]
        } else {
            lo[FACE_AXIS[f]]
        };
        let j = FACE_TO_NEIGHBOR_INDEX[f][exact_index(&ray, centre)] as usize;
        assert_eq!(
            x.right(Some((f, quarter_signs(j)))),
            Some(true),
            "{ray:?} in {lo}..{hi}: face {} quarter {j}, exact {:?} {:?}",
            FACE_NAMES[f],
            x.faces,
            x.quarters
        );
    }
    assert!(judged > 15_000);
}

#[test]
fn the_box_oracle_knows_edges_corners_centre_lines_and_touches() {
    let (lo, hi) = (Vec3::ZERO, Vec3::splat(2.0));
    let exit = |org: [f32; 3], dir: [f32; 3]| {
        let x = box_exit(
            lo,
            hi,
            &Ray {
                org: org.into(),
                dir: dir.into(),
            },
        )
        .unwrap();
        let faces: Vec<&str> = x.faces.iter().map(|&f| FACE_NAMES[f]).collect();
        (x.crosses, faces, x.quarters)
    };
    // Through the middle of the +x face: the centre of both centre lines, every quarter.
    let (c, f, q) = exit([1.0, 1.0, 1.0], [1.0, 0.0, 0.0]);
    assert!(c);
    assert_eq!(f, ["+x"]);
    assert_eq!(q, [vec![[-1, -1], [-1, 1], [1, -1], [1, 1]]]);
    // Through the edge x = 2, y = 2 at z = 1.5: two faces, z above the centre.
    let (c, f, q) = exit([1.0, 1.0, 1.0], [1.0, 1.0, 0.5]);
    assert!(c);
    assert_eq!(f, ["+x", "+y"]);
    assert_eq!(q, [vec![[1, 1]], vec![[1, 1]]]);
    // Through the corner (0, 0, 0).
    let (c, f, _) = exit([1.0, 1.0, 1.0], [-1.0, -1.0, -1.0]);
    assert!(c);
    assert_eq!(f, ["-x", "-y", "-z"]);
    // Only touching the edge y = 0, z = 0: not judged, but the faces it leaves through are named.
    let (c, f, _) = exit([1.0, -1.0, 1.0], [0.0, 1.0, -1.0]);
    assert!(!c);
    assert_eq!(f, ["-z"]);
    // In the plane x = 0 of a face, and missing the box.
    assert!(!exit([0.0, 1.0, 1.0], [0.0, 1.0, 0.0]).0);
    assert_eq!(exit([5.0, 5.0, 5.0], [1.0, 0.0, 0.0]).1, Vec::<&str>::new());
}

/// A little closed scene: two axis-aligned boxes of triangles, one far from the other.
fn scene() -> Vec<Tri> {
    let mut tris = Vec::new();
    for (lo, s) in [(Vec3::splat(0.0), 1.0f32), (Vec3::new(3.0, 0.5, 0.25), 0.5)] {
        let p = |x: f32, y: f32, z: f32| lo + Vec3::new(x, y, z) * s;
        let quads = [
            [p(0., 0., 0.), p(0., 1., 0.), p(1., 1., 0.), p(1., 0., 0.)],
            [p(0., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(0., 1., 1.)],
            [p(0., 0., 0.), p(1., 0., 0.), p(1., 0., 1.), p(0., 0., 1.)],
            [p(0., 1., 0.), p(0., 1., 1.), p(1., 1., 1.), p(1., 1., 0.)],
            [p(0., 0., 0.), p(0., 0., 1.), p(0., 1., 1.), p(0., 1., 0.)],
            [p(1., 0., 0.), p(1., 1., 0.), p(1., 1., 1.), p(1., 0., 1.)],
        ];
        for [a, b, c, d] in quads {
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

#[test]
fn the_octree_keeps_regularity_and_every_link() {
    let tris = scene();
    let o = Octree::build(
        &tris,
        Settings {
            depth: 6,
            capacity: 1,
        },
    )
    .unwrap();
    assert!(
        o.leaves.len() > o.unconstrained_leaves,
        "the constraint splits more"
    );
    for (i, _) in o.leaves.iter().enumerate() {
        for f in 0..6 {
            let n = o.neighbors(o.address[i], f);
            assert!(matches!(n.len(), 0 | 1 | 4));
            for &a in n {
                let j = o.address.iter().position(|&x| x == a).unwrap();
                assert!(o.leaves[i].level.abs_diff(o.leaves[j].level) <= 1);
            }
        }
    }
    // A broken link is found and named.
    let mut broken = o.clone();
    let at = broken.address[0] as usize + 4;
    broken.words[at] = broken.address[broken.leaves.len() - 1];
    let e = broken.check().unwrap_err().to_string();
    assert!(e.starts_with("cell 0 "), "{e}");
}

#[test]
fn the_exact_octree_walk_ends_at_the_exact_first_hit() {
    let tris = scene();
    let o = Octree::build(
        &tris,
        Settings {
            depth: 5,
            capacity: 2,
        },
    )
    .unwrap();
    let exact = family_by_name::<OctreeCells>("exact")
        .unwrap()
        .walk(Model::Plain);
    let hit = tetwalk::family::by_name::<tetwalk::family::Triangle>("mt")
        .unwrap()
        .hit(Model::Plain);
    let mut r = rng(9);
    let mut hits = 0;
    for i in 0..3000 {
        let org = Vec3::new(-2.0, r.random_range(-1.0..2.0), r.random_range(-1.0..2.0));
        // Half the rays aimed exactly at a vertex or edge point of the scene's grid.
        let aim = if i % 2 == 0 {
            Vec3::new(
                r.random_range(0..9) as f32 * 0.5,
                r.random_range(0..5) as f32 * 0.25,
                r.random_range(0..5) as f32 * 0.25,
            )
        } else {
            Vec3::new(
                r.random_range(0.0..4.0),
                r.random_range(-0.5..1.5),
                r.random_range(-0.5..1.5),
            )
        };
        let ray = Ray {
            org,
            dir: aim - org,
        };
        let w = exact(&o, &tris, hit, &ray, 10_000);
        // Brute force: the nearest exact crossing over every triangle.
        let best = tris
            .iter()
            .enumerate()
            .filter_map(|(k, t)| tetwalk::exact::hit::perturbed_crossing(*t, &ray).map(|t| (k, t)))
            .min_by(|a, b| a.1.cmp(&b.1));
        match (w.end, best) {
            (tetwalk::walk::octree::End::Hit { tri, .. }, Some((_, t))) => {
                let mine =
                    tetwalk::exact::hit::perturbed_crossing(tris[tri as usize], &ray).unwrap();
                assert_eq!(mine, t, "{ray:?}");
                hits += 1;
            }
            (tetwalk::walk::octree::End::Miss, None) => {}
            (end, best) => panic!("{ray:?}: {end:?} against {best:?}"),
        }
    }
    assert!(hits > 1000);
}

#[test]
fn box_exit_answers_each_method_beside_the_exact_faces_and_quarters() {
    let case = br#"{"box": [[0, 0, 0], [2, 2, 2]], "org": [1, 1, 1], "dir": [1, 1, 0.5]}
{"box": [[0, 0, 0], [2, 2, 2]], "org": [1, 1, 1], "dir": [-1, -1, -1]}
{"box": [[0, 0, 0], [0, 2, 2]], "org": [1, 1, 1], "dir": [1, 0, 0]}
"#;
    let (code, out, _) =
        common::run_tetwalk(&["box-exit", "--method", "portalez16-direction"], case);
    assert_eq!(code, 1, "the flat box is an error line");
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines[0]["exact_faces"], serde_json::json!(["+x", "+y"]));
    assert_eq!(lines[0]["correct"], true);
    assert!(face_named(lines[0]["face"].as_str().unwrap()).is_some());
    // Exactly through the corner (0, 0, 0), the exit vertex 0: all three orientations vanish and eq.
    // 8 gives 7, no face.
    assert_eq!(lines[1]["face"], serde_json::Value::Null);
    assert_eq!(lines[1]["correct"], false);
    assert!(lines[2]["error"].as_str().unwrap().contains("box"));
}

/// The octree methods' WGSL answers the stress rows' cells as the CPU does, plain (llvmpipe does not
/// fuse; another GPU's compiler may), but for a few near ties.
#[test]
fn the_cell_test_on_the_gpu_answers_as_the_cpu() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    use tetwalk::choice::Choice;
    use tetwalk::scenes::cells::{CellAim, CellPlace, case};
    let mut r = rng(17);
    let mut cases = Vec::new();
    for i in 0..4000 {
        let (lo, hi, ray) = case(
            CellAim::ALL[i % CellAim::ALL.len()],
            CellPlace::ALL[i % 3],
            4,
            &mut r,
        );
        cases.push(tetwalk::cases::BoxCase {
            lo,
            hi,
            org: ray.org,
            dir: ray.dir,
        });
    }
    let cpu = tetwalk::backend::Backend::Cpu {
        model: Model::Plain,
    };
    for m in tetwalk::registry::OCTREE_METHODS {
        let (a, b) = (
            gpu.box_exits(m, &cases).unwrap(),
            cpu.box_exits(m, &cases).unwrap(),
        );
        let same = a.iter().zip(&b).filter(|(x, y)| x == y).count();
        println!("{}: {same} of {} as on the CPU", m.name(), cases.len());
        assert!(
            same * 100 >= cases.len() * 99,
            "{}: {same} of {}",
            m.name(),
            cases.len()
        );
    }
}

/// The octree walk in WGSL ends as the CPU's walk ends on a bunny view, ray for ray, but for a few near
/// ties (llvmpipe does not fuse; another GPU's compiler may).
#[test]
fn the_octree_walk_on_the_gpu_ends_as_on_the_cpu() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    let mesh = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required)
        .unwrap()
        .mesh;
    let views = tetwalk::scenes::camera::Views::new(160, 64, 64, 1);
    let (lo, hi) = tetwalk::mesh::bounds(&mesh.points);
    let cam = views.camera(lo, hi, 3);
    let start = tetwalk::walk::locate(&mesh, cam.eye, 0).unwrap();
    let region = tetwalk::mesh::surface::region_of(&mesh, start);
    let (tris, _) = tetwalk::mesh::surface::scene_triangles(&mesh, &region);
    let o = Octree::build(&tris, Settings::PAPER).unwrap();
    let rays = views.rays(&cam);
    let mt = tetwalk::family::by_name::<tetwalk::family::Triangle>("mt").unwrap();
    let cap = tetwalk::walk::octree::default_max_steps(&o);
    let cpu = tetwalk::backend::Backend::Cpu {
        model: Model::Plain,
    };
    for m in tetwalk::registry::OCTREE_METHODS
        .iter()
        .filter(|m| !m.is_reference())
    {
        let (on_gpu, on_cpu) = (gpu.octree(&o, &tris, &[]), cpu.octree(&o, &tris, &[]));
        let a = gpu
            .octree_walks(m, mt, &o, &tris, &on_gpu, &rays, cap)
            .unwrap();
        let b = cpu
            .octree_walks(m, mt, &o, &tris, &on_cpu, &rays, cap)
            .unwrap();
        let same = a
            .iter()
            .zip(&b)
            .filter(|(x, y)| x.end.kind() == y.end.kind() && x.cells == y.cells)
            .count();
        println!("{}: {same} of {} as on the CPU", m.name(), rays.len());
        assert!(
            same * 100 >= rays.len() * 99,
            "{}: {same} of {}",
            m.name(),
            rays.len()
        );
        assert!(
            a.iter()
                .any(|w| matches!(w.end, tetwalk::walk::octree::End::Hit { .. }))
        );
    }
}
