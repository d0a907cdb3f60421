//! Case generators shared by the integration tests, as proptest strategies over the crate's seeded
//! generators (so a failing case is reproduced from its seed and persisted under corpora/proptest/).
#![allow(dead_code)]

use glam::Vec3;
use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence};
use tetwalk::backend::{Backend, BackendKind};
use tetwalk::exact::Classification;
use tetwalk::family::{ExitFace, Family, Verdict};
use tetwalk::methods::Model;
use tetwalk::registry::Method;
use tetwalk::scenes::rng;
use tetwalk::scenes::tets::{self, Target, TetShape};
use tetwalk::tet::{Case, Ray, Tet};

/// Proptest configuration persisting failures under `corpora/proptest/<name>.txt`: `cases` cases, or
/// as many as `PROPTEST_CASES` asks. Cases a test rejects (`prop_assume!`, filters) may be up to
/// [`REJECTS_PER_CASE`] per case asked, so that a run of any size ends on its cases, not on rejects
/// (`PROPTEST_MAX_GLOBAL_REJECTS` raises it further).
pub fn config(name: &'static str, cases: u32) -> Config {
    let path: &'static str = Box::leak(
        format!("{}/corpora/proptest/{name}.txt", env!("CARGO_MANIFEST_DIR")).into_boxed_str(),
    );
    let from_env = Config::default();
    let cases = match std::env::var("PROPTEST_CASES") {
        Ok(_) => from_env.cases,
        Err(_) => cases,
    };
    Config {
        cases,
        max_global_rejects: from_env
            .max_global_rejects
            .max(cases.saturating_mul(REJECTS_PER_CASE)),
        max_local_rejects: from_env
            .max_local_rejects
            .max(cases.saturating_mul(REJECTS_PER_CASE)),
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(path))),
        ..from_env
    }
}

/// Rejected inputs allowed per case asked (the tests' filters reject fewer than one in two).
pub const REJECTS_PER_CASE: u32 = 4;

/// How a generated case's ray meets its tetrahedron.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    Stab,
    Through(Target),
    Near(Target, i32),
}

pub fn family() -> impl Strategy<Value = TetShape> {
    prop_oneof![
        Just(TetShape::Well),
        Just(TetShape::Sliver),
        Just(TetShape::Cap),
        Just(TetShape::Needle),
        Just(TetShape::Wedge),
    ]
}

pub fn kind() -> impl Strategy<Value = Kind> {
    prop_oneof![
        3 => Just(Kind::Stab),
        1 => Just(Kind::Through(Target::Edge)),
        1 => Just(Kind::Through(Target::Vertex)),
        1 => (1..8i32).prop_map(|k| Kind::Near(Target::Edge, k)),
        1 => (1..8i32).prop_map(|k| Kind::Near(Target::Vertex, k)),
    ]
}

/// A generated case.
pub fn make(
    family: TetShape,
    flatness: f32,
    kind: Kind,
    offset: f32,
    seed: u64,
) -> Option<(Tet, Ray)> {
    let mut r = rng(seed);
    let (t, ray) = match kind {
        Kind::Stab => {
            let t = tets::tet(family, flatness, &mut r);
            (t, tets::stabbing_ray(&t, &mut r))
        }
        Kind::Through(target) => tets::through(family, flatness, target, &mut r)?,
        Kind::Near(target, k) => tets::near(family, flatness, target, k, &mut r)?,
    };
    tets::translated(&t, &ray, Vec3::splat(offset))
}

/// Any case: every family and flatness down to 1e-4, every ray kind, near the origin or far from it.
pub fn any_case() -> impl Strategy<Value = (Tet, Ray)> {
    (
        family(),
        prop_oneof![Just(1.0f32), Just(0.1), Just(1e-2), Just(1e-3), Just(1e-4)],
        kind(),
        prop_oneof![3 => Just(0.0f32), 1 => Just(1.0e4), 1 => Just(1.0e5), 1 => Just(-1.0e6)],
        any::<u64>(),
    )
        .prop_filter_map("rounding flattened it", |(f, fl, k, off, seed)| {
            make(f, fl, k, off, seed)
        })
}

/// Cases on small-integer geometry: every coordinate in -4..=4, so ties are everywhere.
pub fn lattice_case() -> impl Strategy<Value = (Tet, Ray)> {
    let p = || {
        (-4i32..=4, -4i32..=4, -4i32..=4)
            .prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32))
    };
    ([p(), p(), p(), p()], p(), p())
        .prop_filter("flat tetrahedron or zero direction", |(t, _, d)| {
            tetwalk::tet::orientation(t) != 0 && *d != Vec3::ZERO
        })
        .prop_map(|(t, o, d)| (t, Ray { org: o, dir: d }))
}

/// The GPU backend, or `None` with a printed notice; a failure instead when TETWALK_REQUIRE_GPU=1 (as
/// in CI).
pub fn gpu_or_skip() -> Option<Backend> {
    match Backend::open(BackendKind::Gpu) {
        Ok(g) => {
            println!("GPU: {}", g.describe());
            Some(g)
        }
        Err(e) if tetwalk::gpu::required() => panic!("TETWALK_REQUIRE_GPU=1 but: {e}"),
        Err(e) => {
            eprintln!("SKIPPED: no GPU ({e}); set TETWALK_REQUIRE_GPU=1 to make this a failure");
            None
        }
    }
}

/// A method's exit face beside the exact ones, and whether it is right (`None`: the line misses the
/// tetrahedron).
#[derive(Debug)]
pub struct Judged {
    pub face: Option<u8>,
    pub exact_exit: Vec<usize>,
    pub correct: Option<bool>,
}

/// `m`'s answer on a case on the CPU in an arithmetic model, judged against its classification.
pub fn judge(case: &Case, c: &Classification, m: &Method, model: Model) -> Judged {
    let face = Backend::Cpu { model }
        .exit_face(m, case)
        .unwrap()
        .map(|f| f as u8);
    Judged {
        face,
        exact_exit: c.exit.to_vec(),
        correct: match ExitFace::verdict(case, c, &face) {
            Verdict::Right => Some(true),
            Verdict::Wrong(_) => Some(false),
            Verdict::NotJudged => None,
        },
    }
}

/// Every CPU arithmetic model (`Model::ALL`).
pub fn model() -> impl Strategy<Value = Model> {
    proptest::sample::select(Model::ALL.to_vec())
}

/// How long a command may run before the tests call it hung (far beyond any loaded run).
const HANG: std::time::Duration = std::time::Duration::from_secs(900);

/// insta settings storing snapshots in `golden/`.
pub fn settings() -> insta::Settings {
    let mut s = insta::Settings::clone_current();
    s.set_snapshot_path(concat!(env!("CARGO_MANIFEST_DIR"), "/golden"));
    s.set_prepend_module_to_snapshot(false);
    s
}

/// Run the tetwalk binary with `stdin`: status, standard output and error. A run still going after
/// [`HANG`] is killed and fails the test as a hang.
pub fn run_tetwalk(args: &[&str], stdin: &[u8]) -> (i32, String, String) {
    run_tetwalk_env(args, stdin, &[])
}

/// [`run_tetwalk`] with these environment variables set.
pub fn run_tetwalk_env(args: &[&str], stdin: &[u8], env: &[(&str, &str)]) -> (i32, String, String) {
    use std::io::Write;
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let mut child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(args)
        .envs(env.iter().copied())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = child.stdin.take().unwrap();
    let stdin = stdin.to_vec();
    // Fed and read on threads, so that large input or output cannot block against a full pipe.
    let feeder = std::thread::spawn(move || {
        let _ = input.write_all(&stdin);
    });
    let drain = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut b = Vec::new();
            let _ = r.read_to_end(&mut b);
            b
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        // A hang guard, not a timing test: the slowest command here takes well under a minute on two
        // cores (the paper run, 8 views of 64², about 4 s), so only a run that never ends reaches it.
        if start.elapsed() > HANG {
            child.kill().unwrap();
            panic!("tetwalk {args:?} hung");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    feeder.join().unwrap();
    let text = |b: Vec<u8>| String::from_utf8_lossy(&b).to_string();
    (
        status.code().unwrap_or(-1),
        text(stdout.join().unwrap()),
        text(stderr.join().unwrap()),
    )
}
