//! Replays every case the fuzzers found (corpora/found/<method>/*.json): each must still fail for the
//! method that failed, on the backend it failed on, with the same recorded answer — it documents that
//! method's weakness — and must pass for every other method that claims robustness unless that
//! failure is filed too; where there is a GPU adapter, the robust methods are replayed there too.
//! Every found file is also read by `tetwalk exit` as it is.

mod common;

use tetwalk::backend::Backend;
use tetwalk::cases::Subject;
use tetwalk::found::{Answer, Record, Replay, check, check_boxes, check_hits, replay};
use tetwalk::methods::Model;
use tetwalk::registry::{METHODS, OCTREE_METHODS, TRIANGLE_METHODS, octree_by_name};

fn findings() -> Vec<(String, Record)> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/found");
    let mut out = Vec::new();
    for dir in std::fs::read_dir(root).unwrap().flatten() {
        for file in std::fs::read_dir(dir.path()).unwrap().flatten() {
            let text = std::fs::read_to_string(file.path()).unwrap();
            let r = Record::parse(text.trim())
                .unwrap_or_else(|e| panic!("{}: {e}", file.path().display()));
            out.push((file.path().display().to_string(), r));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// What is wrong with a found case's replay, if anything: it must fail again with its recorded answer.
fn replay_problem(name: &str, r: &Record) -> Option<String> {
    let f = r.failure.as_ref()?;
    match replay(r).unwrap_or_else(|e| panic!("{name}: {e}")) {
        Replay::Holds => None,
        Replay::Skipped(why) => {
            eprintln!("SKIPPED {name}: recorded on {:?}: {why}", f.backend);
            None
        }
        Replay::Right => Some(format!("{name}: {} is now right here", f.method)),
        Replay::OtherAnswer(a) => Some(format!(
            "{name}: {} now answers {a:?}, not the recorded {:?}",
            f.method, f.answer
        )),
    }
}

#[test]
fn found_cases_fail_again_with_their_recorded_answer() {
    let found = findings();
    assert!(
        found.len() >= 50,
        "the corpus of found cases is kept, not lost ({})",
        found.len()
    );
    let problems: Vec<String> = found
        .iter()
        .filter_map(|(name, r)| replay_problem(name, r))
        .collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn changing_one_recorded_answer_fails_the_replay() {
    let found = findings();
    let shape = |s: &Subject| match s {
        Subject::Exit(_) => 0,
        Subject::Walk(_) => 1,
        Subject::Hit(_) => 2,
        Subject::Box(_) => 3,
    };
    for want in 0..4 {
        let (name, r) = found
            .iter()
            .find(|(_, r)| shape(&r.subject) == want)
            .expect("found cases of every shape");
        let mut changed = r.clone();
        let f = changed.failure.as_mut().unwrap();
        f.answer = match f.answer {
            Answer::Face(x) => Answer::Face(Some(x.map_or(0, |x| (x + 1) % 4))),
            Answer::Walk(o) => {
                let (kind, tet, x) = o.parts();
                Answer::Walk(tetwalk::walk::Outcome::from_parts(kind, tet + 1, x))
            }
            Answer::Hit(h) => Answer::Hit(match h {
                Some((i, t)) => Some((i ^ 1, t)),
                None => Some((0, 1.0)),
            }),
            Answer::Box(b) => Answer::Box(match b {
                Some((f, q)) => Some(((f + 1) % 6, q)),
                None => Some((0, [1, 1])),
            }),
        };
        // Through the file format, as a hand edit would be.
        let changed = Record::parse(&changed.to_json()).unwrap();
        assert!(
            replay_problem(name, &changed).is_some(),
            "{name}: a changed answer went unnoticed"
        );
        assert!(replay_problem(name, r).is_none());
    }
}

#[test]
fn robust_methods_are_right_on_every_found_case_unless_their_failure_is_filed() {
    let found = findings();
    let backends = [
        &Backend::Cpu {
            model: Model::Plain,
        },
        &Backend::Cpu {
            model: Model::Fused,
        },
    ];
    for (name, r) in &found {
        let failed = &r.failure.as_ref().unwrap().method;
        let filed = |m: &str| {
            found
                .iter()
                .any(|(_, g)| g.failure.as_ref().unwrap().method == m && g.key() == r.key())
        };
        if let Subject::Hit(h) = &r.subject {
            // The watertight claim: no leak on a closed mesh.
            for m in TRIANGLE_METHODS
                .iter()
                .filter(|m| m.claims_watertight && m.name != failed && !filed(m.name))
            {
                let now = check_hits(std::slice::from_ref(h), &[m], &backends, true).unwrap();
                assert_eq!(now, None, "{name}: {} must not leak here", m.name);
            }
            continue;
        }
        if let Subject::Box(c) = &r.subject {
            // No octree method's paper claims robustness; the exact reference must be right.
            let exact = octree_by_name("exact").unwrap();
            let now = check_boxes(std::slice::from_ref(c), &[exact], &backends).unwrap();
            assert_eq!(
                now, None,
                "{name}: the exact octree exit must be right here"
            );
            continue;
        }
        for m in METHODS
            .iter()
            .filter(|m| m.claims_robust && m.name != failed)
        {
            let filed = found
                .iter()
                .any(|(_, g)| g.failure.as_ref().unwrap().method == m.name && g.key() == r.key());
            if !filed {
                let now = check(&r.subject, &[m], &backends).unwrap();
                assert_eq!(now, None, "{name}: {} must be right here", m.name);
            }
        }
    }
}

#[test]
fn every_found_file_is_read_by_tetwalk_exit_hit_or_box_exit_as_it_is() {
    for (name, r) in findings() {
        let (command, methods) = match r.subject {
            Subject::Hit(_) => ("hit", TRIANGLE_METHODS.len()),
            Subject::Box(_) => ("box-exit", OCTREE_METHODS.len()),
            _ => ("exit", METHODS.len()),
        };
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_tetwalk"))
            .args([command, "--method", "all", &name])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(text.lines().count(), methods, "{name}: {text}");
        assert!(!text.contains("\"error\""), "{name}: {text}");
    }
}

#[test]
fn found_cases_replay_on_the_gpu() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    let found = findings();
    for (name, r) in &found {
        let failed = &r.failure.as_ref().unwrap().method;
        if let Subject::Hit(h) = &r.subject {
            for m in TRIANGLE_METHODS.iter().filter(|m| m.claims_watertight) {
                let now = check_hits(std::slice::from_ref(h), &[m], &[&gpu], true).unwrap();
                assert_eq!(now, None, "{name}: {} leaks on the GPU", m.name);
            }
            continue;
        }
        if let Subject::Box(_) = &r.subject {
            // The octree methods run on the CPU only so far.
            continue;
        }
        for m in METHODS
            .iter()
            .filter(|m| matches!(m.gpu, tetwalk::registry::Gpu::Wgsl(_)))
        {
            let now = check(&r.subject, &[m], &[&gpu]).unwrap();
            let filed = found
                .iter()
                .any(|(_, g)| g.failure.as_ref().unwrap().method == m.name && g.key() == r.key());
            if m.name == failed || filed {
                println!("{name}: {} on {}: {:?}", m.name, gpu.describe(), now);
            } else if m.claims_robust {
                assert_eq!(now, None, "{name}: {} on the GPU", m.name);
            }
        }
    }
}

/// A GPU fuzz check: a found case's neighbourhood (the case and its rays a few ulps away, 53 cases)
/// goes to the GPU in one batch; the failure found there records the adapter, reads back as written,
/// replays on this adapter with its recorded answer, and is skipped, with a notice naming both, on
/// another adapter.
#[test]
fn gpu_findings_record_their_adapter_and_replay_only_on_it() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    let maria17 = tetwalk::registry::by_name("maria17").unwrap();
    let exits: Vec<Record> = findings()
        .into_iter()
        .map(|(_, r)| r)
        .filter(|r| {
            matches!(r.subject, Subject::Exit(_)) && r.failure.as_ref().unwrap().method == "maria17"
        })
        .collect();
    assert!(!exits.is_empty());
    let mut found = 0;
    for r in &exits {
        let batch = tetwalk::found::neighbourhood(&r.subject);
        assert_eq!(batch[0], r.subject, "the case itself comes first");
        assert!(batch.len() > 40 && batch.len() <= 53, "{}", batch.len());
        let Some((i, f)) = tetwalk::found::check_batch(&batch, &[maria17], &[&gpu]).unwrap() else {
            continue;
        };
        found += 1;
        assert_eq!(f.adapter, gpu.adapter(), "a GPU finding names its adapter");
        let finding = Record {
            subject: batch[i],
            failure: Some(f.clone()),
        };
        let read = Record::parse(&finding.to_json()).unwrap();
        assert_eq!(read, finding, "the adapter is written and read back");
        assert_eq!(replay(&read).unwrap(), Replay::Holds);
        let mut elsewhere = read.clone();
        elsewhere.failure.as_mut().unwrap().adapter = Some("Some Other GPU (Vulkan)".into());
        match replay(&elsewhere).unwrap() {
            Replay::Skipped(why) => {
                assert!(
                    why.contains("Some Other GPU") && why.contains(&gpu.adapter().unwrap()),
                    "{why}"
                )
            }
            other => panic!("replayed on another adapter: {other:?}"),
        }
    }
    assert!(
        found > 0,
        "maria17's found cases fail on the GPU too (neighbourhoods included)"
    );
}

/// The README's register of claims ("What the papers claim and what we found"): its counterexample,
/// written out there exactly, is replayed here. One tetrahedron with a ray entering through face 1 and
/// leaving through face 3 only (no tie): both readings of seed 000 §3.4 answer face 2, seed 003's scaled
/// basis answers face 0 where the unscaled one is right, and `certified` is right.
#[test]
fn the_claims_register_counterexample_replays() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpora/found/maria17/exit_face-wrong_face-50e741ec2f3d.json"
    ))
    .unwrap();
    let r = Record::parse(text.trim()).unwrap();
    let Subject::Exit(case) = r.subject else {
        panic!("an exit case")
    };
    let written = r#"{"tet":[[6.5,-5.583333,1.0],[15.5,15.0,15.5],[-5.5,-16.0,-16.0],[-16.0,-16.0,-16.0]],"org":[-64.0,-64.0,-64.0],"dir":[70.5,58.416668,65.0],"entry":1}"#;
    assert_eq!(
        Subject::parse(written).unwrap(),
        r.subject,
        "the README writes it out exactly"
    );
    let c = tetwalk::cases::classify(&case).unwrap();
    assert_eq!(c.exit.to_vec(), vec![3]);
    assert_eq!(c.entry.to_vec(), vec![1]);
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    for (name, answer) in [
        ("maria17", 2),
        ("maria17-translated", 2),
        ("aman20", 3),
        ("aman20-scaled", 0),
        ("certified", 3),
    ] {
        let m = tetwalk::registry::by_name(name).unwrap();
        assert_eq!(cpu.exit_face(m, &case).unwrap(), Some(answer), "{name}");
    }
}

/// `check_batch` names the failing case by its index in the batch it was given, also where cases of
/// another kind sit in between (they are left out, not counted).
#[test]
fn a_batch_failure_names_its_own_case() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpora/found/maria17/exit_face-wrong_face-50e741ec2f3d.json"
    ))
    .unwrap();
    let wrong = Record::parse(text.trim()).unwrap().subject;
    let right = Subject::parse(
        r#"{"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[0.2,0.2,-1],"dir":[0.01,0.02,1]}"#,
    )
    .unwrap();
    let walk = Subject::parse(
        r#"{"mesh":"kuhn","size":3,"offset":0,"org":[1.5,1.25,1.125],"dir":[1,0.5,0.25]}"#,
    )
    .unwrap();
    let maria17 = tetwalk::registry::by_name("maria17").unwrap();
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    assert_eq!(check(&right, &[maria17], &[&cpu]).unwrap(), None);
    let (i, f) = tetwalk::found::check_batch(&[right, walk, wrong], &[maria17], &[&cpu])
        .unwrap()
        .expect("maria17 fails on the third case");
    assert_eq!(i, 2);
    assert_eq!(f.method, "maria17");
}
