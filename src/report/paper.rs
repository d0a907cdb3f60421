//! `tetwalk paper`: the seeds' tables that tetwalk reproduces, ours beside theirs, with what differs —
//! seed 000 Tables 3, 4 and 5, seed 003 Tables 1–4, seed 004 Figure 5 and seed 001 Tables 1 and 3 with
//! an exact count of its octree walk on each backend; a GPU backend adds its columns, with its adapter
//! and driver.

use crate::backend::{Backend, BackendError};
use crate::mesh::Mesh;
use crate::mesh::layout::Layout;
use crate::methods::Query;
use crate::registry::{METHODS, Method, OCTREE_METHODS, TRIANGLE_METHODS};
use crate::report::bench::{self, BenchReport};
use crate::report::count::{self, CountError, CountReport, Shard, Sharded};
use crate::report::octree::{self, OctreeCountReport};
use crate::report::scene_info::SceneInfo;
use crate::report::triangle::{self, SpeedReport};

/// Seed 000 Table 3, the BUNNY column: tetrahedra, occlusive faces, non-occlusive faces, memory (MB).
const SEED000_TABLE3_BUNNY: (usize, usize, usize, f64) = (682_733, 222_775, 1_142_650, 62.0);

/// Seed 000 Table 4, the BUNNY column: wrong rays per 1024² image on the GPU, averaged over about
/// 1,300 views ("Ours" is maria17).
const SEED000_TABLE4_BUNNY: [(&str, f64); 5] = [
    ("ray-plane", 40.85),
    ("plucker", 22.25),
    ("stp", 204.89),
    ("ms06", 0.004),
    ("maria17", 0.0),
];

/// Seed 000 Table 5: ms for 10,000 tetrahedra × 16,384 rays, CPU (one thread) and GPU.
const SEED000_TABLE5: [(&str, f64, f64); 5] = [
    ("ray-plane", 15_623.0, 36.0),
    ("plucker", 10_101.0, 28.0),
    ("stp", 4_876.0, 29.0),
    ("ms06", 5_994.0, 21.0),
    ("maria17", 2_663.0, 13.0),
];

/// Seed 000 Table 3, the BUNNY column: ray casting in Mrays/s on its CPU (an i7-4930K, OpenMP) and
/// GPU (a GTX 680).
const SEED000_TABLE3_MRAYS: (f64, f64) = (10.5, 289.0);

/// Seed 003's structures as tetwalk walks them: the method, and `cells` or one of seed 003's layouts.
const SEED003_STRUCTURES: [(&str, &str, &str); 5] = [
    ("Tet-mesh-ScTP", "stp", "cells"),
    ("Tet-mesh-80", "maria17", "cells"),
    ("Tet-mesh-32", "aman20", "tet32"),
    ("Tet-mesh-20", "aman20", "tet20"),
    ("Tet-mesh-16", "aman20", "tet16"),
];

/// Seed 003 Tables 1 and 2: CPU rendering times (ms) of its 15 scenes, per structure in
/// [`SEED003_STRUCTURES`]' order.
const SEED003_CPU: [[f64; 15]; 5] = [
    [
        261.5, 293.4, 232.5, 306.7, 268.9, 279.6, 402.6, 430.0, 449.5, 455.0, 554.035, 525.523,
        436.716, 333.291, 344.483,
    ],
    [
        244.1, 278.9, 218.1, 262.4, 236.5, 261.0, 355.7, 384.7, 411.2, 419.6, 488.299, 466.933,
        400.589, 312.152, 320.361,
    ],
    [
        150.7, 181.7, 148.5, 182.5, 158.7, 176.1, 247.2, 268.5, 265.5, 269.9, 353.444, 333.274,
        265.337, 202.472, 207.239,
    ],
    [
        125.8, 142.3, 117.1, 145.3, 127.1, 137.0, 196.3, 211.1, 205.6, 210.2, 282.211, 265.337,
        215.118, 163.814, 166.619,
    ],
    [
        136.3, 152.4, 124.6, 153.2, 135.9, 152.0, 223.9, 241.4, 237.4, 240.3, 313.335, 293.351,
        238.027, 183.198, 186.125,
    ],
];

/// Seed 003 Table 3: GPU kernel times (ms) of its 6 scenes, per structure in [`SEED003_STRUCTURES`]'
/// order.
const SEED003_GPU: [[f64; 6]; 5] = [
    [20.021, 19.612, 20.898, 43.910, 43.633, 22.560],
    [7.790, 7.136, 7.941, 13.454, 14.360, 9.023],
    [19.541, 18.950, 20.958, 42.690, 44.544, 21.320],
    [6.156, 5.803, 6.529, 11.322, 12.172, 6.931],
    [7.120, 6.477, 7.328, 12.157, 13.444, 8.231],
];

/// Seed 003 Table 4: MB per layout (Tet-mesh-32, -20, -16, -80) for its smallest and largest scenes.
const SEED003_TABLE4: [(&str, f64, f64); 4] = [
    ("Tet32", 12.3, 885.1),
    ("Tet20", 9.2, 673.6),
    ("Tet16", 8.2, 603.1),
    ("Tet80", 20.6, 1410.0),
];

/// Why a run of the seeds' tables could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PaperError {
    #[error(transparent)]
    Count(#[from] CountError),
    #[error(transparent)]
    Bench(#[from] bench::BenchError),
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error(transparent)]
    Method(#[from] crate::registry::UnknownMethod),
}

/// How large a run is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Size {
    /// Views and image side of the count (seed 000: 1,282 views of 1024²).
    pub views: usize,
    pub side: u32,
    /// Tetrahedra and rays per tetrahedron of Table 5 (seed 000: 10,000 × 16,384).
    pub tets: usize,
    pub rays: usize,
    /// Image side of seed 004 Figure 5's view (seed 004: 256²).
    pub triangle_side: u32,
    /// Views (of `side`²) timed for the walk speeds of seed 000 Table 3 and seed 003 Tables 1–3.
    pub bench_views: usize,
}

impl Size {
    /// A run of a minute or two on two cores.
    pub const REDUCED: Size = Size {
        views: 32,
        side: 256,
        tets: 1_000,
        rays: 512,
        triangle_side: 64,
        bench_views: 32,
    };
    /// The papers' sizes, but Table 5 at a tenth of the rays per tetrahedron (the whole would hold
    /// about 40 GB of queries at once).
    pub const FULL: Size = Size {
        views: 1282,
        side: 1024,
        tets: 10_000,
        rays: 1_638,
        triangle_side: 256,
        bench_views: 16,
    };
}

/// Table 5: ns per query per method.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct QueryTime {
    pub method: String,
    pub ns_per_query: f64,
}

/// Table 5 on a GPU: each method's kernel time per query.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct GpuQueryTimes {
    /// The backend, with its adapter and driver.
    pub backend: String,
    pub times: Vec<QueryTime>,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PaperReport {
    /// The UTC date of the run.
    pub date: String,
    pub scene: String,
    pub size: Size,
    /// The views counted (`--shard I/N`); `0/1` for all of them.
    pub shard: Shard,
    pub scene_info: SceneInfo,
    /// Seed 000 Table 4, one count per backend.
    pub counts: Vec<CountReport>,
    /// Seed 000 Table 5 (CPU, one thread).
    pub table5: Vec<QueryTime>,
    /// Seed 000 Table 5 on each GPU backend that measures kernel times.
    pub table5_gpu: Vec<GpuQueryTimes>,
    /// Walk speeds on every backend: seed 000 Table 3's ray casting, seed 003 Tables 1–3's structures.
    pub speed: BenchReport,
    /// Seed 004 Figure 5 (CPU, one thread).
    pub figure5: SpeedReport,
    /// Seed 001's octree walk over the scene's constrained faces, judged as the counts are, one
    /// count per backend.
    pub octrees: Vec<OctreeCountReport>,
}

/// Run every reproducible table on `mesh` (scene `scene`) with the counts on `backends`; the counts
/// over the views `shard` holds ([`count::merge`] adds the shards up), the timings whole.
pub fn run(
    scene: &str,
    mesh: &Mesh,
    size: Size,
    shard: Shard,
    backends: &[Backend],
    tick: &(dyn Fn() + Sync),
) -> Result<PaperReport, PaperError> {
    // Judged against `certified`, as the default count is; the reference's own row comes first.
    let reference = "certified";
    let methods: Vec<&Method> = METHODS
        .iter()
        .filter(|m| !m.reference && m.name != reference)
        .collect();
    let settings = count::Settings {
        scene: scene.to_string(),
        views: crate::scenes::camera::Views {
            views: size.views,
            width: size.side,
            height: size.side,
            seed: 1,
            fov_deg: crate::scenes::camera::Views::FOV_DEG,
        },
        reference: reference.into(),
        audit: 1000,
        shard,
    };
    let counts = backends
        .iter()
        .map(|b| count::run(mesh, &settings, &methods, b, tick, None))
        .collect::<Result<Vec<_>, _>>()?;
    let (tets, queries) = crate::methods::table5_queries(size.tets, size.rays, 5);
    let table5 = METHODS
        .iter()
        .map(|m| {
            let (secs, _) = m.time_queries()(&tets, &queries, if m.reference { 1 } else { 3 });
            QueryTime {
                method: m.name.to_string(),
                ns_per_query: secs * 1e9 / queries.len().max(1) as f64,
            }
        })
        .collect();
    let table5_gpu = backends
        .iter()
        .filter(|b| b.measures_kernels())
        .map(|b| {
            Ok(GpuQueryTimes {
                backend: b.describe(),
                times: gpu_query_times(b, &tets, &queries)?,
            })
        })
        .collect::<Result<Vec<_>, BackendError>>()?;
    // The methods of seed 003's structures (maria17 among them, for seed 000 Table 3).
    let names: Vec<&str> = SEED003_STRUCTURES.iter().map(|s| s.1).collect();
    let timed = crate::registry::parse_list(&names.join(","))?;
    // cpu-fma is not timed: in a portable build its fused multiply-adds are library calls.
    let timed_on: Vec<&Backend> = backends
        .iter()
        .filter(|b| b.kind() != crate::backend::BackendKind::CpuFma)
        .collect();
    let speed = bench::run(
        scene,
        mesh,
        false,
        &crate::scenes::camera::Views {
            views: size.bench_views,
            ..settings.views
        },
        &timed,
        &timed_on,
        (BENCH_BATCH, true),
        &|| (),
    )?;
    let views = crate::scenes::camera::Views {
        width: size.triangle_side,
        height: size.triangle_side,
        ..settings.views
    };
    let triangle_methods: Vec<_> = TRIANGLE_METHODS.iter().collect();
    let figure5 = triangle::speed(mesh, scene, &views, &triangle_methods, 3)?;
    let octree_methods: Vec<_> = OCTREE_METHODS.iter().filter(|m| !m.reference).collect();
    let octree_settings = octree::CountSettings {
        scene: scene.to_string(),
        views: settings.views,
        reference: reference.into(),
        octree: crate::octree::Settings::PAPER,
        triangle_method: "mt".into(),
        audit: 1000,
        shard,
    };
    let octrees = backends
        .iter()
        .map(|b| octree::count(mesh, &octree_settings, &octree_methods, b, tick, None))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(PaperReport {
        date: today(),
        scene: scene.to_string(),
        size,
        shard,
        scene_info: SceneInfo::of(mesh, crate::octree::Settings::PAPER),
        counts,
        table5,
        table5_gpu,
        speed,
        figure5,
        octrees,
    })
}

/// Rays per batch of the walk speeds: 4 M, a reduced run's 32 views of 256² in one batch.
const BENCH_BATCH: usize = 1 << 22;

/// Queries per GPU dispatch of Table 5 (the cases are made per run, not all at once).
const GPU_QUERY_RUN: usize = 1 << 20;

/// Seed 000 Table 5 on a GPU: each method's kernel time over every query, in runs of
/// [`GPU_QUERY_RUN`], after one untimed run; the best of three.
fn gpu_query_times(
    backend: &Backend,
    tets: &[crate::tet::Tet],
    queries: &[Query],
) -> Result<Vec<QueryTime>, BackendError> {
    let cases = |run: &[Query]| -> Vec<crate::tet::Case> {
        run.iter()
            .map(|(t, r, e)| crate::tet::Case {
                tet: tets[*t as usize],
                org: r.org,
                dir: r.dir,
                entry: e.map(|e| e as u8),
            })
            .collect()
    };
    let gpu_methods = METHODS
        .iter()
        .filter(|m| !m.reference && matches!(m.gpu, crate::registry::Gpu::Wgsl(_)));
    gpu_methods
        .map(|m| {
            let first = cases(&queries[..queries.len().min(GPU_QUERY_RUN)]);
            backend.exit_faces_timed(m, &first)?;
            let mut best = f64::INFINITY;
            for _ in 0..3 {
                let mut total = 0.0;
                for run in queries.chunks(GPU_QUERY_RUN) {
                    total += backend
                        .exit_faces_timed(m, &cases(run))?
                        .1
                        .unwrap_or(f64::NAN);
                }
                best = best.min(total);
            }
            Ok(QueryTime {
                method: m.name.to_string(),
                ns_per_query: best * 1e9 / queries.len().max(1) as f64,
            })
        })
        .collect()
}

/// A run's shards (`--shard I/N`) add up: each backend's count and the octree count; the scene, the
/// timings and the date are shard 0's.
/// Each of a run's counts `items` (named `name`) checked, of the run's shard and views.
fn check_each<R: Sharded>(
    name: &str,
    items: &[R],
    shard: Shard,
    views: usize,
    views_of: impl Fn(&R) -> usize,
) -> Result<(), (String, String)> {
    for (k, c) in items.iter().enumerate() {
        let at = |f: &str| format!("{name}[{k}].{f}");
        if c.shard() != shard {
            return count::inconsistent(at("settings.shard"), "not the run's shard");
        }
        if views_of(c) != views {
            return count::inconsistent(
                at("settings.views.views"),
                format!("not the run's {views} views"),
            );
        }
        c.check().map_err(|(f, why)| (at(&f), why))?;
    }
    Ok(())
}

impl Sharded for PaperReport {
    fn same(&self) -> serde_json::Value {
        let backends: Vec<_> = self.counts.iter().map(|c| c.same()).collect();
        let octrees: Vec<_> = self.octrees.iter().map(|c| c.same()).collect();
        serde_json::json!({"scene": self.scene, "size": self.size, "counts": backends, "octrees": octrees})
    }

    fn shard(&self) -> Shard {
        self.shard
    }

    fn methods(&self) -> Vec<String> {
        self.counts.first().map_or(Vec::new(), Sharded::methods)
    }

    fn check(&self) -> Result<(), (String, String)> {
        if self.counts.is_empty() {
            return count::inconsistent(
                "counts",
                "no count: a paper run counts on one backend at least",
            );
        }
        let views = |c: &CountReport| c.settings.views.views;
        check_each("counts", &self.counts, self.shard, self.size.views, views)?;
        let views = |c: &OctreeCountReport| c.settings.views.views;
        check_each("octrees", &self.octrees, self.shard, self.size.views, views)?;
        let methods = self.methods();
        if let Some(k) = self.counts.iter().position(|c| c.methods() != methods) {
            return count::inconsistent(
                format!("counts[{k}].methods"),
                "not the methods of counts[0]",
            );
        }
        Ok(())
    }

    fn add(&mut self, other: &Self) {
        for (c, o) in self.counts.iter_mut().zip(&other.counts) {
            c.add(o);
        }
        for (o, other) in self.octrees.iter_mut().zip(&other.octrees) {
            o.add(other);
        }
    }

    fn finish(&mut self) {
        self.shard = Shard::ALL;
        self.counts.iter_mut().for_each(Sharded::finish);
        self.octrees.iter_mut().for_each(Sharded::finish);
    }
}

impl PaperReport {
    pub fn markdown(&self) -> String {
        let i = &self.scene_info;
        let (t, occl, other, mb) = SEED000_TABLE3_BUNNY;
        let tet80 = Layout::BYTES
            .iter()
            .find(|b| b.0 == "Tet80")
            .map_or(80, |b| b.1);
        let mut out = format!(
            "# The seeds' tables, ours beside theirs\n\n`tetwalk paper`, {} (UTC). Scene `{}`; counts of {} views of {}², Table 5 over {} tetrahedra × {} rays.\n\n",
            self.date, self.scene, self.size.views, self.size.side, self.size.tets, self.size.rays
        );
        out += &adapters(self.counts.iter().map(|c| c.backend.as_str()));
        out += "## Seed 000 Table 3: the scene\n\n| | seed 000, BUNNY (quality CDT) | ours |\n|---|---|---|\n";
        out += &format!("| tetrahedra | {t} | {} |\n", i.tetrahedra);
        out += &format!("| occlusive faces | {occl} | {} |\n", i.constrained_faces);
        out += &format!("| non-occlusive faces | {other} | {} |\n", i.other_faces);
        out += &format!(
            "| memory, Tet80 (MB) | {mb} | {:.1} |\n\nOurs tetrahedralizes the npm `bunny` model, a much coarser one than the paper's, so the counts differ by orders of magnitude.\n\n",
            (i.tetrahedra * tet80) as f64 / 1e6
        );
        out += &self.ray_casting();
        out += "## Seed 000 Table 4: wrong rays per 1024² image\n\nThe paper's are on its GPU (GTX 680), about 1,300 views. Ours are judged exactly, scaled from our image size to 1024² by the pixel count, one column per backend.\n\n| method | seed 000, BUNNY (GPU) |";
        for c in &self.counts {
            out += &format!(" ours, {} |", kind(&c.backend));
        }
        out += "\n|---|---|";
        out += &"---|".repeat(self.counts.len());
        out += "\n";
        let scale = (1024.0 * 1024.0) / (self.size.side as f64 * self.size.side as f64);
        if let Some(first) = self.counts.first() {
            for m in &first.methods {
                let paper = SEED000_TABLE4_BUNNY
                    .iter()
                    .find(|p| p.0 == m.method)
                    .map_or("-".to_string(), |p| format!("{}", p.1));
                out += &format!("| {} | {paper} |", m.method);
                for c in &self.counts {
                    let ours = c.methods.iter().find(|x| x.method == m.method);
                    out += &format!(
                        " {} |",
                        ours.map_or("-".into(), |x| format!("{:.3}", x.per_image.wrong * scale))
                    );
                }
                out += "\n";
            }
        }
        out += "\nThe paper's claim that maria17 (\"Ours\") is never wrong does not hold under exact judging; see the README's register of claims.\n\n";
        out += "## Seed 000 Table 5: exit-face search, ratio to maria17\n\nOurs on this CPU, one thread, each ray's data prepared once, and on each GPU backend the kernel time of one dispatch per million queries (each query uploaded with its tetrahedron); the paper's CPU and GPU times as ratios.\n\n| method | ours, cpu: ns/query | ratio |";
        for g in &self.table5_gpu {
            out += &format!(" ours, {}: ns/query | ratio |", kind(&g.backend));
        }
        out += " seed 000 CPU ratio | seed 000 GPU ratio |\n|---|---|---|";
        out += &"---|---|".repeat(self.table5_gpu.len());
        out += "---|---|\n";
        let base = self
            .table5
            .iter()
            .find(|q| q.method == "maria17")
            .map_or(1.0, |q| q.ns_per_query);
        for q in &self.table5 {
            let paper = SEED000_TABLE5.iter().find(|p| p.0 == q.method);
            let (cpu, gpu) = paper.map_or(("-".into(), "-".into()), |p| {
                (
                    format!("{:.2}", p.1 / 2_663.0),
                    format!("{:.2}", p.2 / 13.0),
                )
            });
            out += &format!(
                "| {} | {:.1} | {:.2} |",
                q.method,
                q.ns_per_query,
                q.ns_per_query / base
            );
            for g in &self.table5_gpu {
                let base = g.times.iter().find(|t| t.method == "maria17");
                out += &match (g.times.iter().find(|t| t.method == q.method), base) {
                    (Some(t), Some(b)) => format!(
                        " {:.3} | {:.2} |",
                        t.ns_per_query,
                        t.ns_per_query / b.ns_per_query
                    ),
                    _ => " - | - |".into(),
                };
            }
            out += &format!(" {cpu} | {gpu} |\n");
        }
        out += "\nWhy the gaps differ: `corpora/results/table5.md`.\n\n";
        out += "## Seed 003 Table 4: memory per layout, as ratios to Tet80\n\n| layout | bytes per tetrahedron | ours, MB | ours, ratio to Tet80 | seed 003, Torus Knots | seed 003, Exhaust Pipe |\n|---|---|---|---|---|---|\n";
        for (name, bytes) in Layout::BYTES {
            let paper = SEED003_TABLE4.iter().find(|p| p.0 == name);
            let tet80_paper = SEED003_TABLE4[3];
            out += &format!(
                "| {name} | {bytes} | {:.2} | {:.2} | {} | {} |\n",
                (i.tetrahedra * bytes) as f64 / 1e6,
                bytes as f64 / tet80 as f64,
                paper.map_or("-".into(), |p| format!("{:.2}", p.1 / tet80_paper.1)),
                paper.map_or("-".into(), |p| format!("{:.2}", p.2 / tet80_paper.2)),
            );
        }
        out += "\nThe paper's sizes include the points and the constrained-face data; ours count the tetrahedra only.\n";
        out += &self.structures();
        out += "\n## Seed 004 Figure 5: packet intersection speed, ratio to the improved Möller test\n\n";
        out += "The paper's figure gives bars, its text \"about 1.1x to 1.4x\" for its packet method over the improved Möller test (2x2 packets) and the Plücker packet test below it. Ours: ";
        out += &self.figure5.markdown();
        out += "\n## Seed 001 Tables 1 and 3, §5.1: the octree\n\n";
        if let Some(o) = &i.octree {
            out += &o.markdown();
        }
        out += "\nOurs is built over the constrained faces of the scene above (the same decimated bunny), at the paper's depth for the bunny; the paper's bunny has 69k triangles.\n\n";
        out += "## Seed 001: the octree walk, judged exactly\n\nThe paper gives speeds (Table 2, a GTX 980) and no robustness claim; ours counts wrong rays, each judged against the exact first hit.\n\n";
        if let Some(first) = self.octrees.first() {
            out += &first.markdown();
        }
        if self.octrees.len() > 1 {
            out += &self.octree_backends();
        }
        out
    }
}

impl PaperReport {
    /// The octree walk's wrong rays per image on each backend, side by side.
    fn octree_backends(&self) -> String {
        let mut out = "\nWrong rays per image on each backend (the walk's loop in WGSL on a GPU, the entry cell from the cube map on the CPU):\n\n| method |".to_string();
        for o in &self.octrees {
            out += &format!(" {} |", kind(&o.backend));
        }
        out += "\n|---|";
        out += &"---|".repeat(self.octrees.len());
        out += "\n";
        for (i, m) in self.octrees[0].methods.iter().enumerate() {
            out += &format!("| {} |", m.method);
            for o in &self.octrees {
                out += &o
                    .methods
                    .get(i)
                    .map_or(" - |".into(), |x| format!(" {:.3} |", x.wrong_per_image));
            }
            out += "\n";
        }
        out
    }

    /// Seed 000 Table 3's ray casting speed beside maria17's walks on each backend.
    fn ray_casting(&self) -> String {
        let b = &self.speed;
        let (cpu, gpu) = SEED000_TABLE3_MRAYS;
        let mut out = format!(
            "Ray casting, maria17 over the mesh's cells: ours on {} primary rays ({} views of {}x{} with the camera inside the mesh), on {} CPU threads.\n\n| backend | ours, end to end Mrays/s | ours, kernel Mrays/s | seed 000, BUNNY (Mrays/s) |\n|---|---|---|---|\n",
            b.rows.first().map_or(0, |r| r.rays),
            b.views_timed,
            b.views.width,
            b.views.height,
            rayon::current_num_threads()
        );
        for r in b
            .rows
            .iter()
            .filter(|r| r.method == "maria17" && r.layout == "cells")
        {
            let paper = match r.backend.as_str() {
                "cpu" => format!("{cpu} (i7-4930K, 6 cores, OpenMP)"),
                "gpu" => format!("{gpu} (GTX 680, CUDA)"),
                _ => "-".into(),
            };
            out += &format!(
                "| {} | {:.2} | {} | {paper} |\n",
                r.backend,
                r.rays as f64 / r.seconds / 1e6,
                r.kernel_seconds
                    .map_or("-".into(), |k| format!("{:.2}", r.rays as f64 / k / 1e6)),
            );
        }
        out + "\n"
    }

    /// Seed 003 Tables 1–3: each structure's walk time as a ratio to Tet-mesh-80, ours per backend
    /// beside the paper's range over its scenes.
    fn structures(&self) -> String {
        let b = &self.speed;
        let mut kinds: Vec<&str> = Vec::new();
        for r in &b.rows {
            if !kinds.contains(&r.backend.as_str()) {
                kinds.push(&r.backend);
            }
        }
        let time = |kind: &str, method: &str, layout: &str| {
            b.rows
                .iter()
                .find(|r| r.backend == kind && r.method == method && r.layout == layout)
                .map(|r| r.kernel_seconds.unwrap_or(r.seconds))
        };
        let mut out = format!(
            "\n## Seed 003 Tables 1–3: walk time per structure, as ratios to Tet-mesh-80\n\nOurs: the walks of the rays above ({} views of {}x{}), the mesh as loaded; on a GPU the kernel time. Seed 003 sorts each mesh along a space-filling curve (Hilbert order changed these ratios by under 1% on an H100: `corpora/results/h100-layouts.md`); its Tables 1 and 2 time whole renderings of 1920x1440 on six CPU cores (15 scenes), its Table 3 the kernel on a GTX 1060 (6 scenes); the paper's columns give the range over its scenes.\n\n| structure (seed 003) | ours walks |",
            b.views_timed, b.views.width, b.views.height
        );
        for k in &kinds {
            out += &format!(" ours, {k} |");
        }
        out += " seed 003, CPU (Tables 1, 2) | seed 003, GPU (Table 3) |\n|---|---|";
        out += &"---|".repeat(kinds.len());
        out += "---|---|\n";
        let range = |times: &[f64], base: &[f64]| {
            let ratios: Vec<f64> = times.iter().zip(base).map(|(t, b)| t / b).collect();
            let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = ratios.iter().copied().fold(0.0, f64::max);
            if format!("{lo:.2}") == format!("{hi:.2}") {
                format!("{lo:.2}")
            } else {
                format!("{lo:.2}–{hi:.2}")
            }
        };
        for (i, (name, method, layout)) in SEED003_STRUCTURES.iter().enumerate() {
            out += &format!("| {name} | {method} over {layout} |");
            for k in &kinds {
                let ratio = time(k, method, layout).zip(time(k, "maria17", "cells"));
                out += &ratio.map_or(" - |".into(), |(t, base)| format!(" {:.2} |", t / base));
            }
            out += &format!(
                " {} | {} |\n",
                range(&SEED003_CPU[i], &SEED003_CPU[1]),
                range(&SEED003_GPU[i], &SEED003_GPU[1])
            );
        }
        out
    }
}

/// A backend's kind (`cpu`, `cpu-fma`, `gpu`) from its description.
fn kind(backend: &str) -> &str {
    backend.split(':').next().unwrap_or(backend)
}

/// The adapter and driver of each GPU among `backends`, a line each; a software adapter is said to
/// be one, since its times are a CPU's. Without a hardware GPU, where the last runs on one are kept.
fn adapters<'a>(backends: impl Iterator<Item = &'a str>) -> String {
    let mut out = String::new();
    let mut hardware = false;
    for b in backends.filter(|b| b.contains(':')) {
        out += &format!("- {b}");
        if b.contains(", Cpu,") {
            out += " — a software adapter: its counts are the WGSL as this Vulkan driver compiles it, its times a CPU's";
        } else {
            hardware = true;
        }
        out += "\n";
    }
    if !hardware {
        out += "- no hardware GPU in this run; runs on one (an H100 and an H200, with adapter, driver and date) are in `corpora/results/h100.md` (stress and count), `h100-bench.md` (walk speeds), `h100-layouts.md` (seed 003 Table 3) and `h100-certified.md`\n";
    }
    out + "\n"
}

/// Today's date, UTC, as YYYY-MM-DD (Howard Hinnant's days-to-civil).
fn today() -> String {
    let days = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() / 86_400) as i64;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + (m <= 2) as i64;
    format!("{y:04}-{m:02}-{d:02}")
}
