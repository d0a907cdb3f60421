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
    .unwrap()
    .mesh;
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

/// Cases with a known exact answer: a tetrahedron whose line leaves through face 0, a triangle hit at
/// `t = 1`, and a closed mesh (an octahedron) hit first on triangle 0 at `t = 5/2`.
fn known_cases() -> String {
    let tet = json!({"tet": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "org": [0.1,0.1,0.1], "dir": [1,1,1], "entry": null});
    let tri = json!({"tri": [[-1,-1,1],[1,-1,1],[0,1,1]], "org": [0,0,0], "dir": [0,0,1]});
    let s = 2;
    let v = [
        [s, 0, 0],
        [-s, 0, 0],
        [0, s, 0],
        [0, -s, 0],
        [0, 0, s],
        [0, 0, -s],
    ];
    // Outward octahedron faces, +z first: the ray from below along +z leaves the inside through it.
    let f = |a: usize, b: usize, c: usize| json!([v[a], v[b], v[c]]);
    let tris = json!([
        f(0, 2, 4),
        f(2, 1, 4),
        f(1, 3, 4),
        f(3, 0, 4),
        f(2, 0, 5),
        f(1, 2, 5),
        f(3, 1, 5),
        f(0, 3, 5)
    ]);
    let closed = json!({"tris": tris, "org": [0.25, 0.25, -1], "dir": [0, 0, 1]});
    format!("{tet}\n{tri}\n{closed}\n")
}

/// The exact answers to [`known_cases`].
const RIGHT: &str = "{\"line\":1,\"face\":0}\n{\"line\":2,\"hit\":true,\"t\":1}\n{\"line\":3,\"tri\":0,\"t\":2.5}\n";

/// Judge `answers` against [`known_cases`]: status, verdict lines, standard error.
fn judge(answers: &str, extra: &[&str]) -> (i32, Vec<Value>, String) {
    let (_d, at) = tmp();
    let (cases, given) = (at("cases.jsonl"), at("answers.jsonl"));
    std::fs::write(&cases, known_cases()).unwrap();
    std::fs::write(&given, answers).unwrap();
    let mut args = vec!["judge", cases.as_str(), given.as_str()];
    args.extend_from_slice(extra);
    let (code, out, err) = run_tetwalk(&args, b"");
    let lines = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    (code, lines, err)
}

#[test]
fn judge_reads_answers_as_strictly_as_cases_and_names_the_line() {
    // Right answers first: the exact ones.
    let (code, v, err) = judge(RIGHT, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(v.iter().all(|l| l["correct"] == true), "{v:?}");
    // Missing, misspelled and other families' keys: an error for that line, the field named.
    let bad = [
        (
            "{\"line\":1,\"hit\":true,\"t\":1.0}",
            "unknown field \"hit\"",
        ),
        ("{\"line\":1,\"fcae\":1}", "unknown field \"fcae\""),
        ("{\"line\":1}", "missing field \"face\""),
        ("{\"line\":2,\"face\":2}", "unknown field \"face\""),
        ("{\"line\":2,\"hit\":true}", "needs its \"t\""),
        ("{\"line\":2,\"hit\":false,\"t\":1}", "given for a miss"),
        ("{\"line\":3,\"face\":2}", "unknown field \"face\""),
        ("{\"line\":3,\"hit\":true,\"t\":1}", "unknown field \"hit\""),
        (
            "{\"line\":3,\"tri\":9,\"t\":1}",
            "not a triangle of the case",
        ),
    ];
    for (answer, says) in bad {
        let n: usize = answer[8..9].parse().unwrap();
        let others: String = (1..=3)
            .filter(|&k| k != n)
            .map(|k| match k {
                1 => "{\"line\":1,\"face\":0}\n",
                2 => "{\"line\":2,\"hit\":true,\"t\":1}\n",
                _ => "{\"line\":3,\"tri\":0,\"t\":2.5}\n",
            })
            .collect();
        let (code, v, err) = judge(&format!("{others}{answer}\n"), &[]);
        assert_eq!(code, 1, "{answer}: {err}");
        let line = v.iter().find(|l| l["line"] == n).unwrap();
        let e = line["error"]
            .as_str()
            .unwrap_or_else(|| panic!("{answer}: {line}"));
        assert!(e.contains(says), "{answer}: {e}");
    }
}

#[test]
fn a_null_answer_is_judged_wrong_where_the_exact_answer_is_a_hit() {
    let (code, v, err) = judge(
        "{\"line\":1,\"face\":null}\n{\"line\":2,\"hit\":false}\n{\"line\":3,\"tri\":null}\n",
        &[],
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(v.len(), 3);
    for l in &v {
        assert_eq!(l["correct"], false, "{l}");
    }
}

#[test]
fn a_hit_needs_a_positive_t_near_the_exact_one() {
    let answers = |t: &str| {
        let t3: f64 = t.parse::<f64>().unwrap() * 2.5;
        format!(
            "{{\"line\":1,\"face\":0}}\n{{\"line\":2,\"hit\":true,\"t\":{t}}}\n{{\"line\":3,\"tri\":0,\"t\":{t3}}}\n"
        )
    };
    for t in ["-1", "0", "1000", "1.01"] {
        let (code, v, err) = judge(&answers(t), &[]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(v[1]["correct"], false, "t = {t}: {}", v[1]);
        assert_eq!(v[2]["correct"], false, "t = {t}: {}", v[2]);
    }
    // One ulp of 1 above the exact t: right under the default bound, wrong under --t-ulps 0.
    let up = f32::from_bits(1f32.to_bits() + 1);
    let (_, v, _) = judge(&answers(&up.to_string()), &[]);
    assert_eq!(v[1]["correct"], true, "{}", v[1]);
    assert_eq!(v[1]["t_ulps"], 1.0, "{}", v[1]);
    let (_, v, err) = judge(&answers(&up.to_string()), &["--t-ulps", "0"]);
    assert_eq!(v[1]["correct"], false, "{}", v[1]);
    // The summary counts it apart: its triangle is right.
    assert!(
        err.contains("2 wrong (of them 2 wrong for t alone: the triangle right"),
        "{err}"
    );
    assert!(!err.contains("back face"), "{err}");
    let (code, _, err) = judge(&answers("1"), &["--t-ulps", "-3"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--t-ulps -3"), "{err}");
}

#[test]
fn a_failed_judge_writes_no_report_and_fail_on_wrong_gates() {
    let (_d, at) = tmp();
    let json = at("summary.json");
    // An answer for a line without a case: status 2, and no summary.
    let (code, _, err) = judge(
        &format!("{RIGHT}{{\"line\":9,\"face\":1}}\n"),
        &["--json", &json],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("answers for line 9, with no case"), "{err}");
    assert!(
        !std::path::Path::new(&json).exists(),
        "a failed run writes no report"
    );
    // Wrong answers: status 0 without --fail-on, 1 with it, with the method's summary line.
    let wrong = "{\"line\":1,\"face\":1}\n{\"line\":2,\"hit\":false}\n{\"line\":3,\"tri\":null}\n";
    let (code, _, err) = judge(wrong, &[]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = judge(wrong, &["--fail-on", "wrong", "--name", "kernel"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("kernel: 3 wrong of 3 judged"), "{err}");
    let (code, _, err) = judge(RIGHT, &["--fail-on", "wrong"]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = judge(RIGHT, &["--fail-on", "claims"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--fail-on wrong"), "{err}");
}

#[test]
fn judge_refuses_a_rays_file_whose_body_is_not_its_headers() {
    let (_d, at) = tmp();
    let rays = at("rays.jsonl");
    let (code, _, err) = run_tetwalk(
        &[
            "count",
            "--scene",
            "kuhn",
            "--views",
            "2",
            "--size",
            "8x8",
            "--rays-out",
            &rays,
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&rays).unwrap();
    let answers = at("answers.jsonl");
    std::fs::write(&answers, maria17_answers(&text)).unwrap();
    let (code, _, err) = run_tetwalk(&["judge", &rays, &answers], b"");
    assert_eq!(code, 0, "the whole file is judged: {err}");
    let lines: Vec<&str> = text.lines().collect();
    // Cut in half mid-line, a ray changed, a line added: refused, the place named.
    let cut = &text[..text.len() / 2];
    let mut edited = lines.clone();
    let changed = lines[5].replace("\"view\":0", "\"view\":1");
    edited[5] = &changed;
    let extra = format!("{text}{}\n", lines[1]);
    for (name, body, says) in [
        ("cut", cut.to_string(), "cut short"),
        ("edited", edited.join("\n") + "\n", ":6: not the ray"),
        ("extra", extra, "after the 128 rays"),
    ] {
        let p = at(&format!("{name}.jsonl"));
        std::fs::write(&p, body).unwrap();
        let (code, _, err) = run_tetwalk(&["judge", &p, &answers], b"");
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
    }
}

/// Cases from a pipe (`judge /dev/stdin ANSWERS`) are judged as from a file, a scene's rays too; an
/// answer in a common wrong spelling (`"tri": -1`, Python's `Infinity`) gets an error for its own
/// line that names the expected form, and the other lines are judged.
#[test]
fn judge_reads_cases_from_a_pipe_and_names_the_miss_spelling() {
    let (_d, at) = tmp();
    let (_, cases, _) = run_tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "4"], b"");
    let answers = at("answers.jsonl");
    std::fs::write(
        &answers,
        "{\"line\":1,\"tri\":0,\"t\":1}\n{\"line\":2,\"tri\":-1}\n{\"line\":3,\"tri\":null,\"t\":Infinity}\n{\"line\":4,\"tri\":null}\n",
    )
    .unwrap();
    let (code, piped, err) = run_tetwalk(&["judge", "/dev/stdin", &answers], cases.as_bytes());
    assert_eq!(code, 1, "{err}");
    let file = at("cases.jsonl");
    std::fs::write(&file, &cases).unwrap();
    let (_, from_file, _) = run_tetwalk(&["judge", &file, &answers], b"");
    assert_eq!(piped, from_file);
    let v: Vec<serde_json::Value> = piped
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(v.len(), 4, "{piped}");
    assert_eq!(v[0]["correct"], true, "{}", v[0]);
    let e = |i: usize| v[i]["error"].as_str().unwrap_or_default().to_string();
    assert!(e(1).contains("a miss is written \"tri\": null"), "{}", e(1));
    assert!(e(2).contains("Infinity are not JSON numbers"), "{}", e(2));
    assert!(v[3].get("correct").is_some(), "{}", v[3]);

    let rays = at("rays.jsonl");
    let mut args = vec!["count", "--scene", "kuhn", "--rays-out", &rays];
    args.extend(VIEWS);
    run_tetwalk(&args, b"");
    let text = std::fs::read_to_string(&rays).unwrap();
    let walks = at("walks.jsonl");
    std::fs::write(&walks, maria17_answers(&text)).unwrap();
    let (code, piped, err) = run_tetwalk(&["judge", "/dev/stdin", &walks], text.as_bytes());
    assert_eq!(code, 0, "{err}");
    let (_, from_file, _) = run_tetwalk(&["judge", &rays, &walks], b"");
    // The given walks' row and the totals (the reference's speed column aside).
    let table = |t: &str| {
        t.lines()
            .filter(|l| l.starts_with("| yours") || l.starts_with("totals"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(table(&piped).len(), 2, "{piped}");
    assert_eq!(table(&piped), table(&from_file));
}
