//! Replays every case the fuzzers found (corpora/found/<method>/*.json), whatever its family: each
//! must still fail for the method that failed, on the backend it failed on, with the same recorded
//! answer — it documents that method's weakness — and must hold for every other method that makes a
//! claim unless that failure is filed too; where there is a GPU adapter, the claims are held there
//! too. Every found file is also read by `tetwalk exit`, `hit` or `box-exit` as it is.

mod common;

use tetwalk::backend::Backend;
use tetwalk::cases::object;
use tetwalk::choice::Choice;
use tetwalk::engine::found::{Found, Hold, Replay, check, replay};
use tetwalk::family::{ExitFace, Family, Kind, owner};
use tetwalk::methods::Model;
use tetwalk::registry::{GpuVersion, METHODS, Named, OCTREE_METHODS, TRIANGLE_METHODS};

/// Every found file, with its text, sorted by path.
fn files() -> Vec<(String, String)> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/found");
    let mut out = Vec::new();
    for dir in std::fs::read_dir(root).unwrap().flatten() {
        for file in std::fs::read_dir(dir.path()).unwrap().flatten() {
            let text = std::fs::read_to_string(file.path()).unwrap();
            out.push((file.path().display().to_string(), text.trim().to_string()));
        }
    }
    out.sort();
    out
}

/// The family a found file's case belongs to.
fn kind(text: &str) -> Kind {
    owner(&object(text).unwrap())
}

/// Every found case of family `F`, with its file.
fn findings<F: Family>() -> Vec<(String, Found<F>)> {
    files()
        .into_iter()
        .filter(|(_, t)| kind(t).name() == F::NAME)
        .map(|(name, t)| {
            let r = Found::<F>::parse(&t).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, r)
        })
        .collect()
}

/// What is wrong with a found case's replay, if anything: it must fail again with its recorded answer.
fn replay_problem<F: Family>(name: &str, r: &Found<F>) -> Option<String> {
    let f = r.failure.as_ref()?;
    match replay(r).unwrap_or_else(|e| panic!("{name}: {e}")) {
        Replay::Holds => None,
        Replay::Skipped(why) => {
            eprintln!("SKIPPED {name}: recorded on {:?}: {why}", f.backend);
            None
        }
        Replay::Right => Some(format!("{name}: {} is now right here", f.method)),
        Replay::OtherAnswer(a) => Some(format!(
            "{name}: {} now answers {a}, not the recorded {:?}",
            f.method, f.answer
        )),
    }
}

/// Every found case of family `F` that does not fail again with its recorded answer.
fn problems<F: Family>() -> Vec<String> {
    findings::<F>()
        .iter()
        .filter_map(|(name, r)| replay_problem(name, r))
        .collect()
}

#[test]
fn found_cases_fail_again_with_their_recorded_answer() {
    assert!(
        files().len() >= 50,
        "the corpus of found cases is kept, not lost ({})",
        files().len()
    );
    let mut all = Vec::new();
    for &k in Kind::ALL {
        assert!(
            tetwalk::with_family!(k, F => !findings::<F>().is_empty()),
            "found cases of every family ({})",
            k.name()
        );
        all.extend(tetwalk::with_family!(k, F => problems::<F>()));
    }
    assert!(all.is_empty(), "{}", all.join("\n"));
}

/// A found case's recorded answer changed as a hand edit of its file would: another face, tetrahedron,
/// triangle or cell face.
fn changed_answer(k: Kind, answer: &serde_json::Value) -> serde_json::Value {
    use serde_json::json;
    match k {
        Kind::ExitFace => json!(answer.as_u64().map_or(0, |f| (f + 1) % 4)),
        Kind::Walk => {
            let mut a = answer.clone();
            a["tet"] = json!(a["tet"].as_u64().unwrap() + 1);
            a
        }
        Kind::Triangle => match answer["tri"].as_u64() {
            Some(i) => json!({"tri": i ^ 1, "t": answer["t"]}),
            None => json!({"tri": 0, "t": 1.0}),
        },
        Kind::Octree => match answer["face"].as_str() {
            Some(f) => {
                json!({"face": if f == "-x" { "+x" } else { "-x" }, "quarter": answer["quarter"]})
            }
            None => json!({"face": "-x", "quarter": [1, 1]}),
        },
    }
}

#[test]
fn changing_one_recorded_answer_fails_the_replay() {
    for &k in Kind::ALL {
        let (name, text) = files()
            .into_iter()
            .find(|(_, t)| kind(t) == k && !t.contains("\"answer\":null"))
            .expect("found cases of every family with an answer");
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["answer"] = changed_answer(k, &v["answer"]);
        // Through the file format, as a hand edit would be.
        let (before, after) = tetwalk::with_family!(k, F => {
            let r = Found::<F>::parse(&text).unwrap();
            let changed = Found::<F>::parse(&v.to_string()).unwrap();
            (replay_problem(&name, &r), replay_problem(&name, &changed))
        });
        assert!(after.is_some(), "{name}: a changed answer went unnoticed");
        assert!(before.is_none());
    }
}

/// Whether method `m`'s failure on the case of `r` is filed too: a found case of `m` on the same case
/// as found (each is kept shrunk for its own method, the case as found beside it).
fn filed<F: Family>(found: &[(String, Found<F>)], m: &str, r: &Found<F>) -> bool {
    let as_found = |g: &Found<F>| g.original.unwrap_or(g.case);
    found
        .iter()
        .any(|(_, g)| g.failure.as_ref().unwrap().method == m && as_found(g) == as_found(r))
}

/// Each method of family `F` that makes a claim holds it on every found case (on the CPU, plain and
/// fused) unless that failure is filed too.
fn claims_hold_unless_filed<F: Family>(backends: &[&Backend]) {
    let found = findings::<F>();
    for (name, r) in &found {
        let failed = &r.failure.as_ref().unwrap().method;
        let filed = |m: &str| filed(&found, m, r);
        for m in F::methods()
            .iter()
            .filter(|m| m.info().claim.is_some() && m.name() != failed && !filed(m.name()))
        {
            let now = check::<F>(std::slice::from_ref(&r.case), &[(m, Hold::Claim)], backends);
            assert_eq!(
                now.unwrap(),
                None,
                "{name}: {}'s claim must hold here",
                m.name()
            );
        }
    }
}

#[test]
fn claims_hold_on_every_found_case_unless_their_failure_is_filed() {
    let backends = [
        &Backend::Cpu {
            model: Model::Plain,
        },
        &Backend::Cpu {
            model: Model::Fused,
        },
    ];
    for &k in Kind::ALL {
        tetwalk::with_family!(k, F => claims_hold_unless_filed::<F>(&backends));
    }
}

#[test]
fn every_found_file_is_read_by_tetwalk_exit_hit_or_box_exit_as_it_is() {
    for (name, text) in files() {
        let (command, methods) = match kind(&text) {
            Kind::Triangle => ("hit", TRIANGLE_METHODS.len()),
            Kind::Octree => ("box-exit", OCTREE_METHODS.len()),
            Kind::ExitFace | Kind::Walk => ("exit", METHODS.len()),
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

/// Each method of family `F` with a GPU version on every found case, on the GPU: a method that makes
/// a claim holds it there unless the case is its own finding.
fn claims_hold_on_the_gpu<F: Family>(gpu: &Backend) {
    let found = findings::<F>();
    for (name, r) in &found {
        let failed = &r.failure.as_ref().unwrap().method;
        for m in F::methods()
            .iter()
            .filter(|m| matches!(m.info().gpu, GpuVersion::Wgsl(_)))
        {
            let hold = if m.info().claim.is_some() {
                Hold::Claim
            } else {
                Hold::Every
            };
            let now = check::<F>(std::slice::from_ref(&r.case), &[(m, hold)], &[gpu]).unwrap();
            let filed = filed(&found, m.name(), r);
            if m.name() == failed || filed {
                println!("{name}: {} on {}: {:?}", m.name(), gpu.describe(), now);
            } else if hold == Hold::Claim {
                assert_eq!(now, None, "{name}: {}'s claim on the GPU", m.name());
            }
        }
    }
}

#[test]
fn found_cases_replay_on_the_gpu() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    for &k in Kind::ALL {
        tetwalk::with_family!(k, F => claims_hold_on_the_gpu::<F>(&gpu));
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
    let exits: Vec<Found<ExitFace>> = findings::<ExitFace>()
        .into_iter()
        .map(|(_, r)| r)
        .filter(|r| r.failure.as_ref().unwrap().method == "maria17")
        .collect();
    assert!(!exits.is_empty());
    let mut found = 0;
    for r in &exits {
        let batch = tetwalk::engine::fuzz::neighbourhood::<ExitFace>(&r.case);
        assert_eq!(batch[0], r.case, "the case itself comes first");
        assert!(batch.len() > 40 && batch.len() <= 53, "{}", batch.len());
        let Some((i, f)) = check::<ExitFace>(&batch, &[(maria17, Hold::Every)], &[&gpu]).unwrap()
        else {
            continue;
        };
        found += 1;
        assert_eq!(
            f.adapter,
            gpu.ran().adapter,
            "a GPU finding names its adapter"
        );
        let finding = Found::of(batch[i], f.clone());
        let read = Found::<ExitFace>::parse(&finding.to_json()).unwrap();
        assert_eq!(read, finding, "the adapter is written and read back");
        assert_eq!(replay(&read).unwrap(), Replay::Holds);
        let mut elsewhere = read.clone();
        elsewhere.failure.as_mut().unwrap().adapter = Some("Some Other GPU (Vulkan)".into());
        match replay(&elsewhere).unwrap() {
            Replay::Skipped(why) => {
                assert!(
                    why.contains("Some Other GPU") && why.contains(&gpu.ran().adapter.unwrap()),
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
/// written out there exactly as it was found (the found case's `original`; the file holds it shrunk),
/// is replayed here. One tetrahedron with a ray entering through face 1 and leaving through face 3 only
/// (no tie): both readings of seed 000 §3.4 answer face 2, seed 003's scaled basis answers face 0
/// where the unscaled one is right, and `certified` is right.
#[test]
fn the_claims_register_counterexample_replays() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpora/found/maria17/exit_face-wrong_face-50e741ec2f3d.json"
    ))
    .unwrap();
    let found = Found::<ExitFace>::parse(text.trim()).unwrap();
    let case = found.original.unwrap_or(found.case);
    let written = r#"{"tet":[[6.5,-5.583333,1.0],[15.5,15.0,15.5],[-5.5,-16.0,-16.0],[-16.0,-16.0,-16.0]],"org":[-64.0,-64.0,-64.0],"dir":[70.5,58.416668,65.0],"entry":1}"#;
    assert_eq!(
        Found::<ExitFace>::parse(written).unwrap().case,
        case,
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

/// `check` names the failing case by its index in the batch it was given, also where cases the oracle
/// does not judge (a line that misses the tetrahedron) sit in between.
#[test]
fn a_batch_failure_names_its_own_case() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpora/found/maria17/exit_face-wrong_face-50e741ec2f3d.json"
    ))
    .unwrap();
    let parse = |line: &str| Found::<ExitFace>::parse(line).unwrap().case;
    let wrong = parse(text.trim());
    let right = parse(
        r#"{"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[0.2,0.2,-1],"dir":[0.01,0.02,1]}"#,
    );
    let missing =
        parse(r#"{"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[5,5,-1],"dir":[0,0,1]}"#);
    let maria17 = tetwalk::registry::by_name("maria17").unwrap();
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let held = [(maria17, Hold::Every)];
    assert_eq!(check::<ExitFace>(&[right], &held, &[&cpu]).unwrap(), None);
    let (i, f) = check::<ExitFace>(&[right, missing, wrong], &held, &[&cpu])
        .unwrap()
        .expect("maria17 fails on the third case");
    assert_eq!(i, 2);
    assert_eq!(f.method, "maria17");
}

/// A closed mesh's false miss that lets the ray through its surface (at an edge) says so: its found
/// line carries `"leak": true` beside its kind and reads back; a false miss beside an edge (inside a
/// triangle) carries none, and a line claiming a leak there is refused naming the field.
#[test]
fn a_leak_is_filed_as_one() {
    use tetwalk::family::Triangle;
    let read = |path: &str| {
        let line = std::fs::read_to_string(format!("corpora/found/{path}")).unwrap();
        Found::<Triangle>::parse(line.lines().next().unwrap()).unwrap()
    };
    let leak = read("mt/stress-sliver-edge-origin-false_miss-0200f303db781c7d.json");
    let written = leak.to_json();
    assert!(
        written.contains(r#""kind":"false_miss""#) && written.contains(r#""leak":true"#),
        "{written}"
    );
    assert_eq!(Found::<Triangle>::parse(&written).unwrap(), leak);
    let beside =
        read("komatsu-packet/stress-sliver-near-edge-origin-false_miss-8ea14a8f98356819.json");
    let written = beside.to_json();
    assert!(
        written.contains(r#""kind":"false_miss""#) && !written.contains("leak"),
        "{written}"
    );
    let claimed = written.replacen(r#""kind":"#, r#""leak":true,"kind":"#, 1);
    let err = Found::<Triangle>::parse(&claimed).unwrap_err().to_string();
    assert!(
        err.contains("leak") && err.contains("lets no ray through"),
        "{err}"
    );
}
