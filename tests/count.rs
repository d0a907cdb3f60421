//! `tetwalk count` on a generated scene: internally consistent, `exact` never wrong, and the same
//! numbers whatever the thread count.

use std::process::Command;

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
fn count_is_consistent_and_exact_is_never_wrong() {
    let dir = tempfile::tempdir().unwrap();
    for scene in ["jitter", "kuhn-far"] {
        let (table, one) = count("1", &dir.path().join("one.json"), scene);
        let (_, two) = count("2", &dir.path().join("two.json"), scene);
        let strip = |v: &serde_json::Value| {
            v["methods"]
                .as_array()
                .unwrap()
                .iter()
                .map(|m| (m["method"].clone(), m["wrong"].clone(), m["steps"].clone()))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            strip(&one),
            strip(&two),
            "{scene}: counts must not depend on the thread count"
        );
        assert_eq!(one["views_counted"], 3);
        assert_eq!(one["rays"], 3 * 40 * 30);
        let methods = one["methods"].as_array().unwrap();
        assert_eq!(methods[0]["method"], "exact");
        assert_eq!(methods[0]["wrong"], serde_json::json!([0, 0, 0, 0, 0]));
        assert_eq!(methods.len(), tetwalk::registry::METHODS.len());
        let reference_steps = methods[0]["steps"].as_u64().unwrap();
        assert!(
            reference_steps >= 3 * 40 * 30,
            "every ray traverses at least one tetrahedron"
        );
        for m in methods {
            // Table rows are the JSON divided by the views: wrong rays = sum of the kinds.
            let kinds: Vec<u64> = m["wrong"]
                .as_array()
                .unwrap()
                .iter()
                .map(|k| k.as_u64().unwrap())
                .collect();
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
