//! The walk: locate the tetrahedron holding the ray origin, then step from tetrahedron to tetrahedron
//! with a method until a constrained face or the mesh boundary. Always bounded; always a typed outcome.

pub mod layouts;
mod locate;
pub mod octree;

pub use locate::{LocateError, locate};

use crate::exact::{self, FaceSet};
use crate::mesh::Mesh;
use crate::methods::{Arith, ExitMethod};
use crate::tet::Ray;

/// How a walk ended, without its data: the one vocabulary of outcome kinds, used by the CPU walk, the
/// layout walks, the GPU (its codes are generated from [`OutcomeKind::code`]), the count, the renders
/// and found cases. Its serde form is [`OutcomeKind::name`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OutcomeKind {
    Hit,
    LeftMesh,
    NoExitFace,
    Cycle,
    StepLimit,
}

/// What the vocabulary says of one kind.
struct KindRow {
    kind: OutcomeKind,
    /// Its name and serde form.
    name: &'static str,
    /// What it is called when the walk should have ended otherwise.
    wrong: &'static str,
    /// The same, as a key.
    wrong_key: &'static str,
    /// The WGSL constant holding its code.
    wgsl: &'static str,
    /// Its colour in failure maps.
    colour: [u8; 3],
}

const KIND_TABLE: [KindRow; 5] = [
    KindRow {
        kind: OutcomeKind::Hit,
        name: "hit",
        wrong: "wrong face",
        wrong_key: "wrong_face",
        wgsl: "HIT",
        colour: [230, 30, 30],
    },
    KindRow {
        kind: OutcomeKind::LeftMesh,
        name: "left_mesh",
        wrong: "false miss",
        wrong_key: "false_miss",
        wgsl: "LEFT_MESH",
        colour: [250, 200, 0],
    },
    KindRow {
        kind: OutcomeKind::NoExitFace,
        name: "no_exit_face",
        wrong: "no exit face",
        wrong_key: "no_exit_face",
        wgsl: "NO_EXIT_FACE",
        colour: [30, 120, 255],
    },
    KindRow {
        kind: OutcomeKind::Cycle,
        name: "cycle",
        wrong: "cycle",
        wrong_key: "cycle",
        wgsl: "CYCLE",
        colour: [200, 0, 200],
    },
    KindRow {
        kind: OutcomeKind::StepLimit,
        name: "step_limit",
        wrong: "step limit",
        wrong_key: "step_limit",
        wgsl: "STEP_LIMIT",
        colour: [0, 200, 200],
    },
];

impl OutcomeKind {
    /// Every kind, in table order (its [`OutcomeKind::code`]).
    pub const ALL: [OutcomeKind; 5] = [
        OutcomeKind::Hit,
        OutcomeKind::LeftMesh,
        OutcomeKind::NoExitFace,
        OutcomeKind::Cycle,
        OutcomeKind::StepLimit,
    ];

    fn row(self) -> &'static KindRow {
        &KIND_TABLE[self as usize]
    }

    /// `hit`, `left_mesh`, `no_exit_face`, `cycle`, `step_limit`.
    pub(crate) fn name(self) -> &'static str {
        self.row().name
    }

    /// What this ending is when it is wrong: wrong face, false miss, no exit face, cycle, step limit.
    pub fn wrong(self) -> &'static str {
        self.row().wrong
    }

    /// [`OutcomeKind::wrong`] as a key (found cases, JSON): `wrong_face`, `false_miss`, ….
    pub(crate) fn wrong_key(self) -> &'static str {
        self.row().wrong_key
    }

    /// The kind whose [`OutcomeKind::wrong_key`] is `key`.
    pub(crate) fn from_wrong_key(key: &str) -> Option<OutcomeKind> {
        KIND_TABLE
            .iter()
            .find(|r| r.wrong_key == key)
            .map(|r| r.kind)
    }

    /// The kind called `name`.
    pub(crate) fn from_name(name: &str) -> Option<OutcomeKind> {
        KIND_TABLE.iter().find(|r| r.name == name).map(|r| r.kind)
    }

    /// The code the GPU writes, and position in tables.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The kind with GPU code `code`; `None` for a code no kind has.
    pub fn from_code(code: u32) -> Option<OutcomeKind> {
        Self::ALL.get(code as usize).copied()
    }

    /// The WGSL constant holding [`OutcomeKind::code`].
    pub fn wgsl_name(self) -> &'static str {
        self.row().wgsl
    }

    /// Its colour in failure maps.
    pub(crate) fn colour(self) -> [u8; 3] {
        self.row().colour
    }
}

impl serde::Serialize for OutcomeKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for OutcomeKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        OutcomeKind::from_name(&s)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown outcome kind '{s}'")))
    }
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

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Outcome {
    /// Stopped on constrained face `face` of `tet`.
    Hit { tet: u32, face: u8 },
    /// Left through boundary face `face` of `tet`.
    LeftMesh { tet: u32, face: u8 },
    /// The method found no exit face in `tet`.
    NoExitFace { tet: u32 },
    /// The walk came back to a state it had been in (same tetrahedron, same entry face): it would loop
    /// forever; `period` tetrahedra per turn.
    Cycle { tet: u32, period: u32 },
    /// `max_steps` tetrahedra traversed without ending.
    StepLimit { tet: u32 },
}

impl Outcome {
    pub fn kind(&self) -> OutcomeKind {
        self.parts().0
    }

    /// Kind, tetrahedron, and the face (hit, left mesh) or period (cycle), else 0: the GPU's record.
    pub(crate) fn parts(&self) -> (OutcomeKind, u32, u32) {
        match *self {
            Outcome::Hit { tet, face } => (OutcomeKind::Hit, tet, face as u32),
            Outcome::LeftMesh { tet, face } => (OutcomeKind::LeftMesh, tet, face as u32),
            Outcome::NoExitFace { tet } => (OutcomeKind::NoExitFace, tet, 0),
            Outcome::Cycle { tet, period } => (OutcomeKind::Cycle, tet, period),
            Outcome::StepLimit { tet } => (OutcomeKind::StepLimit, tet, 0),
        }
    }

    /// The outcome from its [`Outcome::parts`].
    pub(crate) fn from_parts(kind: OutcomeKind, tet: u32, x: u32) -> Outcome {
        match kind {
            OutcomeKind::Hit => Outcome::Hit { tet, face: x as u8 },
            OutcomeKind::LeftMesh => Outcome::LeftMesh { tet, face: x as u8 },
            OutcomeKind::NoExitFace => Outcome::NoExitFace { tet },
            OutcomeKind::Cycle => Outcome::Cycle { tet, period: x },
            OutcomeKind::StepLimit => Outcome::StepLimit { tet },
        }
    }
}

/// A walk's outcome and the number of tetrahedra it traversed (exit faces asked for).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Walk {
    pub outcome: Outcome,
    pub steps: u32,
}

impl Walk {
    /// A place for a walk not made yet: no step taken.
    pub(crate) const NONE: Walk = Walk {
        outcome: Outcome::StepLimit { tet: 0 },
        steps: 0,
    };
}

/// The first step of a checked walk at which the method's face was not an exact exit face.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Divergence {
    /// 1-based step.
    pub(crate) step: u32,
    pub(crate) tet: u32,
    /// The face the walk entered `tet` through (none in the starting tetrahedron).
    pub(crate) entry: Option<u8>,
    /// What the method answered.
    pub(crate) face: Option<u8>,
    /// The exact exit faces there (empty when the line misses that tetrahedron).
    pub(crate) exact_exit: Vec<u8>,
}

/// A walk specialised to one method and arithmetic: `(mesh, ray, start tetrahedron, max_steps)`.
pub(crate) type WalkFn = fn(&Mesh, &Ray, u32, u32) -> Walk;
/// The same over many rays, each with its start ([`walks`]).
pub(crate) type WalksFn = fn(&Mesh, &[(Ray, u32)], u32) -> Vec<Walk>;
/// The same, checking every step against the oracle.
pub(crate) type CheckedWalkFn = fn(&Mesh, &Ray, u32, u32) -> (Walk, Option<Divergence>);

/// A generous step cap for `mesh`: a walk has at most `4 × tetrahedra` distinct states, so any walk
/// longer than that has cycled, and cycle detection stops it within twice that.
pub fn default_max_steps(mesh: &Mesh) -> u32 {
    (mesh.tets.len() as u32)
        .saturating_mul(8)
        .saturating_add(64)
}

/// [`walk`], also listing the tetrahedra visited, in order.
pub fn walk_traced<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
) -> (Walk, Vec<u32>) {
    let mut visited = Vec::new();
    let w = walk_observed::<M, A>(mesh, ray, start, max_steps, |t, _, _| visited.push(t));
    (w, visited)
}

/// Walk with method `M` from `start` (which must contain the ray origin).
pub fn walk<M: ExitMethod, A: Arith>(mesh: &Mesh, ray: &Ray, start: u32, max_steps: u32) -> Walk {
    walk_unwatched_first::<M, A>(mesh, ray, start, max_steps, UNWATCHED)
}

/// [`walk`], its first `unwatched` steps not watched for cycles ([`UNWATCHED`]).
fn walk_unwatched_first<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
    unwatched: u32,
) -> Walk {
    A::run(
        (mesh, ray),
        #[inline(always)]
        |(mesh, ray)| {
            let limit = max_steps.min(unwatched);
            let end = match Walker::<M>::first::<A>(mesh, ray, start, limit, &mut |_, _, _| {}) {
                Ok(mut walker) => loop {
                    if let Some(end) = walker.step::<A>(mesh, limit, &mut |_, _, _| {}) {
                        break end;
                    }
                },
                Err(end) => end,
            };
            watched_if_long::<M, A>(end, mesh, ray, start, max_steps)
        },
    )
}

/// [`walk`], judging every step with the exact oracle and reporting the first wrong one.
pub(crate) fn walk_checked<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
) -> (Walk, Option<Divergence>) {
    A::run(
        (mesh, ray),
        #[inline(always)]
        |(mesh, ray)| {
            let mut first = None;
            let mut step = 0;
            let w = walk_observed::<M, A>(mesh, ray, start, max_steps, |tet, entry, face| {
                step += 1;
                if first.is_some() {
                    return;
                }
                let exit = crate::fpenv::standard(mesh.tet(tet), |t| exact::classify(&t, ray))
                    .map_or(FaceSet::default(), |c| c.exit);
                if !face.is_some_and(|f| exit.contains(f)) {
                    first = Some(Divergence {
                        step,
                        tet,
                        entry: entry.map(|e| e as u8),
                        face: face.map(|f| f as u8),
                        exact_exit: exit.iter().map(|f| f as u8).collect(),
                    });
                }
            });
            (w, first)
        },
    )
}

/// The walk loop, watched for cycles by Brent's detector from its first step; `observe(tet, entry,
/// face)` sees every step (a no-op closure compiles away).
#[inline(always)]
fn walk_observed<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
    mut observe: impl FnMut(u32, Option<usize>, Option<usize>),
) -> Walk {
    let mut walker = match Walker::<M>::first::<A>(mesh, ray, start, max_steps, &mut observe) {
        Ok(w) => w,
        Err(end) => return end,
    };
    let mut brent = Brent::new((start, None));
    loop {
        if let Some(period) = brent.step((walker.tet, Some(walker.entry))) {
            return Walk {
                outcome: Outcome::Cycle {
                    tet: walker.tet,
                    period,
                },
                steps: walker.steps,
            };
        }
        if let Some(end) = walker.step::<A>(mesh, max_steps, &mut observe) {
            return end;
        }
    }
}

/// Steps a walk takes before it is watched for cycles. A step depends only on the walk's state (its
/// tetrahedron and entry face), so a walk that ends never repeated a state and Brent's detector would
/// not have fired in it: the first steps go unwatched, and a walk still going after them is walked
/// again from its start, watched ([`walk_observed`]), to the same ending it would have had.
const UNWATCHED: u32 = 1024;

/// `end`, a walk of `ray` from `start` taken unwatched and bounded by its unwatched steps (at most
/// `max_steps`); where that bound stopped it, the walk again from its start, watched, to `max_steps`.
#[inline(always)]
fn watched_if_long<M: ExitMethod, A: Arith>(
    end: Walk,
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
) -> Walk {
    if end.outcome.kind() == OutcomeKind::StepLimit {
        walk_watched::<M, A>(mesh, ray, start, max_steps)
    } else {
        end
    }
}

/// [`walk_observed`] observing nothing, in `A`'s environment: a long walk's second run (also a test's
/// watched walk).
#[cold]
#[inline(never)]
fn walk_watched<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
) -> Walk {
    A::run(
        (mesh, ray),
        #[inline(always)]
        |(mesh, ray)| walk_observed::<M, A>(mesh, ray, start, max_steps, |_, _, _| {}),
    )
}

/// The most walks in flight at once on one thread ([`walks`]).
pub(crate) const MAX_LANES: usize = 4;

/// `$body` once for each lane `$k` in `0..MAX_LANES`, written out with the lane a constant, so that each
/// lane's walker is a variable of its own (a loop over the lanes ran 7–9 % more instructions).
macro_rules! each_lane {
    ($k:ident => $body:expr) => {{
        const _: () = assert!(MAX_LANES == 4);
        {
            let $k = 0;
            $body
        }
        {
            let $k = 1;
            $body
        }
        {
            let $k = 2;
            $body
        }
        {
            let $k = 3;
            $body
        }
    }};
}

/// [`walk`] of every ray from its starting tetrahedron; where [`ExitMethod::LANES`] is more than one,
/// that many neighbouring rays at a time, interleaved step by step until the last of them ends: a walk
/// step waits on the tetrahedron it reads and on the face it computes, so one thread advances several
/// independent walks in turn, and neighbouring rays mostly take the same steps, so a group ends
/// together and its walks read the same cells (each ends exactly as [`walk`] would end it).
pub(crate) fn walks<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    rays: &[(Ray, u32)],
    max_steps: u32,
) -> Vec<Walk> {
    walks_unwatched_first::<M, A>(mesh, rays, max_steps, UNWATCHED)
}

/// [`walks`], the first `unwatched` steps of each not watched for cycles ([`UNWATCHED`]).
fn walks_unwatched_first<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    rays: &[(Ray, u32)],
    max_steps: u32,
    unwatched: u32,
) -> Vec<Walk> {
    A::run(
        (mesh, rays),
        #[inline(always)]
        |(mesh, rays)| {
            if M::LANES <= 1 {
                // `walk` enters `A::run` again per ray: its closure is always inlined there, and the
                // fused model's FMA instruction reaches only code inlined into that run (the
                // iterator's closure here is compiled apart).
                return rays
                    .iter()
                    .map(|(r, start)| {
                        walk_unwatched_first::<M, A>(mesh, r, *start, max_steps, unwatched)
                    })
                    .collect();
            }
            let lanes = M::LANES.min(MAX_LANES);
            let limit = max_steps.min(unwatched);
            let mut out = vec![Walk::NONE; rays.len()];
            for (done, group) in out.chunks_mut(lanes).zip(rays.chunks(lanes)) {
                let mut left = 0;
                // Lanes past the group's rays stay `None`.
                let mut walkers: [Option<Walker<M>>; MAX_LANES] = [const { None }; MAX_LANES];
                each_lane!(k => if let Some((ray, start)) = group.get(k) {
                    match Walker::first::<A>(mesh, ray, *start, limit, &mut |_, _, _| {}) {
                        Ok(w) => {
                            walkers[k] = Some(w);
                            left += 1;
                        }
                        Err(end) => {
                            done[k] = watched_if_long::<M, A>(end, mesh, ray, *start, max_steps);
                        }
                    }
                });
                while left > 0 {
                    each_lane!(k => if let Some(w) = &mut walkers[k]
                        && let Some(end) = w.step::<A>(mesh, limit, &mut |_, _, _| {})
                    {
                        let (ray, start) = &group[k];
                        done[k] = watched_if_long::<M, A>(end, mesh, ray, *start, max_steps);
                        walkers[k] = None;
                        left -= 1;
                    });
                }
            }
            out
        },
    )
}

/// One walk in progress past its first tetrahedron: the tetrahedron it is in, the face it entered
/// that through, and the steps taken; no allocation.
struct Walker<M: ExitMethod> {
    data: M::RayData,
    tet: u32,
    entry: usize,
    steps: u32,
}

impl<M: ExitMethod> Walker<M> {
    /// The walk of `ray` from `start` after its first step, taken there without an entry face; the
    /// walk when it ends there.
    #[inline(always)]
    fn first<A: Arith>(
        mesh: &Mesh,
        ray: &Ray,
        start: u32,
        max_steps: u32,
        observe: &mut impl FnMut(u32, Option<usize>, Option<usize>),
    ) -> Result<Self, Walk> {
        let mut walker = Walker {
            data: M::prepare::<A>(ray),
            tet: start,
            entry: 0,
            steps: 0,
        };
        match walker.cross::<A>(mesh, max_steps, None, observe) {
            Some(end) => Err(end),
            None => Ok(walker),
        }
    }

    /// One step, from the face the walk entered through; the walk when it ends.
    #[inline(always)]
    fn step<A: Arith>(
        &mut self,
        mesh: &Mesh,
        max_steps: u32,
        observe: &mut impl FnMut(u32, Option<usize>, Option<usize>),
    ) -> Option<Walk> {
        // `& 3` tells the methods' tables the face is one of four (it is: `Link::mirror`).
        let entry = self.entry & 3;
        self.cross::<A>(mesh, max_steps, Some(entry), observe)
    }

    /// The step in the walk's tetrahedron entered through `entry` (none once `max_steps` are taken):
    /// the method's exit face, and across it the next tetrahedron; the walk when it ends.
    #[inline(always)]
    fn cross<A: Arith>(
        &mut self,
        mesh: &Mesh,
        max_steps: u32,
        entry: Option<usize>,
        observe: &mut impl FnMut(u32, Option<usize>, Option<usize>),
    ) -> Option<Walk> {
        let tet = self.tet;
        if self.steps >= max_steps {
            return Some(Walk {
                outcome: Outcome::StepLimit { tet },
                steps: max_steps,
            });
        }
        self.steps += 1;
        let cell = &mesh.cells[tet as usize];
        let face = M::exit_face::<A>(&cell.v, &self.data, entry);
        observe(tet, entry, face);
        let end = |outcome| {
            Some(Walk {
                outcome,
                steps: self.steps,
            })
        };
        let Some(f) = face else {
            return end(Outcome::NoExitFace { tet });
        };
        let link = cell.links[f];
        if link.constrained() {
            return end(Outcome::Hit { tet, face: f as u8 });
        }
        let Some(next) = link.neighbor() else {
            return end(Outcome::LeftMesh { tet, face: f as u8 });
        };
        self.entry = link.mirror();
        self.tet = next;
        None
    }
}

/// One step of a walk asked from outside ([`walks_asking`]): the walk's tetrahedron as the mesh
/// stores it, the line the walk follows now and the face it entered through (mesh numbering); the
/// ray's index and the step (from 0).
pub(crate) struct Step {
    pub(crate) ray: usize,
    pub(crate) step: u32,
    pub(crate) case: crate::tet::Case,
}

/// What the asker made of a [`Step`].
pub(crate) enum Asked {
    /// The exit face answered (mesh numbering), the line the walk follows on, and the case as it
    /// was sent with its verdict, where the step was judged when asked (under a contract).
    Face {
        face: Option<u8>,
        line: Ray,
        judged: Option<(crate::tet::Case, Judged)>,
    },
    /// No case the contract allows could be made for the step: the walk ends.
    Unmade,
}

/// A step judged when asked: right, or wrong with the kind of the wrong answer (a wrong face, or no
/// exit face) and the exact exit faces of the case sent (its numbering).
pub(crate) enum Judged {
    Right,
    Wrong { kind: OutcomeKind, exact: Vec<u8> },
}

/// A walk's first wrong step: where (mesh numbering), the case it was sent there, and the kind of
/// the wrong answer.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Fault {
    pub(crate) divergence: Divergence,
    pub(crate) sent: crate::tet::Case,
    pub(crate) kind: OutcomeKind,
}

/// How a walk given from outside is judged.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Stepped {
    /// By its ending, against the reference walk (walks given whole, or asked without a contract).
    ByEnding,
    /// Every step judged when asked (under a contract), each right.
    Right,
    /// Its first wrong step; the walk went on as the answers took it, each case still made under
    /// the contract.
    Wrong(Box<Fault>),
    /// A step the contract could not make before any wrong one: the ray is not judged.
    LeftOut,
}

/// How a view's walks are judged: from `start`, within `max_steps`, each by its ending unless
/// `stepped` says otherwise (pixel by pixel, walks given judged step by step under a contract).
pub(crate) struct Judging<'a> {
    pub(crate) start: u32,
    pub(crate) max_steps: u32,
    pub(crate) stepped: Option<&'a [Stepped]>,
}

/// A walk given from outside, and how it is judged.
pub struct GivenWalk {
    pub(crate) walk: Walk,
    pub(crate) stepped: Stepped,
}

/// Walks of `rays` from `start`, every step's exit face asked of `ask` in batches — each batch every
/// unfinished walk's next step ([`Step`]) — for a program outside tetwalk (`count --answerer`); the
/// walks end as a method's do: on a constrained face, out of the mesh, without an exit face, in a
/// cycle (Brent, over tetrahedron and entry face) or at `max_steps`; or where the asker could not
/// make a step's case ([`Asked::Unmade`]: without an exit face, and left out unless a step was
/// wrong before).
pub(crate) fn walks_asking<E>(
    mesh: &Mesh,
    rays: &[Ray],
    start: u32,
    max_steps: u32,
    mut ask: impl FnMut(&[Step]) -> Result<Vec<Asked>, E>,
) -> Result<Vec<GivenWalk>, E> {
    struct Going {
        tet: u32,
        entry: Option<u8>,
        line: Ray,
        steps: u32,
        brent: Brent<(u32, Option<u8>)>,
        stepped: Stepped,
    }
    let mut going: Vec<Going> = rays
        .iter()
        .map(|&line| Going {
            tet: start,
            entry: None,
            line,
            steps: 0,
            brent: Brent::new((start, None)),
            stepped: Stepped::ByEnding,
        })
        .collect();
    let mut done: Vec<Option<GivenWalk>> = (0..rays.len()).map(|_| None).collect();
    let mut active: Vec<usize> = (0..rays.len()).collect();
    while !active.is_empty() {
        let steps: Vec<Step> = active
            .iter()
            .map(|&i| Step {
                ray: i,
                step: going[i].steps,
                case: crate::tet::Case {
                    tet: mesh.cells[going[i].tet as usize].v,
                    org: going[i].line.org,
                    dir: going[i].line.dir,
                    entry: going[i].entry,
                },
            })
            .collect();
        let asked = ask(&steps)?;
        let mut next = Vec::with_capacity(active.len());
        for (&i, asked) in active.iter().zip(asked) {
            let g = &mut going[i];
            let tet = g.tet;
            g.steps += 1;
            let face = match asked {
                Asked::Unmade => {
                    if matches!(g.stepped, Stepped::ByEnding | Stepped::Right) {
                        g.stepped = Stepped::LeftOut;
                    }
                    None
                }
                Asked::Face { face, line, judged } => {
                    g.line = line;
                    match (judged, &g.stepped) {
                        (Some((_, Judged::Right)), Stepped::ByEnding) => g.stepped = Stepped::Right,
                        (
                            Some((sent, Judged::Wrong { kind, exact })),
                            Stepped::ByEnding | Stepped::Right,
                        ) => {
                            g.stepped = Stepped::Wrong(Box::new(Fault {
                                divergence: Divergence {
                                    step: g.steps,
                                    tet,
                                    entry: g.entry,
                                    face,
                                    exact_exit: exact,
                                },
                                sent,
                                kind,
                            }))
                        }
                        _ => {}
                    }
                    face
                }
            };
            // How it is judged, copied only where the walk ends.
            let end = |outcome| {
                Some(GivenWalk {
                    walk: Walk {
                        outcome,
                        steps: g.steps,
                    },
                    stepped: g.stepped.clone(),
                })
            };
            let link = face.map(|f| mesh.cells[tet as usize].links[f as usize]);
            let ended = match (face, link) {
                (Some(f), Some(link)) if link.constrained() => end(Outcome::Hit { tet, face: f }),
                (Some(f), Some(link)) => match link.neighbor() {
                    None => end(Outcome::LeftMesh { tet, face: f }),
                    Some(n) => {
                        g.tet = n;
                        g.entry = Some(link.mirror() as u8);
                        match g.brent.step((g.tet, g.entry)) {
                            Some(period) => end(Outcome::Cycle { tet: g.tet, period }),
                            None if g.steps >= max_steps => end(Outcome::StepLimit { tet: g.tet }),
                            None => None,
                        }
                    }
                },
                _ => end(Outcome::NoExitFace { tet }),
            };
            match ended {
                Some(w) => done[i] = Some(w),
                None => next.push(i),
            }
        }
        active = next;
    }
    Ok(done.into_iter().flatten().collect())
}

/// Whether walk `w` ends rightly, `reference` being the `exact` walk of the same ray: both leave the
/// mesh, or `w` stops on a constrained face that contains the exact point where the ray first meets the
/// constrained faces — the reference's hit point (a point on a shared edge or vertex may be claimed by
/// any face holding it), or, where the reference left the mesh, a point where the ray grazes the
/// boundary of a constrained face (the reference's perturbation passes beside it; the true ray touches it).
pub fn same_result(mesh: &Mesh, ray: &Ray, w: &Walk, reference: &Walk) -> bool {
    let tri = |t: u32, f: u8| {
        let mut v = mesh.face(t, f as usize);
        v.sort_unstable();
        v
    };
    let crossing = |t: u32, f: u8| {
        let p = mesh.face(t, f as usize).map(|i| mesh.points[i as usize]);
        exact::hit::line_triangle(p, ray).filter(|c| c.t.cmp0().is_ge())
    };
    match (w.outcome, reference.outcome) {
        (Outcome::LeftMesh { .. }, Outcome::LeftMesh { .. }) => true,
        (Outcome::Hit { tet, face }, Outcome::Hit { tet: rt, face: rf }) => {
            (tet, face) == (rt, rf)
                || tri(tet, face) == tri(rt, rf)
                || matches!((crossing(tet, face), crossing(rt, rf)), (Some(x), Some(y)) if x.t == y.t)
        }
        (Outcome::Hit { tet, face }, Outcome::LeftMesh { .. }) => {
            crossing(tet, face).is_some_and(|c| c.on_boundary)
        }
        _ => false,
    }
}

/// Which kind of wrong `w` is (the kind of its ending), or `None` when it is right ([`same_result`]).
pub(crate) fn judge(mesh: &Mesh, ray: &Ray, w: &Walk, reference: &Walk) -> Option<OutcomeKind> {
    (!same_result(mesh, ray, w, reference)).then(|| w.outcome.kind())
}

/// Brent's cycle detection over a walk's states (tetrahedron and entry face; the vertex across the
/// exit face for a layout walk; an octree cell's address): the one loop of it in Rust, as
/// `brent_step` is in WGSL (`src/gpu/common.wgsl`).
pub(crate) struct Brent<S> {
    saved: S,
    power: u32,
    lam: u32,
}

impl<S: PartialEq> Brent<S> {
    pub(crate) fn new(s: S) -> Self {
        Brent {
            saved: s,
            power: 1,
            lam: 0,
        }
    }

    /// Feed the next state; the cycle length once a state repeats.
    #[inline(always)]
    pub(crate) fn step(&mut self, s: S) -> Option<u32> {
        self.lam += 1;
        if s == self.saved {
            return Some(self.lam);
        }
        if self.lam == self.power {
            self.saved = s;
            self.power = self.power.saturating_mul(2);
            self.lam = 0;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::Plain;
    use crate::tet::Tet;

    /// A toy method that leaves a tetrahedron through a face drawn by hashing its vertices, the entry
    /// face and `K` (never the entry face), walked `L` rays at a time: its walks wander, end after
    /// few steps or many, and many come back to a state they were in.
    struct Wander<const K: u32, const L: usize>;

    impl<const K: u32, const L: usize> ExitMethod for Wander<K, L> {
        type RayData = ();
        const LANES: usize = L;
        fn prepare<A: Arith>(_: &Ray) {}
        fn exit_face<A: Arith>(tet: &Tet, _: &(), entry: Option<usize>) -> Option<usize> {
            let mut h = K.wrapping_add(entry.map_or(7, |e| e as u32));
            for c in tet.iter().flat_map(|v| v.to_array()) {
                h = (h ^ c.to_bits()).wrapping_mul(0x9e37_79b9);
            }
            let turn = (h >> 16) as usize % 3 + 1;
            Some(entry.map_or(turn, |e| (e + turn) % 4))
        }
    }

    /// `Wander`'s walks from every seventh tetrahedron, unwatched for their first `unwatched` steps (one ray
    /// and `L` at a time), against the walks watched from their first step; how many of each ending
    /// (cycle, step limit, other) came within and after the unwatched steps.
    fn unwatched_against_watched<const K: u32, const L: usize>(
        mesh: &Mesh,
        unwatched: u32,
        seen: &mut [[usize; 2]; 3],
    ) {
        let ray = Ray {
            org: glam::Vec3::ZERO,
            dir: glam::Vec3::X,
        };
        let starts: Vec<(Ray, u32)> = (0..mesh.tets.len() as u32)
            .step_by(7)
            .map(|t| (ray, t))
            .collect();
        for max in [
            default_max_steps(mesh),
            unwatched + 20,
            unwatched.saturating_sub(5),
            0,
        ] {
            let together =
                walks_unwatched_first::<Wander<K, L>, Plain>(mesh, &starts, max, unwatched);
            for (&(_, start), got) in starts.iter().zip(&together) {
                let want = walk_watched::<Wander<K, L>, Plain>(mesh, &ray, start, max);
                assert_eq!(*got, want, "hash {K}, lanes {L}, start {start}, max {max}");
                let alone =
                    walk_unwatched_first::<Wander<K, L>, Plain>(mesh, &ray, start, max, unwatched);
                assert_eq!(alone, want, "hash {K}, one lane, start {start}, max {max}");
                let kind = match want.outcome {
                    Outcome::Cycle { .. } => 0,
                    Outcome::StepLimit { .. } => 1,
                    _ => 2,
                };
                seen[kind][(want.steps > unwatched) as usize] += 1;
            }
        }
    }

    /// Walks unwatched for cycles at first end as walks watched from their first step end: the same
    /// outcome, tetrahedron, period and steps, whether they end, cycle or reach the step bound before
    /// or after the unwatched steps, one ray, three (a lane left empty) and four at a time.
    #[test]
    fn walks_unwatched_at_first_end_as_watched_walks() {
        let stem = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/scenes/bunny-quality");
        let mesh = crate::mesh::load_tetgen(std::path::Path::new(stem)).unwrap();
        let mut seen = [[0; 2]; 3];
        for unwatched in [1, 8, 40] {
            unwatched_against_watched::<0, 1>(&mesh, unwatched, &mut seen);
            unwatched_against_watched::<0, 4>(&mesh, unwatched, &mut seen);
            unwatched_against_watched::<1, 4>(&mesh, unwatched, &mut seen);
            unwatched_against_watched::<2, 3>(&mesh, unwatched, &mut seen);
        }
        assert!(seen.iter().flatten().all(|&n| n > 0), "{seen:?}");
    }

    #[test]
    fn brent_finds_the_period() {
        let seq = [1u32, 2, 3, 4, 5, 6, 4, 5, 6, 4, 5, 6, 4, 5, 6, 4, 5, 6];
        let mut b = Brent::new((0u32, None::<usize>));
        let found = seq.iter().find_map(|&x| b.step((x, None)));
        assert_eq!(found, Some(3));
    }
}
