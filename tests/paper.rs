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
    let mesh = tetwalk::scenes::load("kuhn", tetwalk::mesh::Faces::Required).unwrap();
    let backends = [
        Backend::Cpu {
            model: Model::Plain,
        },
        Backend::Cpu {
            model: Model::Fused,
        },
    ];
    paper::run("kuhn", &mesh, TINY, shard, &backends, &|| ()).unwrap()
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
    assert_eq!(merged.table5.len(), shards[0].table5.len());

    let missing = merge(&named(&shards[..2])).unwrap_err().to_string();
    assert!(missing.contains("[0, 1] of 3"), "{missing}");
    let twice = [shards[0].clone(), shards[1].clone(), shards[1].clone()];
    let err = merge(&named(&twice)).unwrap_err().to_string();
    assert!(err.contains("[0, 1, 1] of 3"), "{err}");
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
