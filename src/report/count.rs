//! `tetwalk count`: for a scene, how many rays of an image each method gets wrong in f32 (seed 000
//! Table 4), judged exactly against the `exact` walk, with traversed tetrahedra per image (Φ) and speed.

use crate::backend::{Backend, BackendError};
use crate::mesh::Mesh;
use crate::registry::{Method, by_name, reference};
use crate::report::wrong::{Class, Seen, WrongRay};
use crate::scenes::camera::{Camera, Views};
use crate::tet::Ray;
use crate::walk::{OutcomeKind, Walk, default_max_steps, judge, locate};
use rayon::prelude::*;
use std::time::Instant;

/// What is counted, and how the rays are made.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    pub scene: String,
    pub views: Views,
    /// The walk every method is judged against: `exact`, or `certified` (which ends where `exact` ends,
    /// faster).
    pub reference: String,
    /// Rays re-judged with the full `exact` walk (chosen by the seed, about this many): the reference
    /// must agree on each.
    pub audit: u64,
    /// Which slice of the views this run counts: views `v` with `v % count == index`.
    pub shard: Shard,
}

/// One of `count` disjoint slices of the views (`--shard INDEX/COUNT`); `0/1` is all of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    pub fn holds(self, view: usize) -> bool {
        view % self.count == self.index
    }

    /// How many of `views` views this shard holds.
    pub fn held(self, views: usize) -> usize {
        (0..views).filter(|&v| self.holds(v)).count()
    }
}

/// Why a count could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CountError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error(transparent)]
    NoReference(#[from] crate::registry::UnknownMethod),
    #[error("writing the dump: {0}")]
    Dump(std::io::Error),
    /// The octree of a scene could not be built.
    #[error("octree: {0}")]
    Octree(String),
    /// Walks given from outside that do not fit the view (`tetwalk judge`).
    #[error("{0}")]
    Given(String),
    #[error(
        "audit: the reference {reference} and the exact walk disagree on view {view} pixel {pixel:?}: {got:?} against {want:?}"
    )]
    Audit {
        reference: String,
        view: usize,
        pixel: [u32; 2],
        got: Walk,
        want: Walk,
    },
    #[error(
        "no view could be counted: none of the {0} camera positions lies inside the mesh (a scene needs the box around the model that `tetwalk scene build` adds)"
    )]
    NoView(usize),
}

/// Numbers per kind of wrong ending, in [`OutcomeKind::ALL`] order; written as a map labelled by
/// [`OutcomeKind::wrong_key`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PerKind<T>(pub [T; 5]);

impl<'de, T: serde::Deserialize<'de> + Default + Copy> serde::Deserialize<'de> for PerKind<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let m = std::collections::BTreeMap::<String, T>::deserialize(d)?;
        let mut out = [T::default(); 5];
        for (k, v) in m {
            let kind = OutcomeKind::from_wrong_key(&k).ok_or_else(|| {
                serde::de::Error::custom(format!("unknown kind of wrong ray '{k}'"))
            })?;
            out[kind.code() as usize] = v;
        }
        Ok(PerKind(out))
    }
}

impl<T: serde::Serialize> serde::Serialize for PerKind<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(5))?;
        for (k, v) in OutcomeKind::ALL.iter().zip(&self.0) {
            m.serialize_entry(k.wrong_key(), v)?;
        }
        m.end()
    }
}

/// One method's numbers per image: the totals over the views counted.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct PerImage {
    pub wrong: f64,
    pub by_kind: PerKind<f64>,
    pub wrong_face_adjacent: f64,
    pub wrong_face_elsewhere: f64,
    /// Tetrahedra traversed per image (Φ).
    pub tetrahedra: f64,
}

/// One method's totals over all views.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct MethodCount {
    pub method: String,
    /// Wrong rays, summed over views.
    pub wrong_total: u64,
    /// Wrong rays by the kind of their ending, summed over views.
    pub wrong: PerKind<u64>,
    /// Wrong faces whose triangle touches a triangle holding the exact hit point.
    pub wrong_face_adjacent: u64,
    /// Wrong faces elsewhere.
    pub wrong_face_elsewhere: u64,
    /// Tetrahedra traversed, summed over views.
    pub steps: u64,
    /// The same numbers per image.
    pub per_image: PerImage,
    /// Wall-clock seconds spent walking.
    pub seconds: f64,
    /// Rays walked per second, in millions (0 for walks given from outside, not timed here).
    pub mrays_per_second: f64,
    /// Wrong rays under each of the 12 orientation-preserving relabellings of the tetrahedra
    /// (`crate::tet::EVEN_PERMUTATIONS`, the mesh's own labelling first), with `count --relabel all`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relabelled: Option<[u64; 12]>,
}

/// One view's wrong rays for one method (`walks` beside the `exact` walks `reference`, pixel `i` at
/// column `i % width`), each described; wrong rays are few, so each is described where it is found.
#[allow(clippy::too_many_arguments)]
pub fn wrong_rays(
    mesh: &Mesh,
    seen: &Seen,
    width: u32,
    rays: &[Ray],
    walks: &[Walk],
    reference: &[Walk],
    start: u32,
    max_steps: u32,
) -> Vec<WrongRay> {
    let wrong: Vec<usize> = (0..rays.len())
        .into_par_iter()
        .filter(|&i| judge(mesh, &rays[i], &walks[i], &reference[i]).is_some())
        .collect();
    wrong
        .par_iter()
        .map(|&i| {
            let seen = Seen {
                pixel: [i as u32 % width, i as u32 / width],
                ..*seen
            };
            WrongRay::of(
                mesh,
                &seen,
                &rays[i],
                &walks[i],
                &reference[i],
                start,
                max_steps,
            )
        })
        .collect()
}

impl MethodCount {
    /// Count one wrong ray.
    pub fn add(&mut self, kind: OutcomeKind, class: Option<Class>) {
        self.wrong.0[kind.code() as usize] += 1;
        self.wrong_total += 1;
        match class {
            Some(Class::Adjacent) => self.wrong_face_adjacent += 1,
            Some(Class::Elsewhere) => self.wrong_face_elsewhere += 1,
            None => {}
        }
    }

    /// Fill in the per-image numbers and the speed, once every view is counted.
    pub fn finish(&mut self, views: usize, rays: u64) {
        let v = views.max(1) as f64;
        self.per_image = PerImage {
            wrong: self.wrong_total as f64 / v,
            by_kind: PerKind(self.wrong.0.map(|n| n as f64 / v)),
            wrong_face_adjacent: self.wrong_face_adjacent as f64 / v,
            wrong_face_elsewhere: self.wrong_face_elsewhere as f64 / v,
            tetrahedra: self.steps as f64 / v,
        };
        self.mrays_per_second = if self.seconds > 0.0 {
            rays as f64 / self.seconds / 1e6
        } else {
            0.0
        };
    }
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CountReport {
    pub settings: Settings,
    /// Rays the audit re-judged with the full `exact` walk, all in agreement.
    pub audited: u64,
    /// The backend the methods ran on (the `exact` reference always runs on the CPU).
    pub backend: String,
    pub tetrahedra: usize,
    /// Rays judged (all pixels of all views whose camera is inside the mesh).
    pub rays: u64,
    pub views_counted: usize,
    /// The `exact` walk, first, then every method.
    pub methods: Vec<MethodCount>,
}

/// A count's last line: each method's wrong rays over all the rays counted.
pub fn totals<'a>(rays: u64, methods: impl Iterator<Item = (&'a str, u64)>) -> String {
    let each: Vec<String> = methods.map(|(m, n)| format!("{m} {n}")).collect();
    format!("\ntotals over {rays} rays: {}\n", each.join(", "))
}

/// Whether ray `index` (counted over all views) is audited: about `audit` of `total`, chosen by `seed`.
pub fn audited(seed: u64, index: u64, audit: u64, total: u64) -> bool {
    let mut z = seed ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z % total.max(1)) < audit
}

/// The views that `holds` keeps whose camera lies inside the mesh, each with its camera and the
/// tetrahedron holding it (located from the previous view's); `tick` is called for every view tried.
pub fn located_views<'a>(
    mesh: &'a Mesh,
    views: &'a Views,
    holds: impl Fn(usize) -> bool + 'a,
    tick: &'a (dyn Fn() + Sync),
) -> impl Iterator<Item = (usize, Camera, u32)> + 'a {
    let (lo, hi) = crate::mesh::bounds(&mesh.points);
    let mut start = 0;
    (0..views.views)
        .filter(move |&v| holds(v))
        .filter_map(move |v| {
            let cam = views.camera(lo, hi, v);
            tick();
            let located = locate(mesh, cam.eye, start).ok()?;
            start = located;
            Some((v, cam, located))
        })
}

/// Where each wrong ray goes besides the tallies (`count --dump`).
pub type Sink<'a> = dyn FnMut(&WrongRay) -> std::io::Result<()> + 'a;

/// Count wrong rays per method over the views; `tick` is called once per view, and `sink` sees every
/// wrong ray written out ([`WrongRay`]). Memory holds one view's rays and walks at a time.
pub fn run(
    mesh: &Mesh,
    s: &Settings,
    methods: &[&Method],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
    sink: Option<&mut Sink>,
) -> Result<CountReport, CountError> {
    let walkers: Vec<Walker> = methods.iter().map(|m| Walker::Method(m)).collect();
    run_walkers(mesh, s, &walkers, backend, tick, sink)
}

/// Whose walks a count judges.
#[derive(Clone, Copy)]
pub enum Walker<'a> {
    /// A method, walked on the count's backend.
    Method(&'a Method),
    /// Walks computed elsewhere (`tetwalk judge`), named: given a view, every pixel's walk, row by row.
    Given(&'a str, &'a GivenWalks<'a>),
}

/// Walks given from outside for one view (its index and its rays).
pub type GivenWalks<'a> = dyn Fn(usize, &[Ray]) -> Result<Vec<Walk>, CountError> + 'a;

impl Walker<'_> {
    fn name(&self) -> &str {
        match self {
            Walker::Method(m) => m.name,
            Walker::Given(name, _) => name,
        }
    }
}

/// [`run`] over walkers: methods on `backend`, or walks given from outside.
pub fn run_walkers(
    mesh: &Mesh,
    s: &Settings,
    methods: &[Walker],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
    mut sink: Option<&mut Sink>,
) -> Result<CountReport, CountError> {
    let exact = by_name(&s.reference)?;
    let full = reference();
    let max = default_max_steps(mesh);
    let total_rays = s.views.views as u64 * s.views.width as u64 * s.views.height as u64;
    let on = backend.mesh(mesh);
    let mut totals: Vec<MethodCount> = std::iter::once(exact)
        .map(|m| m.name.to_string())
        .chain(methods.iter().map(|w| w.name().to_string()))
        .map(|method| MethodCount {
            method,
            ..Default::default()
        })
        .collect();
    let (mut rays_counted, mut views_counted, mut audits) = (0u64, 0usize, 0u64);
    for (v, cam, located) in located_views(mesh, &s.views, |v| s.shard.holds(v), tick) {
        views_counted += 1;
        let rays = s.views.rays(&cam);
        rays_counted += rays.len() as u64;
        let t0 = Instant::now();
        let reference = backend.walks(exact, &on, &rays, located, max)?;
        totals[0].seconds += t0.elapsed().as_secs_f64();
        totals[0].steps += reference.iter().map(|w| w.steps as u64).sum::<u64>();
        if s.audit > 0 {
            let first = v as u64 * rays.len() as u64;
            let picked: Vec<usize> = (0..rays.len())
                .filter(|&i| audited(s.views.seed, first + i as u64, s.audit, total_rays))
                .collect();
            let picked_rays: Vec<Ray> = picked.iter().map(|&i| rays[i]).collect();
            let want = backend.walks(full, &on, &picked_rays, located, max)?;
            audits += picked.len() as u64;
            for (&i, w) in picked.iter().zip(&want) {
                if reference[i] != *w {
                    return Err(CountError::Audit {
                        reference: exact.name.to_string(),
                        view: v,
                        pixel: [i as u32 % s.views.width, i as u32 / s.views.width],
                        got: reference[i],
                        want: *w,
                    });
                }
            }
        }
        for (m, total) in methods.iter().zip(&mut totals[1..]) {
            let t0 = Instant::now();
            // Given walks were timed elsewhere, if at all: their speed is not measured here.
            let walks = match m {
                Walker::Method(m) => {
                    let w = backend.walks(m, &on, &rays, located, max)?;
                    total.seconds += t0.elapsed().as_secs_f64();
                    w
                }
                Walker::Given(_, given) => given(v, &rays)?,
            };
            total.steps += walks.iter().map(|w| w.steps as u64).sum::<u64>();
            let seen = Seen {
                scene: &s.scene,
                view: v,
                pixel: [0, 0],
                name: m.name(),
                walked: match m {
                    Walker::Method(m) => Some((*m, backend.for_method(*m).kind())),
                    Walker::Given(..) => None,
                },
            };
            let described = wrong_rays(
                mesh,
                &seen,
                s.views.width,
                &rays,
                &walks,
                &reference,
                located,
                max,
            );
            for d in &described {
                let kind = d.kind().expect("a wrong ray has a kind");
                total.add(kind, d.class);
                if let Some(sink) = sink.as_mut() {
                    sink(d).map_err(CountError::Dump)?;
                }
            }
        }
    }
    if views_counted == 0 {
        return Err(CountError::NoView(s.views.views));
    }
    for t in &mut totals {
        t.finish(views_counted, rays_counted);
    }
    Ok(CountReport {
        settings: s.clone(),
        audited: audits,
        backend: backend.describe(),
        tetrahedra: mesh.tets.len(),
        rays: rays_counted,
        views_counted,
        methods: totals,
    })
}

impl CountReport {
    /// The table: per method, wrong rays per image by kind (wrong faces also split into adjacent and
    /// elsewhere), Φ per image, and speed; then the totals.
    pub fn markdown(&self) -> String {
        let s = &self.settings.views;
        let mut out = format!(
            "scene {} ({} tetrahedra), {} views of {}x{}, backend {}, seed {}, reference {}{}; per image, averaged over views\n\n",
            self.settings.scene,
            self.tetrahedra,
            self.views_counted,
            s.width,
            s.height,
            self.backend,
            s.seed,
            self.settings.reference,
            if self.audited > 0 {
                format!(
                    " (audited against exact on {} rays, all agreeing)",
                    self.audited
                )
            } else {
                String::new()
            }
        );
        out += &format!(
            "| method | wrong rays | {} | wrong face adjacent | wrong face elsewhere | Φ (tetrahedra) | Mrays/s |\n",
            OutcomeKind::ALL.map(|k| k.wrong()).join(" | ")
        );
        out += &format!(
            "|---|---|{}---|---|---|---|\n",
            "---|".repeat(OutcomeKind::ALL.len())
        );
        for m in &self.methods {
            let p = &m.per_image;
            let kinds: Vec<String> = p.by_kind.0.iter().map(|w| format!("{w:.3}")).collect();
            let speed = if m.seconds > 0.0 {
                format!("{:.2}", m.mrays_per_second)
            } else {
                "-".into()
            };
            out += &format!(
                "| {} | {:.3} | {} | {:.3} | {:.3} | {:.0} | {speed} |\n",
                m.method,
                p.wrong,
                kinds.join(" | "),
                p.wrong_face_adjacent,
                p.wrong_face_elsewhere,
                p.tetrahedra,
            );
        }
        out += &totals(
            self.rays,
            self.methods
                .iter()
                .map(|m| (m.method.as_str(), m.wrong_total)),
        );
        if self.methods.iter().any(|m| m.relabelled.is_some()) {
            out += "\nwrong rays under the 12 orientation-preserving relabellings of the tetrahedra\n\n";
            out += "| method | own labelling | min | median | max |\n|---|---|---|---|---|\n";
            for m in &self.methods {
                if let Some(r) = &m.relabelled {
                    out += &format!("| {} | {} |\n", m.method, super::relabel_spread(r));
                }
            }
        }
        out
    }
}

/// Why sharded reports cannot be merged; each names the report's file (or name) and the field.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("nothing to merge")]
    Empty,
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
    #[error("the shards do not cover the views once each: have {have:?} of {count}")]
    Shards { have: Vec<usize>, count: usize },
    /// A report whose own numbers contradict each other (edited, or cut).
    #[error("{file}: {field}: {why}")]
    Inconsistent {
        file: String,
        field: String,
        why: String,
    },
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

/// The first field (a dotted path) where `a` and `b` differ, with both values.
fn first_difference(
    a: &serde_json::Value,
    b: &serde_json::Value,
) -> Option<(String, String, String)> {
    use serde_json::Value;
    let join = |at: String, rest: (String, String, String)| {
        let path = match (at.is_empty(), rest.0.is_empty(), rest.0.starts_with('[')) {
            (_, true, _) => at,
            (true, false, _) | (false, false, true) => at + &rest.0,
            (false, false, false) => format!("{at}.{}", rest.0),
        };
        (path, rest.1, rest.2)
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => x
            .iter()
            .find_map(|(k, v)| match y.get(k) {
                Some(w) => first_difference(v, w).map(|d| join(k.clone(), d)),
                None => Some((k.clone(), v.to_string(), "absent".into())),
            })
            .or_else(|| {
                y.iter()
                    .find(|(k, _)| !x.contains_key(*k))
                    .map(|(k, w)| (k.clone(), "absent".into(), w.to_string()))
            }),
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (v, w))| first_difference(v, w).map(|d| join(format!("[{i}]"), d))),
        _ => (a != b).then(|| (String::new(), a.to_string(), b.to_string())),
    }
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
        return Err(MergeError::Shards { have, count });
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

/// A failed [`Sharded::check`]: `field`, and why.
pub fn inconsistent(
    field: impl Into<String>,
    why: impl Into<String>,
) -> Result<(), (String, String)> {
    Err((field.into(), why.into()))
}

/// The checks every sharded count's totals share: its shard is one of its views' slices, at least
/// one view counted and no more than the shard holds, every pixel of each counted view judged,
/// audited rays among them.
pub fn check_totals(
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
pub fn check_wrong(
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

impl Sharded for CountReport {
    fn same(&self) -> serde_json::Value {
        let settings = Settings {
            shard: Shard::ALL,
            ..self.settings.clone()
        };
        serde_json::json!({"settings": settings, "backend": self.backend, "tetrahedra": self.tetrahedra})
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
        if self.methods.first().is_none_or(|m| m.method != s.reference) {
            return inconsistent(
                "methods",
                format!("the first row is not the reference {}", s.reference),
            );
        }
        for (i, m) in self.methods.iter().enumerate() {
            let at = format!("methods[{i}] ({})", m.method);
            check_wrong(&at, m.wrong_total, &m.wrong.0, self.rays, i == 0)?;
            let faces = m.wrong.0[OutcomeKind::Hit.code() as usize];
            if m.wrong_face_adjacent as u128 + m.wrong_face_elsewhere as u128 != faces as u128 {
                return inconsistent(
                    format!("{at}.wrong_face_adjacent"),
                    format!(
                        "{} adjacent and {} elsewhere, but {faces} wrong faces",
                        m.wrong_face_adjacent, m.wrong_face_elsewhere
                    ),
                );
            }
            if let Some(r) = &m.relabelled
                && r[0] != m.wrong_total
            {
                return inconsistent(
                    format!("{at}.relabelled[0]"),
                    format!(
                        "{}, not wrong_total {} (the own labelling)",
                        r[0], m.wrong_total
                    ),
                );
            }
            // The per-image figures are the totals' over the views, as `finish` makes them.
            let mut derived = m.clone();
            derived.finish(self.views_counted, self.rays);
            let got = serde_json::json!(m.per_image);
            let want = serde_json::json!(derived.per_image);
            if let Some((field, got, want)) = first_difference(&got, &want) {
                return inconsistent(
                    format!("{at}.per_image.{field}"),
                    format!(
                        "{got}, not {want}, its total over {} views",
                        self.views_counted
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
            (0..5).for_each(|k| t.wrong.0[k] += m.wrong.0[k]);
            t.wrong_face_adjacent += m.wrong_face_adjacent;
            t.wrong_face_elsewhere += m.wrong_face_elsewhere;
            t.steps += m.steps;
            t.seconds += m.seconds;
            t.relabelled = t
                .relabelled
                .zip(m.relabelled)
                .map(|(a, b)| std::array::from_fn(|k| a[k] + b[k]));
        }
    }

    fn finish(&mut self) {
        self.settings.shard = Shard::ALL;
        for t in &mut self.methods {
            t.finish(self.views_counted, self.rays);
        }
    }
}
