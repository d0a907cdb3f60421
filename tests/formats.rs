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
