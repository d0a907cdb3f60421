//! Scenes: the shipped bunny tetrahedralizations and the generated ones load, validate, report counts
//! that independent counts confirm, and `exact` walks of camera rays end on the brute-force first hit.

use std::process::Command;
use tetwalk::engine::info::SceneInfo;
use tetwalk::exact::hit::first_hit;
use tetwalk::methods::Model;
use tetwalk::registry::by_name;
use tetwalk::scenes::camera::view;
use tetwalk::walk::{Outcome, default_max_steps, locate};

const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/scenes");

/// The first number of a TetGen file (its count).
fn header_count(path: &str) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    text.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn bunny_scenes_load_and_their_counts_check_out() {
    let off = std::fs::read_to_string(format!("{SCENES}/bunny.off")).unwrap();
    let model_triangles: usize = off
        .lines()
        .nth(1)
        .unwrap()
        .split_whitespace()
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(model_triangles, 3674);
    for name in tetwalk::scenes::BUILT_IN {
        let mesh = tetwalk::scenes::load(name, tetwalk::mesh::Faces::Required)
            .unwrap()
            .mesh;
        let info = SceneInfo::of(&mesh, tetwalk::octree::Settings::PAPER);
        assert_eq!(
            info.tetrahedra,
            header_count(&format!("{SCENES}/{name}.ele")),
            "{name}"
        );
        assert_eq!(
            info.points,
            header_count(&format!("{SCENES}/{name}.node")),
            "{name}"
        );
        // -Y keeps every input triangle as one face: the model's and the box's twelve.
        assert_eq!(info.constrained_faces, model_triangles + 12, "{name}");
        assert_eq!(
            header_count(&format!("{SCENES}/{name}.face")),
            model_triangles + 12,
            "{name}"
        );
        // Every face is shared by two tetrahedra except the 12 hull (box) triangles.
        assert_eq!(
            info.constrained_faces + info.other_faces,
            (4 * info.tetrahedra + 12) / 2,
            "{name}"
        );
        assert_eq!(info.layout_bytes[3].1, 16 * info.tetrahedra);
        assert_eq!(
            info.min_dihedral_deg_5.iter().sum::<usize>(),
            info.tetrahedra
        );
        assert_eq!(
            info.volume_ratio_decades.iter().sum::<usize>(),
            info.tetrahedra
        );
        assert_eq!(
            mesh.flipped,
            mesh.tets.len(),
            "TetGen's negative tetrahedra are all normalised"
        );
    }
    for far in ["bunny-far", "bunny-quality-far"] {
        let far = tetwalk::scenes::load(far, tetwalk::mesh::Faces::Required)
            .unwrap()
            .mesh;
        assert!(
            far.points.iter().all(|p| p.min_element() > 65536.0 - 100.0),
            "bunny-far is far from the origin"
        );
    }
}

#[test]
fn exact_walks_of_camera_rays_end_on_the_brute_force_first_hit() {
    for name in ["bunny-quality", "bunny-far", "jitter", "kuhn-far"] {
        let mesh = tetwalk::scenes::load(name, tetwalk::mesh::Faces::Required)
            .unwrap()
            .mesh;
        let (lo, hi) = tetwalk::mesh::bounds(&mesh.points);
        let exact = by_name("exact").unwrap();
        let max = default_max_steps(&mesh);
        let mut hits = 0;
        for v in 0..4 {
            let cam = view(lo, hi, v, 4, 3, 40.0, 1.0);
            let start = locate(&mesh, cam.eye, 0).unwrap();
            for k in 0..8 {
                let ray = cam.ray(3 + 4 * k, 2 + 4 * k, 32, 32);
                let w = exact.walk(Model::Plain)(&mesh, &ray, start, max);
                match (w.outcome, first_hit(&mesh, &ray)) {
                    (Outcome::Hit { tet, face }, Some((_, faces))) => {
                        hits += 1;
                        let tri = |t: u32, f: u8| {
                            let mut v = mesh.face(t, f as usize);
                            v.sort_unstable();
                            v
                        };
                        assert!(
                            faces.iter().any(|&(t, f)| tri(t, f) == tri(tet, face)),
                            "{name}: {ray:?}"
                        );
                    }
                    (Outcome::LeftMesh { .. }, None) => {}
                    (o, b) => panic!("{name}: exact walk {o:?}, brute force {b:?}"),
                }
            }
        }
        assert!(hits >= 16, "{name}: camera rays should mostly hit ({hits})");
    }
}

fn tetwalk(args: &[&str], path: Option<&str>) -> (bool, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tetwalk"));
    c.args(args);
    if let Some(p) = path {
        c.env("PATH", p);
    }
    let out = c.output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr),
    )
}

#[test]
fn scene_build_runs_tetgen_and_refuses_bad_models() {
    let dir = tempfile::tempdir().unwrap();
    let d = |f: &str| dir.path().join(f).to_str().unwrap().to_string();
    let model = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/twobox.off");
    let (ok, out) = tetwalk(
        &["scene", "build", model, "--quality", "--out", &d("two")],
        None,
    );
    assert!(ok, "{out}");
    let mesh = tetwalk::mesh::load_tetgen(std::path::Path::new(&d("two"))).unwrap();
    let info = SceneInfo::of(&mesh, tetwalk::octree::Settings::PAPER);
    assert_eq!(
        info.constrained_faces,
        24 + 12,
        "two model boxes and the scene box"
    );
    let (ok, out) = tetwalk(&["scene", "info", &d("two")], None);
    assert!(
        ok && out.contains(&format!("| {} |", mesh.tets.len())),
        "{out}"
    );
    assert!(
        out.contains("| seed 000's BUNNY (Table 3) | - | 682733 | 222775 | 1142650 | 62 |"),
        "the paper's Table 3 row beside the scene's: {out}"
    );

    let text = std::fs::read_to_string(model).unwrap();
    // A hole: drop the last triangle.
    let holed: Vec<&str> = text.lines().collect();
    let n = holed.len();
    let holed = holed[..n - 1].join("\n").replace("16 24 0", "16 23 0");
    std::fs::write(d("holed.off"), holed).unwrap();
    let (ok, out) = tetwalk(&["scene", "build", &d("holed.off")], None);
    assert!(!ok && out.contains("not closed"), "{out}");
    // Two closed boxes passing through each other.
    let crossing = text
        .replace("1.5 1.5 1.5", "-1 1.5 1.5")
        .replace("1.5 2.5 1.5", "-1 2.5 1.5")
        .replace("1.5 1.5 2.5", "-1 1.5 2.5")
        .replace("1.5 2.5 2.5", "-1 2.5 2.5");
    assert_ne!(crossing, text);
    std::fs::write(d("crossing.off"), crossing).unwrap();
    let (ok, out) = tetwalk(&["scene", "build", &d("crossing.off")], None);
    assert!(!ok && out.contains("intersect"), "{out}");
    let (ok, out) = tetwalk(&["scene", "build", model, "--out", &d("x")], Some(""));
    assert!(!ok && out.contains("tetgen is not installed"), "{out}");
}

/// A model 1e-30 across works end to end: `scene build` meshes it, every camera ray is finite and
/// every ray is judged (the f32 methods' products underflow there: they fail, and are counted).
#[test]
fn a_model_1e_30_across_is_built_counted_and_its_rays_are_finite() {
    let dir = tempfile::tempdir().unwrap();
    let d = |f: &str| dir.path().join(f).to_str().unwrap().to_string();
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/twobox.off"
    ))
    .unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for l in &mut lines[2..18] {
        let scaled: Vec<String> = l
            .split_whitespace()
            .map(|x| format!("{:e}", x.parse::<f64>().unwrap() * 1e-30))
            .collect();
        *l = scaled.join(" ");
    }
    std::fs::write(d("tiny.off"), lines.join("\n")).unwrap();
    let (ok, out) = tetwalk(
        &["scene", "build", &d("tiny.off"), "--out", &d("tiny")],
        None,
    );
    assert!(ok, "{out}");
    let tiny = d("tiny");
    let count = |more: &[&str]| {
        let mut args = vec!["count", "--scene", &tiny, "--views", "3", "--size", "8x8"];
        args.extend_from_slice(more);
        let (ok, out) = tetwalk(&args, None);
        assert!(ok, "{out}");
    };
    let json = d("count.json");
    count(&["--json", &json]);
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["rays"], 3 * 64, "every view counted: {r}");
    assert_eq!(r["methods"][0]["wrong_total"], 0);
    let rays = d("rays.jsonl");
    count(&["--rays-out", &rays]);
    let text = std::fs::read_to_string(&rays).unwrap();
    assert_eq!(text.lines().count(), 1 + 3 * 64);
    assert!(!text.contains("null"), "every ray finite");
}

/// A camera's rays do not depend on the scale of the scene, bit for bit, by powers of two (its
/// direction is scaled to about 1 before it is normalised).
#[test]
fn camera_rays_are_the_same_at_every_power_of_two_scale() {
    let (lo, hi) = (
        glam::Vec3::new(-3.0, -1.5, 0.25),
        glam::Vec3::new(2.0, 4.0, 3.5),
    );
    let rays = |s: f32| -> Vec<(u32, u32, u32)> {
        let cam = view(lo * s, hi * s, 5, 16, 1, 40.0, 1.0);
        (0..16)
            .map(|i| cam.ray(i % 4, i / 4, 4, 4).dir)
            .map(|d| (d.x.to_bits(), d.y.to_bits(), d.z.to_bits()))
            .collect()
    };
    let one = rays(1.0);
    for e in [-120, -100, -60, -20, 20, 60, 100] {
        assert_eq!(rays(2f32.powi(e)), one, "scale 2^{e}");
    }
}

/// `scene subdivide` is byte for byte the same on every run, keeps the model closed and quadruples
/// its triangles per level (the first step of corpora/scenes/bunny-paper.sh).
#[test]
fn subdividing_the_bunny_is_byte_for_byte_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/scenes/bunny.off");
    let run = |name: &str| {
        let out = dir.path().join(name);
        let (ok, said) = tetwalk(
            &[
                "scene",
                "subdivide",
                bunny,
                "--levels",
                "2",
                "--out",
                out.to_str().unwrap(),
            ],
            None,
        );
        assert!(ok && said.contains("58784 triangles"), "{said}");
        std::fs::read(out).unwrap()
    };
    let (a, b) = (run("a.off"), run("b.off"));
    assert_eq!(a, b);
    let json = dir.path().join("said.json");
    let (ok, said) = tetwalk(
        &[
            "scene",
            "subdivide",
            bunny,
            "--out",
            dir.path().join("c.off").to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
        ],
        None,
    );
    assert!(ok, "{said}");
    let said: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    assert_eq!(
        (said["levels"].as_u64(), said["triangles"].as_u64()),
        (Some(1), Some(3674 * 4))
    );
    let m = tetwalk::scenes::model::Surface::read(&dir.path().join("a.off")).unwrap();
    assert_eq!(m.triangles.len(), 3674 * 16);
    m.check_closed().unwrap();
    let (ok, said) = tetwalk(
        &[
            "scene",
            "subdivide",
            bunny,
            "--levels",
            "9",
            "--out",
            "x.off",
        ],
        None,
    );
    assert!(!ok && said.contains("--levels 9"), "{said}");
}
