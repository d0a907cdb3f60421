//! The seeds' tables that tetwalk reproduces (`tetwalk paper`), run: seed 000 Tables 3, 4 and 5, seed
//! 003 Tables 1–4, seed 004 Figure 5 and seed 001 Tables 1 and 3 with an exact count of its octree
//! walk, on each backend; the report (`crate::report::paper`) sets them beside the papers'.

use crate::backend::{Backend, BackendError, Ran};
use crate::choice::Instruction;
use crate::engine::bench::{self, BenchReport};
use crate::engine::count::{
    self, AnswerSource, CountReport, CountSettings, ReferenceWalk, Shard, Sharded,
};
use crate::engine::info::SceneInfo;
use crate::family::count::{CountError, inconsistent};
use crate::family::octree::OctreeCountSettings;
use crate::family::triangle::engine::SpeedReport;
use crate::family::{OctreeCells, Walks};
use crate::methods::Query;
use crate::registry::{ByName, GpuVersion, METHODS, Named, OCTREE_METHODS, TRIANGLE_METHODS};
use crate::scenes::Loaded;

/// Seed 003's structures as tetwalk walks them: the method, and `cells` or one of seed 003's layouts.
pub(crate) const SEED003_STRUCTURES: [(&str, &str, &str); 5] = [
    ("Tet-mesh-ScTP", "stp", "cells"),
    ("Tet-mesh-80", "maria17", "cells"),
    ("Tet-mesh-32", "aman20", "tet32"),
    ("Tet-mesh-20", "aman20", "tet20"),
    ("Tet-mesh-16", "aman20", "tet16"),
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
    pub(crate) const FULL: Size = Size {
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
    pub(crate) method: String,
    pub ns_per_query: f64,
}

/// Table 5 on a GPU: each method's kernel time per query.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct GpuQueryTimes {
    /// The backend, with its adapter and driver.
    pub backend: Ran,
    pub times: Vec<QueryTime>,
}

/// The seeds' timed tables.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Timings {
    /// Seed 000 Table 5 (CPU, one thread).
    pub table5: Vec<QueryTime>,
    /// Seed 000 Table 5 on each GPU backend that measures kernel times.
    pub table5_gpu: Vec<GpuQueryTimes>,
    /// Walk speeds on every backend: seed 000 Table 3's ray casting, seed 003 Tables 1–3's structures.
    pub speed: BenchReport,
    /// Seed 004 Figure 5 (CPU, one thread).
    pub(crate) figure5: SpeedReport,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PaperReport {
    /// The UTC date of the run.
    pub(crate) date: String,
    pub scene: String,
    pub(crate) size: Size,
    /// The views counted (`--shard I/N`); `0/1` for all of them.
    pub shard: Shard,
    pub(crate) scene_info: SceneInfo,
    /// Seed 000 Table 4, one count per backend.
    pub counts: Vec<CountReport<Walks>>,
    /// The timed tables: a whole run's, and shard 0's of a sharded one (the other shards count only).
    pub timings: Option<Timings>,
    /// Seed 001's octree walk over the scene's constrained faces, judged as the counts are, one
    /// count per backend.
    pub octrees: Vec<CountReport<OctreeCells>>,
}

/// Run every reproducible table on `scene` with the counts on `backends`; the counts
/// over the views `shard` holds ([`count::merge`] adds the shards up), the timings whole on shard 0
/// only (a merge keeps shard 0's).
pub fn run(
    scene: &Loaded,
    size: Size,
    shard: Shard,
    backends: &[Backend],
    tick: &(dyn Fn() + Sync),
) -> Result<PaperReport, PaperError> {
    // Judged against `certified`, as the default count is; the reference's own row comes first.
    let reference = ReferenceWalk::default();
    let methods = AnswerSource::<Walks>::judged(None, METHODS, reference);
    let settings = CountSettings::<Walks> {
        views: crate::scenes::camera::Views::new(size.views, size.side, size.side, 1),
        reference,
        family: (),
        audit: 1000,
        shard,
        answerer: None,
    };
    let counts = backends
        .iter()
        .map(|b| count::run(scene, &settings, &methods, b, tick, None))
        .collect::<Result<Vec<_>, _>>()?;
    let timings = if shard.index == 0 {
        Some(timings(scene, size, &settings.views, backends)?)
    } else {
        None
    };
    let octree_methods = AnswerSource::<OctreeCells>::judged(None, OCTREE_METHODS, reference);
    let octree_settings = CountSettings::<OctreeCells> {
        views: settings.views,
        reference,
        family: OctreeCountSettings {
            octree: crate::octree::Settings::PAPER,
            triangle_method: ByName::named("mt").expect("mt is registered"),
        },
        audit: 1000,
        shard,
        answerer: None,
    };
    let octrees = backends
        .iter()
        .map(|b| count::run(scene, &octree_settings, &octree_methods, b, tick, None))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(PaperReport {
        date: today(),
        scene: scene.name.clone(),
        size,
        shard,
        scene_info: SceneInfo::of(&scene.mesh, crate::octree::Settings::PAPER),
        counts,
        timings,
        octrees,
    })
}

/// The timed tables: Table 5 (CPU and each GPU's kernels), the walk speeds and Figure 5.
fn timings(
    scene: &Loaded,
    size: Size,
    views: &crate::scenes::camera::Views,
    backends: &[Backend],
) -> Result<Timings, PaperError> {
    let (tets, queries) = crate::engine::bench::table5_queries(size.tets, size.rays, 5);
    let table5 = METHODS
        .iter()
        .map(|m| {
            let (secs, _) = m.time_queries()(&tets, &queries, if m.is_reference() { 1 } else { 3 });
            QueryTime {
                method: m.name().to_string(),
                ns_per_query: secs * 1e9 / queries.len().max(1) as f64,
            }
        })
        .collect();
    let table5_gpu = backends
        .iter()
        .filter(|b| b.measures_kernels())
        .map(|b| {
            Ok(GpuQueryTimes {
                backend: b.ran(),
                times: gpu_query_times(b, &tets, &queries)?,
            })
        })
        .collect::<Result<Vec<_>, BackendError>>()?;
    // The methods of seed 003's structures (maria17 among them, for seed 000 Table 3).
    let names: Vec<&str> = SEED003_STRUCTURES.iter().map(|s| s.1).collect();
    let timed = crate::family::parse_list::<Walks>(&names.join(","))?;
    // A fused model is not timed: in a portable build its fused multiply-adds are library calls.
    let fused = |b: &Backend| b.kind().model().map(|m| m.instruction()) == Some(Instruction::Fma);
    let timed_on: Vec<&Backend> = backends.iter().filter(|b| !fused(b)).collect();
    let speed = bench::run(
        scene,
        false,
        &crate::scenes::camera::Views {
            views: size.bench_views,
            ..*views
        },
        &timed,
        &timed_on,
        (BENCH_BATCH, true, 1),
        &|| (),
    )?;
    let views = crate::scenes::camera::Views {
        width: size.triangle_side,
        height: size.triangle_side,
        ..*views
    };
    let triangle_methods: Vec<_> = TRIANGLE_METHODS.iter().collect();
    let figure5 = crate::family::triangle::engine::speed(scene, &views, &triangle_methods, 3)?;
    Ok(Timings {
        table5,
        table5_gpu,
        speed,
        figure5,
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
        .filter(|m| !m.is_reference() && matches!(m.info.gpu, GpuVersion::Wgsl(_)));
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
                method: m.name().to_string(),
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
            return inconsistent(at("settings.shard"), "not the run's shard");
        }
        if views_of(c) != views {
            return inconsistent(
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
            return inconsistent(
                "counts",
                "no count: a paper run counts on one backend at least",
            );
        }
        let views = |c: &CountReport<Walks>| c.settings.count.views.views;
        check_each("counts", &self.counts, self.shard, self.size.views, views)?;
        let views = |c: &CountReport<OctreeCells>| c.settings.count.views.views;
        check_each("octrees", &self.octrees, self.shard, self.size.views, views)?;
        let methods = self.methods();
        if let Some(k) = self.counts.iter().position(|c| c.methods() != methods) {
            return inconsistent(
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
