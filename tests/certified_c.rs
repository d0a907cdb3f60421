//! `kernels/c/certified.h`, the fix where kernels live, judged as any kernel is: built by the C
//! compiler at -O0 and -O3, with contraction off and fused (`-mfma -ffp-contract=fast`, where the
//! processor has FMA), asked through the answerer protocol (`kernels/c/answerer.c`). On every
//! exit-face row at scales across f32's range (the direction at its own scale too) it is never wrong
//! and answers as tetwalk's `certified` does, case for case, also with subnormals flushed and read
//! as zero (x86's FTZ and DAZ); walks through the built-in scenes step by step are never wrong
//! either.

mod common;

use common::run_tetwalk as tetwalk;
use serde_json::Value;

/// The answerer built with `flags` in `dir`.
fn built(dir: &std::path::Path, name: &str, flags: &[&str]) -> String {
    let exe = dir.join(name);
    let root = env!("CARGO_MANIFEST_DIR");
    let status = std::process::Command::new("cc")
        .args(flags)
        .args(["-std=c99", "-Wall", "-Werror", "-I"])
        .arg(format!("{root}/kernels/c"))
        .arg("-o")
        .arg(&exe)
        .arg(format!("{root}/kernels/c/answerer.c"))
        .status()
        .expect("a C compiler, cc (.ci/setup installs it)");
    assert!(status.success(), "cc {flags:?}");
    exe.to_str().unwrap().to_string()
}

/// The builds: -O0 and -O3, contraction off, and fused where the processor can.
fn builds(dir: &std::path::Path) -> Vec<(String, String)> {
    let mut flags: Vec<(&str, Vec<&str>)> = vec![
        ("O0", vec!["-O0", "-ffp-contract=off"]),
        ("O3", vec!["-O3", "-ffp-contract=off"]),
    ];
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("fma") {
        flags.push(("O3-fma", vec!["-O3", "-mfma", "-ffp-contract=fast"]));
    }
    flags
        .into_iter()
        .map(|(name, f)| (name.to_string(), built(dir, name, &f)))
        .collect()
}

/// Each line's face of `exit` on `cases`, with `args` choosing who answers.
fn faces(cases: &str, args: &[&str]) -> Vec<Value> {
    let mut all = vec!["exit"];
    all.extend(args);
    let (code, out, err) = tetwalk(&all, cases.as_bytes());
    assert_eq!(code, 0, "{args:?}: {err}");
    out.lines()
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap();
            assert_eq!(v["correct"], true, "{args:?}: {l}");
            v["face"].clone()
        })
        .collect()
}

#[test]
fn the_header_is_never_wrong_and_answers_as_certified_does() {
    let dir = tempfile::tempdir().unwrap();
    let builds = builds(dir.path());
    let rows = [
        "well",
        "sliver",
        "needle",
        "near-edge",
        "near-vertex",
        "through-edge",
        "through-vertex",
        "far-offset",
        "mm-offset",
    ];
    for scale in ["0", "-140", "-100", "60", "110", "0/-60", "0/40"] {
        for row in rows {
            let (code, cases, err) = tetwalk(
                &[
                    "gen-cases",
                    "--row",
                    row,
                    "--count",
                    "300",
                    "--scale",
                    scale,
                ],
                b"",
            );
            if code != 0 {
                // A row none of whose cases f32 holds at this scale (a far offset at 2^110).
                assert!(
                    err.contains("can be made at scale"),
                    "{row} at {scale}: {err}"
                );
                continue;
            }
            let ours = faces(&cases, &["--method", "certified"]);
            for (name, exe) in &builds {
                let theirs = faces(&cases, &["--answerer", exe, "--answerer-format", "binary"]);
                assert_eq!(theirs, ours, "{name}: {row} at scale {scale}");
            }
            // Subnormals flushed and read as zero where the processor can be told so.
            #[cfg(target_arch = "x86_64")]
            {
                let flushed = format!("TETWALK_FTZ=1 {}", builds[1].1);
                let theirs = faces(
                    &cases,
                    &["--answerer", &flushed, "--answerer-format", "binary"],
                );
                assert_eq!(theirs, ours, "O3 flushed: {row} at scale {scale}");
            }
        }
    }
}

/// Walked step by step through the built-in scenes and the lattice-tie meshes (`count --answerer`,
/// every step asked), the header is never wrong: its claim holds under `--fail-on claims`.
#[test]
fn walks_through_the_header_are_never_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let exe = built(dir.path(), "O2", &["-O2"]);
    for scene in ["bunny-quality", "kuhn", "kuhn-far", "jitter-far", "fan"] {
        let (code, _, err) = tetwalk(
            &[
                "count",
                "--scene",
                scene,
                "--views",
                "2",
                "--size",
                "32x32",
                "--answerer",
                &exe,
                "--answerer-format",
                "binary",
                "--answerer-claims",
                "--fail-on",
                "claims",
            ],
            b"",
        );
        assert_eq!(code, 0, "{scene}: {err}");
        assert!(err.contains("claims robust: holds here"), "{scene}: {err}");
    }
}

/// Every sign each stage of the header decides is the exact one: the f32 stage (its gate applied),
/// the f64 filter and the expansions, on side products whose inputs are drawn from every exponent
/// regime of f32 — subnormal, tiny, normal, huge, mixed within one case, near ties (points on or a
/// step off the line) — compared with tetwalk's oracle, subnormals flushed and read as zero or not.
#[test]
fn every_sign_the_header_decides_is_the_exact_one() {
    use glam::Vec3;
    use rand::{RngExt, SeedableRng};
    let dir = tempfile::tempdir().unwrap();
    let root = env!("CARGO_MANIFEST_DIR");
    let exe = dir.path().join("signs");
    let ok = std::process::Command::new("cc")
        .args(["-O3", "-std=c99", "-Wall", "-Werror", "-I"])
        .arg(format!("{root}/kernels/c"))
        .arg("-o")
        .arg(&exe)
        .arg(format!("{root}/kernels/c/signs.c"))
        .status()
        .unwrap();
    assert!(ok.success());
    let mut rng = rand_pcg::Pcg64::seed_from_u64(64);
    let x = |rng: &mut rand_pcg::Pcg64, e: i32| {
        let m = rng.random_range(1.0f32..2.0) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        match rng.random_range(0..12) {
            0 => 0.0,
            1 => f32::from_bits(rng.random_range(1..0x0080_0000)) * m.signum(),
            _ => m * 2f32.powi(e.clamp(-126, 126)),
        }
    };
    let mut cases: Vec<[Vec3; 4]> = Vec::new();
    for k in 0..60_000 {
        // Each case at one exponent, or each number at its own (mixed scales within one case).
        let e = rng.random_range(-149..=127);
        let mixed = k % 3 == 0;
        let v = |rng: &mut rand_pcg::Pcg64| {
            let f = |rng: &mut rand_pcg::Pcg64| {
                let e = if mixed {
                    rng.random_range(-149..=127)
                } else {
                    e + rng.random_range(-3..=3)
                };
                x(rng, e)
            };
            Vec3::new(f(rng), f(rng), f(rng))
        };
        let (a, b, o, mut d) = (v(&mut rng), v(&mut rng), v(&mut rng), v(&mut rng));
        if k % 5 == 1 {
            // Near a tie: the direction towards a point of the edge, or a step off it.
            d = ((a + b) * 0.5 - o).map(|c| if rng.random_bool(0.5) { c } else { c.next_up() });
        }
        if [a, b, o, d].iter().all(|p| p.is_finite()) && d != Vec3::ZERO {
            cases.push([a, b, o, d]);
        }
    }
    let input: Vec<u8> = cases
        .iter()
        .flat_map(|c| c.iter().flat_map(|p| p.to_array()))
        .flat_map(f32::to_le_bytes)
        .collect();
    for env in ["0", "1"] {
        let mut child = std::process::Command::new(&exe)
            .env("TETWALK_FTZ", env)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let bytes = input.clone();
        let writer = std::thread::spawn(move || std::io::Write::write_all(&mut stdin, &bytes));
        let out = child.wait_with_output().unwrap();
        writer.join().unwrap().unwrap();
        let lines: Vec<&str> = std::str::from_utf8(&out.stdout).unwrap().lines().collect();
        assert_eq!(lines.len(), cases.len());
        let (mut by_f32, mut by_f64) = (0, 0);
        for (c, l) in cases.iter().zip(&lines) {
            let s: Vec<i8> = l.split(' ').map(|w| w.parse().unwrap()).collect();
            let ray = tetwalk::tet::Ray {
                org: c[2],
                dir: c[3],
            };
            let exact = tetwalk::exact::side(c[0], c[1], &ray);
            assert_eq!(s[2], exact, "FTZ {env}: the expansions on {c:?}");
            for (stage, sign) in [("f32", s[0]), ("f64", s[1])] {
                assert!(
                    sign == 0 || sign == exact,
                    "FTZ {env}: the {stage} stage on {c:?}: {sign}, exactly {exact}"
                );
            }
            by_f32 += (s[0] != 0) as usize;
            by_f64 += (s[1] != 0) as usize;
        }
        // Each stage decides most of what it can: the checks are not vacuous.
        // (Most inputs across every regime are gated or overflow f32: it decides those it may.)
        assert!(
            by_f32 > cases.len() / 20 && by_f64 > cases.len() / 2,
            "{by_f32} {by_f64} of {}",
            cases.len()
        );
    }
}
