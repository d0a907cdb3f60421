//! Answers computed anywhere, for a scene: `count --rays-out` writes every ray's exact inputs, another
//! program (here, this test, walking tetwalk's `maria17` outside the command) answers each with its
//! walk, and `judge` counts them as `count` counts `maria17` itself: the same wrong rays by kind, the
//! same tetrahedra.

mod common;

use common::run_tetwalk;
use serde_json::{Value, json};
use tetwalk::methods::Model;
use tetwalk::registry::by_name;
use tetwalk::walk::default_max_steps;

const VIEWS: [&str; 4] = ["--views", "6", "--size", "24x24"];

fn tmp() -> (tempfile::TempDir, impl Fn(&str) -> String) {
    let d = tempfile::tempdir().unwrap();
    let root = d.path().to_path_buf();
    (d, move |f: &str| root.join(f).to_str().unwrap().to_string())
}

/// `maria17`'s walk of every ray in a `--rays-out` file, one answer line each.
fn maria17_answers(rays: &str) -> String {
    let mut lines = rays.lines();
    let header: Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    let mesh = tetwalk::scenes::load(
        header["scene"].as_str().unwrap(),
        tetwalk::mesh::Faces::Required,
    )
    .unwrap();
    let walk = by_name("maria17").unwrap().walk(Model::Plain);
    let max = default_max_steps(&mesh);
    let mut out = String::new();
    for l in lines {
        let r: Value = serde_json::from_str(l).unwrap();
        let v3 =
            |k: &str| glam::Vec3::from(serde_json::from_value::<[f32; 3]>(r[k].clone()).unwrap());
        let ray = tetwalk::tet::Ray {
            org: v3("org"),
            dir: v3("dir"),
        };
        let w = walk(&mesh, &ray, r["start"].as_u64().unwrap() as u32, max);
        let mut a = serde_json::to_value(w.outcome).unwrap();
        a["view"] = r["view"].clone();
        a["pixel"] = r["pixel"].clone();
        a["steps"] = json!(w.steps);
        out += &format!("{a}\n");
    }
    out
}

#[test]
fn judge_counts_a_scenes_given_walks_as_count_counts_the_method() {
    let (_d, at) = tmp();
    let rays = at("rays.jsonl");
    let mut args = vec!["count", "--scene", "kuhn-far", "--rays-out", &rays];
    args.extend(VIEWS);
    let (code, _, err) = run_tetwalk(&args, b"");
    assert_eq!(code, 0, "{err}");
    let answers = at("answers.jsonl");
    std::fs::write(
        &answers,
        maria17_answers(&std::fs::read_to_string(&rays).unwrap()),
    )
    .unwrap();
    let (judged, counted) = (at("judged.json"), at("counted.json"));
    let (code, table, err) = run_tetwalk(
        &[
            "judge",
            &rays,
            &answers,
            "--name",
            "maria17-outside",
            "--json",
            &judged,
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(table.contains("maria17-outside"), "{table}");
    let mut args = vec![
        "count",
        "--scene",
        "kuhn-far",
        "--methods",
        "maria17",
        "--json",
        &counted,
    ];
    args.extend(VIEWS);
    let (code, _, err) = run_tetwalk(&args, b"");
    assert_eq!(code, 0, "{err}");
    let read =
        |p: &str| -> Value { serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap() };
    let (j, c) = (read(&judged), read(&counted));
    assert_eq!(j["rays"], c["rays"]);
    let (mine, theirs) = (&j["methods"][1], &c["methods"][1]);
    for k in [
        "wrong_total",
        "wrong",
        "wrong_face_adjacent",
        "wrong_face_elsewhere",
        "steps",
    ] {
        assert_eq!(mine[k], theirs[k], "{k}");
    }
    assert!(
        mine["wrong_total"].as_u64().unwrap() > 0,
        "maria17 goes wrong on the far Kuhn grid"
    );
}

#[test]
fn judge_refuses_missing_and_impossible_walks_naming_the_place() {
    let (_d, at) = tmp();
    let rays = at("rays.jsonl");
    let (code, _, err) = run_tetwalk(
        &[
            "count",
            "--scene",
            "kuhn",
            "--views",
            "1",
            "--size",
            "4x4",
            "--rays-out",
            &rays,
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let all = maria17_answers(&std::fs::read_to_string(&rays).unwrap());
    let answers = at("answers.jsonl");
    let first_view = all
        .lines()
        .next()
        .map(|l| serde_json::from_str::<Value>(l).unwrap()["view"].clone())
        .unwrap();
    // One ray left unanswered.
    std::fs::write(&answers, all.lines().skip(1).collect::<Vec<_>>().join("\n")).unwrap();
    let (code, _, err) = run_tetwalk(&["judge", &rays, &answers], b"");
    assert_eq!(code, 2);
    assert!(
        err.contains(&format!("no answer for view {first_view} pixel [0, 0]")),
        "{err}"
    );
    // A field no walk has, then a tetrahedron the scene does not have: each named at its line.
    let rest: Vec<&str> = all.lines().skip(1).collect();
    let mut first: Value = serde_json::from_str(all.lines().next().unwrap()).unwrap();
    for (field, value, why) in [
        ("colour", json!("red"), "unknown field `colour`"),
        (
            "tet",
            json!(4_000_000_000u32),
            "tet 4000000000 is not a tetrahedron of the scene",
        ),
    ] {
        first[field] = value;
        std::fs::write(&answers, format!("{first}\n{}", rest.join("\n"))).unwrap();
        let (code, _, err) = run_tetwalk(&["judge", &rays, &answers], b"");
        assert_eq!(code, 2);
        assert!(err.contains(&format!("answers.jsonl:1: {why}")), "{err}");
        first.as_object_mut().unwrap().remove("colour");
    }
}
