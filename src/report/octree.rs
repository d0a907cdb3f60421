//! Octree reports (seed 001): wrong exit faces and quarters per million cells and rays, per method
//! and row ([`stress`]), and wrong rays per image on a scene ([`count`]), every answer judged exactly.

use super::count::{
    CountError, Shard, Sharded, Sink, check_totals, check_wrong, inconsistent, located_views,
};
use super::triangle::{SceneTriangles, region_of, scene_triangles};
use super::wrong::{Seen, WrongRay};
use crate::backend::{Backend, BackendError, OctreeOn};
use crate::cases::{BoxCase, Subject};
use crate::choice::Choice;
use crate::exact::boxes::{BoxExit, box_exit};
use crate::found::{Answer, Failure, Record};
use crate::mesh::Mesh;
use crate::methods::Model;
use crate::octree::cell::quarter_signs;
use crate::octree::{Octree, Settings};
use crate::registry::OctreeMethod;
use crate::registry::{by_name, octree_by_name, triangle_by_name};
use crate::scenes::camera::Views;
use crate::scenes::cells::{Aim, Place, case};
use crate::walk::octree::{self as walk_octree, OctreeWalk};
use crate::walk::{OutcomeKind, Walk, default_max_steps, same_result};
use rayon::prelude::*;
use std::time::Instant;

/// Settings of an octree stress run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StressSettings {
    /// Cases per row.
    pub cases: usize,
    pub aims: Vec<Aim>,
    pub places: Vec<Place>,
    pub seed: u64,
    pub backend: String,
    pub ulps: i32,
}

/// One method's counts on one row.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct CellTally {
    pub method: String,
    /// Cases whose line crosses the open cell (the others are not judged).
    pub judged: u64,
    /// A face through which the line does not leave, or the wrong quarter of one it does.
    pub wrong: u64,
    /// Of those, the right face but a wrong quarter (a wrong neighbour among four).
    pub wrong_quarter: u64,
    /// No exit face (eq. 8's 7).
    pub no_exit_face: u64,
}

/// One row: an aim and a place.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CellRow {
    pub aim: Aim,
    pub place: Place,
    pub tallies: Vec<CellTally>,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct CellStressReport {
    pub settings: StressSettings,
    pub methods: Vec<String>,
    pub rows: Vec<CellRow>,
}

/// A row's cases with their exact answers; case `i` a pure function of the seed, the row's aim and
/// place, and `i` (whichever rows are run with it).
fn row_cases(s: &StressSettings, aim: Aim, place: Place) -> Vec<(BoxCase, BoxExit)> {
    let row = (aim as u64) << 8 | place as u64;
    (0..s.cases)
        .into_par_iter()
        .filter_map(|i| {
            let mut rng = crate::scenes::rng(
                s.seed
                    .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    .wrapping_add(row << 32 | i as u64),
            );
            let (lo, hi, ray) = case(aim, place, s.ulps, &mut rng);
            let c = BoxCase {
                lo,
                hi,
                org: ray.org,
                dir: ray.dir,
            };
            let x = box_exit(lo, hi, &ray).ok()?;
            Some((c, x))
        })
        .collect()
}

/// Every row of `s` (aims × places) with each method on `backend`; `wrong` sees each wrong answer as a
/// found case, with its row's name.
pub fn stress(
    s: &StressSettings,
    methods: &[&OctreeMethod],
    backend: &Backend,
    wrong: &mut dyn FnMut(&str, Record),
) -> Result<CellStressReport, BackendError> {
    let mut rows = Vec::new();
    for &aim in &s.aims {
        for &place in &s.places {
            let cases = row_cases(s, aim, place);
            let name = format!("{}-{}", aim.name(), place.name());
            let mut tallies = Vec::new();
            for m in methods {
                let mut t = CellTally {
                    method: m.name.into(),
                    ..CellTally::default()
                };
                let asked: Vec<BoxCase> = cases.iter().map(|(c, _)| *c).collect();
                let answers: Vec<_> = backend
                    .box_exits(m, &asked)?
                    .into_iter()
                    .map(|a| a.map(|(f, q)| (f, quarter_signs(q))))
                    .collect();
                let on = backend.for_method(*m);
                for ((c, x), a) in cases.iter().zip(answers) {
                    let Some(right) = x.right(a) else { continue };
                    t.judged += 1;
                    if right {
                        continue;
                    }
                    t.wrong += 1;
                    t.no_exit_face += a.is_none() as u64;
                    t.wrong_quarter += a.is_some_and(|(f, _)| x.faces.contains(&f)) as u64;
                    wrong(
                        &name,
                        Record {
                            subject: Subject::Box(*c),
                            failure: Some(Failure {
                                method: m.name.into(),
                                backend: on.kind(),
                                adapter: on.adapter(),
                                answer: Answer::Box(a.map(|(f, q)| (f as u8, q))),
                            }),
                        },
                    );
                }
                tallies.push(t);
            }
            rows.push(CellRow {
                aim,
                place,
                tallies,
            });
        }
    }
    Ok(CellStressReport {
        settings: s.clone(),
        methods: methods.iter().map(|m| m.name.to_string()).collect(),
        rows,
    })
}

impl CellStressReport {
    pub fn markdown(&self) -> String {
        let s = &self.settings;
        let mut out = format!(
            "{} cells and rays per row, seed {}, {}, near-* within {} ulps; cells: wrong (of which wrong quarter / no exit face) per million judged cases\n\n| row | judged |",
            s.cases, s.seed, s.backend, s.ulps
        );
        for m in &self.methods {
            out += &format!(" {m} |");
        }
        out += "\n|---|---|";
        out += &"---|".repeat(self.methods.len());
        out += "\n";
        let pm = |n: u64, of: u64| super::stress::Tally::per_million(n, of);
        for r in &self.rows {
            let judged = r.tallies.first().map_or(0, |t| t.judged);
            out += &format!("| {}-{} | {judged} |", r.aim.name(), r.place.name());
            for t in &r.tallies {
                out += &format!(
                    " {:.0} ({:.0} / {:.0}) |",
                    pm(t.wrong, t.judged),
                    pm(t.wrong_quarter, t.judged),
                    pm(t.no_exit_face, t.judged)
                );
            }
            out += "\n";
        }
        out
    }
}

/// Settings of an octree count.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CountSettings {
    pub scene: String,
    pub views: Views,
    /// The tetrahedral walk whose stopping face is the exact first hit (`certified` or `exact`).
    pub reference: String,
    pub octree: Settings,
    /// The ray–triangle method testing each leaf's triangles.
    pub triangle_method: String,
    /// Rays also walked by the exact octree walk, which must end where the reference ends.
    pub audit: u64,
    /// The views counted (`tetwalk paper --shard`).
    pub shard: Shard,
}

/// One method's count over the views.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct OctreeCount {
    pub method: String,
    pub wrong_total: u64,
    /// Wrong rays by the kind of their ending ([`OutcomeKind::ALL`] order): wrong triangle, false
    /// miss, no exit face, cycle, step limit.
    pub wrong: [u64; 5],
    pub wrong_per_image: f64,
    /// Cells visited, summed over rays (Φ).
    pub cells: u64,
    /// Seconds walking.
    pub seconds: f64,
    pub mrays_per_second: f64,
}

impl OctreeCount {
    /// The per-image and per-second figures of the totals over `views` and `rays`.
    fn finish(&mut self, views: usize, rays: u64) {
        self.wrong_per_image = self.wrong_total as f64 / views.max(1) as f64;
        self.mrays_per_second = rays as f64 / self.seconds.max(1e-12) / 1e6;
    }
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct OctreeCountReport {
    pub settings: CountSettings,
    /// The scene's triangles (its constrained faces facing the cameras).
    pub triangles: usize,
    pub leaves: usize,
    pub unconstrained_leaves: usize,
    pub rays: u64,
    pub views_counted: usize,
    /// Rays the exact octree walk re-walked, all ending where the reference ends.
    pub audited: u64,
    /// Where the octree methods walked (the references on the CPU).
    pub backend: String,
    pub methods: Vec<OctreeCount>,
}

/// Count, per octree method, the primary rays whose walk through the octree over the scene's
/// triangles ends wrongly, judged against the reference walk's exact first hit as `count` judges
/// walks ([`same_result`]); `tick` is called once per view, and `sink` sees every wrong ray written
/// out ([`WrongRay`]: the hit as the tetrahedron and face its triangle came from).
pub fn count(
    mesh: &Mesh,
    s: &CountSettings,
    methods: &[&OctreeMethod],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
    mut sink: Option<&mut Sink>,
) -> Result<OctreeCountReport, CountError> {
    let reference = by_name(&s.reference)?;
    let tri = triangle_by_name(&s.triangle_method)?;
    let hit = tri.hit(Model::Plain);
    let exact = octree_by_name("exact")?.walk(Model::Plain);
    let max = default_max_steps(mesh);
    let cpu = &crate::backend::CPU;
    let on = cpu.mesh(mesh);
    let mut totals: Vec<(OctreeCount, f64)> = methods
        .iter()
        .map(|m| {
            let c = OctreeCount {
                method: m.name.into(),
                ..OctreeCount::default()
            };
            (c, 0.0)
        })
        .collect();
    let total_rays = s.views.views as u64 * s.views.width as u64 * s.views.height as u64;
    let (mut rays_counted, mut views_counted, mut audited) = (0u64, 0usize, 0u64);
    // The cameras' region, its triangles, their octree, and the octree made ready on the backend.
    let mut scene: Option<(Vec<bool>, SceneTriangles, Octree, OctreeOn)> = None;
    for (v, cam, located) in located_views(mesh, &s.views, |v| s.shard.holds(v), tick) {
        views_counted += 1;
        if scene
            .as_ref()
            .is_none_or(|(region, ..)| !region[located as usize])
        {
            let region = region_of(mesh, located);
            let tris = scene_triangles(mesh, &region);
            let octree =
                Octree::build(&tris.0, s.octree).map_err(|e| CountError::Octree(e.to_string()))?;
            let ready = backend.octree(&octree, &tris.0);
            scene = Some((region, tris, octree, ready));
        }
        let (_, (tris, from), octree, ready) = scene.as_ref().expect("set above");
        let cap = walk_octree::default_max_steps(octree);
        let rays = s.views.rays(&cam);
        rays_counted += rays.len() as u64;
        let walks = cpu.walks(reference, &on, &rays, located, max)?;
        let first = v as u64 * rays.len() as u64;
        let picked: Vec<usize> = (0..rays.len())
            .filter(|&i| super::count::audited(s.views.seed, first + i as u64, s.audit, total_rays))
            .collect();
        for &i in &picked {
            let w = exact(octree, tris, hit, &rays[i], cap);
            let got = Walk {
                outcome: w.end.outcome(from),
                steps: w.cells,
            };
            if !same_result(mesh, &rays[i], &got, &walks[i]) {
                return Err(CountError::Audit {
                    reference: "the exact octree walk".into(),
                    view: v,
                    pixel: [i as u32 % s.views.width, i as u32 / s.views.width],
                    got,
                    want: walks[i],
                });
            }
        }
        audited += picked.len() as u64;
        for (m, (total, seconds)) in methods.iter().zip(&mut totals) {
            let t0 = Instant::now();
            let ends: Vec<OctreeWalk> =
                backend.octree_walks(m, tri, octree, tris, ready, &rays, cap)?;
            *seconds += t0.elapsed().as_secs_f64();
            for (i, ((ray, w), reference)) in rays.iter().zip(&ends).zip(&walks).enumerate() {
                total.cells += w.cells as u64;
                let mine = Walk {
                    outcome: w.end.outcome(from),
                    steps: w.cells,
                };
                if !same_result(mesh, ray, &mine, reference) {
                    total.wrong_total += 1;
                    total.wrong[w.end.kind().code() as usize] += 1;
                    if let Some(sink) = sink.as_mut() {
                        let seen = Seen {
                            scene: &s.scene,
                            view: v,
                            pixel: [i as u32 % s.views.width, i as u32 / s.views.width],
                            name: m.name,
                            walked: None,
                        };
                        let d = WrongRay::of(mesh, &seen, ray, &mine, reference, located, max);
                        sink(&d).map_err(CountError::Dump)?;
                    }
                }
            }
        }
    }
    if views_counted == 0 {
        return Err(CountError::NoView(s.views.views));
    }
    let (triangles, leaves, unconstrained_leaves) =
        scene.as_ref().map_or((0, 0, 0), |(_, (t, _), o, _)| {
            (t.len(), o.leaves.len(), o.unconstrained_leaves)
        });
    Ok(OctreeCountReport {
        settings: s.clone(),
        triangles,
        leaves,
        unconstrained_leaves,
        rays: rays_counted,
        views_counted,
        audited,
        backend: backend.describe(),
        methods: totals
            .into_iter()
            .map(|(mut c, seconds)| {
                c.seconds = seconds;
                c.finish(views_counted, rays_counted);
                c
            })
            .collect(),
    })
}

impl Sharded for OctreeCountReport {
    fn same(&self) -> serde_json::Value {
        let settings = CountSettings {
            shard: Shard::ALL,
            ..self.settings.clone()
        };
        serde_json::json!({
            "settings": settings, "backend": self.backend, "triangles": self.triangles,
            "leaves": self.leaves, "unconstrained_leaves": self.unconstrained_leaves,
        })
    }

    fn shard(&self) -> Shard {
        self.settings.shard
    }

    fn methods(&self) -> Vec<String> {
        self.methods.iter().map(|m| m.method.clone()).collect()
    }

    fn check(&self) -> Result<(), (String, String)> {
        let s = &self.settings;
        check_totals(
            s.shard,
            &s.views,
            self.views_counted,
            self.rays,
            self.audited,
        )?;
        for (i, m) in self.methods.iter().enumerate() {
            let at = format!("methods[{i}] ({})", m.method);
            check_wrong(&at, m.wrong_total, &m.wrong, self.rays, false)?;
            // As `finish` makes it from the total.
            let mut derived = m.clone();
            derived.finish(self.views_counted, self.rays);
            if m.wrong_per_image != derived.wrong_per_image {
                return inconsistent(
                    format!("{at}.wrong_per_image"),
                    format!(
                        "{}, not wrong_total {} over {} views",
                        m.wrong_per_image, m.wrong_total, self.views_counted
                    ),
                );
            }
        }
        Ok(())
    }

    fn add(&mut self, r: &Self) {
        self.rays += r.rays;
        self.views_counted += r.views_counted;
        self.audited += r.audited;
        for (t, m) in self.methods.iter_mut().zip(&r.methods) {
            t.wrong_total += m.wrong_total;
            (0..5).for_each(|k| t.wrong[k] += m.wrong[k]);
            t.cells += m.cells;
            t.seconds += m.seconds;
        }
    }

    fn finish(&mut self) {
        self.settings.shard = Shard::ALL;
        for t in &mut self.methods {
            t.finish(self.views_counted, self.rays);
        }
    }
}

impl OctreeCountReport {
    pub fn markdown(&self) -> String {
        let s = &self.settings;
        let mut out = format!(
            "scene {} ({} triangles: its constrained faces, each facing the cameras' side), octree of depth {} and leaf capacity {} ({} leaves; {} without the regularity constraint), {} views of {}x{}, seed {}, backend {}, each leaf's triangles tested with {}; each walk judged against the {} walk's exact first hit (the exact octree walk audited against it on {} rays, all agreeing)\n\n",
            s.scene,
            self.triangles,
            s.octree.depth,
            s.octree.capacity,
            self.leaves,
            self.unconstrained_leaves,
            self.views_counted,
            s.views.width,
            s.views.height,
            s.views.seed,
            self.backend,
            s.triangle_method,
            s.reference,
            self.audited
        );
        out += &format!(
            "| method | wrong rays per image | {} | cells per ray | Mrays/s |\n|---|---|---|---|---|---|---|---|---|\n",
            OutcomeKind::ALL.map(|k| k.wrong()).join(" | ")
        );
        for m in &self.methods {
            out += &format!(
                "| {} | {:.3} | {} | {:.2} | {:.3} |\n",
                m.method,
                m.wrong_per_image,
                m.wrong.map(|n| n.to_string()).join(" | "),
                m.cells as f64 / self.rays.max(1) as f64,
                m.mrays_per_second
            );
        }
        out += &super::count::totals(
            self.rays,
            self.methods
                .iter()
                .map(|m| (m.method.as_str(), m.wrong_total)),
        );
        out
    }
}
