//! The triangle family's engine beyond its `Family` (a file of the engine's layer in the family's
//! folder): seed 004 Figure 5's measure, `bench --family triangle`.

use crate::engine::count::located_views;
use crate::family::count::CountError;
use crate::mesh::Mesh;
use crate::mesh::surface::{region_of, scene_triangles};
use crate::methods::Model;
use crate::methods::triangle::SideError;
use crate::registry::{Named, TriangleMethod};
use crate::scenes::camera::{Views, packet_order};
use crate::tet::Ray;
use std::time::Instant;

/// Seed 004 Figure 5's measure: each method's intersection time over a view's primary rays against
/// each tile's candidate triangles ([`super::bins`], as the triangle count tests them), one
/// thread, rays in packets of `p × p`; the 4-wide (SIMD) versions beside the scalar ones.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SpeedRow {
    pub method: String,
    /// Whether this is the method's 4-wide version (SSE; seed 004 timed SIMD code).
    #[serde(default)]
    pub wide: bool,
    /// Packet side `p` (packets of `p × p` rays).
    pub packet: u32,
    /// Nanoseconds per ray–triangle test, the best of the repeats.
    pub ns_per_test: f64,
    /// `mt-precomputed`'s time per test in packets of the same side, scalar or 4-wide as this row is,
    /// over this one's: seed 004's speedup, the loops alike (triangles outer, the packet's rays inner).
    pub speedup: f64,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SpeedReport {
    pub scene: String,
    pub views: Views,
    pub triangles: usize,
    pub rays: usize,
    /// Ray–triangle tests of each method in 2×2 packets (each ray against its tile's candidates for
    /// the method's error scale).
    #[serde(default)]
    pub tests: Vec<(String, u64)>,
    pub repeats: usize,
    pub rows: Vec<SpeedRow>,
}

/// The packet sides timed.
pub const PACKETS: [u32; 4] = [1, 2, 4, 8];

/// Time every method (and its 4-wide version) at every packet side of [`PACKETS`] on the primary rays
/// of `views`' first view that lies inside the mesh, each ray against its tile's candidates for the
/// method's error scale, the best of `repeats` runs each, all in one run; speedups per test relative
/// to `mt-precomputed` at the same packet side and width.
pub fn speed(
    mesh: &Mesh,
    scene: &str,
    views: &Views,
    methods: &[&TriangleMethod],
    repeats: usize,
) -> Result<SpeedReport, CountError> {
    let (_, cam, located) = located_views(mesh, views, |_| true, &|| {})
        .next()
        .ok_or(CountError::NoView(views.views))?;
    let (tris, _) = scene_triangles(mesh, &region_of(mesh, located));
    let all = views.rays(&cam);
    let (w, h) = (views.width, views.height);
    let mut times = Vec::new();
    let mut tests: Vec<(String, u64)> = Vec::new();
    for p in PACKETS {
        let tile = p.max(super::bins::MIN_TILE);
        let rays: Vec<Ray> = packet_order(w, h, p, tile)
            .iter()
            .map(|&i| all[i])
            .collect();
        let binned = super::bins::bins(&cam, w, h, tile, &tris).among(w, h);
        for m in methods {
            let scale = m.side_error.unwrap_or(SideError::OriginScaled);
            let among = binned.get(scale);
            let n = among.tests();
            if p == 2 {
                tests.push((m.name().to_string(), n));
            }
            let versions = std::iter::once((false, m.trace(Model::Plain)))
                .chain(m.wide.map(|wide| (true, wide.trace)));
            for (wide, trace) in versions {
                let mut best = f64::INFINITY;
                for _ in 0..repeats.max(1) {
                    let t0 = Instant::now();
                    std::hint::black_box(trace(
                        std::hint::black_box(&tris),
                        &among.ids,
                        &among.groups,
                        &rays,
                        (p * p) as usize,
                    ));
                    best = best.min(t0.elapsed().as_secs_f64());
                }
                times.push((m.name(), wide, p, best * 1e9 / n.max(1) as f64));
            }
        }
    }
    let base = |p: u32, wide: bool| {
        times
            .iter()
            .find(|(n, w, q, _)| *n == "mt-precomputed" && *q == p && *w == wide)
            .map(|t| t.3)
    };
    Ok(SpeedReport {
        scene: scene.to_string(),
        views: *views,
        triangles: tris.len(),
        rays: all.len(),
        tests,
        repeats,
        rows: times
            .iter()
            .map(|&(method, wide, packet, ns)| SpeedRow {
                method: method.to_string(),
                wide,
                packet,
                ns_per_test: ns,
                speedup: base(packet, wide).map_or(f64::NAN, |b| b / ns),
            })
            .collect(),
    })
}
