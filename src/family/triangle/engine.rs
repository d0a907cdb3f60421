//! The triangle family's engine beyond its `Family` (a file of the engine's layer in the family's
//! folder): seed 004 Figure 5's measure, `bench --family triangle`; a leak map's grid of rays
//! through and beside an edge, each method's hits judged against every triangle (`render leak`).

use crate::backend::{Backend, BackendError};
use crate::cases::HitCase;
use crate::engine::count::located_views;
use crate::family::count::CountError;
use crate::mesh::surface::{region_of, scene_triangles};
use crate::methods::Model;
use crate::methods::triangle::SideError;
use crate::registry::{Named, TriangleMethod};
use crate::scenes::Loaded;
use crate::scenes::camera::{Views, packet_order};
use crate::scenes::closed::{self, MeshShape, TriPlace};
use crate::scenes::tets::ulps;
use crate::tet::Ray;
use rayon::prelude::*;
use std::time::Instant;

/// Seed 004 Figure 5's measure: each method's intersection time over a view's primary rays against
/// each tile's candidate triangles ([`super::bins`], as the triangle count tests them), one
/// thread, rays in packets of `p × p`; the 4-wide (SIMD) versions beside the scalar ones.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SpeedRow {
    pub(crate) method: String,
    /// Whether this is the method's 4-wide version (SSE; seed 004 timed SIMD code).
    #[serde(default)]
    pub(crate) wide: bool,
    /// Packet side `p` (packets of `p × p` rays).
    pub(crate) packet: u32,
    /// Nanoseconds per ray–triangle test, the best of the repeats.
    pub(crate) ns_per_test: f64,
    /// `mt-precomputed`'s time per test in packets of the same side, scalar or 4-wide as this row is,
    /// over this one's: seed 004's speedup, the loops alike (triangles outer, the packet's rays inner).
    pub(crate) speedup: f64,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SpeedReport {
    pub(crate) scene: String,
    pub(crate) views: Views,
    pub(crate) triangles: usize,
    pub(crate) rays: usize,
    /// Ray–triangle tests of each method in 2×2 packets (each ray against its tile's candidates for
    /// the method's error scale).
    #[serde(default)]
    pub(crate) tests: Vec<(String, u64)>,
    pub(crate) repeats: usize,
    pub(crate) rows: Vec<SpeedRow>,
}

/// The packet sides timed.
pub(crate) const PACKETS: [u32; 4] = [1, 2, 4, 8];

/// The triangle a case's ray first crosses, alone with the ray (`gen-cases --single`); `None` where
/// the ray crosses none.
pub(crate) fn first_crossed(c: &HitCase, x: &crate::exact::hit::HitTruth) -> Option<HitCase> {
    let first = x.first_crossing()?.holding[0] as usize;
    Some(HitCase::single(c.tris()[first], c.ray()))
}

/// Time every method (and its 4-wide version) at every packet side of [`PACKETS`] on the primary rays
/// of `views`' first view that lies inside the mesh, each ray against its tile's candidates for the
/// method's error scale, the best of `repeats` runs each, all in one run; speedups per test relative
/// to `mt-precomputed` at the same packet side and width.
pub(crate) fn speed(
    scene: &Loaded,
    views: &Views,
    methods: &[&TriangleMethod],
    repeats: usize,
) -> Result<SpeedReport, CountError> {
    let mesh = &scene.mesh;
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
        scene: scene.name.clone(),
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

/// Which of the two triangles sharing an edge report a hit: a leak map's cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeHit {
    First,
    Second,
    /// Both: a double hit (right where the ray meets the edge itself).
    Both,
    /// A leak, judged against every triangle of the mesh: the ray crosses the surface and no triangle
    /// around the crossing reports it.
    Neither,
    /// Neither, as the exact ray: it passes beside both.
    Beside,
    /// Neither of the two, but another triangle around the crossing (the ray passes beside the pair
    /// onto a neighbour): not a leak.
    Other,
}

impl EdgeHit {
    fn of(first: bool, second: bool) -> EdgeHit {
        match (first, second) {
            (true, true) => EdgeHit::Both,
            (true, false) => EdgeHit::First,
            (false, true) => EdgeHit::Second,
            (false, false) => EdgeHit::Neither,
        }
    }

    pub(crate) const ALL: [EdgeHit; 6] = [
        EdgeHit::First,
        EdgeHit::Second,
        EdgeHit::Both,
        EdgeHit::Neither,
        EdgeHit::Beside,
        EdgeHit::Other,
    ];

    /// Its letter in the golden text and its colour in the PNG.
    pub fn letter(self) -> char {
        ['a', 'b', '2', '0', '.', 'o'][self as usize]
    }

    pub fn colour(self) -> [u8; 3] {
        [
            [40, 110, 255],
            [40, 200, 80],
            [250, 210, 0],
            [230, 30, 30],
            [0, 0, 0],
            [150, 90, 200],
        ][self as usize]
    }

    /// What it means, for the legend.
    pub(crate) fn words(self) -> &'static str {
        [
            "the first triangle only",
            "the second only",
            "both (a double hit)",
            "a leak (no triangle of the mesh catches the ray)",
            "neither, as the exact ray",
            "a neighbouring triangle (not a leak)",
        ][self as usize]
    }

    /// The leak maps' key: each kind of cell, its words and colour.
    pub(crate) fn key() -> Vec<(&'static str, [u8; 3])> {
        EdgeHit::ALL
            .iter()
            .map(|c| (c.words(), c.colour()))
            .collect()
    }
}

/// A leak map's grid of `size × size` rays around the triangle case's, which passes exactly through
/// the edge the triangles `pair` share: across (x) the origin moved parallel to the edge by a power-of-
/// two fraction of it, so that the middle row's rays cross the edge line at points of its middle half
/// (exactly, where the moved origins are f32 values: the far places), as the stress rows' exact-edge
/// rays do; down (y) the direction moved by ulp steps in its component, other than the largest, across
/// which the edge runs least, so that the other rows pass beside the edge by a few ulps. Each cell
/// says which of the two triangles report a hit, or a leak. The exact cells are judged once, when the
/// grid is made; every method's are set beside them.
pub struct LeakGrid {
    cases: Vec<HitCase>,
    pair: [u32; 2],
    exact: Vec<EdgeHit>,
    /// Each cell's exact first crossings, against which a leak is judged.
    truths: Vec<Option<crate::exact::hit::HitTruth>>,
}

impl LeakGrid {
    pub fn new(case: &HitCase, pair: [u32; 2], size: u32) -> LeakGrid {
        let half = (size / 2) as i32;
        // Along x, the origin moves parallel to the edge, so that the middle row's rays pass exactly
        // through the edge line (where the moved origins are f32 values exactly: the far places);
        // the stress rows' exact-edge rays, at points from one end of the edge's middle half to the
        // other.
        let [t, u] = pair.map(|i| case.tris()[i as usize]);
        let shared: Vec<glam::Vec3> = t.iter().copied().filter(|p| u.contains(p)).collect();
        let edge = match shared[..] {
            [a, b] => b - a,
            _ => glam::Vec3::ZERO,
        };
        // Points from a quarter of the edge before its midpoint to a quarter after, at steps of
        // edge · 2^-m: the finest that keeps every moved origin an f32 value exactly (so every ray of
        // the middle row passes exactly through the edge line), at most one point a column.
        let exact = |m: i32| {
            let step = edge * 2f32.powi(-m);
            (-(1i32 << (m - 2))..=1 << (m - 2)).all(|j| {
                let o = case.org + step * j as f32;
                (0..3).all(|a| {
                    o[a] as f64 == case.org[a] as f64 + step[a] as f64 * j as f64
                        && step[a] as f64 == edge[a] as f64 * 2f64.powi(-m)
                })
            })
        };
        let finest = (4 * half.max(1) as u32)
            .next_power_of_two()
            .trailing_zeros() as i32;
        let m = (2..=finest).rev().find(|&m| exact(m)).unwrap_or(2);
        let (step, points) = (edge * 2f32.powi(-m), 1i32 << (m - 2));
        let along = |x: i32| step * ((x - half) as i64 * points as i64 / half.max(1) as i64) as f32;
        // Along y, the direction moves by ulp steps in the component (not the largest) across which
        // the edge runs least.
        let k = case.dir.abs().max_position();
        let (a1, a2) = ((k + 1) % 3, (k + 2) % 3);
        let ay = if edge[a1].abs() <= edge[a2].abs() {
            a1
        } else {
            a2
        };
        let step = ulps(case.dir[ay].abs(), 1) - case.dir[ay].abs();
        let cases: Vec<HitCase> = (0..size)
            .flat_map(|y| (0..size).map(move |x| (x, y)))
            .map(|(x, y)| {
                let mut c = *case;
                c.org += along(x as i32);
                c.dir[ay] += (half - y as i32) as f32 * step;
                c
            })
            .collect();
        let truths = cases
            .par_iter()
            .map(|c| crate::exact::hit::judge_hit(c.tris(), c.closed, &c.ray()).ok())
            .collect();
        let exact = cases
            .par_iter()
            .map(|c| {
                let ray = c.ray();
                let hit = |i: u32| {
                    crate::exact::hit::ray_triangle(c.tris()[i as usize], &ray).is_ok_and(|h| h.hit)
                };
                match EdgeHit::of(hit(pair[0]), hit(pair[1])) {
                    EdgeHit::Neither => EdgeHit::Beside,
                    e => e,
                }
            })
            .collect();
        LeakGrid {
            cases,
            pair,
            exact,
            truths,
        }
    }

    /// The exact cells (both on the edge itself).
    pub fn exact(&self) -> &[EdgeHit] {
        &self.exact
    }

    /// `method`'s cells on `backend`: a leak where, judged against every triangle of the mesh, the
    /// ray crosses the surface and no triangle around the crossing reports it; else which of the two
    /// it hits, or another around the crossing.
    pub fn of(
        &self,
        method: &TriangleMethod,
        backend: &Backend,
    ) -> Result<Vec<EdgeHit>, BackendError> {
        let [p, q] = self.pair;
        Ok(backend
            .triangle_hits(method, &self.cases)?
            .iter()
            .zip(self.exact.iter().zip(&self.truths))
            .map(|(h, (e, truth))| {
                let ids: Vec<u32> = h.iter().map(|&(k, _)| k).collect();
                if truth.as_ref().is_some_and(|t| t.leaks(&ids)) {
                    return EdgeHit::Neither;
                }
                match (EdgeHit::of(ids.contains(&p), ids.contains(&q)), e) {
                    (EdgeHit::Neither, EdgeHit::Beside) => EdgeHit::Beside,
                    (EdgeHit::Neither, _) => EdgeHit::Other,
                    (c, _) => c,
                }
            })
            .collect())
    }
}

/// A leak map's case: a case of the triangle stress rows' `edge` row of `shape` at `place` (the same
/// generator: a closed mesh, a ray from a lattice point outside it exactly through the midpoint of an
/// edge) whose ray crosses the surface there, between the edge's two triangles (the pair): the first
/// under `seed` that one of `leaking` leaks through on the CPU (plain f32), else the first; `None` if
/// 1,000 draws found none.
pub fn leak_case(
    shape: MeshShape,
    place: TriPlace,
    seed: u64,
    leaking: &[&TriangleMethod],
) -> Option<(HitCase, [u32; 2])> {
    let candidates = (0..1000u64).filter_map(|i| {
        let mut rng = crate::scenes::rng(seed.wrapping_mul(1000).wrapping_add(i));
        let (mesh, ray) = closed::case(shape, closed::TriAim::Edge, place, 1e-3, 4, &mut rng);
        let case = HitCase::closed(&mesh, ray).ok()?;
        let truth = crate::exact::hit::judge_hit(case.tris(), case.closed, &case.ray()).ok()?;
        let first = truth.first()?;
        let [p, q] = first.holding[..] else {
            return None;
        };
        first.crosses.then_some((case, [p, q], truth))
    });
    let mut fallback = None;
    for (case, pair, truth) in candidates {
        let leaks = leaking.iter().any(|m| {
            Backend::Cpu {
                model: Model::Plain,
            }
            .triangle_hits(m, std::slice::from_ref(&case))
            .is_ok_and(|h| truth.leaks(&h[0].iter().map(|&(k, _)| k).collect::<Vec<_>>()))
        });
        if leaks || leaking.is_empty() {
            return Some((case, pair));
        }
        fallback.get_or_insert((case, pair));
    }
    fallback
}
