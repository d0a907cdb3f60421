//! `tetwalk count`: internally consistent, the reference never wrong, the same numbers whatever the
//! thread count or sharding; its judge and tallies with known answers; the audit.

use std::process::Command;
use tetwalk::methods::Model;

/// Per method: name, wrong rays by kind, and tetrahedra (`steps`) or octree cells (`cells`) walked —
/// what must not depend on threads or shards.
fn strip(v: &serde_json::Value) -> Vec<[serde_json::Value; 4]> {
    v["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| ["method", "wrong", "steps", "cells"].map(|k| m[k].clone()))
        .collect()
}

fn count(threads: &str, json: &std::path::Path, scene: &str) -> (String, serde_json::Value) {
    let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args([
            "count",
            "--scene",
            scene,
            "--views",
            "3",
            "--size",
            "40x30",
            "--json",
            json.to_str().unwrap(),
        ])
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    (String::from_utf8(out.stdout).unwrap(), v)
}

#[test]
fn count_is_consistent_and_the_reference_is_never_wrong() {
    let dir = tempfile::tempdir().unwrap();
    for scene in ["jitter", "kuhn-far"] {
        let (table, one) = count("1", &dir.path().join("one.json"), scene);
        let (_, two) = count("2", &dir.path().join("two.json"), scene);
        assert_eq!(
            strip(&one),
            strip(&two),
            "{scene}: counts must not depend on the thread count"
        );
        assert_eq!(one["views_counted"], 3);
        assert_eq!(one["rays"], 3 * 40 * 30);
        let methods = one["methods"].as_array().unwrap();
        // The reference (certified, audited against exact on about 1000 rays) is counted first.
        assert_eq!(methods[0]["method"], "certified");
        assert!(one["audited"].as_u64().unwrap() > 500);
        assert_eq!(
            methods[0]["wrong"],
            serde_json::json!({"wrong_face": 0, "false_miss": 0, "no_exit_face": 0, "cycle": 0, "step_limit": 0})
        );
        // Every method but exact (which the audit runs) and the reference itself.
        assert_eq!(methods.len(), tetwalk::registry::METHODS.len() - 1);
        let reference_steps = methods[0]["steps"].as_u64().unwrap();
        assert!(
            reference_steps >= 3 * 40 * 30,
            "every ray traverses at least one tetrahedron"
        );
        for m in methods {
            // Table rows are the JSON divided by the views: wrong rays = sum of the kinds.
            let kinds: Vec<u64> = m["wrong"]
                .as_object()
                .unwrap()
                .values()
                .map(|k| k.as_u64().unwrap())
                .collect();
            assert_eq!(
                m["wrong_total"].as_u64().unwrap(),
                kinds.iter().sum::<u64>()
            );
            let row = table
                .lines()
                .find(|l| l.starts_with(&format!("| {} |", m["method"].as_str().unwrap())))
                .unwrap();
            let cols: Vec<f64> = row
                .split('|')
                .skip(2)
                .take(6)
                .map(|c| c.trim().parse().unwrap())
                .collect();
            assert!(
                (cols[0] - kinds.iter().sum::<u64>() as f64 / 3.0).abs() < 1e-3,
                "{row}"
            );
            assert!(
                (cols[0] - cols[1..].iter().sum::<f64>()).abs() < 1e-2,
                "kinds sum to the total: {row}"
            );
        }
    }
}

/// The count's judge and tallies with known answers: one right walk and one walk of every wrong kind,
/// made by hand beside the `exact` walk of a ray through a Kuhn grid, each counted under its kind; a
/// wrong face touching the right one is adjacent, one far away is elsewhere.
#[test]
fn the_count_judges_and_tallies_every_kind_as_it_is() {
    use glam::Vec3;
    use tetwalk::backend::BackendKind;
    use tetwalk::engine::count::wrong_rays;
    use tetwalk::family::count::Counts;
    use tetwalk::family::walk::MethodCount;
    use tetwalk::family::wrong::{Class, Seen};
    use tetwalk::registry::{by_name, reference};
    use tetwalk::scenes::{Generated, generated_mesh};
    use tetwalk::tet::Ray;
    use tetwalk::walk::{Outcome, OutcomeKind, Walk, default_max_steps, locate};

    let mesh = generated_mesh(Generated::Kuhn, 6, Vec3::ZERO, 1).unwrap();
    let org = Vec3::new(0.4, 0.45, 0.3);
    let ray = Ray {
        org,
        dir: Vec3::new(1.0, 0.9, 0.8),
    };
    let start = locate(&mesh, org, 0).unwrap();
    let max = default_max_steps(&mesh);
    let exact = reference().walk(Model::Plain)(&mesh, &ray, start, max);
    let Outcome::Hit { tet, face } = exact.outcome else {
        panic!("the ray hits the inner box: {exact:?}");
    };
    let right_face = mesh.face(tet, face as usize);
    // Constrained faces sharing a vertex with the right one, and sharing none.
    let constrained: Vec<(u32, u8)> = (0..mesh.tets.len() as u32)
        .flat_map(|t| (0..4).map(move |f| (t, f as u8)))
        .filter(|&(t, f)| mesh.is_constrained(t, f as usize))
        .collect();
    let shares = |(t, f): (u32, u8)| {
        mesh.face(t, f as usize)
            .iter()
            .any(|v| right_face.contains(v))
    };
    let near = *constrained
        .iter()
        .find(|&&c| shares(c) && mesh.face(c.0, c.1 as usize) != right_face)
        .unwrap();
    let far = *constrained.iter().find(|&&c| !shares(c)).unwrap();
    let walk = |outcome| Walk { outcome, steps: 7 };
    let walks = [
        exact,
        walk(Outcome::Hit {
            tet: near.0,
            face: near.1,
        }),
        walk(Outcome::Hit {
            tet: far.0,
            face: far.1,
        }),
        walk(Outcome::LeftMesh { tet: 0, face: 0 }),
        walk(Outcome::NoExitFace { tet }),
        walk(Outcome::Cycle { tet, period: 3 }),
        walk(Outcome::StepLimit { tet }),
    ];
    let rays = vec![ray; walks.len()];
    let seen = Seen {
        scene: "kuhn",
        view: 0,
        pixel: [0, 0],
        name: "maria17",
        backend: Some(BackendKind::Cpu),
        walker: Some(by_name("maria17").unwrap()),
    };
    // Each beside the reference walk's ending, the exact one.
    let candidates: Vec<(usize, Walk, Walk)> = walks
        .iter()
        .enumerate()
        .map(|(i, w)| (i, *w, exact))
        .collect();
    let wrong = wrong_rays(&mesh, &seen, 7, &rays, &candidates, start, max);
    let kinds: Vec<_> = wrong.iter().map(|w| w.kind().unwrap()).collect();
    use OutcomeKind::*;
    assert_eq!(
        kinds,
        [Hit, Hit, LeftMesh, NoExitFace, Cycle, StepLimit],
        "the right walk is not counted; every other one is, under its kind"
    );
    assert_eq!(wrong[0].class, Some(Class::Adjacent));
    assert_eq!(wrong[1].class, Some(Class::Elsewhere));
    assert!(wrong[2..].iter().all(|w| w.class.is_none()));
    assert_eq!(wrong[0].pixel, [1, 0]);
    assert_eq!(wrong[0].exact.vertices, Some(right_face));
    let mut total = MethodCount::default();
    for w in &wrong {
        total.add_wrong(w.kind().unwrap(), w.class);
    }
    total.finish(2);
    assert_eq!(total.wrong.0, [2, 1, 1, 1, 1]);
    assert_eq!(
        (total.wrong_face_adjacent, total.wrong_face_elsewhere),
        (1, 1)
    );
    assert_eq!(total.wrong_total, 6);
    assert_eq!(total.per_image.wrong, 3.0);
}

/// The stress table's tally with known answers: a wrong face, a wrong "no exit face", a right answer
/// and a line that misses, each where it belongs.
#[test]
fn the_stress_tally_counts_each_answer_where_it_belongs() {
    use tetwalk::exact::{Classification, FaceSet};
    use tetwalk::family::exit_face::ExitTally;
    use tetwalk::family::{ExitFace, Family};
    use tetwalk::tet::Case;
    let case = Case {
        tet: [glam::Vec3::ZERO; 4],
        org: glam::Vec3::ZERO,
        dir: glam::Vec3::X,
        entry: None,
    };
    // The line leaves through face 2 only, or misses the tetrahedron.
    let meets = Classification {
        exit: FaceSet(1 << 2),
        entry: FaceSet(1 << 3),
    };
    let misses = Classification {
        exit: FaceSet(0),
        entry: FaceSet(0),
    };
    let mut t = ExitTally::default();
    for (x, face) in [
        (meets, Some(1)),
        (meets, None),
        (meets, None),
        (meets, Some(2)),
        (misses, Some(0)),
    ] {
        ExitFace::tally(&mut t, &case, &x, &face);
    }
    assert_eq!((t.judged, t.wrong_face, t.no_exit_face), (4, 1, 2));
}

/// A change to a report's JSON.
type Edit = fn(&mut serde_json::Value);

/// The report without what is timed (seconds, speeds): what a merge must reproduce exactly.
fn untimed(v: &serde_json::Value) -> serde_json::Value {
    match v {
        serde_json::Value::Object(m) => m
            .iter()
            .filter(|(k, _)| !["seconds", "mrays_per_second"].contains(&k.as_str()))
            .map(|(k, v)| (k.clone(), untimed(v)))
            .collect(),
        serde_json::Value::Array(a) => a.iter().map(untimed).collect(),
        x => x.clone(),
    }
}

/// A sharded count merges to the unsharded report exactly, every field but the timings, for walks
/// through the tetrahedra (on a scene with wrong rays of several kinds, wrong faces adjacent and
/// elsewhere) and through the octree; a missing shard, shards of both families, or a shard whose own
/// numbers contradict each other is an error naming the file and the field.
#[test]
fn sharded_counts_merge_to_the_whole_count() {
    let dir = tempfile::tempdir().unwrap();
    let run = |family: &str, scene: &str, extra: &[&str], json: &str| {
        let path = dir.path().join(format!("{family}-{json}"));
        let p = path.to_str().unwrap().to_string();
        let mut args = vec![
            "count", "--family", family, "--scene", scene, "--views", "5", "--size", "24x16",
            "--json", &p,
        ];
        args.extend_from_slice(extra);
        let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
            .args(&args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        path
    };
    let merge = |shards: &[&std::path::PathBuf], json: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_tetwalk"))
            .args(["count", "merge"])
            .args(shards)
            .args(["--json", json.to_str().unwrap()])
            .output()
            .unwrap()
    };
    let read = |p: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let mut one_each = Vec::new();
    for (family, scene) in [("exit-face", "fan-far"), ("octree", "jitter")] {
        let whole = run(family, scene, &[], "whole.json");
        let a = run(family, scene, &["--shard", "0/3"], "a.json");
        let b = run(family, scene, &["--shard", "1/3"], "b.json");
        let c = run(family, scene, &["--shard", "2/3"], "c.json");
        let merged = dir.path().join(format!("{family}-merged.json"));
        let out = merge(&[&c, &a, &b], &merged);
        assert!(
            out.status.success(),
            "{family}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (w, m) = (read(&whole), read(&merged));
        assert!(
            w["rays"].as_u64().unwrap() > 0,
            "{family}: something counted"
        );
        assert_eq!(untimed(&w), untimed(&m), "{family}");
        if family == "exit-face" {
            // The comparison is worth something only where the counts are not all zero.
            let sum = |k: &str| -> u64 {
                w["methods"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|m| m[k].as_u64().unwrap())
                    .sum()
            };
            let kind = |k: &str| -> u64 {
                w["methods"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|m| m["wrong"][k].as_u64().unwrap())
                    .sum()
            };
            for k in ["wrong_face_adjacent", "wrong_face_elsewhere"] {
                assert!(sum(k) > 0, "{scene} has no {k}: {w}");
            }
            for k in ["wrong_face", "false_miss", "no_exit_face"] {
                assert!(kind(k) > 0, "{scene} has no {k}: {w}");
            }
        }
        // Missing a shard is an error.
        let out = merge(&[&a, &b], &dir.path().join("never.json"));
        assert!(!out.status.success());
        assert!(String::from_utf8_lossy(&out.stderr).contains("shards"));
        // A shard edited so that its numbers contradict each other is refused, file and field named.
        let edits: [(&str, Edit); 4] = [
            ("methods[1]", |v| {
                let n = v["methods"][1]["wrong_total"].as_u64().unwrap();
                v["methods"][1]["wrong_total"] = (n + 1000).into();
            }),
            // A kind edited with its per-image figure, the total left: only the kinds' sum says so.
            ("kinds add up", |v| {
                let views = v["views_counted"].as_f64().unwrap();
                let m = &mut v["methods"][1];
                match &mut m["wrong"] {
                    serde_json::Value::Array(k) => k[3] = (k[3].as_u64().unwrap() + 2).into(),
                    w => {
                        let n = w["cycle"].as_u64().unwrap();
                        w["cycle"] = (n + 2).into();
                        let f = m["per_image"]["by_kind"]["cycle"].as_f64().unwrap();
                        m["per_image"]["by_kind"]["cycle"] = (f + 2.0 / views).into();
                    }
                }
            }),
            ("rays", |v| v["rays"] = 1_000_000_000_000u64.into()),
            ("audited", |v| {
                v["audited"] = (v["rays"].as_u64().unwrap() + 1).into()
            }),
        ];
        for (field, edit) in edits {
            let mut v = read(&b);
            edit(&mut v);
            let edited = dir.path().join("edited.json");
            std::fs::write(&edited, v.to_string()).unwrap();
            let out = merge(&[&a, &edited, &c], &dir.path().join("never.json"));
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{family} {field}: {err}");
            assert!(
                err.contains("edited.json: ") && err.contains(field),
                "{family} {field}: {err}"
            );
        }
        one_each.push(a);
    }
    let out = merge(
        &[&one_each[0], &one_each[1]],
        &dir.path().join("never.json"),
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("merge each family apart"), "{err}");
    assert!(!dir.path().join("never.json").exists(), "nothing written");
}

/// The reference's own row is wrong nowhere: a shard saying otherwise is refused.
#[test]
fn a_shard_whose_reference_is_wrong_somewhere_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("a.json");
    let (_, mut v) = count("2", &p, "kuhn");
    v["methods"][0]["wrong_total"] = 7.into();
    v["methods"][0]["wrong"]["no_exit_face"] = 7.into();
    std::fs::write(&p, v.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(["count", "merge", p.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("methods[0] (certified).wrong_total: 7"),
        "{err}"
    );
}

/// The audit catches a reference that is not the exact walk: with a method that fails as the
/// reference, re-judging every ray with `exact` stops the count.
#[test]
fn the_audit_stops_a_count_whose_reference_is_wrong() {
    use tetwalk::backend::Backend;
    use tetwalk::engine::count::{CountSettings, ReferenceWalk, Shard, run};
    use tetwalk::family::Walks;
    use tetwalk::family::count::CountError;
    use tetwalk::scenes::camera::Views;
    let scene = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required).unwrap();
    let views = Views::new(16, 64, 64, 1);
    let settings = |reference: &str| CountSettings::<Walks> {
        views,
        reference: ReferenceWalk::named(reference).unwrap(),
        family: (),
        audit: u64::MAX,
        shard: Shard::ALL,
        answerer: None,
    };
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let ok = run(&scene, &settings("certified"), &[], &cpu, &|| {}, None).unwrap();
    assert_eq!(ok.audited, ok.rays, "every ray audited");
    // halfspace finds no exit face on one of these rays (the dump of the same count shows it).
    match run(&scene, &settings("halfspace"), &[], &cpu, &|| {}, None) {
        Err(CountError::Audit { reference, .. }) => assert_eq!(reference, "halfspace"),
        other => panic!("the audit must stop it: {other:?}"),
    }
    // A reference that ends as the exact walk does, on a constrained face, but another one: maria17
    // on the far bunny, whose wrong rays are nearly all wrong faces. The audit holds the face, not
    // only the kind of ending.
    let far = tetwalk::scenes::load("bunny-quality-far", tetwalk::mesh::Faces::Required).unwrap();
    let few = CountSettings::<Walks> {
        views: Views::new(4, 64, 64, 1),
        ..settings("maria17")
    };
    match run(&far, &few, &[], &cpu, &|| {}, None) {
        Err(CountError::Audit {
            reference,
            walked,
            answered,
            ..
        }) => {
            use tetwalk::walk::Outcome;
            assert_eq!(reference, "maria17");
            assert!(
                matches!(
                    (walked.outcome, answered.outcome),
                    (Outcome::Hit { .. }, Outcome::Hit { .. })
                ) && walked != answered,
                "the same kind of ending, another walk: {walked:?} {answered:?}"
            );
        }
        other => panic!("the audit must stop it: {other:?}"),
    }
    // The rule itself: the reference agrees with the exact walk only step for step, the same face of
    // the same tetrahedron in the same steps; the same kind of ending elsewhere does not agree.
    use tetwalk::family::count::Counted;
    use tetwalk::walk::{Outcome, Walk};
    let ray = tetwalk::tet::Ray {
        org: glam::Vec3::ZERO,
        dir: glam::Vec3::X,
    };
    let at = |tet, face, steps| Walk {
        outcome: Outcome::Hit { tet, face },
        steps,
    };
    let m = &far.mesh;
    assert!(Walks::agrees(m, &ray, &at(7, 1, 9), &at(7, 1, 9)));
    for other in [at(7, 2, 9), at(8, 1, 9), at(7, 1, 10)] {
        assert!(!Walks::agrees(m, &ray, &at(7, 1, 9), &other), "{other:?}");
    }
}

/// A count relabelled under the 12 labellings of its tetrahedra (`relabel_all`) gets each row's
/// wrong rays under all 12, its own labelling's first (as counted); a report of another scene than
/// the one given is refused, naming both, and left as it was.
#[test]
fn a_count_is_relabelled_on_its_own_scene_only() {
    use tetwalk::backend::Backend;
    use tetwalk::engine::count::{CountSettings, ReferenceWalk, Shard, relabel_all, run};
    use tetwalk::family::Walks;
    use tetwalk::family::count::CountError;
    use tetwalk::scenes::camera::Views;
    let scene = tetwalk::scenes::load("kuhn-far", tetwalk::mesh::Faces::Required).unwrap();
    let settings = CountSettings::<Walks> {
        views: Views::new(2, 16, 16, 1),
        reference: ReferenceWalk::default(),
        family: (),
        audit: 0,
        shard: Shard::ALL,
        answerer: None,
    };
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let methods = ["maria17", "ms06"].map(|m| tetwalk::registry::by_name(m).unwrap());
    let answerers = tetwalk::engine::count::AnswerSource::<Walks>::judged(
        None,
        methods,
        ReferenceWalk::default(),
    );
    let mut report = run(&scene, &settings, &answerers, &cpu, &|| {}, None).unwrap();
    let other = tetwalk::scenes::Loaded {
        name: "kuhn".to_string(),
        mesh: scene.mesh.clone(),
    };
    match relabel_all(&mut report, &other, &answerers, &cpu, &|| {}) {
        Err(e @ CountError::OtherScene { .. }) => {
            let said = e.to_string();
            assert!(
                said.contains("kuhn-far") && said.contains("not kuhn"),
                "{said}"
            );
        }
        other => panic!("refused: {other:?}"),
    }
    assert!(report.methods.iter().all(|m| m.relabelled.is_none()));
    relabel_all(&mut report, &scene, &answerers, &cpu, &|| {}).unwrap();
    for m in &report.methods {
        let r = m.relabelled.as_ref().unwrap();
        assert_eq!((r.len(), r[0]), (12, m.counts.wrong_total), "{}", m.method);
    }
}

/// A count's reference walk is read back by name from a report, is one of the walks tetwalk vouches
/// for when `count --reference` offers it (`exact`, `certified`), defaults to the one that is not
/// `exact` itself, and an unknown name in a report is an error naming it; the octree count's
/// ray–triangle method reads back from the triangle registry, not the exit-face one.
#[test]
fn the_reference_walk_is_a_registered_method_by_name() {
    use tetwalk::engine::count::ReferenceWalk;
    let vouched: Vec<&str> = ReferenceWalk::vouched().map(|r| r.name()).collect();
    assert_eq!(vouched, ["exact", "certified"]);
    assert_eq!(ReferenceWalk::default().name(), "certified");
    let r: ReferenceWalk = serde_json::from_str("\"exact\"").unwrap();
    assert_eq!(serde_json::to_string(&r).unwrap(), "\"exact\"");
    let e = serde_json::from_str::<ReferenceWalk>("\"nope\"").unwrap_err();
    assert!(e.to_string().contains("unknown method 'nope'"), "{e}");
    use tetwalk::registry::{ByName, TriangleMethod};
    let t: ByName<TriangleMethod> = serde_json::from_str("\"woop-watertight\"").unwrap();
    assert_eq!(t.name(), "woop-watertight");
    assert!(serde_json::from_str::<ByName<TriangleMethod>>("\"certified\"").is_err());
}

/// A view's camera is located as a function of the mesh and the camera alone (the point perturbed
/// symbolically, so one tetrahedron holds it), so that a count and each of its shards start its rays
/// in the same tetrahedron: on a mesh one of whose vertices is view 5's camera (a box starred from
/// that point: all 12 tetrahedra hold it unperturbed), a walk from any of them locates it in the
/// same one, and every view is located alike whichever views its shard holds before it.
#[test]
fn a_cameras_tetrahedron_does_not_depend_on_the_views_before_it() {
    use glam::Vec3;
    use tetwalk::engine::count::located_views;
    use tetwalk::mesh::{Mesh, RawMesh};
    use tetwalk::scenes::camera::Views;
    let views = Views::new(8, 4, 4, 1);
    let mut points: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32))
        .collect();
    let eye = views.camera(Vec3::ZERO, Vec3::ONE, 5).eye;
    points.push(eye);
    // The cube's faces, counterclockwise seen from outside, each split in two and joined to the eye.
    let tets: Vec<[u32; 4]> = tetwalk::scenes::build::BOX_FACES
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2], 8], [q[0], q[2], q[3], 8]])
        .collect();
    let mesh = Mesh::build(RawMesh {
        points,
        tets,
        ..RawMesh::default()
    })
    .unwrap();
    let from_0 = tetwalk::walk::locate(&mesh, eye, 0).unwrap();
    for t in 1..12 {
        assert_eq!(
            tetwalk::walk::locate(&mesh, eye, t).unwrap(),
            from_0,
            "the camera located from tetrahedron {t}"
        );
    }
    let whole: Vec<(usize, u32)> = located_views(&mesh, &views, |_| true, &|| ())
        .map(|(v, _, t)| (v, t))
        .collect();
    assert_eq!(whole.len(), 8, "every camera is inside the box");
    for shard in 2..=4 {
        for index in 0..shard {
            for (v, _, t) in located_views(&mesh, &views, |v| v % shard == index, &|| ()) {
                assert_eq!(
                    (v, t),
                    whole[v],
                    "view {v} in shard {index}/{shard} starts where the whole count's does"
                );
            }
        }
    }
}
