//! How a family counts a scene (seed 000 Table 4's measure): each primary ray of a view answered by a
//! method, the answer an ending in the tetrahedral mesh's terms (a constrained face hit, the mesh
//! left, no exit face, a cycle, the step limit), judged against the reference walk as `count` judges
//! walks ([`crate::walk::same_result`]). The view loop, the audit, the dump, the labellings and the
//! shards are `crate::engine::count`'s, once for every family.

use super::Family;
use super::wrong::Class;
use crate::backend::{Backend, BackendError, MeshOn, Pending, Traffic};
use crate::mesh::Mesh;
use crate::registry::Method;
use crate::scenes::camera::{Camera, Views};
use crate::tet::Ray;
use crate::walk::{OutcomeKind, Walk, same_result};

/// `Serialize` and `Deserialize` for a struct of one type parameter that derives both with
/// `#[serde(remote = "Self")]` because it flattens a field: serde_json, with the `arbitrary_precision`
/// the case format needs, reads such a struct from a `serde_json::Value` but not straight from text
/// (the flattened part's numbers would come as maps), so it is read through one.
macro_rules! through_value {
    ($t:ident<$p:ident: $b:path>) => {
        impl<'de, $p: $b> serde::Deserialize<'de> for $t<$p> {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = <serde_json::Value as serde::Deserialize>::deserialize(d)?;
                $t::deserialize(v).map_err(serde::de::Error::custom)
            }
        }

        impl<$p: $b> serde::Serialize for $t<$p> {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                $t::serialize(self, s)
            }
        }
    };
}
pub(crate) use through_value;

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
        "audit: the reference {reference} and {exact} disagree on view {view} pixel {pixel:?}: {walked:?} against {answered:?}"
    )]
    Audit {
        reference: String,
        exact: &'static str,
        view: usize,
        pixel: [u32; 2],
        /// Where the reference walk ended.
        walked: Walk,
        /// What the exact answer was.
        answered: Walk,
    },
    #[error(
        "audit: {method}'s nearest hit among the binned candidates differs from its brute-force one on view {view} pixel {pixel:?}: {binned:?} against {brute:?} (triangle, t); the bins' derivation (family::triangle::bins) does not hold here"
    )]
    Bins {
        method: String,
        view: usize,
        pixel: [u32; 2],
        binned: Option<(u32, f32)>,
        brute: Option<(u32, f32)>,
    },
    /// Every ray of a row left out of judging by its contract.
    #[error(
        "{method} judged no ray: each of the {rays} rays' walks reached a step its contract ({contract}) leaves no case"
    )]
    NothingJudged {
        method: String,
        rays: u64,
        contract: String,
    },
    #[error(transparent)]
    Relabel(#[from] crate::mesh::MeshError),
    /// A report of one scene counted again on another (`engine::count::relabel_all`).
    #[error("the report counts scene {report}, not {scene}: it cannot be relabelled with {scene}")]
    OtherScene { report: String, scene: String },
    #[error(
        "no view could be counted: none of the {0} camera positions lies inside the mesh (a scene needs the box around the model that `tetwalk scene build` adds)"
    )]
    NoView(usize),
}

/// A scene as a count walks it: the scene loaded (its name and mesh), the mesh made ready on the backend, its step bound, and the views
/// (each view's rays come in pixel order, row by row).
pub struct Scene<'a> {
    pub(crate) loaded: &'a crate::scenes::Loaded,
    pub(crate) on: MeshOn<'a>,
    pub(crate) max_steps: u32,
    pub(crate) views: Views,
}

/// What a count's methods answer one view's rays with: the backend, the scene made ready for the
/// view's camera region, the family's settings, and the camera's tetrahedron.
pub struct Prepared<'a, C: Counted> {
    pub(crate) backend: &'a Backend,
    pub(crate) scene: &'a Scene<'a>,
    pub(crate) ready: &'a C::Ready,
    pub(crate) settings: &'a C::CountSettings,
    pub(crate) located: u32,
    /// The view counted, its camera, and its rays (row by row) the audit re-judges.
    pub(crate) view: usize,
    pub(crate) camera: &'a Camera,
    pub(crate) audited: &'a [usize],
}

/// A family whose methods answer a scene's primary rays.
pub trait Counted: Family {
    /// What the family's count sets beyond the scene, views, reference, audit and shard.
    type CountSettings: Clone
        + std::fmt::Debug
        + PartialEq
        + serde::Serialize
        + serde::de::DeserializeOwned
        + Send
        + Sync;
    /// The scene as the methods answer it from a camera's region (its triangles, their octree),
    /// made ready on the backend.
    type Ready: Send + Sync;
    /// What the report says of the scene.
    type SceneFacts: Clone + std::fmt::Debug + serde::Serialize + serde::de::DeserializeOwned;
    /// One method's counts.
    type Counts: Counts;

    /// What the family's exact answer to a ray is called in the audit's report.
    const EXACT: &'static str;
    /// Views and image size a count takes by default.
    const DEFAULT_VIEWS: (usize, &'static str);
    /// Other families' names `count --family` takes for this one (a walk count counts the exit-face
    /// methods' walks).
    const COUNT_ALIASES: &'static [&'static str] = &[];

    /// Whether the reference walk's row is the family's own (its methods walk the mesh): it comes
    /// first in the report, timed and wrong nowhere.
    fn reference_row() -> bool {
        false
    }

    /// Settings that cannot be counted with, refused before any work.
    fn check(_s: &Self::CountSettings) -> Result<(), String> {
        Ok(())
    }

    /// The scene made ready for cameras in the region of tetrahedron `located`.
    fn prepare(
        scene: &Scene,
        s: &Self::CountSettings,
        backend: &Backend,
        located: u32,
    ) -> Result<Self::Ready, CountError>;

    /// Whether `ready` serves a camera in tetrahedron `located` (its region).
    fn serves(_ready: &Self::Ready, _located: u32) -> bool {
        true
    }

    /// What the report says of the scene, as the last view made it ready.
    fn facts(scene: &Scene, ready: Option<&Self::Ready>) -> Self::SceneFacts;

    /// `m`'s answer to each ray of a view, in pixel order: each a walk's ending and the steps it took
    /// (tetrahedra or cells visited, or none).
    fn answer_rays(
        at: &Prepared<Self>,
        m: &Self::Method,
        rays: &[Ray],
    ) -> Result<Vec<Walk>, CountError>;

    /// `m`'s answers compared with the reference walk where they are made, where the backend can
    /// ([`Backend::walks_against`]: a GPU holding the reference's endings; the engine asks only
    /// where the reference walk's endings are kept there), queued there: the engine reads a view's
    /// back at once with the reference walk ([`Backend::gather_view`]), the steps summed and only
    /// the rays not settled there, each with its walk; `None` where every answer comes back
    /// ([`Counted::answer_rays`]). The count is the same either way, ray for ray.
    fn answer_against<'a>(
        _at: &'a Prepared<Self>,
        _m: &'a Self::Method,
        _rays: &'a [Ray],
    ) -> Result<Option<Pending<'a>>, CountError> {
        Ok(None)
    }

    /// The family's exact answer ([`Counted::EXACT`]) to each audited ray of a view, which must agree
    /// with the reference walk ([`Counted::agrees`]).
    fn audit(at: &Prepared<Self>, rays: &[Ray]) -> Result<Vec<Walk>, CountError>;

    /// Whether the exact answer `exact` to `ray` agrees with the reference walk's: by default it ends
    /// on the same exact point ([`same_result`]).
    fn agrees(mesh: &Mesh, ray: &Ray, exact: &Walk, reference: &Walk) -> bool {
        same_result(mesh, ray, exact, reference)
    }

    /// The exit-face method behind `m`, whose CPU walk a dump follows step by step to find where it
    /// first left the exact exit set.
    fn walker(_m: &Self::Method) -> Option<&Method> {
        None
    }
}

/// One method's totals over a count's views: its family's counts, the time spent walking and the
/// speed, and its wrong rays under each labelling of the tetrahedra.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(remote = "Self", bound = "")]
pub struct CountRow<C: Counts> {
    pub method: String,
    #[serde(flatten)]
    pub counts: C,
    /// Wall-clock seconds spent answering (where views were counted at once, its share of their wall
    /// time: `engine::count::run`).
    #[serde(default)]
    pub(crate) seconds: f64,
    /// Rays answered per second, in millions (0 for answers given from outside, not timed here).
    pub(crate) mrays_per_second: f64,
    /// Wrong rays under each of the 12 orientation-preserving relabellings of the tetrahedra
    /// (`crate::tet::EVEN_PERMUTATIONS`, the mesh's own labelling first), with `count --relabel all`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relabelled: Option<Vec<u64>>,
    /// On a GPU, what its answers moved between the CPU and the GPU.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) transfer: Option<Transfer>,
    /// Walks asked step by step under a contract (`count --answerer --origin …`): rays not judged,
    /// their walk having reached a step the contract leaves no case before any wrong one (of
    /// `rays`, the rest judged).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) left_out: Option<u64>,
}

through_value!(CountRow<C: Counts>);

/// What a count row's answers moved between the CPU and a GPU, summed over its views, and per ray: the
/// pipeline measured on any adapter.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Transfer {
    /// The totals (`bytes_written`, `bytes_read`, `dispatches`, `kernel_seconds` where measured).
    #[serde(flatten)]
    pub(crate) total: Traffic,
    /// Per ray counted ([`CountRow::finish`]).
    pub(crate) bytes_written_per_ray: f64,
    pub(crate) bytes_read_per_ray: f64,
    /// The kernels' share of the row's wall time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) kernel_share: Option<f64>,
}

impl<C: Counts> CountRow<C> {
    pub(crate) fn new(method: &str) -> Self {
        CountRow {
            method: method.to_string(),
            counts: C::default(),
            seconds: 0.0,
            mrays_per_second: 0.0,
            relabelled: None,
            transfer: None,
            left_out: None,
        }
    }

    /// Count what a view's answers moved between the CPU and the GPU.
    pub(crate) fn add_traffic(&mut self, t: &Traffic) {
        let total = self.transfer.as_ref().map_or(*t, |s| s.total.plus(t));
        self.transfer = Some(Transfer {
            total,
            ..Transfer::default()
        });
    }

    /// Count a view's work: steps (tetrahedra or cells visited) and seconds answering.
    /// Rays left out of a contract's judging (none where the row is judged by endings).
    pub(crate) fn add_left_out(&mut self, left_out: Option<u64>) {
        if let Some(n) = left_out {
            *self.left_out.get_or_insert(0) += n;
        }
    }

    pub(crate) fn add_work(&mut self, steps: u64, seconds: f64) {
        self.counts.add_steps(steps);
        self.seconds += seconds;
    }

    /// Another shard's totals.
    pub(crate) fn add(&mut self, o: &Self) {
        self.counts.add(&o.counts);
        self.seconds += o.seconds;
        self.add_left_out(o.left_out);
        if let Some(t) = &o.transfer {
            self.add_traffic(&t.total);
        }
        self.relabelled = self
            .relabelled
            .take()
            .zip(o.relabelled.as_ref())
            .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x + y).collect());
    }

    /// The per-image and per-second figures, once every view is counted.
    pub(crate) fn finish(&mut self, views: usize, rays: u64) {
        self.counts.finish(views);
        self.mrays_per_second = if self.seconds > 0.0 {
            rays as f64 / self.seconds / 1e6
        } else {
            0.0
        };
        let seconds = self.seconds;
        if let Some(t) = &mut self.transfer {
            let per_ray = |bytes: u64| bytes as f64 / rays.max(1) as f64;
            t.bytes_written_per_ray = per_ray(t.total.written);
            t.bytes_read_per_ray = per_ray(t.total.read);
            t.kernel_share = t
                .total
                .kernel_seconds
                .filter(|_| seconds > 0.0)
                .map(|k| k / seconds);
        }
    }

    /// Whether its own numbers agree with each other (beyond the kinds adding up, which the engine
    /// checks): the field that does not, and why.
    pub(crate) fn check(&self, at: &str, views: usize) -> Result<(), (String, String)> {
        let total = self.counts.wrong_total();
        if let Some(r) = &self.relabelled
            && r.first() != Some(&total)
        {
            return inconsistent(
                format!("{at}.relabelled[0]"),
                format!(
                    "{:?}, not wrong_total {total} (the own labelling)",
                    r.first()
                ),
            );
        }
        self.counts.check(at, views)
    }
}

/// A family's counts of one method over a count's views, as its report has always written them.
pub trait Counts:
    Clone + Default + std::fmt::Debug + serde::Serialize + serde::de::DeserializeOwned + Send + Sync
{
    /// Wrong rays by the kind of their ending ([`OutcomeKind::ALL`] order).
    fn kinds(&self) -> [u64; 5];
    fn wrong_total(&self) -> u64 {
        self.kinds().iter().sum()
    }
    /// Count one wrong ray (a wrong face: adjacent to the exact hit, or elsewhere).
    fn add_wrong(&mut self, kind: OutcomeKind, class: Option<Class>);
    /// Count the steps (tetrahedra or cells visited) of a view's answers.
    fn add_steps(&mut self, _steps: u64) {}
    /// Another shard's counts.
    fn add(&mut self, other: &Self);
    /// The per-image figures, once every view is counted.
    fn finish(&mut self, views: usize);
    /// Whether the per-image figures and any split of the totals agree with the totals.
    fn check(&self, at: &str, views: usize) -> Result<(), (String, String)>;
}

/// A failed check: `field`, and why.
pub(crate) fn inconsistent(
    field: impl Into<String>,
    why: impl Into<String>,
) -> Result<(), (String, String)> {
    Err((field.into(), why.into()))
}

/// The check of a per-image figure `figure` (`wrong_per_image`) against its total over `views`, as
/// `finish` makes it.
pub(crate) fn per_image(
    at: &str,
    figure: f64,
    total: u64,
    views: usize,
) -> Result<(), (String, String)> {
    if figure != total as f64 / views.max(1) as f64 {
        return inconsistent(
            format!("{at}.wrong_per_image"),
            format!("{figure}, not wrong_total {total} over {views} views"),
        );
    }
    Ok(())
}

/// The first field (a dotted path) where `a` and `b` differ, with both values.
pub(crate) fn first_difference(
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
