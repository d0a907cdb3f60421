//! Users' own meshes (`corpora/meshes/`, written by Gmsh, meshio and TetGen): Gmsh MSH 4.1 (ASCII and
//! binary) and 2.2, VTK legacy (ASCII and binary) and XML, and MEDIT files load as the same mesh as
//! the TetGen files of it, and count the same; what cannot be walked is refused, naming the place.

mod common;

use tetwalk::mesh::{Faces, Mesh};

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/meshes");

const FORMATS: [&str; 8] = [
    "box41.msh",
    "box41-bin.msh",
    "box22.msh",
    "box.vtk",
    "box-bin.vtk",
    "box.vtu",
    "box.mesh",
    "box",
];

fn load(name: &str) -> Result<Mesh, String> {
    tetwalk::scenes::load(&format!("{DIR}/{name}"), Faces::Required)
        .map(|s| s.mesh)
        .map_err(|e| e.to_string())
}

/// Every file is the TetGen files' mesh: the same points, tetrahedra (labelled alike), neighbours and
/// constrained faces.
#[test]
fn every_format_loads_the_same_mesh_as_tetgen() {
    let tetgen = load("box").unwrap();
    assert_eq!(
        (tetgen.points.len(), tetgen.tets.len()),
        (45, 100),
        "the fixture"
    );
    let constrained: u32 = tetgen.constrained.iter().map(|c| c.count_ones()).sum();
    assert_eq!(constrained, 84);
    for name in FORMATS {
        let m = load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.points, tetgen.points, "{name}");
        assert_eq!(m.tets, tetgen.tets, "{name}");
        assert_eq!(m.neighbors, tetgen.neighbors, "{name}");
        assert_eq!(m.constrained, tetgen.constrained, "{name}");
    }
}

/// `count` on a Gmsh, a VTK and a MEDIT file gives what it gives on the TetGen files, to the step.
#[test]
fn counts_are_the_same_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let count = |name: &str| {
        let json = dir.path().join(format!("{name}.json"));
        let scene = format!("{DIR}/{name}");
        let mut args: Vec<&str> = "count --views 4 --size 32x32".split(' ').collect();
        args.extend(["--scene", &scene, "--json", json.to_str().unwrap()]);
        let (code, _, err) = common::run_tetwalk(&args, b"");
        assert_eq!(code, 0, "{name}: {err}");
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let methods: Vec<serde_json::Value> = v["methods"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| {
                let mut m = m.clone();
                let o = m.as_object_mut().unwrap();
                o.retain(|k, _| !k.contains("second"));
                m
            })
            .collect();
        (v["rays"].as_u64().unwrap(), methods)
    };
    let tetgen = count("box");
    assert!(tetgen.0 > 0);
    for name in ["box41.msh", "box22.msh", "box.vtu", "box.mesh"] {
        assert_eq!(count(name), tetgen, "{name}");
    }
}

/// What tetwalk cannot walk, or a file that contradicts itself, is refused with the place named.
#[test]
fn bad_files_are_refused_naming_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let refused = |name: &str, text: &str, says: &[&str]| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let e = tetwalk::scenes::load(path.to_str().unwrap(), Faces::Required)
            .err()
            .unwrap_or_else(|| panic!("{name} loaded"))
            .to_string();
        for s in says {
            assert!(e.contains(s), "{name}: {e} lacks {s}");
        }
    };
    let msh22 = |elements: &str| {
        format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 0\n$EndNodes\n$Elements\n{elements}$EndElements\n"
        )
    };
    // No triangles: a scene without surfaces only when asked for.
    refused(
        "tets.msh",
        &msh22("1\n7 4 2 0 1 1 2 3 4\n"),
        &["tets.msh", "no triangles", "--no-faces"],
    );
    let path = dir.path().join("tets.msh");
    let m = tetwalk::scenes::load(path.to_str().unwrap(), Faces::Optional)
        .unwrap()
        .mesh;
    assert_eq!(m.tets.len(), 1);
    // A hexahedron, an unknown node, a flat tetrahedron (named by its element tag).
    refused(
        "hex.msh",
        &msh22("1\n3 5 0 1 2 3 4 5 1 2 3\n"),
        &["hex.msh line 14, element 3", "hexahedron"],
    );
    refused(
        "node.msh",
        &msh22("1\n9 4 0 1 2 3 6\n"),
        &["element 9", "node 6"],
    );
    refused(
        "flat.msh",
        &msh22("2\n4 4 0 1 2 3 5\n5 2 0 1 2 3\n"),
        &["flat.msh, element 4", "flat"],
    );
    refused(
        "old.msh",
        "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n",
        &["MSH version 4.0", "4.1", "2.2"],
    );
    refused(
        "cut.msh",
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n",
        &["cut.msh line 5", "announces 3"],
    );
    // VTK: not an unstructured grid; MEDIT: TetGen's miscounted Triangles, an index out of range.
    refused(
        "poly.vtk",
        "# vtk DataFile Version 2.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n",
        &["poly.vtk", "not an unstructured grid"],
    );
    // A malformed .vtu on which vtkio panics (found by the mesh_load fuzz target): an error instead.
    let panics = std::fs::read(format!("{DIR}/vtkio-panic.vtu")).unwrap();
    let e = tetwalk::mesh::formats::parse(
        &panics,
        tetwalk::mesh::formats::Format::Vtu,
        Faces::Required,
        "vtkio-panic.vtu",
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("vtkio-panic.vtu: the VTK reader (vtkio) failed on it"),
        "{e}"
    );
    // A .vtu whose zlib header claims about 1.2 TiB (300 blocks of 4 GiB): refused before vtkio
    // would allocate it, as are more blocks than the file could hold.
    let good = std::fs::read_to_string(format!("{DIR}/box.vtu")).unwrap();
    let header = "AQAAAACAAAA4BAAALAEAAA==";
    assert!(good.contains(header), "box.vtu's first array header");
    for (name, claim, says) in [
        ("huge.vtu", "LAEAAP////8AAAAALAEAAA==", "claim"),
        (
            "blocks.vtu",
            "/////wCAAAA4BAAALAEAAA==",
            "more than the file could hold",
        ),
        // No block, but blocks of 4 GiB: the reader's `size · (blocks - 1)` would wrap.
        ("zero.vtu", "AAAAAP////8AAAAALAEAAA==", "claims no block"),
    ] {
        let e = tetwalk::mesh::formats::parse(
            good.replacen(header, claim, 1).as_bytes(),
            tetwalk::mesh::formats::Format::Vtu,
            Faces::Required,
            name,
        )
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains(name) && e.contains(says), "{e}");
    }
    let tetgen_g = std::fs::read_to_string(format!("{DIR}/tetgen-g.mesh")).unwrap();
    refused(
        "tetgen-g.mesh",
        &tetgen_g,
        &["line 145", "Triangles announces 242 entries", "after 84"],
    );
    refused(
        "range.mesh",
        "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 1\nTetrahedra\n1\n1 2 3 4 0\nEnd\n",
        &["range.mesh line 8", "vertex 2 out of range"],
    );
}

/// The other commands read them too: `scene export` and `render` take a Gmsh file.
#[test]
fn scene_commands_read_other_formats() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box.json");
    let scene = format!("{DIR}/box22.msh");
    let (code, _, err) =
        common::run_tetwalk(&["scene", "export", &scene, out.to_str().unwrap()], b"");
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["tets"].as_array().map(Vec::len), Some(100), "{v}");
    let png = dir.path().join("box.png");
    let scene = format!("{DIR}/box.vtu");
    let mut args: Vec<&str> = "render shaded --size 16x16".split(' ').collect();
    args.extend(["--scene", &scene, "--out", png.to_str().unwrap()]);
    let (code, _, err) = common::run_tetwalk(&args, b"");
    assert_eq!(code, 0, "{err}");
    assert!(png.exists());
}

/// Points as coordinate bits, sorted.
type PointSet = Vec<[u32; 3]>;

/// A mesh as point sets: each tetrahedron's corners and each constrained face's, as coordinate bits,
/// sorted (independent of the order points are listed or numbered in, and of orientation).
fn point_sets(m: &Mesh) -> (Vec<PointSet>, Vec<PointSet>) {
    let p = |i: u32| m.points[i as usize].to_array().map(f32::to_bits);
    let mut tets: Vec<Vec<[u32; 3]>> = m
        .tets
        .iter()
        .map(|t| {
            let mut v: Vec<_> = t.iter().map(|&i| p(i)).collect();
            v.sort();
            v
        })
        .collect();
    tets.sort();
    let mut faces: Vec<Vec<[u32; 3]>> = triangles(m)
        .iter()
        .map(|t| {
            let mut v: Vec<_> = t.iter().map(|&i| p(i)).collect();
            v.sort();
            v
        })
        .collect();
    faces.sort();
    faces.dedup();
    (tets, faces)
}

/// The constrained faces as point triples, each once.
fn triangles(m: &Mesh) -> Vec<[u32; 3]> {
    let mut out: Vec<[u32; 3]> = Vec::new();
    for (t, &bits) in m.tets.iter().zip(&m.constrained) {
        for (f, v) in tetwalk::tet::FACE_VERTICES.iter().enumerate() {
            if bits >> f & 1 == 1 {
                let mut tri = v.map(|k| t[k]);
                tri.sort();
                out.push(tri);
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// The mesh written in `format` with its points listed in the order `order` (the `k`-th listed is
/// point `order[k]`), each point `i` named `tag(i)` where the format names points by tag (Gmsh), by
/// its place in the listing where it names them by position (VTK, MEDIT).
fn written(m: &Mesh, format: &str, order: &[usize], tag: &dyn Fn(usize) -> u64) -> Vec<u8> {
    let mut place = vec![0usize; order.len()];
    for (k, &i) in order.iter().enumerate() {
        place[i] = k;
    }
    let name = |i: u32, base: usize| -> u64 {
        match format {
            "msh41" | "msh41-bin" | "msh22" => tag(i as usize),
            _ => (place[i as usize] + base) as u64,
        }
    };
    let coords = |i: usize| m.points[i].to_array().map(|x| x as f64);
    let tris = triangles(m);
    let mut s = String::new();
    let mut b: Vec<u8> = Vec::new();
    match format {
        "msh41" => {
            let tags: Vec<u64> = order.iter().map(|&i| tag(i)).collect();
            let (lo, hi) = (tags.iter().min().unwrap(), tags.iter().max().unwrap());
            s += &format!(
                "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {} {lo} {hi}\n3 1 0 {}\n",
                order.len(),
                order.len()
            );
            for t in &tags {
                s += &format!("{t}\n");
            }
            for &i in order {
                let [x, y, z] = coords(i);
                s += &format!("{x:?} {y:?} {z:?}\n");
            }
            let n = m.tets.len() + tris.len();
            s += &format!(
                "$EndNodes\n$Elements\n2 {n} 1 {n}\n3 1 4 {}\n",
                m.tets.len()
            );
            for (e, t) in m.tets.iter().enumerate() {
                let [a, b2, c, d] = t.map(|i| name(i, 1));
                s += &format!("{} {a} {b2} {c} {d}\n", e + 1);
            }
            s += &format!("2 1 2 {}\n", tris.len());
            for (e, t) in tris.iter().enumerate() {
                let [a, b2, c] = t.map(|i| name(i, 1));
                s += &format!("{} {a} {b2} {c}\n", m.tets.len() + e + 1);
            }
            s += "$EndElements\n";
        }
        "msh41-bin" => {
            let z = |v: u64, b: &mut Vec<u8>| b.extend(v.to_le_bytes());
            let i4 = |v: i32, b: &mut Vec<u8>| b.extend(v.to_le_bytes());
            b.extend(b"$MeshFormat\n4.1 1 8\n");
            i4(1, &mut b);
            b.extend(b"\n$EndMeshFormat\n$Nodes\n");
            let tags: Vec<u64> = order.iter().map(|&i| tag(i)).collect();
            for v in [
                1,
                order.len() as u64,
                *tags.iter().min().unwrap(),
                *tags.iter().max().unwrap(),
            ] {
                z(v, &mut b);
            }
            for v in [3, 1, 0] {
                i4(v, &mut b);
            }
            z(order.len() as u64, &mut b);
            for &t in &tags {
                z(t, &mut b);
            }
            for &i in order {
                for x in coords(i) {
                    b.extend(x.to_le_bytes());
                }
            }
            b.extend(b"\n$EndNodes\n$Elements\n");
            let n = (m.tets.len() + tris.len()) as u64;
            for v in [2, n, 1, n] {
                z(v, &mut b);
            }
            for v in [3, 1, 4] {
                i4(v, &mut b);
            }
            z(m.tets.len() as u64, &mut b);
            for (e, t) in m.tets.iter().enumerate() {
                z(e as u64 + 1, &mut b);
                for &i in t {
                    z(name(i, 1), &mut b);
                }
            }
            for v in [2, 1, 2] {
                i4(v, &mut b);
            }
            z(tris.len() as u64, &mut b);
            for (e, t) in tris.iter().enumerate() {
                z((m.tets.len() + e + 1) as u64, &mut b);
                for &i in t {
                    z(name(i, 1), &mut b);
                }
            }
            b.extend(b"\n$EndElements\n");
            return b;
        }
        "msh22" => {
            s += &format!(
                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{}\n",
                order.len()
            );
            for &i in order {
                let [x, y, z] = coords(i);
                s += &format!("{} {x:?} {y:?} {z:?}\n", tag(i));
            }
            s += &format!("$EndNodes\n$Elements\n{}\n", m.tets.len() + tris.len());
            for (e, t) in m.tets.iter().enumerate() {
                let [a, b2, c, d] = t.map(|i| name(i, 1));
                s += &format!("{} 4 0 {a} {b2} {c} {d}\n", e + 1);
            }
            for (e, t) in tris.iter().enumerate() {
                let [a, b2, c] = t.map(|i| name(i, 1));
                s += &format!("{} 2 0 {a} {b2} {c}\n", m.tets.len() + e + 1);
            }
            s += "$EndElements\n";
        }
        "vtk" => {
            s += &format!(
                "# vtk DataFile Version 2.0\npermuted\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {} double\n",
                order.len()
            );
            for &i in order {
                let [x, y, z] = coords(i);
                s += &format!("{x:?} {y:?} {z:?}\n");
            }
            let cells = m.tets.len() + tris.len();
            s += &format!("CELLS {cells} {}\n", 5 * m.tets.len() + 4 * tris.len());
            for t in &m.tets {
                let [a, b2, c, d] = t.map(|i| name(i, 0));
                s += &format!("4 {a} {b2} {c} {d}\n");
            }
            for t in &tris {
                let [a, b2, c] = t.map(|i| name(i, 0));
                s += &format!("3 {a} {b2} {c}\n");
            }
            s += &format!("CELL_TYPES {cells}\n");
            s += &"10\n".repeat(m.tets.len());
            s += &"5\n".repeat(tris.len());
        }
        "vtk51" => {
            s += &format!(
                "# vtk DataFile Version 5.1\npermuted\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {} double\n",
                order.len()
            );
            for &i in order {
                let [x, y, z] = coords(i);
                s += &format!("{x:?} {y:?} {z:?}\n");
            }
            let cells = m.tets.len() + tris.len();
            s += &format!(
                "CELLS {} {}\nOFFSETS vtktypeint64\n0\n",
                cells + 1,
                4 * m.tets.len() + 3 * tris.len()
            );
            let mut end = 0;
            for _ in &m.tets {
                end += 4;
                s += &format!("{end}\n");
            }
            for _ in &tris {
                end += 3;
                s += &format!("{end}\n");
            }
            s += "CONNECTIVITY vtktypeint64\n";
            for t in &m.tets {
                s += &format!("{}\n", t.map(|i| name(i, 0).to_string()).join(" "));
            }
            for t in &tris {
                s += &format!("{}\n", t.map(|i| name(i, 0).to_string()).join(" "));
            }
            s += &format!("CELL_TYPES {cells}\n");
            s += &"10\n".repeat(m.tets.len());
            s += &"5\n".repeat(tris.len());
        }
        "vtu" => {
            let cells = m.tets.len() + tris.len();
            s += &format!(
                "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{cells}\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
                order.len()
            );
            for &i in order {
                let [x, y, z] = coords(i);
                s += &format!("{x:?} {y:?} {z:?}\n");
            }
            s += "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
            let mut offsets = Vec::new();
            let mut end = 0;
            for t in &m.tets {
                s += &format!("{}\n", t.map(|i| name(i, 0).to_string()).join(" "));
                end += 4;
                offsets.push(end);
            }
            for t in &tris {
                s += &format!("{}\n", t.map(|i| name(i, 0).to_string()).join(" "));
                end += 3;
                offsets.push(end);
            }
            s += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
            s += &offsets
                .iter()
                .map(|o| o.to_string())
                .collect::<Vec<_>>()
                .join(" ");
            s += "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
            s += &"10 ".repeat(m.tets.len());
            s += &"5 ".repeat(tris.len());
            s += "\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
        }
        _ => {
            s += &format!(
                "MeshVersionFormatted 1\nDimension 3\nVertices\n{}\n",
                order.len()
            );
            for &i in order {
                let [x, y, z] = coords(i);
                s += &format!("{x:?} {y:?} {z:?} 0\n");
            }
            s += &format!("Triangles\n{}\n", tris.len());
            for t in &tris {
                let [a, b2, c] = t.map(|i| name(i, 1));
                s += &format!("{a} {b2} {c} 1\n");
            }
            s += &format!("Tetrahedra\n{}\n", m.tets.len());
            for t in &m.tets {
                let [a, b2, c, d] = t.map(|i| name(i, 1));
                s += &format!("{a} {b2} {c} {d} 0\n");
            }
            s += "End\n";
        }
    }
    s.into_bytes()
}

/// Meshes read as their files say: the box written in every format with its points listed out of
/// order — neighbours' tags swapped (`2 1 4 3 …`, dense, as MSH 4.1 allows), listed in reverse, tags
/// sparse and shuffled (Gmsh), or the points reordered and every index renumbered (VTK, MEDIT) —
/// loads as the same tetrahedra and faces, compared as point sets; a tag defined twice is refused.
#[test]
fn meshes_with_permuted_tags_read_as_their_files_say() {
    let m = load("box").unwrap();
    let want = point_sets(&m);
    let n = m.points.len();
    let swapped: Vec<usize> = (0..n)
        .map(|k| {
            if k % 2 == 0 {
                (k + 1).min(n - 1)
            } else {
                k - 1
            }
        })
        .collect();
    let mut seen = vec![false; n];
    let swapped: Vec<usize> = swapped
        .into_iter()
        .chain(0..n)
        .filter(|&i| !std::mem::replace(&mut seen[i], true))
        .collect();
    let reversed: Vec<usize> = (0..n).rev().collect();
    let shuffled: Vec<usize> = (0..n).map(|k| k * 17 % n).collect();
    assert_eq!(
        shuffled
            .iter()
            .collect::<std::collections::HashSet<_>>()
            .len(),
        n
    );
    let dense = |i: usize| i as u64 + 1;
    let sparse = |i: usize| 1000 + 7 * ((i * 13) % n) as u64;
    let dir = tempfile::tempdir().unwrap();
    for (format, ext) in [
        ("msh41", "msh"),
        ("msh41-bin", "msh"),
        ("msh22", "msh"),
        ("vtk", "vtk"),
        ("vtk51", "vtk"),
        ("vtu", "vtu"),
        ("medit", "mesh"),
    ] {
        for (how, order, tag) in [
            ("swapped", &swapped, &dense as &dyn Fn(usize) -> u64),
            ("reversed", &reversed, &dense),
            ("shuffled, sparse", &shuffled, &sparse),
        ] {
            let path = dir.path().join(format!("{format}.{ext}"));
            std::fs::write(&path, written(&m, format, order, tag)).unwrap();
            let got = tetwalk::scenes::load(path.to_str().unwrap(), Faces::Required)
                .unwrap_or_else(|e| panic!("{format}, {how}: {e}"))
                .mesh;
            assert!(point_sets(&got) == want, "{format}, {how}: another mesh");
        }
    }
    // A tag defined twice: refused, naming it.
    let twice = |i: usize| (i.max(1)) as u64;
    for format in ["msh41", "msh41-bin"] {
        let path = dir.path().join("twice.msh");
        std::fs::write(&path, written(&m, format, &reversed, &twice)).unwrap();
        let e = tetwalk::scenes::load(path.to_str().unwrap(), Faces::Required)
            .err()
            .unwrap_or_else(|| panic!("{format}: a tag defined twice loaded"))
            .to_string();
        assert!(e.contains("node 1 defined twice"), "{format}: {e}");
    }
}

/// A file read as something else fails naming the line or element, briefly: a legacy VTK file with a
/// NaN coordinate (the point named), a negative index, counts that lie; a Gmsh file announcing more
/// nodes than it could hold (a short message, no dump of its bytes). A scene that is not there, a
/// folder, or a file of an extension tetwalk does not read is an error of `scene check` (status 2),
/// not an invalid mesh (status 1).
#[test]
fn a_misread_file_is_named_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let vtk = |points: &str, cells: &str| {
        format!(
            "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n{points}\nCELLS 2 9\n{cells}\nCELL_TYPES 2\n10\n5\n"
        )
    };
    let good = "0 0 0\n1 0 0\n0 1 0\n0 0 1";
    let cells = "4 0 1 2 3\n3 0 1 2";
    for (name, text, says) in [
        (
            "nan.vtk",
            vtk("0 0 0\n1 nan 0\n0 1 0\n0 0 1", cells),
            "point 1",
        ),
        (
            "negative.vtk",
            vtk(good, "4 0 1 -2 3\n3 0 1 2"),
            "line 11: '-2' is not cell 0",
        ),
        (
            "short.vtk",
            vtk(good, "4 0 1 2 3\n3 0 1"),
            "line 13: 'CELL_TYPES' is not cell 1",
        ),
        (
            "lie.vtk",
            vtk(good, "4 0 1 2 3\n7 0 1 2 3 0 1 2"),
            "cell 1 names 7 points, past the 9 entries",
        ),
        (
            "huge.vtk",
            vtk(good, cells).replace("CELLS 2 9", "CELLS 2 9000000000"),
            "announces 9000000000 entries, more than the file",
        ),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, &text).unwrap();
        let e = tetwalk::scenes::load(path.to_str().unwrap(), Faces::Required)
            .err()
            .unwrap_or_else(|| panic!("{name} loaded"))
            .to_string();
        assert!(e.contains(name) && e.contains(says), "{name}: {e}");
    }
    let msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4000000000 1 4000000000\n3 1 0 4000000000\n1\n$EndNodes\n";
    let path = dir.path().join("many.msh");
    std::fs::write(&path, msh).unwrap();
    let e = tetwalk::scenes::load(path.to_str().unwrap(), Faces::Required)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("4000000000 nodes") && e.len() < 400, "{e}");
    let folder = dir.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    let odd = dir.path().join("mesh.foo");
    std::fs::write(&odd, "").unwrap();
    for (scene, says) in [
        (folder.to_str().unwrap().to_string(), "is a folder"),
        (format!("{}/none.msh", dir.path().display()), "cannot read"),
        (format!("{}/none", dir.path().display()), "no such scene"),
        (
            odd.to_str().unwrap().to_string(),
            "(.foo) is not one tetwalk reads",
        ),
    ] {
        let (code, _, err) = common::run_tetwalk(&["scene", "check", &scene], b"");
        assert_eq!(code, 2, "{scene}: {err}");
        assert!(err.contains(says), "{scene}: {err}");
    }
}
