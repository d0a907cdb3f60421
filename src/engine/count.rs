//! Counts, for every family that answers a scene's primary rays ([`Counted`]): seed 000 Table 4's
//! measure — for a scene, how many rays of an image each method gets wrong in f32, judged exactly
//! against the reference walk (`certified`, which ends where `exact` ends, or `exact`), with the work
//! per image and speed. One view loop for every family: the reference walk, the audit (the family's
//! exact answer on about 1,000 rays must agree with the reference), each method's answers judged and
//! each wrong ray described ([`WrongRay`]), shards that add up, the labellings of the tetrahedra.

use crate::backend::{Against, Backend, Ran, Traffic};
use crate::choice::{BackendKind, Choice};
use crate::family::CountKind;
use crate::family::Family;
use crate::family::count::{
    CountError, CountRow, Counted, Counts, Scene, first_difference, inconsistent,
};
use crate::family::count::{Prepared, through_value};
use crate::family::wrong::{Counting, Seen, WrongRay};
use crate::mesh::Faces;
use crate::mesh::Mesh;
use crate::registry::{ByName, Claim, Method, Named, Registered};
use crate::scenes::Loaded;
use crate::scenes::camera::{Camera, Views};
use crate::tet::Ray;
use crate::walk::{GivenWalk, Judging, Stepped, Walk, default_max_steps, judge, locate};
use rayon::prelude::*;
use std::collections::HashMap;
use std::time::Instant;

/// The walk a count judges every method against: a registered exit-face method, by name in settings
/// and reports. `count --reference` offers those tetwalk vouches for as robust
/// ([`ReferenceWalk::vouched`]: `exact`, and `certified`, which ends where `exact` ends); the audit
/// holds any to `exact`.
pub type ReferenceWalk = ByName<Method>;

impl ByName<Method> {
    /// The methods tetwalk vouches for as robust: each ends where `exact` ends.
    pub fn vouched() -> impl Iterator<Item = ReferenceWalk> {
        Method::registered()
            .iter()
            .filter(|m| m.info.ours && m.info.claim == Some(Claim::Robust))
            .map(ByName)
    }
}

/// The default reference walk: the vouched walk that is not `exact` itself (`certified`, several
/// times faster).
impl Default for ByName<Method> {
    fn default() -> Self {
        ReferenceWalk::vouched()
            .find(|r| !r.0.is_reference())
            .expect("a vouched walk beside exact is registered")
    }
}

/// One of `count` disjoint slices of the views (`--shard INDEX/COUNT`); `0/1` is all of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    pub(crate) fn holds(self, view: usize) -> bool {
        view % self.count == self.index
    }

    /// How many of `views` views this shard holds.
    pub(crate) fn held(self, views: usize) -> usize {
        (0..views).filter(|&v| self.holds(v)).count()
    }
}

/// The labellings `--relabel all` counts under: the mesh's own and the 11 other even permutations
/// of every tetrahedron's vertices.
pub(crate) const RELABELLINGS: usize = crate::tet::EVEN_PERMUTATIONS.len();

/// Whether ray `index` (counted over all views) is audited: about `audit` of `total`, chosen by `seed`.
pub(crate) fn audited(seed: u64, index: u64, audit: u64, total: u64) -> bool {
    (mixed(seed, index) % total.max(1)) < audit
}

/// `index` mixed with `seed` (SplitMix64's finaliser): a ray's draw, the same on every run.
pub(crate) fn mixed(seed: u64, index: u64) -> u64 {
    let mut z = seed ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The views that `holds` keeps whose camera lies inside the mesh, each with its camera and the
/// tetrahedron holding it (located from the previous view's); `skipped` is called for every view kept
/// whose camera lies outside.
pub fn located_views<'a>(
    mesh: &'a Mesh,
    views: &'a Views,
    holds: impl Fn(usize) -> bool + 'a,
    skipped: &'a (dyn Fn() + Sync),
) -> impl Iterator<Item = (usize, Camera, u32)> + 'a {
    let (lo, hi) = crate::mesh::bounds(&mesh.points);
    let mut start = 0;
    (0..views.views)
        .filter(move |&v| holds(v))
        .filter_map(move |v| {
            let cam = views.camera(lo, hi, v);
            let Ok(located) = locate(mesh, cam.eye, start) else {
                skipped();
                return None;
            };
            start = located;
            Some((v, cam, located))
        })
}

/// What is counted in a scene, and how the rays are made.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(remote = "Self", bound = "")]
pub struct CountSettings<F: Counted> {
    pub views: Views,
    /// The walk every method is judged against: `exact`, or `certified` (which ends where `exact` ends,
    /// faster).
    pub reference: ReferenceWalk,
    /// What the family's count sets besides (the packets, the octree).
    #[serde(flatten)]
    pub family: F::CountSettings,
    /// Rays the family's exact answer re-judges (chosen by the seed, about this many): it must agree
    /// with the reference on each.
    pub audit: u64,
    /// Which slice of the views this run counts: views `v` with `v % count == index`.
    pub shard: Shard,
    /// The program outside tetwalk asked every step (`--answerer`), as shards of one run must share it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub answerer: Option<crate::engine::answerer::Asked>,
}

/// A count's report, one shape for every family: its settings, the rays and views counted and
/// audited, where the methods ran, what the family says of the scene, and each method's totals (the
/// reference walk's first where it is one of the family's methods).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(remote = "Self", bound = "")]
pub struct CountReport<F: Counted> {
    /// The family counted (`count merge` reads it).
    pub(crate) family: String,
    pub(crate) settings: Recorded<F>,
    /// Rays the audit re-judged with the family's exact answer, all in agreement.
    pub audited: u64,
    /// Where the methods ran (the `exact` reference always on the CPU).
    pub backend: Ran,
    #[serde(flatten)]
    pub(crate) scene: F::SceneFacts,
    /// Rays judged (all pixels of all views whose camera is inside the mesh).
    pub rays: u64,
    pub views_counted: usize,
    pub methods: Vec<CountRow<F::Counts>>,
}

/// A count's settings as its report records them: the scene counted (its name, from the
/// [`Loaded`] scene), and the settings.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(bound = "")]
pub struct Recorded<F: Counted> {
    pub(crate) scene: String,
    #[serde(flatten)]
    pub(crate) count: CountSettings<F>,
}

through_value!(CountSettings<F: Counted>);
through_value!(CountReport<F: Counted>);

/// Whose answers a count judges.
pub enum AnswerSource<'a, F: Family> {
    /// A method, run on the count's backend.
    Method(&'a F::Method),
    /// Walks computed elsewhere (`tetwalk judge`), named: given a view, every pixel's walk, row by row.
    Given(&'a str, &'a GivenWalks<'a>),
}

/// Walks given from outside for one view: its index, its rays, the tetrahedron they start in and the
/// steps a walk may take; each walk with how it is judged.
pub(crate) type GivenWalks<'a> =
    dyn Fn(usize, &[Ray], u32, u32) -> Result<Vec<GivenWalk>, CountError> + Sync + 'a;

impl<'a, F: Family> AnswerSource<'a, F> {
    /// Whose answers a count judges against `reference`: walks given from outside first, then each
    /// of `methods` but the family's own reference and `reference` (the count's first row).
    pub fn judged(
        given: Option<(&'a str, &'a GivenWalks<'a>)>,
        methods: impl IntoIterator<Item = &'a F::Method>,
        reference: ReferenceWalk,
    ) -> Vec<AnswerSource<'a, F>> {
        let given = given.map(|(name, walks)| AnswerSource::Given(name, walks));
        let methods = methods
            .into_iter()
            .filter(move |m| !m.is_reference() && m.name() != reference.name())
            .map(AnswerSource::Method);
        given.into_iter().chain(methods).collect()
    }

    fn name(&self) -> &str {
        match self {
            AnswerSource::Method(m) => m.name(),
            AnswerSource::Given(name, _) => name,
        }
    }
}

/// Where each wrong ray goes besides the tallies (`count --dump`).
pub(crate) type Sink<'a> = dyn FnMut(&WrongRay) -> std::io::Result<()> + 'a;

/// Views counted at once per thread on the CPU (each view's walks split between the threads as
/// well): while one view's serial steps run (its rays, its audit) or its last walks end, the
/// threads walk another's.
const VIEWS_PER_THREAD: usize = 2;

/// Memory the views counted at once may take, at about [`bytes_per_ray`] each ray: fewer views at
/// once where images are large or methods many (three of 1024² with the ten walk methods, about the
/// 0.9 GB they held at once before the figure was measured).
const VIEWS_MEMORY: u64 = 2 << 30;

/// A view's bytes per ray while it is counted, rendered or its walks given, beside [`WALK_BYTES`] per
/// method: the ray (24), the reference walk (16), the ray with its start as the backend takes it
/// (28), the pixel's tallies, with room to spare (about 88 measured, `tests/bad_input.rs`).
pub(crate) const RAY_BYTES: u64 = 160;

/// A view's bytes per ray for each method counted beside the reference: its walks and their
/// judging, all kept until the view is judged (about 36 measured).
pub(crate) const WALK_BYTES: u64 = 48;

/// A view's bytes per ray with `methods` methods counted, rendered or given: the views planned at
/// once, and the largest view accepted, follow from it.
pub fn bytes_per_ray(methods: usize) -> u64 {
    RAY_BYTES + WALK_BYTES * methods as u64
}

/// One view's tallies: per row (the reference walk's first where it is one), the steps, the seconds
/// its answers took and its wrong rays, described; and the rays audited.
struct ViewCount {
    work: Vec<(u64, f64, Option<Traffic>)>,
    wrong: Vec<Vec<WrongRay>>,
    /// Per row, rays not judged (a step their contract could not make); `None` for rows judged by
    /// their endings.
    left_out: Vec<Option<u64>>,
    audits: u64,
    rays: u64,
}

/// Count wrong rays per answerer over the views the shard holds; `tick` is called once per view
/// (counted, or skipped for a camera outside the mesh), and `sink` sees every wrong ray written out
/// ([`WrongRay`]), view by view in order. On the CPU several views are counted at once
/// (`VIEWS_PER_THREAD`, as many as `VIEWS_MEMORY` holds); memory holds those views' rays and
/// walks.
pub fn run<F: Counted>(
    loaded: &Loaded,
    s: &CountSettings<F>,
    answerers: &[AnswerSource<F>],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
    mut sink: Option<&mut Sink>,
) -> Result<CountReport<F>, CountError> {
    let reference = s.reference.method();
    let mesh = &loaded.mesh;
    let max = default_max_steps(mesh);
    let scene = Scene {
        loaded,
        on: backend.mesh(mesh),
        max_steps: max,
        views: s.views,
    };
    let own = F::reference_row() as usize;
    let mut rows: Vec<CountRow<F::Counts>> = std::iter::once(reference.name())
        .take(own)
        .chain(answerers.iter().map(|a| a.name()))
        .map(CountRow::new)
        .collect();
    // A GPU takes one batch at a time: its views one by one.
    let at_once = match backend.kind() {
        crate::choice::BackendKind::Gpu => 1,
        _ => {
            let rays = s.views.width as u64 * s.views.height as u64;
            let fit = VIEWS_MEMORY / (rays * bytes_per_ray(answerers.len())).max(1);
            (VIEWS_PER_THREAD * rayon::current_num_threads()).min(fit.max(1) as usize)
        }
    };
    let (mut rays_counted, mut views_counted, mut audits) = (0u64, 0usize, 0u64);
    let counting = Counting {
        family: F::NAME.to_string(),
        views: s.views,
        settings: serde_json::to_value(&s.family)
            .map_err(|e| CountError::Dump(std::io::Error::other(e)))?,
    };
    let mut ready: Option<F::Ready> = None;
    // One view at a time, the last one answered and not yet judged, and the next one's rays.
    let mut unjudged: Option<Unjudged> = None;
    let mut next_rays: Option<(usize, Vec<Ray>)> = None;
    let mut views = located_views(mesh, &s.views, |v| s.shard.holds(v), tick).peekable();
    loop {
        // The next views that one preparation serves, at most `at_once`.
        let mut group = Vec::new();
        while group.len() < at_once
            && let Some(&(_, _, located)) = views.peek()
        {
            if ready.as_ref().is_none_or(|r| !F::serves(r, located)) {
                if !group.is_empty() {
                    break;
                }
                ready = Some(F::prepare(&scene, &s.family, backend, located)?);
            }
            group.extend(views.next());
        }
        let last = group.is_empty();
        if last && unjudged.is_none() {
            break;
        }
        let t0 = Instant::now();
        let judge = |u| judge_view(&scene, s, answerers, backend, u);
        let counted: Vec<_> = if last {
            unjudged.take().map(judge).into_iter().map(Ok).collect()
        } else if at_once == 1 {
            let ready = ready.as_ref().expect("made ready above");
            // One view at a time (a GPU): while its answers are made, the previous view's are
            // judged and the next view's rays made; the last view judged after the loop.
            let view = (group[0].0, &group[0].1, group[0].2);
            let (previous, next) = (unjudged.take(), views.peek().map(|&(v, cam, _)| (v, cam)));
            let made = next_rays
                .take()
                .filter(|(v, _)| *v == view.0)
                .map(|(_, r)| r);
            let (u, (judged, next)) = count_view(
                &scene,
                s,
                answerers,
                reference,
                backend,
                ready,
                view,
                made,
                || {
                    rayon::join(
                        || previous.map(judge),
                        || next.map(|(v, cam)| (v, s.views.rays(&cam))),
                    )
                },
            )?;
            tick();
            (unjudged, next_rays) = (Some(u), next);
            judged.into_iter().map(Ok).collect()
        } else {
            let ready = ready.as_ref().expect("made ready above");
            group
                .par_iter()
                .map(|&(v, cam, located)| {
                    let c = count_view(
                        &scene,
                        s,
                        answerers,
                        reference,
                        backend,
                        ready,
                        (v, &cam, located),
                        None,
                        || (),
                    );
                    tick();
                    c.map(|(u, ())| judge(u))
                })
                .collect()
        };
        let wall = t0.elapsed().as_secs_f64();
        let summed: f64 = counted
            .iter()
            .flatten()
            .flat_map(|c| c.work.iter().map(|w| w.1))
            .sum();
        // Views counted at once overlap: where their answers' times add up to more than the wall
        // time, each is scaled down in proportion, so that the rows add up to the wall time.
        let scale = if at_once > 1 && summed > wall {
            wall / summed
        } else {
            1.0
        };
        for c in counted {
            let c = c?;
            views_counted += 1;
            rays_counted += c.rays;
            audits += c.audits;
            for (((row, (steps, seconds, traffic)), wrong), left_out) in
                rows.iter_mut().zip(c.work).zip(c.wrong).zip(c.left_out)
            {
                row.add_work(steps, seconds * scale);
                row.add_left_out(left_out);
                if let Some(t) = &traffic {
                    row.add_traffic(t);
                }
                for d in wrong {
                    row.counts
                        .add_wrong(d.kind().expect("a wrong ray has a kind"), d.class);
                    if let Some(sink) = sink.as_mut() {
                        let d = WrongRay {
                            count: Some(counting.clone()),
                            ..d
                        };
                        sink(&d).map_err(CountError::Dump)?;
                    }
                }
            }
        }
    }
    if views_counted == 0 {
        return Err(CountError::NoView(s.views.views));
    }
    if let Some(row) = rows.iter().find(|r| r.left_out == Some(rays_counted)) {
        return Err(CountError::NothingJudged {
            method: row.method.clone(),
            rays: rays_counted,
            contract: (s.answerer.as_ref().and_then(|a| a.contract.clone())).unwrap_or_default(),
        });
    }
    for row in &mut rows {
        row.finish(views_counted, rays_counted);
    }
    Ok(CountReport {
        family: F::NAME.to_string(),
        settings: Recorded {
            scene: loaded.name.clone(),
            count: s.clone(),
        },
        audited: audits,
        backend: backend.ran(),
        scene: F::facts(&scene, ready.as_ref()),
        rays: rays_counted,
        views_counted,
        methods: rows,
    })
}

/// A view answered, its answers not judged yet ([`judge_view`]): its rays and where they start, per row
/// the steps, seconds and traffic, per answerer the answers to judge (each beside the reference
/// walk's ending), and the rays audited.
struct Unjudged {
    v: usize,
    rays: Vec<Ray>,
    located: u32,
    work: Vec<(u64, f64, Option<Traffic>)>,
    candidates: Vec<Vec<(usize, Walk, Walk)>>,
    /// Per answerer, how each pixel's walk is judged, where it was given judged step by step.
    stepped: Vec<Option<Vec<Stepped>>>,
    audits: u64,
}

/// View `v` answered (its rays made here unless `made`): the reference walk, the audit of its
/// picked rays, and each answerer's answers, with the steps and seconds of each; `meanwhile` runs
/// while the GPU answers (after the view's work is queued there, before it is read back: the
/// previous view judged, the next one's rays made), its result returned beside.
#[allow(clippy::too_many_arguments)]
fn count_view<F: Counted, R>(
    scene: &Scene,
    s: &CountSettings<F>,
    answerers: &[AnswerSource<F>],
    reference: &crate::registry::Method,
    backend: &Backend,
    ready: &F::Ready,
    (v, cam, located): (usize, &Camera, u32),
    made: Option<Vec<Ray>>,
    meanwhile: impl FnOnce() -> R,
) -> Result<(Unjudged, R), CountError> {
    let (mesh, max) = (&scene.loaded.mesh, scene.max_steps);
    let total_rays = s.views.views as u64 * s.views.width as u64 * s.views.height as u64;
    let rays = made.unwrap_or_else(|| s.views.rays(cam));
    let first = v as u64 * rays.len() as u64;
    let picked: Vec<usize> = (0..rays.len())
        .filter(|&i| audited(s.views.seed, first + i as u64, s.audit, total_rays))
        .collect();
    let mut work = Vec::with_capacity(answerers.len() + 1);
    let mut candidates = Vec::with_capacity(answerers.len());
    let mut stepped = Vec::with_capacity(answerers.len());
    // What the GPU moved since `before`, on a GPU.
    let moved = |before: Option<Traffic>| backend.traffic().zip(before).map(|(a, b)| a.since(b));
    // The reference walk, and the methods whose answers are compared with it where they are made,
    // queued there one after another and read back together (one wait a view on a GPU; only the
    // rays not settled there are judged here); elsewhere the reference walk is walked first.
    let t0 = Instant::now();
    let before = backend.traffic();
    let keeping = backend.keep_walks(reference, &scene.on, &rays, located, max, &picked)?;
    let reference_kept = keeping.kept_there();
    let walked = (!reference_kept).then(|| (t0.elapsed().as_secs_f64(), moved(before)));
    let at = Prepared::<F> {
        backend,
        scene,
        ready,
        settings: &s.family,
        located,
        view: v,
        camera: cam,
        audited: &picked,
    };
    // Compared there only where the reference's endings are kept there.
    let (mut rows, mut queued) = (Vec::new(), Vec::new());
    for (k, a) in answerers.iter().enumerate() {
        if reference_kept
            && let AnswerSource::Method(m) = a
            && let Some(p) = F::answer_against(&at, m, &rays)?
        {
            rows.push(k);
            queued.push(p);
        }
    }
    let meanwhile = meanwhile();
    let gathered = backend.gather_view(keeping, queued)?;
    // The wall time shared by the rows read back together, the reference's first where it was.
    let kernels: Vec<_> = (gathered.reference.iter())
        .chain(gathered.answers.iter().map(|(_, t)| t))
        .map(|t| t.kernel_seconds)
        .collect();
    let wall = t0.elapsed().as_secs_f64() - walked.as_ref().map_or(0.0, |w| w.0);
    let mut shares = apportion(wall, &kernels).into_iter();
    let kept = gathered.kept;
    let reference_work = match (walked, gathered.reference) {
        (Some((seconds, traffic)), _) => (seconds, traffic),
        (None, traffic) => (shares.next().expect("one a row"), traffic),
    };
    if F::reference_row() {
        work.push((kept.steps, reference_work.0, reference_work.1));
    }
    if !picked.is_empty() {
        let picked_rays: Vec<Ray> = picked.iter().map(|&i| rays[i]).collect();
        let exact = F::audit(&at, &picked_rays)?;
        for ((&i, e), walked) in picked.iter().zip(&exact).zip(&kept.picked) {
            if !F::agrees(mesh, &rays[i], e, walked) {
                return Err(CountError::Audit {
                    reference: s.reference.to_string(),
                    exact: F::EXACT,
                    view: v,
                    pixel: [i as u32 % s.views.width, i as u32 / s.views.width],
                    walked: *walked,
                    answered: *e,
                });
            }
        }
    }
    // Every reference ending, read back once where an answerer needs them all (its answers are
    // not compared where they are made).
    let mut all = kept.all;
    let mut compared: Vec<_> = answerers.iter().map(|_| None).collect();
    for ((k, (against, traffic)), seconds) in rows.into_iter().zip(gathered.answers).zip(shares) {
        compared[k] = Some((against, seconds, traffic));
    }
    for (a, compared) in answerers.iter().zip(compared) {
        let t0 = Instant::now();
        let before = backend.traffic();
        // Given walks were timed elsewhere, if at all: their speed is not measured here.
        let mut judged = None;
        let (answers, steps, seconds, traffic) = match compared {
            Some((Against { steps, sent }, seconds, traffic)) => {
                (sent, steps, seconds, Some(traffic))
            }
            None => {
                let (walks, seconds) = match a {
                    AnswerSource::Method(m) => {
                        let w = F::answer_rays(&at, m, &rays)?;
                        (w, t0.elapsed().as_secs_f64())
                    }
                    AnswerSource::Given(_, given) => {
                        let (walks, how): (Vec<Walk>, Vec<Stepped>) =
                            given(v, &rays, located, max)?
                                .into_iter()
                                .map(|g| (g.walk, g.stepped))
                                .unzip();
                        judged = how.iter().any(|h| *h != Stepped::ByEnding).then_some(how);
                        (walks, 0.0)
                    }
                };
                let steps = walks.iter().map(|w| w.steps as u64).sum();
                let all = match &mut all {
                    Some(all) => all,
                    None => all.insert(backend.kept_walks(&rays, located)?),
                };
                let candidates = walks
                    .into_iter()
                    .zip(all.iter())
                    .enumerate()
                    .map(|(i, (w, r))| (i, w, *r))
                    .collect();
                (candidates, steps, seconds, moved(before))
            }
        };
        work.push((steps, seconds, traffic));
        candidates.push(answers);
        stepped.push(judged);
    }
    let audits = picked.len() as u64;
    let unjudged = Unjudged {
        v,
        rays,
        located,
        work,
        candidates,
        stepped,
        audits,
    };
    Ok((unjudged, meanwhile))
}

/// A view's answers judged: each answerer's wrong rays, described (none in the reference walk's row,
/// where it is one).
fn judge_view<F: Counted>(
    scene: &Scene,
    s: &CountSettings<F>,
    answerers: &[AnswerSource<F>],
    backend: &Backend,
    u: Unjudged,
) -> ViewCount {
    let wrong = std::iter::repeat_with(Vec::new)
        .take(F::reference_row() as usize)
        .chain(answerers.iter().zip(&u.candidates).zip(&u.stepped).map(
            |((a, candidates), stepped)| {
                let seen = Seen {
                    scene: &scene.loaded.name,
                    view: u.v,
                    pixel: [0, 0],
                    name: a.name(),
                    backend: match a {
                        AnswerSource::Method(m) => Some(backend.for_method(*m).ran().kind),
                        AnswerSource::Given(..) => None,
                    },
                    walker: match a {
                        AnswerSource::Method(m) => F::walker(m),
                        AnswerSource::Given(..) => None,
                    },
                };
                let mesh = &scene.loaded.mesh;
                let (width, max) = (s.views.width, scene.max_steps);
                let judged = Judging {
                    start: u.located,
                    max_steps: max,
                    stepped: stepped.as_deref(),
                };
                wrong_rays_judged(mesh, &seen, width, &u.rays, candidates, &judged)
            },
        ))
        .collect();
    let left_out = std::iter::repeat_n(None, F::reference_row() as usize)
        .chain(u.stepped.iter().map(|h| {
            h.as_ref()
                .map(|h| h.iter().filter(|h| **h == Stepped::LeftOut).count() as u64)
        }))
        .collect();
    ViewCount {
        left_out,
        work: u.work,
        wrong,
        audits: u.audits,
        rays: u.rays.len() as u64,
    }
}

/// `wall` seconds shared among rows run together: in proportion to their kernel times where each
/// was measured and any took time, equally otherwise.
fn apportion(wall: f64, kernels: &[Option<f64>]) -> Vec<f64> {
    let measured: Option<Vec<f64>> = kernels.iter().copied().collect();
    match measured {
        Some(k) if k.iter().sum::<f64>() > 0.0 => {
            let sum: f64 = k.iter().sum();
            k.iter().map(|k| wall * k / sum).collect()
        }
        _ => vec![wall / kernels.len().max(1) as f64; kernels.len()],
    }
}

/// Count again under each other orientation-preserving relabelling of the tetrahedra
/// (`crate::tet::EVEN_PERMUTATIONS`, the same for the whole mesh; `report` is the mesh's own) and keep
/// each row's wrong rays under all 12; refused for another scene than the report's.
pub fn relabel_all<F: Counted>(
    report: &mut CountReport<F>,
    scene: &Loaded,
    answerers: &[AnswerSource<F>],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
) -> Result<(), CountError> {
    if report.settings.scene != scene.name {
        return Err(CountError::OtherScene {
            report: report.settings.scene.clone(),
            scene: scene.name.clone(),
        });
    }
    let wrong_totals = |r: &CountReport<F>| -> Vec<u64> {
        r.methods.iter().map(|m| m.counts.wrong_total()).collect()
    };
    let permutations = &crate::tet::EVEN_PERMUTATIONS;
    let wrong = super::under_labellings(wrong_totals(report), permutations.len(), |k| {
        let relabelled = Loaded {
            name: scene.name.clone(),
            mesh: scene.mesh.relabelled(permutations[k])?,
        };
        let r = run(
            &relabelled,
            &report.settings.count,
            answerers,
            backend,
            tick,
            None,
        )?;
        Ok::<_, CountError>(wrong_totals(&r))
    })?;
    for (m, w) in report.methods.iter_mut().zip(wrong) {
        m.relabelled = Some(w);
    }
    Ok(())
}

/// One view's wrong rays for one method among `candidates` (pixel `i`'s walk beside the reference
/// walk's ending, pixel `i` at column `i % width`: every pixel, or those not settled right where
/// they were walked), each walked from `start` within `max_steps` and judged by its ending, each
/// described; wrong rays are few, so each is described where it is found.
pub fn wrong_rays(
    mesh: &Mesh,
    seen: &Seen,
    width: u32,
    rays: &[Ray],
    candidates: &[(usize, Walk, Walk)],
    start: u32,
    max_steps: u32,
) -> Vec<WrongRay> {
    let judging = Judging {
        start,
        max_steps,
        stepped: None,
    };
    wrong_rays_judged(mesh, seen, width, rays, candidates, &judging)
}

/// [`wrong_rays`], walks judged as `judging` says: one judged step by step is wrong where a step
/// was ([`Stepped::Wrong`]), whatever its ending.
fn wrong_rays_judged(
    mesh: &Mesh,
    seen: &Seen,
    width: u32,
    rays: &[Ray],
    candidates: &[(usize, Walk, Walk)],
    judging: &Judging,
) -> Vec<WrongRay> {
    let how = |i: usize| judging.stepped.map_or(&Stepped::ByEnding, |h| &h[i]);
    let wrong: Vec<(usize, Walk, Walk)> = candidates
        .par_iter()
        .filter(|(i, w, reference)| match how(*i) {
            Stepped::ByEnding => judge(mesh, &rays[*i], w, reference).is_some(),
            Stepped::Wrong(_) => true,
            Stepped::Right | Stepped::LeftOut => false,
        })
        .copied()
        .collect();
    wrong
        .par_iter()
        .map(|&(i, walk, reference)| {
            let seen = Seen {
                pixel: [i as u32 % width, i as u32 / width],
                ..*seen
            };
            let fault = match how(i) {
                Stepped::Wrong(f) => Some(&**f),
                _ => None,
            };
            WrongRay::of(mesh, &seen, &rays[i], (&walk, &reference), judging, fault)
        })
        .collect()
}

/// A count's wrong ray answered again ([`Dumped::line`]): where the method stops now, and whether it is
/// still wrong, and wrong the same way (stopping where it was recorded to).
pub(crate) struct Rerun {
    /// The method's name, as its family's registry spells it.
    pub(crate) method: String,
    pub(crate) now: Walk,
    pub(crate) still_wrong: bool,
    pub(crate) same: bool,
}

/// Why a wrong ray cannot be answered again.
#[derive(Debug, thiserror::Error)]
pub(crate) enum RerunError {
    #[error(
        "a wrong ray of walks given from outside tetwalk (by {0}, through `tetwalk judge` or `count --answerer`): tetwalk replay cannot answer it again without the program (a line of `count --answerer` under a contract holds its first wrong step as `case`: `tetwalk exit --answerer CMD` answers that again)"
    )]
    NotWalked(String),
    #[error(
        "the line records no count (a dump written before tetwalk kept its family, views and settings): count again with --dump"
    )]
    NoCount,
    #[error("the count's family: '{0}' is not a family that counts a scene")]
    Family(String),
    #[error("the count's settings are not a {family} count's: {why}")]
    Settings { family: &'static str, why: String },
    #[error(transparent)]
    Method(#[from] crate::registry::UnknownMethod),
    #[error(
        "the ray ({org:?}, {dir:?}) is not one a walk was made of ({why}): a finite origin and a nonzero direction"
    )]
    Ray {
        org: [f32; 3],
        dir: [f32; 3],
        why: crate::exact::ExactError,
    },
    #[error(
        "view {view} pixel {pixel:?} is not one of the count's ({views} views of {width}x{height})"
    )]
    Pixel {
        view: usize,
        pixel: [u32; 2],
        views: usize,
        width: u32,
        height: u32,
    },
    #[error(
        "{views} views of {width}x{height}: more than a count takes (at most {most} views, a view of at most {gib} GiB at {bytes} bytes a ray)",
        bytes = bytes_per_ray(1),
        most = Views::MOST,
        gib = super::MEMORY_BUDGET >> 30
    )]
    Views {
        views: usize,
        width: u32,
        height: u32,
    },
    #[error(
        "view {view}'s camera lies outside the mesh of scene {scene}: not the mesh counted (counted with --no-faces, or another scene file?)"
    )]
    CameraOutside { view: usize, scene: String },
    #[error(
        "the ray is not view {view} pixel {pixel:?}'s ray of scene {scene}: the line was edited, or the mesh is not the one counted"
    )]
    NotItsRay {
        view: usize,
        pixel: [u32; 2],
        scene: String,
    },
    #[error(transparent)]
    Count(#[from] CountError),
    #[error(transparent)]
    Backend(#[from] crate::backend::BackendError),
    #[error(transparent)]
    Scene(#[from] crate::mesh::MeshError),
}

/// A count's dump answered again line by line ([`Dumped::line`]): each scene loaded once (its
/// constrained faces as `faces` asks), each backend opened once, and the answers of the last view
/// kept, since a dump holds a view's wrong rays together (its lines answer the view once per method).
pub(crate) struct Dumped {
    faces: Faces,
    scenes: HashMap<String, Loaded>,
    backends: super::Backends,
    /// The view (scene, count, index, method, backend) whose answers `walks` holds.
    held: Option<(String, Counting, usize, String, BackendKind)>,
    walks: Vec<Walk>,
}

/// A dump's line answered again ([`Rerun`], and the backend described), or skipped: the backend it
/// records cannot be opened here (why).
pub(crate) enum Redone {
    Rerun(Rerun, String),
    Skipped(String),
}

impl Dumped {
    pub(crate) fn new(faces: Faces) -> Dumped {
        Dumped {
            faces,
            scenes: HashMap::new(),
            backends: Default::default(),
            held: None,
            walks: Vec::new(),
        }
    }

    /// Wrong ray `d` answered again as its count answered it: its view's rays through its scene,
    /// made ready with the family's settings the line records ([`Counting`]), answered by its method
    /// on the backend `d` records, and judged against the exact walk as the count judged it. Walks
    /// given from outside record no backend and are [`RerunError::NotWalked`].
    pub(crate) fn line(&mut self, d: &WrongRay) -> Result<Redone, RerunError> {
        let Some(kind) = d.backend else {
            return Err(RerunError::NotWalked(d.method.clone()));
        };
        if !self.scenes.contains_key(&d.scene) {
            let scene = crate::scenes::load(&d.scene, self.faces)?;
            self.scenes.insert(d.scene.clone(), scene);
        }
        let backend = match self.backends.open(kind) {
            Ok(b) => b,
            Err(why) => return Ok(Redone::Skipped(format!("recorded on {kind:?}: {why}"))),
        };
        let c = d.count.as_ref().ok_or(RerunError::NoCount)?;
        let family = <crate::family::CountKind as crate::choice::Choice>::from_name(&c.family)
            .ok_or_else(|| RerunError::Family(c.family.clone()))?;
        let scene = &self.scenes[&d.scene];
        let (held, walks) = (&mut self.held, &mut self.walks);
        let rerun =
            crate::with_counted!(family, F => rerun::<F>(d, c, scene, backend, held, walks))?;
        Ok(Redone::Rerun(rerun, backend.describe()))
    }
}

/// [`Dumped::line`] in family `F`: `held` names the view (scene, count, index, method, backend)
/// whose answers `walks` holds.
fn rerun<F: Counted>(
    d: &WrongRay,
    c: &Counting,
    loaded: &Loaded,
    backend: &Backend,
    held: &mut Option<(String, Counting, usize, String, BackendKind)>,
    walks: &mut Vec<Walk>,
) -> Result<Rerun, RerunError> {
    let m = crate::family::by_name::<F>(&d.method)?;
    let mesh = &loaded.mesh;
    let ray = d.ray();
    crate::exact::check_ray(&[], &ray).map_err(|why| RerunError::Ray {
        org: ray.org.to_array(),
        dir: ray.dir.to_array(),
        why,
    })?;
    let settings = |why: String| RerunError::Settings {
        family: F::NAME,
        why,
    };
    let family: F::CountSettings =
        serde_json::from_value(c.settings.clone()).map_err(|e| settings(e.to_string()))?;
    F::check(&family).map_err(settings)?;
    let (views, [x, y]) = (c.views, d.pixel);
    if d.view >= views.views || x >= views.width || y >= views.height {
        return Err(RerunError::Pixel {
            view: d.view,
            pixel: d.pixel,
            views: views.views,
            width: views.width,
            height: views.height,
        });
    }
    // Views no count takes (more viewpoints, or a view larger than a run may hold) are refused
    // before a view is placed or its rays made.
    let bytes = views.width as u128 * views.height as u128 * bytes_per_ray(1) as u128;
    if views.views > Views::MOST || bytes > super::MEMORY_BUDGET as u128 {
        return Err(RerunError::Views {
            views: views.views,
            width: views.width,
            height: views.height,
        });
    }
    let (_, camera, located) = located_views(mesh, &views, |v| v == d.view, &|| {})
        .next()
        .ok_or_else(|| RerunError::CameraOutside {
            view: d.view,
            scene: loaded.name.clone(),
        })?;
    let i = (y * views.width + x) as usize;
    let bits = |r: &Ray| [r.org, r.dir].map(|v| v.to_array().map(f32::to_bits));
    if bits(&camera.ray(x, y, views.width, views.height)) != bits(&ray) {
        return Err(RerunError::NotItsRay {
            view: d.view,
            pixel: d.pixel,
            scene: loaded.name.clone(),
        });
    }
    let max_steps = default_max_steps(mesh);
    let view = Some((
        loaded.name.clone(),
        c.clone(),
        d.view,
        d.method.clone(),
        backend.kind(),
    ));
    // The mesh is made ready on the backend (uploaded to a GPU) only where a view is answered.
    if *held != view {
        let scene = Scene {
            loaded,
            on: backend.mesh(mesh),
            max_steps,
            views,
        };
        let ready = F::prepare(&scene, &family, backend, located)?;
        let at = Prepared::<F> {
            backend,
            scene: &scene,
            ready: &ready,
            settings: &family,
            located,
            view: d.view,
            camera: &camera,
            audited: &[],
        };
        *walks = F::answer_rays(&at, m, &views.rays(&camera))?;
        *held = view;
    }
    let now = walks[i];
    // The exact walk runs where the backend runs the reference (the CPU), on the mesh made ready there.
    let reference = crate::registry::reference();
    let there = backend.for_method(reference);
    let exact = there.walks(reference, &there.mesh(mesh), &[ray], located, max_steps)?[0];
    let still_wrong = judge(mesh, &ray, &now, &exact).is_some();
    Ok(Rerun {
        method: m.name().to_string(),
        now,
        still_wrong,
        same: still_wrong && now.outcome == d.stopped.outcome,
    })
}

/// Why sharded reports cannot be merged; each names the report's file (or name) and the field.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("nothing to merge")]
    Empty,
    #[error("{0}: family: not a count report's family ({families})", families = counted_families())]
    NotACount(String),
    #[error("{file}: counts {got} where {first} counts {want}: merge each family apart")]
    Families {
        file: String,
        got: &'static str,
        first: String,
        want: &'static str,
    },
    /// A report that is not one of its family's (a field missing or of another type).
    #[error("{file}: {path}: {why}")]
    Field {
        file: String,
        path: String,
        why: String,
    },
    #[error("{file}: {field} is {got}, but {value} in {first}: a shard of another run")]
    Settings {
        file: String,
        field: String,
        got: String,
        value: String,
        first: String,
    },
    #[error("{file}: judged the methods {got:?}, {first} judged {want:?}")]
    Methods {
        file: String,
        got: Vec<String>,
        first: String,
        want: Vec<String>,
    },
    #[error(
        "the shards do not cover the views once each: of {count} shards, missing {}, given more than once {}",
        runs(missing),
        runs(repeated)
    )]
    Shards {
        missing: Vec<usize>,
        repeated: Vec<usize>,
        count: usize,
    },
    /// A report whose own numbers contradict each other (edited, or cut).
    #[error("{file}: {field}: {why}")]
    Inconsistent {
        file: String,
        field: String,
        why: String,
    },
}

/// The counted families' names, `walk, triangle or octree`.
fn counted_families() -> String {
    let names: Vec<&str> = CountKind::ALL.iter().map(|k| k.name()).collect();
    match names.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// The family of a sharded count's reports, read as JSON (each named by its file): the same for all.
pub(crate) fn shards_family(read: &[(String, serde_json::Value)]) -> Result<CountKind, MergeError> {
    let mut kind: Option<CountKind> = None;
    for (file, r) in read {
        let named = r
            .get("family")
            .and_then(|f| f.as_str())
            .and_then(CountKind::from_name)
            .ok_or_else(|| MergeError::NotACount(file.clone()))?;
        match kind {
            Some(k) if k != named => {
                return Err(MergeError::Families {
                    file: file.clone(),
                    got: named.name(),
                    first: read[0].0.clone(),
                    want: k.name(),
                });
            }
            _ => kind = Some(named),
        }
    }
    kind.ok_or(MergeError::Empty)
}

/// A count's reports of family `F` from their JSON, each named by its file (an error names the file
/// and the field).
pub(crate) fn read_shards<F: Counted>(
    read: Vec<(String, serde_json::Value)>,
) -> Result<Vec<(String, CountReport<F>)>, MergeError> {
    read.into_iter()
        .map(|(file, r)| match serde_path_to_error::deserialize(r) {
            Ok(report) => Ok((file, report)),
            Err(e) => Err(MergeError::Field {
                file,
                path: e.path().to_string(),
                why: e.inner().to_string(),
            }),
        })
        .collect()
}

/// Sorted indices as runs, `0-4, 7, 9-12` (`none` when empty).
fn runs(sorted: &[usize]) -> String {
    let runs: Vec<String> = super::runs(sorted).iter().map(super::run_text).collect();
    if runs.is_empty() {
        "none".into()
    } else {
        runs.join(", ")
    }
}

/// A count that runs in shards (`--shard I/N`, disjoint slices of the views) and adds up.
pub trait Sharded: Clone {
    /// What every shard of one run shares (its settings but the shard, the backend, the scene), as
    /// JSON so that a difference is named by its field.
    fn same(&self) -> serde_json::Value;
    fn shard(&self) -> Shard;
    /// The methods counted, in order.
    fn methods(&self) -> Vec<String>;
    /// Whether the report's own numbers agree with each other: the field that does not, and why.
    fn check(&self) -> Result<(), (String, String)>;
    /// Add `other`'s totals (another shard's) to these.
    fn add(&mut self, other: &Self);
    /// The whole run's report from the added totals (shard `0/1`, per-image and per-second figures).
    fn finish(&mut self);
}

/// The shards of one run (every `I` of `I/N` once, all else alike), each named by its file, added
/// up: the same totals as an unsharded run, exactly; what is not added up (timings, dates) is shard
/// 0's. Each shard's own sums are checked first ([`Sharded::check`]).
pub fn merge<R: Sharded>(reports: &[(String, R)]) -> Result<R, MergeError> {
    let (first_name, first) = reports.first().ok_or(MergeError::Empty)?;
    let count = first.shard().count;
    let (want, names) = (first.same(), first.methods());
    let mut have = Vec::new();
    for (file, r) in reports {
        r.check().map_err(|(field, why)| MergeError::Inconsistent {
            file: file.clone(),
            field,
            why,
        })?;
        let n = r.shard().count;
        let other_count =
            (n != count).then(|| ("shard.count".into(), n.to_string(), count.to_string()));
        if let Some((field, got, value)) = first_difference(&r.same(), &want).or(other_count) {
            return Err(MergeError::Settings {
                file: file.clone(),
                field,
                got,
                value,
                first: first_name.clone(),
            });
        }
        if r.methods() != names {
            return Err(MergeError::Methods {
                file: file.clone(),
                got: r.methods(),
                first: first_name.clone(),
                want: names,
            });
        }
        have.push(r.shard().index);
    }
    have.sort_unstable();
    if have != (0..count).collect::<Vec<_>>() {
        let mut repeated: Vec<usize> = have
            .windows(2)
            .filter(|w| w[0] == w[1])
            .map(|w| w[0])
            .collect();
        repeated.dedup();
        return Err(MergeError::Shards {
            missing: (0..count)
                .filter(|i| have.binary_search(i).is_err())
                .collect(),
            repeated,
            count,
        });
    }
    let mut order: Vec<&R> = reports.iter().map(|(_, r)| r).collect();
    order.sort_by_key(|r| r.shard().index);
    let mut out = order[0].clone();
    for r in &order[1..] {
        out.add(r);
    }
    out.finish();
    Ok(out)
}

/// The checks every sharded count's totals share: its shard is one of its views' slices, at least
/// one view counted and no more than the shard holds, every pixel of each counted view judged,
/// audited rays among them.
pub(crate) fn check_totals(
    shard: Shard,
    views: &Views,
    views_counted: usize,
    rays: u64,
    audited: u64,
) -> Result<(), (String, String)> {
    if shard.count == 0 || shard.index >= shard.count {
        return inconsistent(
            "shard",
            format!("{}/{} is not I/N with 0 <= I < N", shard.index, shard.count),
        );
    }
    let held = shard.held(views.views);
    if views_counted == 0 || views_counted > held {
        return inconsistent(
            "views_counted",
            format!(
                "{views_counted}, not 1 to the {held} views shard {}/{} holds",
                shard.index, shard.count
            ),
        );
    }
    let pixels = views.width as u128 * views.height as u128;
    if rays as u128 != views_counted as u128 * pixels {
        return inconsistent(
            "rays",
            format!(
                "{rays}, not views_counted × pixels = {views_counted} × {}x{}",
                views.width, views.height
            ),
        );
    }
    if audited > rays {
        return inconsistent("audited", format!("{audited}, more than the {rays} rays"));
    }
    Ok(())
}

/// The checks of one method's wrong rays: the kinds add up to the total, no more than the rays, and
/// the reference row (the first) wrong nowhere.
pub(crate) fn check_wrong(
    at: &str,
    total: u64,
    kinds: &[u64; 5],
    rays: u64,
    reference: bool,
) -> Result<(), (String, String)> {
    let sum: u128 = kinds.iter().map(|&k| k as u128).sum();
    if sum != total as u128 {
        return inconsistent(
            format!("{at}.wrong_total"),
            format!("{total}, but its kinds add up to {sum}"),
        );
    }
    if total > rays {
        return inconsistent(
            format!("{at}.wrong_total"),
            format!("{total}, more than the {rays} rays"),
        );
    }
    if reference && total != 0 {
        return inconsistent(
            format!("{at}.wrong_total"),
            format!(
                "{total}: the reference's row is what the others are judged against, wrong nowhere"
            ),
        );
    }
    Ok(())
}

impl<F: Counted> Sharded for CountReport<F> {
    fn same(&self) -> serde_json::Value {
        let settings = Recorded::<F> {
            count: CountSettings {
                shard: Shard::ALL,
                ..self.settings.count.clone()
            },
            ..self.settings.clone()
        };
        let mut same = serde_json::json!({"settings": settings, "backend": self.backend});
        if let (Some(m), serde_json::Value::Object(facts)) =
            (same.as_object_mut(), serde_json::json!(self.scene))
        {
            m.extend(facts);
        }
        same
    }

    fn shard(&self) -> Shard {
        self.settings.count.shard
    }

    fn methods(&self) -> Vec<String> {
        self.methods.iter().map(|m| m.method.clone()).collect()
    }

    fn check(&self) -> Result<(), (String, String)> {
        let s = &self.settings.count;
        check_totals(
            s.shard,
            &s.views,
            self.views_counted,
            self.rays,
            self.audited,
        )?;
        let own = F::reference_row();
        if own
            && self
                .methods
                .first()
                .is_none_or(|m| m.method != s.reference.name())
        {
            return inconsistent(
                "methods",
                format!("the first row is not the reference {}", s.reference),
            );
        }
        for (i, m) in self.methods.iter().enumerate() {
            let at = format!("methods[{i}] ({})", m.method);
            let judged = self.rays.checked_sub(m.left_out.unwrap_or(0));
            let Some(judged) = judged else {
                return inconsistent(
                    format!("{at}.left_out"),
                    format!("{:?}, more than the {} rays", m.left_out, self.rays),
                );
            };
            check_wrong(
                &at,
                m.counts.wrong_total(),
                &m.counts.kinds(),
                judged,
                own && i == 0,
            )?;
            m.check(&at, self.views_counted)?;
        }
        Ok(())
    }

    fn add(&mut self, r: &Self) {
        self.rays += r.rays;
        self.views_counted += r.views_counted;
        self.audited += r.audited;
        for (t, m) in self.methods.iter_mut().zip(&r.methods) {
            t.add(m);
        }
    }

    fn finish(&mut self) {
        self.settings.count.shard = Shard::ALL;
        for t in &mut self.methods {
            t.finish(self.views_counted, self.rays);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::runs;

    /// Missing shards are named as runs, one of a kind apart, so a long gap reads as one range.
    #[test]
    fn runs_of_indices() {
        assert_eq!(runs(&[]), "none");
        assert_eq!(runs(&[5]), "5");
        assert_eq!(runs(&[0, 1, 2, 4, 6, 7, 1281]), "0-2, 4, 6-7, 1281");
    }
}
