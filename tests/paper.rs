//! `tetwalk paper --shard I/N` and `tetwalk paper merge`: a run split by views adds up to the whole
//! run's counts exactly, on every backend and for the octree; shards that are not one run are refused
//! by name, a shard's report goes to JSON only, and the files written get a new file's usual mode.

mod common;

use tetwalk::backend::Backend;
use tetwalk::engine::count::{Shard, merge};
use tetwalk::engine::paper::{self, PaperReport, Size};
use tetwalk::methods::Model;

/// A run small enough for a test: six views of 16², three of which hold a camera inside the mesh.
const TINY: Size = Size {
    views: 6,
    side: 16,
    tets: 20,
    rays: 8,
    triangle_side: 8,
    bench_views: 2,
};

fn run(shard: Shard) -> PaperReport {
    let scene = tetwalk::scenes::load("kuhn", tetwalk::mesh::Faces::Required).unwrap();
    let backends = [
        Backend::Cpu {
            model: Model::Plain,
        },
        Backend::Cpu {
            model: Model::Fused,
        },
    ];
    paper::run(&scene, TINY, shard, &backends, &|| ()).unwrap()
}

/// What must not depend on sharding: per backend and method, the rays, views and wrong rays by kind
/// and tetrahedra; for the octree, the same with cells.
fn counted(r: &PaperReport) -> serde_json::Value {
    let counts: Vec<_> = r
        .counts
        .iter()
        .map(|c| {
            let methods: Vec<_> = c
                .methods
                .iter()
                .map(|m| {
                    serde_json::json!([
                        m.method,
                        m.counts.wrong_total,
                        m.counts.wrong.0,
                        m.counts.steps
                    ])
                })
                .collect();
            serde_json::json!([c.backend, c.rays, c.views_counted, methods])
        })
        .collect();
    let octrees: Vec<_> = r
        .octrees
        .iter()
        .map(|o| {
            let methods: Vec<_> = o
                .methods
                .iter()
                .map(|m| {
                    serde_json::json!([
                        m.method,
                        m.counts.wrong_total,
                        m.counts.wrong,
                        m.counts.cells
                    ])
                })
                .collect();
            serde_json::json!([o.backend, o.rays, o.views_counted, methods])
        })
        .collect();
    serde_json::json!([counts, octrees])
}

#[test]
fn shards_merge_to_the_whole_run_and_strangers_are_refused() {
    let whole = run(Shard::ALL);
    assert!(whole.counts[0].rays > 0, "the tiny run counts something");
    assert_eq!(whole.octrees.len(), 2, "an octree count per backend");
    assert!(whole.octrees.iter().all(|o| o.rays == whole.counts[0].rays));
    let shards: Vec<PaperReport> = (0..3).map(|index| run(Shard { index, count: 3 })).collect();
    assert!(
        shards
            .iter()
            .all(|s| s.counts[0].rays < whole.counts[0].rays),
        "each shard counts part of the views"
    );
    // Merged in any order.
    let order = [shards[2].clone(), shards[0].clone(), shards[1].clone()];
    let named = |rs: &[PaperReport]| -> Vec<(String, PaperReport)> {
        rs.iter()
            .map(|r| (format!("shard{}.json", r.shard.index), r.clone()))
            .collect()
    };
    let merged = merge(&named(&order)).unwrap();
    assert_eq!(merged.shard, Shard::ALL);
    assert_eq!(counted(&merged), counted(&whole));
    let table5 = |r: &PaperReport| r.timings.as_ref().map(|t| t.table5.len());
    assert!(
        table5(&shards[0]).is_some_and(|n| n > 0),
        "shard 0 is timed"
    );
    assert!(
        shards[1..].iter().all(|s| s.timings.is_none()),
        "the other shards count only"
    );
    assert_eq!(
        table5(&merged),
        table5(&shards[0]),
        "the merge keeps shard 0's timings"
    );

    let missing = merge(&named(&shards[..2])).unwrap_err().to_string();
    assert!(
        missing.contains("of 3 shards, missing 2, given more than once none"),
        "{missing}"
    );
    let twice = [shards[0].clone(), shards[1].clone(), shards[1].clone()];
    let err = merge(&named(&twice)).unwrap_err().to_string();
    assert!(err.contains("missing 2, given more than once 1"), "{err}");
    let mut other = shards[2].clone();
    other.scene = "another".into();
    let err = merge(&named(&[shards[0].clone(), shards[1].clone(), other]))
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("shard2.json: "), "{err}");
    assert!(err.contains("scene is \"another\""), "{err}");

    // The command: shards' JSON in, the tables and the merged JSON out.
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["paper".to_string(), "merge".to_string()];
    for (i, s) in shards.iter().enumerate() {
        let p = dir.path().join(format!("shard{i}.json"));
        std::fs::write(&p, serde_json::to_string(s).unwrap()).unwrap();
        args.push(p.to_str().unwrap().to_string());
    }
    let (out, json) = (dir.path().join("paper.md"), dir.path().join("merged.json"));
    args.extend(
        [
            "--out",
            out.to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
        ]
        .map(String::from),
    );
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, stdout, err) = common::run_tetwalk(&args, b"");
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), stdout);
    assert!(stdout.contains("## Seed 000 Table 4"), "{stdout}");
    let back: PaperReport = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(counted(&back), counted(&whole));
    #[cfg(unix)]
    {
        // Written whole through a temporary file, yet with the mode any new file gets here.
        use std::os::unix::fs::PermissionsExt;
        let plain = dir.path().join("plain");
        std::fs::write(&plain, "").unwrap();
        let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode();
        assert_eq!(mode(&out), mode(&plain));
        assert_eq!(mode(&json), mode(&plain));
    }

    let (code, _, err) = common::run_tetwalk(&args[..4], b"");
    assert_eq!(code, 2, "two of three shards are refused: {err}");
}

#[test]
fn a_shard_writes_json_only() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("paper.md");
    let (code, _, err) = common::run_tetwalk(
        &["paper", "--shard", "1/4", "--out", out.to_str().unwrap()],
        b"",
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--shard 1/4") && err.contains("--json"),
        "{err}"
    );
    let (code, _, err) = common::run_tetwalk(&["paper", "--shard", "4/4", "--json", "x"], b"");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--shard 4/4"), "{err}");
    assert!(
        !out.exists() && !std::path::Path::new("x").exists(),
        "nothing written"
    );
}

/// The scripts the GitHub workflow, the GNU parallel line and the Slurm array run
/// (`scripts/paper-shard.sh`, `scripts/paper-merge.sh`), on a small preset: two shards, then the
/// merge, whose tables are the unsharded run's.
#[test]
fn the_shard_and_merge_scripts_add_up_on_a_small_preset() {
    let dir = tempfile::tempdir().unwrap();
    let root = env!("CARGO_MANIFEST_DIR");
    let script = |name: &str, args: &[&str]| {
        let out = std::process::Command::new("bash")
            .arg(format!("{root}/scripts/{name}"))
            .args(args)
            .current_dir(root)
            .env("TETWALK", env!("CARGO_BIN_EXE_tetwalk"))
            .env(
                "PAPER_ARGS",
                "--scene kuhn --views 6 --side 8 --backend cpu",
            )
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        assert!(
            out.status.success(),
            "{name}: {text}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        text
    };
    let shards = dir.path().join("shards");
    let at = shards.to_str().unwrap();
    for i in ["0", "1"] {
        let said = script("paper-shard.sh", &[i, "2", at]);
        assert!(said.contains(&format!("shard {i}/2: ")), "{said}");
    }
    assert!(script("paper-merge.sh", &[at]).contains("merged 2 shards"));
    let merged: PaperReport =
        serde_json::from_str(&std::fs::read_to_string(shards.join("paper.json")).unwrap()).unwrap();
    assert_eq!(merged.shard, Shard::ALL);
    assert!(merged.timings.is_some(), "shard 0's timings kept");
    assert!(
        std::fs::read_to_string(shards.join("paper.md"))
            .unwrap()
            .contains("## Seed 000 Table 4")
    );
    let whole = tetwalk::engine::paper::run(
        &tetwalk::scenes::load("kuhn", tetwalk::mesh::Faces::Required).unwrap(),
        Size {
            views: 6,
            side: 8,
            bench_views: 6,
            ..Size::REDUCED
        },
        Shard::ALL,
        &[Backend::Cpu {
            model: Model::Plain,
        }],
        &|| (),
    )
    .unwrap();
    assert_eq!(counted(&merged), counted(&whole));
}
