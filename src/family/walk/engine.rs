//! The walk family's runs beyond its `Family` (the engine layer in its folder): `tetwalk walk`'s
//! rays through a generated mesh, each method's walk judged step by step against the `exact` walk
//! (also under the 12 orientation-preserving relabellings), a scene's view walked pixel by pixel
//! for `render`, and a scene's rays written for walks made elsewhere (`count --rays-out`), checked
//! when read back, and the walks given for them judged as `count` judges a method's (`judge`).

use super::Walks;
use crate::backend::{Backend, BackendError};
use crate::cases::number;
use crate::engine::answering::reader;
use crate::engine::count::{self, CountReport, CountSettings, ReferenceWalk, Shard, located_views};
use crate::engine::view::{Frame, ViewError, located_view};
use crate::exact::Classification;
use crate::family::Summed;
use crate::family::contract::{self, Contract, Origin};
use crate::family::count::CountError;
use crate::family::{ExitFace, Family, Verdict};
use crate::mesh::layout::Layout;
use crate::mesh::{HULL, Mesh, MeshError};
use crate::methods::Model;
use crate::registry::{Method, Named, reference};
use crate::scenes::Loaded;
use crate::scenes::camera::{Camera, Views};
use crate::tet::Case;
use crate::tet::{EVEN_PERMUTATIONS, Ray};
use crate::walk::layouts::{LayoutKind, Source};
use crate::walk::{
    Asked, GivenWalk, Judged, Outcome, OutcomeKind, Step, Stepped, Walk, default_max_steps, judge,
    locate, same_result, walks_asking,
};
use rayon::prelude::*;
use serde_json::{Value, json};
use std::collections::HashMap;
use std::io::{BufRead, Write};

/// Why a walk run stopped.
#[derive(Debug, thiserror::Error)]
pub(crate) enum WalkRunError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// How the walks are judged: every step on the CPU under an arithmetic model, or (a `--wgsl`
/// function's walks) by their endings, walked on the GPU.
#[derive(Clone, Copy)]
pub(crate) enum Walker<'a> {
    /// Every step judged by the oracle, so that "diverged" is measured.
    Checked(Model),
    /// Walked on this GPU backend, judged by their endings ("diverged" unmeasured).
    Gpu(&'a Backend),
}

/// Bytes `tetwalk walk` holds per ray with `methods` methods: the ray and the exact walk (about 56
/// measured), and per method its walk's tally kept until the table is made (about 72 measured,
/// `tests/bad_input.rs`), with room to spare.
pub fn bytes_per_walked_ray(methods: usize) -> u64 {
    64 + 96 * methods as u64
}

/// One method's walks: how they ended ([`OutcomeKind::ALL`] order), how many ended elsewhere than the
/// `exact` walk, how many took a step outside the exact exit set, and the steps.
#[derive(Default, Clone, Copy, Debug, serde::Serialize)]
pub(crate) struct MethodWalks {
    pub(crate) rays: u64,
    pub(crate) kinds: [u64; 5],
    pub(crate) wrong: u64,
    pub(crate) diverged: u64,
    pub(crate) steps: u64,
}

impl Summed for MethodWalks {
    fn add(&mut self, t: &MethodWalks) {
        self.rays += t.rays;
        self.wrong += t.wrong;
        self.diverged += t.diverged;
        self.steps += t.steps;
        (0..5).for_each(|k| self.kinds[k] += t.kinds[k]);
    }
}

/// One method's row: its walks, and the compact layout it walked over (if it did).
#[derive(serde::Serialize)]
pub(crate) struct MethodRow {
    pub(crate) method: String,
    pub(crate) layout: Option<LayoutKind>,
    #[serde(flatten)]
    pub(crate) tally: MethodWalks,
}

/// One method under the 12 relabellings: wrong results and cycles for each, the identity first.
#[derive(serde::Serialize)]
pub(crate) struct RelabelledWalks {
    pub(crate) method: String,
    pub(crate) wrong: Vec<u64>,
    pub(crate) cycles: Vec<u64>,
}

/// Every method's walks over one mesh's rays: the rays starting outside it (skipped), and one row per
/// method, in the order asked.
pub(crate) struct MethodWalksTable {
    pub(crate) outside: usize,
    pub(crate) rows: Vec<MethodRow>,
}

/// `tetwalk walk`'s report (its JSON): the mesh, the rays, and each method's row.
#[derive(serde::Serialize)]
pub(crate) struct WalkReport {
    pub(crate) mesh: crate::scenes::Generated,
    pub(crate) size: u32,
    pub(crate) offset: f32,
    pub(crate) tetrahedra: usize,
    pub(crate) rays: usize,
    pub(crate) outside: usize,
    pub(crate) seed: u64,
    pub(crate) backend: crate::backend::BackendKind,
    pub(crate) methods: Vec<MethodRow>,
    /// With `--relabel all`.
    pub(crate) relabellings: Option<Vec<RelabelledWalks>>,
}

/// What `tetwalk walk` walks: a generated mesh of `size` (in Hilbert order with `hilbert`) moved by
/// `offset`, and `rays` of its rays, both from `seed`; the methods over `layout` where they can, and
/// under every relabelling with `relabel`.
pub(crate) struct WalkSettings {
    pub(crate) mesh: crate::scenes::Generated,
    pub(crate) size: u32,
    pub(crate) offset: f32,
    pub(crate) rays: usize,
    pub(crate) seed: u64,
    pub(crate) layout: Option<LayoutKind>,
    pub(crate) hilbert: bool,
    pub(crate) relabel: bool,
}

/// A count's walks given by an answerer (`count --answerer`), every step of a view's unfinished
/// walks asked of it as one batch of exit-face cases: as the walk stands (the camera's ray, the face
/// it entered through) under the default contract; else each step's case made under `contract`
/// from the line the previous step's case followed ([`step_within`]) and judged when asked.
pub(crate) fn asked_walks<'a>(
    x: &'a crate::engine::answerer::Answerer,
    mesh: &'a Mesh,
    contract: Contract,
) -> impl Fn(usize, &[Ray], u32, u32) -> Result<Vec<GivenWalk>, CountError> + Sync + 'a {
    move |v, rays, start, max| {
        walks_asking(mesh, rays, start, max, |steps| {
            if contract.is_default() {
                let cases: Vec<Case> = steps.iter().map(|s| s.case).collect();
                let faces = x.answers::<ExitFace>(&cases)?;
                return Ok(steps
                    .iter()
                    .zip(faces)
                    .map(|(s, face)| Asked::Face {
                        face,
                        line: s.case.ray(),
                        judged: None,
                    })
                    .collect());
            }
            let made: Vec<Option<(Case, Classification)>> = steps
                .par_iter()
                .map(|s| step_within(&contract, v, s))
                .collect();
            let sent: Vec<Case> = made.iter().flatten().map(|(c, _)| *c).collect();
            let mut faces = x.answers::<ExitFace>(&sent)?.into_iter();
            Ok(made
                .into_iter()
                .zip(steps)
                .map(|(made, s)| {
                    let Some((c, truth)) = made else {
                        return Asked::Unmade;
                    };
                    let face = faces.next().expect("an answer for each case sent");
                    let judged = match ExitFace::verdict(&c, &truth, &face) {
                        Verdict::Wrong(kind) => Judged::Wrong {
                            kind,
                            exact: truth.exit.iter().map(|f| f as u8).collect(),
                        },
                        _ => Judged::Right,
                    };
                    // Mirrored (`--orientation negative`): vertices 0 and 1 swapped, faces too.
                    let mirrored = c.tet != s.case.tet;
                    Asked::Face {
                        face: face.map(|f| {
                            if mirrored {
                                [1, 0, 2, 3][f as usize]
                            } else {
                                f
                            }
                        }),
                        line: c.ray(),
                        judged: Some((c, judged)),
                    }
                })
                .collect())
        })
        .map_err(|e: crate::engine::answerer::AnswererError| CountError::Given(e.to_string()))
    }
}

/// Step `s` of a walk in view `v` made under `contract` ([`contract::within`]), with its truth:
/// the origin placed as a walk meets it — strictly inside where `inside` is allowed at the first step
/// (the camera's tetrahedron), on the entry face where `entry` is allowed after a crossing, else the
/// placements in turn — on the line the walk follows; `None` where the contract leaves the step no
/// case.
fn step_within(contract: &Contract, v: usize, s: &Step) -> Option<(Case, Classification)> {
    let allowed = contract.origin;
    let key = count::mixed(((v as u64) << 32) ^ s.ray as u64, s.step as u64);
    let placement = match s.step {
        0 if allowed.allows(Origin::Inside) && !allowed.is_anywhere() => Origin::Inside,
        1.. if allowed.allows(Origin::Entry) && !allowed.is_anywhere() => Origin::Entry,
        _ => allowed.for_key(key >> 2),
    };
    let narrowed = Contract {
        origin: placement.into(),
        ..*contract
    };
    contract::within::<ExitFace>(&narrowed, &s.case, key)
}

/// `tetwalk walk`: the mesh and its rays made as `s` says, each method's walks judged by `walker`
/// against the `exact` ones, and with `s.relabel` under each relabelling (every step judged under
/// `walker`'s model).
pub(crate) fn walk_run(
    s: &WalkSettings,
    methods: &[&'static Method],
    walker: Walker,
    backend: crate::backend::BackendKind,
) -> Result<WalkReport, WalkRunError> {
    let offset = glam::Vec3::splat(s.offset);
    let mesh = crate::scenes::generated_mesh(s.mesh, s.size, offset, s.seed)?;
    let mesh = if s.hilbert {
        crate::mesh::reorder::hilbert_sorted(&mesh)
    } else {
        mesh
    };
    let layout = s.layout.map(|_| Layout::build(&mesh));
    let rays = crate::scenes::rays(s.mesh, &mesh, offset, s.rays, s.seed);
    let table = walk_table(&mesh, &rays, methods, walker, s.layout.zip(layout.as_ref()))?;
    let relabellings = match (s.relabel, walker) {
        (true, Walker::Checked(model)) => Some(relabellings(&mesh, &rays, methods, model)?),
        _ => None,
    };
    Ok(WalkReport {
        mesh: s.mesh,
        size: s.size,
        offset: s.offset,
        tetrahedra: mesh.tets.len(),
        rays: rays.len() - table.outside,
        outside: table.outside,
        seed: s.seed,
        backend,
        methods: table.rows,
        relabellings,
    })
}

/// Walk `rays` through `mesh` with each method (over `layout` where the method can), each walk
/// judged against the `exact` one.
fn walk_table(
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
    walker: Walker,
    layout: Option<(LayoutKind, &Layout)>,
) -> Result<MethodWalksTable, WalkRunError> {
    let (per_ray, model) = match walker {
        Walker::Checked(model) => (per_ray(mesh, rays, methods, model, layout, true), model),
        Walker::Gpu(backend) => (gpu_per_ray(backend, mesh, rays, methods)?, Model::Plain),
    };
    let rows = methods
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let mut tally = MethodWalks::default();
            per_ray.iter().flatten().for_each(|t| tally.add(&t[i]));
            MethodRow {
                method: m.name().into(),
                layout: layout
                    .map(|(kind, _)| kind)
                    .filter(|_| m.layout_walk(model).is_some()),
                tally,
            }
        })
        .collect();
    Ok(MethodWalksTable {
        outside: per_ray.iter().filter(|r| r.is_none()).count(),
        rows,
    })
}

/// Per ray (none when its origin is outside the mesh), each method's tally: checked walks (every step
/// judged, so that "diverged" is measured) or plain ones.
fn per_ray(
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
    model: Model,
    layout: Option<(LayoutKind, &Layout)>,
    checked: bool,
) -> Vec<Option<Vec<MethodWalks>>> {
    let max = default_max_steps(mesh);
    let exact = reference();
    rays.par_iter()
        .map(|ray| {
            let start = locate(mesh, ray.org, 0).ok()?;
            let reference = exact.walk(Model::Plain)(mesh, ray, start, max);
            let tallies = methods
                .iter()
                .map(|m| {
                    let (w, div) = match layout.zip(m.layout_walk(model)) {
                        Some(((kind, layout), walk)) => {
                            let (end, steps) = walk(
                                kind,
                                layout,
                                &mesh.points,
                                ray,
                                &Source::new(layout, start),
                                max,
                            );
                            (
                                Walk {
                                    outcome: end.to_outcome(mesh),
                                    steps,
                                },
                                None,
                            )
                        }
                        None if checked => m.walk_checked(model)(mesh, ray, start, max),
                        None => (m.walk(model)(mesh, ray, start, max), None),
                    };
                    tally(mesh, ray, &w, &reference, div.is_some())
                })
                .collect();
            Some(tallies)
        })
        .collect()
}

/// One ray's tally: how walk `w` ended, whether wrongly (against the `exact` walk), whether it
/// diverged.
fn tally(mesh: &Mesh, ray: &Ray, w: &Walk, exact: &Walk, diverged: bool) -> MethodWalks {
    let mut t = MethodWalks {
        rays: 1,
        steps: w.steps as u64,
        wrong: !same_result(mesh, ray, w, exact) as u64,
        diverged: diverged as u64,
        ..MethodWalks::default()
    };
    t.kinds[w.outcome.kind().code() as usize] = 1;
    t
}

/// Per ray (none when its origin is outside the mesh), each method's tally from walks on the GPU
/// (`--wgsl`), judged by their endings against the `exact` walk on the CPU ("diverged" unmeasured).
fn gpu_per_ray(
    backend: &Backend,
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
) -> Result<Vec<Option<Vec<MethodWalks>>>, BackendError> {
    let max = default_max_steps(mesh);
    let starts: Vec<Option<u32>> = rays
        .par_iter()
        .map(|r| locate(mesh, r.org, 0).ok())
        .collect();
    let asked: Vec<(Ray, u32)> = rays
        .iter()
        .zip(&starts)
        .filter_map(|(r, s)| Some((*r, (*s)?)))
        .collect();
    let on = backend.mesh(mesh);
    let mut walks = Vec::new();
    for m in std::iter::once(&reference()).chain(methods) {
        walks.push(backend.walks_from(m, &on, &asked, max)?.walks);
    }
    let mut k = 0;
    Ok(starts
        .iter()
        .map(|s| {
            s.map(|_| {
                let (ray, _) = asked[k];
                let exact = &walks[0][k];
                let t = walks[1..]
                    .iter()
                    .map(|w| tally(mesh, &ray, &w[k], exact, false))
                    .collect();
                k += 1;
                t
            })
        })
        .collect())
}

/// Every method's wrong results and cycles under each of the 12 orientation-preserving relabellings
/// ([`EVEN_PERMUTATIONS`], the identity first).
fn relabellings(
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
    model: Model,
) -> Result<Vec<RelabelledWalks>, MeshError> {
    // Per method its wrong results, then its cycles.
    let measure = |k: usize| -> Result<Vec<u64>, MeshError> {
        let relabelled = mesh.relabelled(EVEN_PERMUTATIONS[k])?;
        let mut n = vec![0; 2 * methods.len()];
        for t in per_ray(&relabelled, rays, methods, model, None, false)
            .iter()
            .flatten()
        {
            for (i, t) in t.iter().enumerate() {
                n[2 * i] += t.wrong;
                n[2 * i + 1] += t.kinds[OutcomeKind::Cycle.code() as usize];
            }
        }
        Ok(n)
    };
    let all = crate::engine::under_labellings(measure(0)?, EVEN_PERMUTATIONS.len(), measure)?;
    Ok(methods
        .iter()
        .zip(all.chunks(2))
        .map(|(m, n)| RelabelledWalks {
            method: m.name().into(),
            wrong: n[0].clone(),
            cycles: n[1].clone(),
        })
        .collect())
}

/// View `index` of `views` (placed as `tetwalk count` places them) walked by the exact walk and by
/// `methods` on `backend`, each method's walks judged against the exact ones, and the exact hits
/// shaded: what `render shaded`, `failures` and `heat` draw.
pub fn frame(
    mesh: &Mesh,
    views: &Views,
    index: usize,
    methods: &[&Method],
    backend: &Backend,
) -> Result<Frame, ViewError> {
    let (cam, start) = located_view(mesh, views, index)?;
    let max = default_max_steps(mesh);
    let rays = views.rays(&cam);
    let on = backend.mesh(mesh);
    let exact = backend.walks(reference(), &on, &rays, start, max)?;
    let mut wrong = Vec::new();
    for m in methods {
        let walks = backend.walks(m, &on, &rays, start, max)?;
        let w: Vec<Option<OutcomeKind>> = rays
            .par_iter()
            .zip(&walks)
            .zip(&exact)
            .map(|((r, w), re)| judge(mesh, r, w, re))
            .collect();
        wrong.push((m.name().to_string(), w));
    }
    let shade = rays
        .iter()
        .zip(&exact)
        .map(|(r, w)| match w.outcome {
            Outcome::Hit { tet, face } => {
                let [a, b, c] = mesh
                    .face(tet, face as usize)
                    .map(|i| mesh.points[i as usize]);
                let n = (b - a).cross(c - a).normalize_or_zero();
                let s = (n.dot(r.dir.normalize()).abs() * 205.0 + 50.0) as u8;
                (s, mesh.neighbors[tet as usize][face as usize] == HULL)
            }
            _ => (0, false),
        })
        .collect();
    Ok(Frame {
        width: views.width,
        height: views.height,
        exact,
        wrong,
        shade,
    })
}

/// The header line of `count --rays-out`, which `tetwalk judge` reads back.
#[derive(serde::Serialize, serde::Deserialize)]
pub(crate) struct RaysHeader {
    /// The scene's name.
    pub(crate) scene: String,
    /// Its views, as the count made them.
    pub(crate) views: Views,
    /// The slice of the views written.
    pub(crate) shard: Shard,
    /// The scene's tetrahedra where the rays were written.
    pub(crate) tetrahedra: usize,
    /// Loaded with `--no-faces`.
    #[serde(default)]
    pub(crate) no_faces: bool,
}

/// Why a scene's rays, or the walks given for them, cannot be judged.
#[derive(Debug, thiserror::Error)]
pub(crate) enum RaysError {
    /// The scene loaded here is not the one the rays were made in.
    #[error(
        "{file}: scene {scene} has {here} tetrahedra here, {there} where the rays were written"
    )]
    Tetrahedra {
        file: String,
        scene: String,
        here: usize,
        there: usize,
    },
    /// The rays file ends before its header's last ray.
    #[error(
        "{file}: ends after line {last}, {rays} rays, before view {view} pixel {pixel}: cut short? (its header names more)"
    )]
    CutShort {
        file: String,
        last: usize,
        rays: u64,
        view: usize,
        pixel: Value,
    },
    /// A line of a file, and what is wrong with it.
    #[error("{file}:{line}: {why}")]
    Line {
        file: String,
        line: usize,
        why: String,
    },
    /// Fewer or more walks given than rays counted.
    #[error("{file}: {given} answers for the {rays} rays of {cases}")]
    Answers {
        file: String,
        given: usize,
        rays: u64,
        cases: String,
    },
    #[error(transparent)]
    Count(#[from] CountError),
    /// The rays file could not be written.
    #[error(transparent)]
    Write(#[from] std::io::Error),
}

/// The lines of `count --rays-out` for view `v` (camera `cam`, starting tetrahedron `start`): each
/// ray's view, pixel, origin, direction and start.
pub(crate) fn ray_lines(
    views: &Views,
    v: usize,
    cam: &Camera,
    start: u32,
) -> impl Iterator<Item = Value> {
    let width = views.width;
    views.rays(cam).into_iter().enumerate().map(move |(i, r)| {
        json!({
            "view": v, "pixel": [i as u32 % width, i as u32 / width],
            "org": r.org.to_array(), "dir": r.dir.to_array(), "start": start,
        })
    })
}

impl RaysHeader {
    /// The header of `scene`'s rays over `views`, those `shard` holds (`no_faces`: the scene loaded
    /// without constrained faces).
    pub(crate) fn of(scene: &Loaded, views: Views, shard: Shard, no_faces: bool) -> RaysHeader {
        RaysHeader {
            scene: scene.name.clone(),
            views,
            shard,
            tetrahedra: scene.mesh.tets.len(),
            no_faces,
        }
    }

    /// `count --rays-out`'s file written to `w`: this header's line, then every ray line
    /// ([`RaysHeader::each_line`]); the rays and the views written. A shard none of whose views has
    /// its camera inside `mesh` is [`CountError::NoView`].
    pub(crate) fn write(&self, mesh: &Mesh, w: impl Write) -> Result<(u64, usize), RaysError> {
        let mut w = std::io::BufWriter::new(w);
        serde_json::to_writer(&mut w, self).map_err(std::io::Error::from)?;
        w.write_all(b"\n")?;
        let mut rays = 0u64;
        let views = self.each_line(mesh, |_, line| -> std::io::Result<()> {
            rays += 1;
            serde_json::to_writer(&mut w, &line)?;
            w.write_all(b"\n")
        })?;
        if views == 0 {
            return Err(CountError::NoView(self.views.views).into());
        }
        w.flush()?;
        Ok((rays, views))
    }

    /// Each ray line of the views the header's shard holds whose camera is inside `mesh`, in order,
    /// handed to `each` with its view; the views walked.
    pub(crate) fn each_line<E>(
        &self,
        mesh: &Mesh,
        mut each: impl FnMut(usize, Value) -> Result<(), E>,
    ) -> Result<usize, E> {
        let mut views = 0;
        for (v, cam, start) in located_views(mesh, &self.views, |v| self.shard.holds(v), &|| ()) {
            views += 1;
            for line in ray_lines(&self.views, v, &cam, start) {
                each(v, line)?;
            }
        }
        Ok(views)
    }

    /// Whether `scene` is the scene the rays were made in (as many tetrahedra); `file` names the
    /// rays.
    pub(crate) fn check_scene(&self, scene: &Loaded, file: &str) -> Result<(), RaysError> {
        match scene.mesh.tets.len() == self.tetrahedra {
            true => Ok(()),
            false => Err(RaysError::Tetrahedra {
                file: file.into(),
                scene: scene.name.clone(),
                here: scene.mesh.tets.len(),
                there: self.tetrahedra,
            }),
        }
    }

    /// The body of a `count --rays-out` file (`input`, its header line first) checked against the
    /// rays the header names, line by line (a file cut short, edited, or of another run is refused,
    /// the line named): the answers are judged for the rays the header rebuilds, so those must be the
    /// rays that were walked.
    pub(crate) fn check_rays(
        &self,
        file: &str,
        input: Box<dyn BufRead + Send>,
        mesh: &Mesh,
    ) -> Result<(), RaysError> {
        let at = |line: usize, why: String| RaysError::Line {
            file: file.into(),
            line,
            why,
        };
        let mut lines = reader(input).into_iter().skip(1);
        let (mut rays, mut last) = (0u64, 1);
        self.each_line(mesh, |v, want| {
            let Some((n, line)) = lines.next() else {
                return Err(RaysError::CutShort {
                    file: file.into(),
                    last,
                    rays,
                    view: v,
                    pixel: want["pixel"].clone(),
                });
            };
            let line = line.map_err(|e| at(n, e))?;
            let got: Value = serde_json::from_str(&line)
                .map_err(|e| at(n, format!("not a whole ray line ({e}): cut short?")))?;
            if !same_ray(&got, &want) {
                return Err(at(
                    n,
                    format!(
                        "not the ray its header names here, {want} (the body is not this header's run)"
                    ),
                ));
            }
            (rays, last) = (rays + 1, n);
            Ok(())
        })?;
        match lines.find(|(_, l)| l.as_ref().map_or(true, |l| !l.trim().is_empty())) {
            Some((n, _)) => Err(at(
                n,
                format!("a line after the {rays} rays its header names"),
            )),
            None => Ok(()),
        }
    }
}

/// Whether a rays line holds the ray `want`: the same keys, integers equal, coordinates the same f32.
fn same_ray(got: &Value, want: &Value) -> bool {
    let (Some(g), Some(w)) = (got.as_object(), want.as_object()) else {
        return false;
    };
    let f32s = |v: &Value| -> Option<Vec<u32>> {
        v.as_array()?
            .iter()
            .map(|x| number(x).ok().map(f32::to_bits))
            .collect()
    };
    g.len() == w.len()
        && w.iter().all(|(k, wv)| match (k.as_str(), g.get(k)) {
            (_, None) => false,
            ("org" | "dir", Some(gv)) => f32s(gv).is_some_and(|g| Some(g) == f32s(wv)),
            (_, Some(gv)) => gv == wv,
        })
}

/// Walks given for a scene's rays, by (view, pixel x, pixel y).
#[derive(Default)]
pub(crate) struct GivenWalksMap(HashMap<(usize, u32, u32), Walk>);

impl GivenWalksMap {
    /// Take one walk answer (`view`, `pixel`, optional `steps`, the rest an [`Outcome`] in its serde
    /// form) for a ray of `mesh`: an error names what is wrong with it.
    pub(crate) fn take(&mut self, mut v: Value, mesh: &Mesh) -> Result<(), String> {
        let o = v.as_object_mut().ok_or("an answer is a JSON object")?;
        let view = o
            .remove("view")
            .and_then(|x| x.as_u64())
            .ok_or("needs \"view\", the ray's view")? as usize;
        let pixel = o
            .remove("pixel")
            .and_then(|p| serde_json::from_value::<[u32; 2]>(p).ok())
            .ok_or("needs \"pixel\": [x, y]")?;
        let steps = match o.remove("steps") {
            None => 0,
            Some(s) => s
                .as_u64()
                .and_then(|s| u32::try_from(s).ok())
                .ok_or("\"steps\" is a count of tetrahedra")?,
        };
        let outcome: Outcome = serde_json::from_value(v).map_err(|e| e.to_string())?;
        if let Outcome::Cycle { period: 0, .. } = outcome {
            return Err("a cycle's \"period\" is 1 or more tetrahedra".into());
        }
        let (kind, tet, face) = outcome.parts();
        if tet as usize >= mesh.tets.len() {
            return Err(format!(
                "tet {tet} is not a tetrahedron of the scene (0..{})",
                mesh.tets.len()
            ));
        }
        if matches!(kind, OutcomeKind::Hit | OutcomeKind::LeftMesh) && face >= 4 {
            return Err("face must be 0..3".into());
        }
        let key = (view, pixel[0], pixel[1]);
        match self.0.insert(key, Walk { outcome, steps }) {
            Some(_) => Err(format!(
                "a second answer for view {view} pixel [{}, {}]",
                pixel[0], pixel[1]
            )),
            None => Ok(()),
        }
    }

    /// The walks judged as `count` judges a method's, named `name` (each wrong ray handed to
    /// `wrong`): every ray of the header's views needs one walk (`file` names the answers, `cases`
    /// the rays), and no walk is for a ray not counted.
    pub(crate) fn judge(
        &self,
        scene: &Loaded,
        header: &RaysHeader,
        name: &str,
        file: &str,
        cases: &str,
        wrong: Option<&mut count::Sink>,
    ) -> Result<CountReport<Walks>, RaysError> {
        let width = header.views.width;
        let lookup = |v: usize, rays: &[Ray], _, _| -> Result<Vec<GivenWalk>, CountError> {
            (0..rays.len() as u32)
                .map(|i| {
                    let (x, y) = (i % width, i / width);
                    let walk = self.0.get(&(v, x, y)).copied().ok_or_else(|| {
                        CountError::Given(format!(
                            "{file}: no answer for view {v} pixel [{x}, {y}]"
                        ))
                    })?;
                    Ok(GivenWalk {
                        walk,
                        stepped: Stepped::ByEnding,
                    })
                })
                .collect()
        };
        let settings = CountSettings::<Walks> {
            views: header.views,
            reference: ReferenceWalk::default(),
            family: (),
            audit: 1000,
            shard: header.shard,
            answerer: None,
        };
        let report = count::run(
            scene,
            &settings,
            &[count::AnswerSource::Given(name, &lookup)],
            &crate::backend::CPU,
            &|| (),
            wrong,
        )?;
        if report.rays != self.0.len() as u64 {
            return Err(RaysError::Answers {
                file: file.into(),
                given: self.0.len(),
                rays: report.rays,
                cases: cases.into(),
            });
        }
        Ok(report)
    }
}
