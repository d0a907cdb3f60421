//! Seed 000 Table 5, in shape: exit-face search over random tetrahedra with many random rays stabbing
//! each, one thread, each method's per-ray data prepared once per ray (untimed), every query in one
//! statically dispatched loop; ns per query and the ratio to maria17 beside the paper's. Then walks:
//! ns per walk step on a jittered grid. `cargo bench --bench table5` (scaled down: 1,000 tetrahedra ×
//! 512 rays); `TABLE5_FULL=1` for the paper's 10,000 × 16,384 (needs about 40 GB and long).

use glam::Vec3;
use tetwalk::engine::bench::table5_queries;
use tetwalk::registry::METHODS;
use tetwalk::registry::Named;
use tetwalk::scenes::{self, Generated};
use tetwalk::walk::{default_max_steps, locate};

/// Seed 000 Table 5, CPU column (ms for 10,000 × 16,384 queries).
const PAPER_MS: [(&str, f64); 5] = [
    ("ray-plane", 15623.0),
    ("plucker", 10101.0),
    ("stp", 4876.0),
    ("ms06", 5994.0),
    ("maria17", 2663.0),
];

fn main() {
    // Skip when cargo test runs benches as tests.
    if std::env::args().any(|a| a == "--test") {
        return;
    }
    let full = std::env::var("TABLE5_FULL").is_ok_and(|v| v == "1");
    let (n_tets, n_rays) = if full { (10_000, 16_384) } else { (1_000, 512) };
    let (tets, queries) = table5_queries(n_tets, n_rays, 5);
    println!(
        "exit-face search, {n_tets} tetrahedra x {n_rays} rays, one thread, best of 5\n\n| method | ns/query | ratio to maria17 | paper (seed 000 Table 5, CPU) |\n|---|---|---|---|"
    );
    let times: Vec<(&str, f64)> = METHODS
        .iter()
        .map(|m| {
            let repeats = if m.is_reference() { 1 } else { 5 };
            let (secs, _) = m.time_queries()(&tets, &queries, repeats);
            (m.name(), secs * 1e9 / queries.len() as f64)
        })
        .collect();
    let base = times
        .iter()
        .find(|(n, _)| *n == "maria17")
        .map_or(1.0, |t| t.1);
    let paper_base = 2663.0;
    for (name, ns) in &times {
        let paper = PAPER_MS
            .iter()
            .find(|(n, _)| n == name)
            .map_or("-".to_string(), |(_, ms)| {
                format!("{:.2}x", ms / paper_base)
            });
        println!("| {name} | {ns:.1} | {:.2}x | {paper} |", ns / base);
    }

    let mesh = tetwalk::mesh::reorder::hilbert_sorted(
        &scenes::generated_mesh(Generated::Jitter, 16, Vec3::ZERO, 1).unwrap(),
    );
    let max = default_max_steps(&mesh);
    // The generator aims every other ray exactly through vertices and edges: ties, where `exact` and
    // `certified` decide signs exactly; the others are generic.
    let all: Vec<_> = scenes::rays(Generated::Jitter, &mesh, Vec3::ZERO, 40_000, 1)
        .into_iter()
        .filter_map(|ray| Some((ray, locate(&mesh, ray.org, 0).ok()?)))
        .collect();
    for (label, rays) in [
        (
            "generic rays",
            all.iter().step_by(2).copied().collect::<Vec<_>>(),
        ),
        (
            "rays through vertices and edges",
            all.iter().skip(1).step_by(2).copied().collect(),
        ),
    ] {
        walk_table(&mesh, max, label, &rays);
    }
}

fn walk_table(
    mesh: &tetwalk::mesh::Mesh,
    max: u32,
    label: &str,
    rays: &[(tetwalk::tet::Ray, u32)],
) {
    println!(
        "\nwalks, {} {label} through a jittered 16^3 grid ({} tetrahedra), one thread, best of 3\n\n| method | ns/step | ratio to maria17 | steps |\n|---|---|---|---|",
        rays.len(),
        mesh.tets.len()
    );
    let walks: Vec<(&str, f64, u64)> = METHODS
        .iter()
        .map(|m| {
            let walk = m.walk(tetwalk::methods::Model::Plain);
            let mut best = f64::INFINITY;
            let mut steps = 0;
            for _ in 0..if m.is_reference() { 1 } else { 3 } {
                let t0 = std::time::Instant::now();
                steps = rays
                    .iter()
                    .map(|(ray, s)| walk(mesh, ray, *s, max).steps as u64)
                    .sum::<u64>();
                best = best.min(t0.elapsed().as_secs_f64());
            }
            (m.name(), best * 1e9 / steps as f64, steps)
        })
        .collect();
    let base = walks.iter().find(|w| w.0 == "maria17").map_or(1.0, |w| w.1);
    for (name, ns, steps) in &walks {
        println!("| {name} | {ns:.1} | {:.2}x | {steps} |", ns / base);
    }
}
