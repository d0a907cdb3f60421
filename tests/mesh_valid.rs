//! Meshes are checked as tetrahedralizations, exactly (`tetwalk::mesh::valid`): overlaps, folds, cracks,
//! open or self-crossing boundaries and neighbours that disagree with the tetrahedra are refused with
//! the tetrahedron or point named; meshes with cavities, islands in them and separate parts load. Every
//! format reaches the same check (`scene check`, `count`).

use glam::Vec3;
use std::process::Command;
use tetwalk::mesh::{Mesh, RawMesh};
use tetwalk::scenes::meshes::kuhn_grid;

/// A Kuhn grid of `n³` unit cubes without its constrained faces.
fn grid(n: u32) -> RawMesh {
    let mut r = kuhn_grid(n);
    r.constrained.clear();
    r
}

/// The grid without the six tetrahedra of the cube at `(x, y, z)`.
fn without_cube(mut r: RawMesh, n: u32, (x, y, z): (u32, u32, u32)) -> RawMesh {
    let cube = (x + n * (y + n * z)) as usize;
    r.tets.drain(6 * cube..6 * cube + 6);
    r
}

/// `r` with a tetrahedron of four new points, `corner` plus a small offset each, positively oriented
/// as the grid's are.
fn with_island(mut r: RawMesh, corner: Vec3, size: f32) -> RawMesh {
    let first = r.points.len() as u32;
    let orientation = tetwalk::tet::orientation(&r.tets[0].map(|i| r.points[i as usize]));
    r.points.extend([
        corner,
        corner + Vec3::X * size,
        corner + Vec3::Y * size,
        corner + Vec3::Z * size,
    ]);
    let mut t = [first, first + 1, first + 2, first + 3];
    if tetwalk::tet::orientation(&t.map(|i| r.points[i as usize])) != orientation {
        t.swap(0, 1);
    }
    r.tets.push(t);
    r
}

fn refused(r: RawMesh) -> String {
    Mesh::build(r)
        .expect_err("an invalid mesh must be refused")
        .to_string()
}

#[test]
fn valid_meshes_load_cavities_islands_and_separate_parts_included() {
    Mesh::build(grid(3)).unwrap();
    // A cavity: the boundary's second component, wound the other way.
    let cavity = without_cube(grid(3), 3, (1, 1, 1));
    let m = Mesh::build(cavity.clone()).unwrap();
    assert_eq!(m.tets.len(), 6 * 26);
    // An island inside the cavity: covered once again.
    Mesh::build(with_island(cavity, Vec3::splat(1.25), 0.5)).unwrap();
    // A separate part, outside the grid.
    Mesh::build(with_island(grid(3), Vec3::splat(5.0), 1.0)).unwrap();
}

#[test]
fn a_tetrahedron_overlapping_others_is_refused() {
    // Inside a cube of the grid, sharing nothing: the inside is covered twice.
    let e = refused(with_island(grid(3), Vec3::splat(1.25), 0.5));
    assert!(
        e.contains("tetrahedron 162") && e.contains("overlaps itself"),
        "{e}"
    );
    // Half in, half out: the boundary crosses itself.
    let e = refused(with_island(grid(3), Vec3::new(2.5, 1.25, 1.25), 1.0));
    assert!(e.contains("crosses itself"), "{e}");
    // Made of the grid's own vertices, across cubes.
    let mut r = grid(3);
    r.tets.push([0, 5, 17, 42]);
    let s = tetwalk::tet::orientation(&r.tets[0].map(|i| r.points[i as usize]));
    if tetwalk::tet::orientation(&[0, 5, 17, 42].map(|i| r.points[i as usize])) != s {
        r.tets.last_mut().unwrap().swap(0, 1);
    }
    let e = refused(r);
    assert!(e.contains("tetrahedron"), "{e}");
    // A tetrahedron given twice: its faces are shared by three or more.
    let mut r = grid(3);
    r.tets.push(r.tets[10]);
    assert!(refused(r).contains("three or more"));
}

#[test]
fn a_fold_is_refused() {
    // Two tetrahedra on the same side of the face they share, both of one orientation.
    let r = RawMesh {
        points: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            Vec3::new(0.2, 0.2, 0.5),
        ],
        tets: vec![[0, 1, 2, 3], [0, 1, 2, 4]],
        neighbors: None,
        constrained: vec![],
    };
    let e = refused(r);
    assert!(e.contains("same side") && e.contains("fold"), "{e}");
}

#[test]
fn a_duplicated_point_that_opens_a_crack_is_refused() {
    let mut r = grid(3);
    // Point (1, 1, 1) copied, and the tetrahedra of the cube below it moved onto the copy.
    let p = 1 + 4 * (1 + 4);
    let copy = r.points.len() as u32;
    r.points.push(r.points[p]);
    for t in &mut r.tets[..6] {
        for v in t.iter_mut() {
            if *v == p as u32 {
                *v = copy;
            }
        }
    }
    let e = refused(r);
    assert!(
        e.contains(&format!("point {copy}")) && e.contains("crack"),
        "{e}"
    );
}

#[test]
fn neighbours_that_disagree_with_the_tetrahedra_are_refused() {
    let mut r = grid(3);
    let m = Mesh::build(r.clone()).unwrap();
    // Every shared face called the boundary on both sides.
    r.neighbors = Some(vec![[-1; 4]; m.tets.len()]);
    let e = refused(r);
    assert!(
        e.contains("the neighbours name none (the boundary), the tetrahedra tetrahedron"),
        "{e}"
    );
}

#[test]
fn an_open_or_self_crossing_boundary_is_refused() {
    // Two tetrahedra crossing through each other, sharing nothing: two components of the boundary
    // that cross.
    let r = RawMesh {
        points: vec![
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
            Vec3::splat(1.0),
            Vec3::new(5.0, 1.0, 1.0),
            Vec3::new(1.0, 5.0, 1.0),
            Vec3::new(1.0, 1.0, 5.0),
        ],
        tets: vec![[0, 1, 2, 3], [4, 5, 6, 7]],
        neighbors: None,
        constrained: vec![],
    };
    let e = refused(r);
    assert!(e.contains("crosses itself"), "{e}");
}

fn tetwalk(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The shipped mesh in TetGen, VTK and MEDIT files, each with one tetrahedron added that overlaps
/// others: `scene check` says so, naming the file and the element, and `count` refuses to count it.
#[test]
fn every_format_refuses_an_overlapping_tetrahedron() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/meshes");
    let write = |name: &str, text: String| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    let read = |name: &str| std::fs::read_to_string(src.join(name)).unwrap();
    // TetGen: a copy of the first tetrahedron with its last vertex replaced by another point (0-based).
    let ele = read("box.ele");
    let mut lines: Vec<String> = ele.lines().map(str::to_string).collect();
    let first: Vec<u32> = lines[1]
        .split_whitespace()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let count: usize = lines[0].split_whitespace().next().unwrap().parse().unwrap();
    lines[0] = lines[0].replacen(&count.to_string(), &(count + 1).to_string(), 1);
    let extra = [first[0], first[1], first[3], first[2]];
    lines.push(format!(
        "{count} {} {} {} {}",
        extra[0], extra[1], extra[2], extra[3]
    ));
    for ext in ["node", "face"] {
        write(&format!("box.{ext}"), read(&format!("box.{ext}")));
    }
    let tetgen = write("box.ele", lines.join("\n") + "\n");
    // VTK: the same tetrahedron appended as a cell (1-based ids there are 0-based).
    let vtk = read("box.vtk");
    let cells: usize = vtk
        .lines()
        .find_map(|l| l.strip_prefix("CELLS "))
        .and_then(|l| l.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    let mut out = String::new();
    for l in vtk.lines() {
        if let Some(rest) = l.strip_prefix("CELLS ") {
            let n: Vec<usize> = rest
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            out += &format!("CELLS {} {}\n", n[0] + 1, n[1] + 5);
        } else if l.starts_with("CELL_TYPES") {
            out += &format!("4 {} {} {} {}\n", extra[0], extra[1], extra[2], extra[3]);
            out += &format!("CELL_TYPES {}\n", cells + 1);
        } else {
            out += l;
            out += "\n";
        }
    }
    out += "10\n";
    let vtk = write("box.vtk", out);
    for (file, place) in [(&tetgen, "box.ele"), (&vtk, "box.vtk")] {
        let (code, stdout, err) = tetwalk(&["scene", "check", file]);
        assert_eq!(code, 1, "{file}: {stdout}{err}");
        assert!(
            stdout.contains(place) && stdout.contains("not a tetrahedralization"),
            "{stdout}"
        );
        let (code, _, err) = tetwalk(&["count", "--scene", file, "--views", "1", "--size", "4x4"]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(place), "{err}");
    }
    let (code, stdout, _) =
        tetwalk(&["scene", "check", &src.join("box.vtk").display().to_string()]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("a tetrahedralization"), "{stdout}");
}

/// A TetGen file with more rows than its header announces is refused, as every other format refuses
/// counts that disagree: the mesh would be read short.
#[test]
fn tetgen_rows_beyond_the_announced_count_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/meshes");
    for ext in ["node", "face"] {
        std::fs::copy(
            src.join(format!("box.{ext}")),
            dir.path().join(format!("box.{ext}")),
        )
        .unwrap();
    }
    let ele = std::fs::read_to_string(src.join("box.ele")).unwrap();
    let count: usize = ele.split_whitespace().next().unwrap().parse().unwrap();
    let short = ele.replacen(&count.to_string(), &(count - 1).to_string(), 1);
    std::fs::write(dir.path().join("box.ele"), short).unwrap();
    let e = tetwalk::mesh::load_tetgen(&dir.path().join("box"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("box.ele line") && e.contains("beyond"), "{e}");
}

/// An independent judge for small meshes on a fine lattice: no tetrahedron flat, all of one
/// orientation, no two vertices in one place, and no two tetrahedra whose interiors overlap — decided
/// by separating axes (the tetrahedra's face normals and the cross products of their edges), in exact
/// integer arithmetic on the lattice coordinates.
fn overlap_free(points: &[Vec3], tets: &[[u32; 4]], scale: f32) -> bool {
    let p: Vec<[i128; 3]> = points
        .iter()
        .map(|v| v.to_array().map(|x| (x * scale) as i128))
        .collect();
    let sub = |a: [i128; 3], b: [i128; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [i128; 3], b: [i128; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [i128; 3], b: [i128; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let vol = |t: &[u32; 4]| {
        let v = t.map(|i| p[i as usize]);
        dot(sub(v[1], v[0]), cross(sub(v[2], v[0]), sub(v[3], v[0]))).signum()
    };
    let signs: Vec<i128> = tets.iter().map(vol).collect();
    if signs.contains(&0) || signs.iter().any(|&s| s != signs[0]) {
        return false;
    }
    let used: std::collections::BTreeSet<u32> = tets.iter().flatten().copied().collect();
    let at: std::collections::BTreeSet<[i128; 3]> = used.iter().map(|&i| p[i as usize]).collect();
    if at.len() != used.len() {
        return false;
    }
    const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];
    for (i, a) in tets.iter().enumerate() {
        for b in &tets[i + 1..] {
            let (va, vb) = (a.map(|k| p[k as usize]), b.map(|k| p[k as usize]));
            let mut axes = Vec::new();
            for v in [va, vb] {
                for f in 0..4 {
                    let [x, y, z] = [0, 1, 2, 3]
                        .iter()
                        .filter(|&&k| k != f)
                        .copied()
                        .collect::<Vec<_>>()[..]
                    else {
                        unreachable!()
                    };
                    axes.push(cross(sub(v[y], v[x]), sub(v[z], v[x])));
                }
            }
            for ea in EDGES {
                for eb in EDGES {
                    axes.push(cross(sub(va[ea[1]], va[ea[0]]), sub(vb[eb[1]], vb[eb[0]])));
                }
            }
            let separated = axes.iter().any(|&n| {
                if n == [0, 0, 0] {
                    return false;
                }
                let pa = va.map(|v| dot(v, n));
                let pb = vb.map(|v| dot(v, n));
                let (lo_a, hi_a) = (*pa.iter().min().unwrap(), *pa.iter().max().unwrap());
                let (lo_b, hi_b) = (*pb.iter().min().unwrap(), *pb.iter().max().unwrap());
                hi_a <= lo_b || hi_b <= lo_a
            });
            if !separated {
                return false;
            }
        }
    }
    true
}

/// The exact rule against the independent judge on 2,000 meshes: a 2³ Kuhn grid (or a 3³ one with a
/// cavity) with one or two of its vertices moved to random points of a 1/64 lattice, near their places or anywhere in and around the
/// grid. Moves that keep the mesh valid and moves that break it both occur (asserted).
#[test]
fn the_rule_agrees_with_separating_axes_on_moved_vertices() {
    use rand::RngExt;
    let mut r = tetwalk::scenes::rng(7);
    let (mut valid, mut invalid) = (0, 0);
    for case in 0..2000 {
        // Every fourth mesh has a cavity: a second boundary component.
        let mut m = match case % 4 {
            3 => without_cube(grid(3), 3, (1, 1, 1)),
            _ => grid(2),
        };
        for _ in 0..r.random_range(1..=2) {
            let v = r.random_range(0..m.points.len());
            let spread = if case % 2 == 0 { 0.6 } else { 2.5 };
            let moved = m.points[v]
                + Vec3::from_array(std::array::from_fn(|_| {
                    (r.random_range(-spread..spread) * 64.0f32).round() / 64.0
                }));
            m.points[v] = moved;
        }
        let rule = Mesh::build(m.clone()).is_ok();
        let judge = overlap_free(&m.points, &m.tets, 64.0);
        assert_eq!(
            rule,
            judge,
            "case {case}: the rule says {}, separating axes {}: {:?}",
            rule,
            judge,
            Mesh::build(m.clone()).err().map(|e| e.to_string())
        );
        if rule { valid += 1 } else { invalid += 1 }
    }
    assert!(
        valid > 200 && invalid > 200,
        "valid {valid}, invalid {invalid}"
    );
}

/// Two vertices equal but for the sign of a zero coordinate are one point: refused as a duplicate,
/// as two equal vertices are.
#[test]
fn a_vertex_equal_to_another_but_for_the_sign_of_zero_is_refused_as_the_same_point() {
    let raw = |second: Vec3| RawMesh {
        points: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            second,
            Vec3::new(1.0, 1.0, 1.0),
        ],
        tets: vec![[0, 1, 2, 3], [4, 1, 2, 5]],
        neighbors: None,
        constrained: Vec::new(),
    };
    for second in [Vec3::new(-0.0, 0.0, 0.0), Vec3::new(0.0, -0.0, -0.0)] {
        let e = refused(raw(second));
        assert!(e.contains("the same point as point 0"), "{second:?}: {e}");
    }
}
