//! Families: the kinds of traversal question tetwalk judges — one tetrahedron's exit face
//! ([`ExitFace`]), a walk through a generated mesh ([`Walks`]), a ray and a closed triangle mesh
//! ([`Triangle`]), an octree cell's exit ([`OctreeCells`]). A family is what its methods are, what a case,
//! an answer and the exact truth are, how a verdict is reached, how a backend answers a batch, its
//! stress rows and their seeding, and its claims; stress, campaigns, found cases and replay, the fuzz
//! targets' policy, the conformance kit, counts and the command line are written once, generic over
//! [`Family`] (`crate::engine`, `crate::kit`). A family is a folder here (`exit_face/`, `walk/`,
//! `triangle/`, `octree/`): its `Family` in `mod.rs`, how it reads in `report.rs` (a file of the report
//! layer); and a line in [`families!`](crate::families). `tests/layering.rs` holds that no file outside the folders and
//! the list names a family (data tables excepted: the claims register, the seeds' tables).

pub mod contract;
pub mod count;
pub mod exit_face;
pub mod octree;
pub mod triangle;
pub mod walk;
pub mod wrong;

pub use exit_face::ExitFace;
pub use octree::OctreeCells;
pub use triangle::Triangle;
pub use walk::Walks;

use crate::backend::{Backend, BackendError};
use crate::cases::CaseError;
use crate::registry::{Named, UnknownMethod};
use crate::tet::Ray;
use crate::walk::OutcomeKind;
use serde_json::{Map, Value};
use std::fmt::Debug;

/// What the oracle says of one answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Right,
    /// Wrong, and what kind of ending the wrong answer is ([`OutcomeKind::wrong`] names it).
    Wrong(OutcomeKind),
    /// The case has no exact answer to judge against (a line that misses the tetrahedron or cell).
    NotJudged,
}

impl Verdict {
    /// A verdict line's `correct`: `None` (`null`) where the case is not judged.
    pub(crate) fn correct(self) -> Option<bool> {
        match self {
            Verdict::Right => Some(true),
            Verdict::Wrong(_) => Some(false),
            Verdict::NotJudged => None,
        }
    }
}

/// What the oracle says of one answer with the facts counted beside right or wrong
/// ([`Family::said`]): whether it leaks, whether the ray first meets a back face there
/// ([`crate::exact::hit::HitTruth::back_face`]), whether a hit is wrong for its `t` alone (its
/// triangle right), and how a tetrahedron's answer was reached.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Said {
    /// Right, wrong, or not judged (`None`).
    pub correct: Option<bool>,
    /// A cell's case (a tetrahedron's or an octree cell's), whose line may miss the cell.
    pub(crate) cell: bool,
    /// A triangle case (leaks, back faces and `t` are counted).
    pub(crate) triangle: bool,
    /// A tetrahedron's case: how it was answered.
    pub(crate) tet: Option<TetSaid>,
    /// A closed mesh's answer lets the ray through the surface ([`crate::exact::hit::HitTruth::leaks`]).
    pub(crate) leak: bool,
    /// The ray first meets a back face.
    pub(crate) back_face: bool,
    /// Wrong for its `t` alone: the triangle right, `t` beyond the bound.
    pub(crate) t_alone: bool,
    /// How many ulps a hit's `t` lies from the exact one, where the hit's triangle has an exact `t`.
    pub(crate) t_ulps: Option<f64>,
    /// What a wrong closed-mesh answer is ([`crate::exact::hit::HitTruth::wrong_kind`]).
    pub(crate) kind: Option<&'static str>,
}

/// What a tetrahedron case's verdict says besides right or wrong.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TetSaid {
    /// Wrong with a face (`wrong_face`) or with none (`no_exit_face`).
    pub(crate) wrong: Option<&'static str>,
    /// More than one face is right: the line leaves through an edge or vertex.
    pub(crate) tie: bool,
    /// The line only touches the tetrahedron (an edge, a vertex, along a face).
    pub(crate) touch_only: bool,
}

/// A power-of-two scale of a case: its points and origin multiplied by 2^`points`, its direction by
/// 2^`direction` (the same line; products of it underflow or overflow sooner or later). Exact where
/// nothing underflows or overflows; the oracle judges the scaled case as it is.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct Scale {
    pub points: i32,
    pub direction: i32,
}

impl Scale {
    /// Points and direction at 2^`e`.
    pub const fn uniform(e: i32) -> Scale {
        Scale {
            points: e,
            direction: e,
        }
    }

    pub(crate) fn is_one(&self) -> bool {
        *self == Scale::default()
    }

    /// Read `E` (points and direction at 2^E) or `E/D` (points at 2^E, direction at 2^D).
    pub(crate) fn parse(s: &str) -> Result<Scale, String> {
        let e = |t: &str| {
            t.trim()
                .parse::<i32>()
                .ok()
                .filter(|e| (-300..=300).contains(e))
                .ok_or_else(|| format!("'{t}' is not a power-of-two exponent in -300..=300"))
        };
        match s.split_once('/') {
            None => Ok(Scale::uniform(e(s)?)),
            Some((p, d)) => Ok(Scale {
                points: e(p)?,
                direction: e(d)?,
            }),
        }
    }

    /// `x` times 2^`e`, rounded once (to a subnormal, zero or infinity where it leaves f32's range).
    pub(crate) fn times(x: f32, e: i32) -> f32 {
        (x as f64 * 2f64.powi(e)) as f32
    }
}

impl std::fmt::Display for Scale {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        if self.points == self.direction {
            write!(f, "2^{}", self.points)
        } else {
            write!(f, "2^{}, direction 2^{}", self.points, self.direction)
        }
    }
}

/// Counts that add up: a stress row's tallies over a campaign's rounds, a count's over shards.
pub trait Summed: Default + Clone + Debug + serde::Serialize + Send + Sync {
    fn add(&mut self, other: &Self);
}

impl Summed for () {
    fn add(&mut self, _: &()) {}
}

/// A family of traversal questions (module docs). Everything generic in tetwalk reaches a family
/// through this trait; nothing else tells the families apart.
pub trait Family: Clone + Copy + Debug + PartialEq + Eq + Send + Sync + 'static {
    /// Its name on the command line and in reports (`--family`).
    const NAME: &'static str;
    /// The cargo-fuzz target whose inputs decode to its cases ([`Family::arbitrary`]).
    const FUZZ_TARGET: &'static str;
    /// How many labellings of a case the methods can see (`--relabel all`); one where the answer
    /// cannot depend on it.
    const LABELLINGS: usize = 1;
    /// Cases per stress row when `--cases` gives none.
    const STRESS_CASES: usize = 100_000;
    /// About how many bytes a stress row holds per case at once (the case, its truth, one method's
    /// answers): runs that would need more than tetwalk plans to hold are refused.
    const BYTES_PER_CASE: u128;

    /// A registered method of the family.
    type Method: Named;
    /// One case: a line of the case format.
    type Case: Copy + Debug + PartialEq + Send + Sync;
    /// The exact answer to a case.
    type Truth: Send + Sync;
    /// A method's answer to a case (for ray–triangle tests every hit it reports, for its leaks).
    type Answer: Copy + Debug + PartialEq + Send + Sync;
    /// What shapes a stress run's cases besides their count and seed: which rows, flatness, ulps.
    type Rows: Clone + Debug + Default + serde::Serialize + Send + Sync;
    /// One stress row, written into its report's row as its fields.
    type Row: Copy + Debug + PartialEq + serde::Serialize + Send + Sync;
    /// What a stress row reports of its cases, whatever the methods.
    type RowFacts: Summed;
    /// One method's counts on one stress row.
    type Tally: Summed;

    /// Every registered method, in the order reports list them.
    fn methods() -> &'static [Self::Method];

    // ---- The case format (`crate::cases`) ----

    /// Whether a JSON object holds this family's case (by its keys).
    fn owns(obj: &Map<String, Value>) -> bool;
    /// Take the case's fields out of `obj`, leaving the others to the caller.
    fn take_case(obj: &mut Map<String, Value>) -> Result<Self::Case, CaseError>;
    /// The case's fields (numbers written so that they read back as the same f32).
    fn case_json(case: &Self::Case) -> Map<String, Value>;
    fn ray(case: &Self::Case) -> Ray;
    /// The same case with another ray.
    fn with_ray(case: &Self::Case, ray: Ray) -> Self::Case;

    // ---- Truth and verdicts ----

    /// The oracle's answer; an error names what is wrong with the case.
    fn truth(case: &Self::Case) -> Result<Self::Truth, CaseError>;
    fn verdict(case: &Self::Case, truth: &Self::Truth, answer: &Self::Answer) -> Verdict;
    /// The verdict with the facts counted beside it, as `exit`, `hit`, `box-exit` and `judge` count
    /// and write them; a hit's `t` is right within `t_ulps` ulps of the exact one (the family's
    /// [`Family::verdict`] judges with the default bound).
    fn said(case: &Self::Case, truth: &Self::Truth, answer: &Self::Answer, _t_ulps: f64) -> Said {
        Said {
            correct: Self::verdict(case, truth, answer).correct(),
            ..Said::default()
        }
    }
    /// What a method of the family claims when it makes a claim: never a wrong answer, or (ray–triangle
    /// tests) no leak; a user's answerer claims it with `--answerer-claims`.
    const CLAIM: crate::registry::Claim = crate::registry::Claim::Robust;
    /// Whether `answer` refutes what the family's claim promises ([`crate::registry::Claim`]): by
    /// default any wrong answer (robust); a ray–triangle test's claim is refuted only by a leak.
    fn refutes_claim(case: &Self::Case, truth: &Self::Truth, answer: &Self::Answer) -> bool {
        matches!(Self::verdict(case, truth, answer), Verdict::Wrong(_))
    }
    /// Whether two exact truths have the same right answers (a shrunk case keeps its original's).
    fn same_truth(_a: &Self::Truth, _b: &Self::Truth) -> bool {
        true
    }
    /// How far the case is from having another right answer, in [0, 1] (f64: a measure, not a
    /// verdict): a shrink keeps at least half of its original's. 1 where the family measures none.
    fn clearance(_case: &Self::Case, _truth: &Self::Truth) -> f64 {
        1.0
    }
    /// Whether a wrong answer may be let pass as one on a line that only touches the case's cell
    /// (`kit::Accept::touch_only`).
    fn touch_only(_case: &Self::Case) -> bool {
        false
    }
    /// Whether the case is an exact tie: more than one answer is right.
    fn tie(_truth: &Self::Truth) -> bool {
        false
    }
    /// The right answers, in words.
    fn right_answers(case: &Self::Case, truth: &Self::Truth) -> String;

    // ---- Answers ----

    /// `method`'s answer to each case on `backend` (the reference on the CPU whatever the backend).
    fn answers(
        backend: &Backend,
        method: &Self::Method,
        cases: &[Self::Case],
    ) -> Result<Vec<Self::Answer>, BackendError>;
    /// `method`'s 4-wide version's answer to each case (plain f32; `tetwalk hit --wide` compares it
    /// with the scalar one), or `None` where the method has no such version.
    fn wide_answers(_method: &Self::Method, _cases: &[Self::Case]) -> Option<Vec<Self::Answer>> {
        None
    }
    /// The kind of ending an answer is (a face or a hit counts as [`OutcomeKind::Hit`]).
    fn kind(answer: &Self::Answer) -> OutcomeKind;
    /// An answer as a found case records it.
    fn answer_json(answer: &Self::Answer) -> Value;
    /// A recorded answer ([`Family::answer_json`]) read back for `case`.
    fn parse_answer(v: &Value, case: &Self::Case) -> Result<Self::Answer, String>;
    /// An answer given from outside (`tetwalk judge`: `{"line": n, …}`), its fields checked strictly.
    fn given(obj: &Map<String, Value>, case: &Self::Case) -> Result<Self::Answer, String>;
    /// Whether answers given from outside ([`Family::given`]: `judge`'s answers file, an `--answerer`)
    /// can be read for its cases line by line.
    const GIVEN: bool = true;
    /// An answer in words.
    fn describe(answer: &Self::Answer) -> String;
    /// A user's WGSL method of this family (`--wgsl`, `TETWALK_FUZZ_WGSL`), where the family has one.
    fn user_wgsl() -> Option<&'static Self::Method> {
        None
    }

    // ---- Stress rows ----

    /// The rows `rows` picks, in order.
    fn rows(rows: &Self::Rows) -> Vec<Self::Row>;
    fn row_name(row: &Self::Row) -> String;
    /// A row's name in a report of cases made under `contract`: its own, or, where the contract
    /// makes its cases other than its name says, what they then are.
    fn row_label(row: &Self::Row, _contract: &contract::Contract) -> String {
        Self::row_name(row)
    }
    /// Case `i` of `row` with its exact truth: a pure function of `(seed, row, i)` (which rows run
    /// beside it, and on which thread, do not matter); `None` for a case the oracle cannot judge.
    fn case(
        rows: &Self::Rows,
        row: Self::Row,
        seed: u64,
        i: usize,
    ) -> Option<(Self::Case, Self::Truth)>;
    /// What a row reports of its cases.
    fn row_facts(_cases: &[(Self::Case, Self::Truth)]) -> Self::RowFacts {
        Self::RowFacts::default()
    }
    /// Count one answer in a method's tally.
    fn tally(t: &mut Self::Tally, case: &Self::Case, truth: &Self::Truth, answer: &Self::Answer);
    /// Answers a tally judged.
    fn judged(facts: &Self::RowFacts, t: &Self::Tally) -> u64;
    /// Wrong answers among them.
    fn wrong(t: &Self::Tally) -> u64;
    /// Answers that refute the family's claim ([`Family::refutes_claim`]).
    fn refuted(t: &Self::Tally) -> u64 {
        Self::wrong(t)
    }
    /// The same rows under labelling `k` (`0..LABELLINGS`, 0 the cases' own).
    fn relabelled(rows: &Self::Rows, _k: usize) -> Self::Rows {
        rows.clone()
    }
    /// A case as the methods see it under `rows`' labelling.
    fn relabel(_rows: &Self::Rows, case: &Self::Case) -> Self::Case {
        *case
    }
    /// An answer to [`Family::relabel`]'s case in the case's own labelling.
    fn unrelabel(_rows: &Self::Rows, answer: Self::Answer) -> Self::Answer {
        answer
    }

    // ---- Shrinking (`crate::engine::shrink`) ----

    /// The command that answers a line of this family's cases (`exit`, `hit`, `box-exit`), for the
    /// one-line command that reproduces a shrunk case; `None` where no command reads them.
    const COMMAND: Option<&'static str> = None;

    /// The case's f32 numbers in a fixed order, for the shrinker to simplify: by default the ray's
    /// origin and direction.
    fn numbers(case: &Self::Case) -> Vec<f32> {
        let r = Self::ray(case);
        [r.org.to_array(), r.dir.to_array()].concat()
    }
    /// The case with its numbers replaced, in [`Family::numbers`]' order; `None` where they make no
    /// case of this shape (the oracle refuses the others).
    fn with_numbers(case: &Self::Case, n: &[f32]) -> Option<Self::Case> {
        let v = |i: usize| glam::Vec3::new(n[i], n[i + 1], n[i + 2]);
        Some(Self::with_ray(
            case,
            Ray {
                org: v(0),
                dir: v(3),
            },
        ))
    }
    /// Smaller cases of the same kind, tried before the numbers (fewer triangles, a smaller mesh).
    fn smaller(_case: &Self::Case) -> Vec<Self::Case> {
        Vec::new()
    }

    /// The case at power-of-two scale `s` ([`Scale`]): every number times 2^`s.points`, then the
    /// direction set to the case's own times 2^`s.direction`; `None` where they make no case.
    fn scaled(case: &Self::Case, s: Scale) -> Option<Self::Case> {
        let n: Vec<f32> = Self::numbers(case)
            .iter()
            .map(|&x| Scale::times(x, s.points))
            .collect();
        let c = Self::with_numbers(case, &n)?;
        let mut r = Self::ray(&c);
        r.dir = Self::ray(case).dir.map(|x| Scale::times(x, s.direction));
        Some(Self::with_ray(&c, r))
    }

    // ---- Answerers (`crate::engine::answerer`) ----

    /// A case as a binary record (docs/answerers.md), `None` where the family has none.
    fn case_record(_case: &Self::Case) -> Option<Vec<u8>> {
        None
    }
    /// Bytes of one binary answer record.
    const ANSWER_RECORD: usize = 0;
    /// A binary answer record read, for `case`.
    fn answer_record(_bytes: &[u8], _case: &Self::Case) -> Result<Self::Answer, String> {
        Err(format!(
            "the {} family has no binary answer record",
            Self::NAME
        ))
    }
    /// An answer given in another numbering of a tetrahedron's faces read in the case's own (answered
    /// face `i` is the case's `faces[i]`); other families' answers are as they are.
    fn renumbered(answer: Self::Answer, _faces: &[u8; 4]) -> Self::Answer {
        answer
    }
    /// The case as a program numbering a tetrahedron's faces `faces` is sent it (its face `i` the
    /// case's `faces[i]`: an entry face given in its numbering); other families' cases as they are.
    fn for_program(case: &Self::Case, _faces: &[u8; 4]) -> Self::Case {
        *case
    }
    /// Whether an answer names a tetrahedron's face, so that an answerer may number the faces its own
    /// way (`--faces`).
    const FACES: bool = false;
    /// `count` well-shaped cases holding `contract`, with their truths, on which an answerer's face
    /// numbering is found (`--faces auto`); none where answers name no face.
    fn numbering_cases(
        _contract: &contract::Contract,
        _count: usize,
    ) -> Vec<(Self::Case, Self::Truth)> {
        Vec::new()
    }

    // ---- Contracts (`contract`) ----

    /// Whether its cases can hold every [`contract::Contract`] (origin, entry face, orientation,
    /// tolerance); the others' hold a unit direction only.
    const CONTRACTS: bool = false;
    /// The case made to hold `contract` (`key` a pure choice per case, such as which cases are
    /// mirrored); `None` where it cannot be. By default only the direction is made a unit one.
    fn contracted(
        contract: &contract::Contract,
        case: &Self::Case,
        _key: u64,
    ) -> Option<Self::Case> {
        if !contract.unit_direction {
            return Some(*case);
        }
        let mut r = Self::ray(case);
        r.dir = contract::unit(r.dir)?;
        Some(Self::with_ray(case, r))
    }
    /// Whether the case, whose exact truth is `truth`, holds `contract`.
    fn holds(contract: &contract::Contract, case: &Self::Case, _truth: &Self::Truth) -> bool {
        !contract.unit_direction || contract::is_unit(Self::ray(case).dir)
    }

    // ---- Fuzzing and the kit ----

    /// A case decoded from fuzzer bytes (favouring near-degenerate geometry); `None` for bytes that
    /// make no case.
    fn arbitrary(u: &mut arbitrary::Unstructured) -> Option<Self::Case>;
    /// Cases per stress row in a kit run asking for `cases`.
    fn kit_row_cases(cases: usize) -> usize {
        cases
    }
    /// Random inputs of the kit's property campaign asking for `properties`.
    fn kit_properties(properties: usize) -> usize {
        properties
    }
}

/// Whether a case's own line reads back as the case (no zero direction, no number out of f32's range,
/// nothing else the case format refuses).
pub(crate) fn readable<F: Family>(case: &F::Case) -> bool {
    let mut obj = F::case_json(case);
    F::take_case(&mut obj).is_ok_and(|c| c == *case && obj.is_empty())
}

/// `case` at `scale` ([`Family::scaled`]), judged again as it then is: none where it no longer reads
/// back ([`readable`]: a number overflowed) or the oracle refuses it.
pub(crate) fn scaled_judged<F: Family>(
    case: &F::Case,
    scale: Scale,
) -> Option<(F::Case, F::Truth)> {
    let c = F::scaled(case, scale).filter(readable::<F>)?;
    Some((c, F::truth(&c).ok()?))
}

/// Points' coordinates, one after another ([`Family::numbers`]).
pub(crate) fn points_numbers<'a>(points: impl IntoIterator<Item = &'a glam::Vec3>) -> Vec<f32> {
    points.into_iter().flat_map(|p| p.to_array()).collect()
}

/// Numbers read back as points, three coordinates each ([`Family::with_numbers`]).
pub(crate) fn numbers_points(n: &[f32]) -> Vec<glam::Vec3> {
    n.chunks_exact(3).map(glam::Vec3::from_slice).collect()
}

/// The method of family `F` called `name`.
pub fn by_name<F: Family>(name: &str) -> Result<&'static F::Method, UnknownMethod> {
    crate::registry::find(F::methods(), name)
}

/// One registered method, as `tetwalk methods` lists it.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct Listed {
    pub(crate) name: &'static str,
    pub(crate) family: &'static str,
    pub(crate) claims_robust: bool,
    pub(crate) reference: bool,
    /// `yes`, or `no: ` and why.
    pub(crate) gpu: String,
    /// The paper, section and equation it implements.
    pub(crate) implements: &'static str,
}

/// Every registered method, each registry once: families that share one (exit faces and walks)
/// list it under the first.
pub(crate) fn listed() -> Vec<Listed> {
    use crate::choice::Choice;
    let mut seen: Vec<*const ()> = Vec::new();
    let mut rows: Vec<Listed> = Vec::new();
    for &k in Kind::ALL {
        crate::with_family!(k, F => {
            let at = F::methods().as_ptr() as *const ();
            if !seen.contains(&at) {
                seen.push(at);
                rows.extend(F::methods().iter().map(|m| {
                    let i = m.info();
                    Listed {
                        name: i.name,
                        family: F::NAME,
                        claims_robust: i.claim.is_some(),
                        reference: i.reference,
                        gpu: match i.gpu {
                            crate::registry::GpuVersion::Wgsl(_) => "yes".into(),
                            crate::registry::GpuVersion::CpuOnly(why) => format!("no: {why}"),
                        },
                        implements: i.source,
                    }
                }));
            }
        });
    }
    rows
}

/// Methods of family `F` from a comma-separated list (`all` for every one).
pub(crate) fn parse_list<F: Family>(names: &str) -> Result<Vec<&'static F::Method>, UnknownMethod> {
    crate::registry::list(F::methods(), names)
}

/// The family's reference method, if it has one.
pub fn reference<F: Family>() -> Option<&'static F::Method> {
    F::methods().iter().find(|m| m.is_reference())
}

/// The families, written once (in the spirit of CGAL's interface macros): `$then!` is called with
/// `[ARGS]` (what follows `$then,` here), each family's line — its [`Kind`] variant, its name, its
/// type, its folder's module — then its sections: `counted`, the families that count a scene;
/// `kit`, the conformance kit's entry points (each in its family's folder); `commands`, each family's
/// own command (its folder's `cli::Args` and `cli::run`, a subcommand named as the variant); `fuzz`,
/// the fuzz targets beyond each family's own ([`Family::FUZZ_TARGET`]), each a function of its
/// folder's `engine.rs` from the bytes a target is given to what a held method fails; `bench`, the
/// families `bench` times (`bench --family NAME`, each its folder's `cli::bench`); `pictures`, the
/// pictures of `render` each family draws (its folder's `cli::render`); `gen_cases`, the families
/// `gen-cases` writes (its folder's `cli::GenFlags` and `cli::gen_cases`; the last writes when no
/// other's flags ask). [`Kind`], [`of`], [`with_family!`], [`CountKind`], [`with_counted!`], the kit's
/// entry points, those subcommands, `fuzz-import`'s targets, `bench`'s families, `render`'s pictures
/// and `gen-cases`' flags expand from it; a new family is a line here and its entries.
#[doc(hidden)]
#[macro_export]
macro_rules! families {
    ($then:ident $(, $($args:tt)*)?) => {
        $crate::$then! {
            [$($($args)*)?]
            {
                /// One tetrahedron's exit face (seeds 000 and 003).
                ExitFace => "exit-face", $crate::family::ExitFace, exit_face;
                /// A walk through a generated mesh, step by step.
                Walk => "walk", $crate::family::Walks, walk;
                /// A ray and a closed triangle mesh (seed 004).
                Triangle => "triangle", $crate::family::Triangle, triangle;
                /// An octree cell's exit (seed 001).
                Octree => "octree", $crate::family::OctreeCells, octree;
            }
            counted { Walk: walk, Triangle: triangle, Octree: octree }
            kit { exit_face, walk, triangle, octree }
            commands { exit_face: Exit, octree: BoxExit, triangle: Hit, walk: Walk }
            fuzz { octree: octree_walk }
            bench { walk: "exit-face", triangle: "triangle" }
            pictures { walk: [Shaded, Failures, Heat], exit_face: [Predicate], octree: [OctreeHeat], triangle: [Leak] }
            gen_cases { triangle, octree, exit_face }
        }
    };
}

/// [`Kind`], [`of`] and [`CountKind`] from [`families!`].
#[doc(hidden)]
#[macro_export]
macro_rules! __family_kinds {
    ([] { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {
        /// A family, by name: a typed `--family` choice ([`families!`](crate::families)).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum Kind {
            $($(#[$doc])* #[serde(rename = $n)] $v,)*
        }

        $crate::choice!(Kind { $($v => $n),* });

        /// Each family's type, by its [`Kind`] variant's name ([`with_family!`](crate::with_family) reads them).
        pub mod of {
            $(
                #[doc = concat!("The `", $n, "` family.")]
                pub type $v = $ty;
            )*
        }

        /// The families that count a scene, by name: a typed `count --family` choice, and a count
        /// report's `family` ([`families!`](crate::families)).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum CountKind {
            $(
                #[doc = concat!("[`Kind::", stringify!($c), "`].")]
                $c,
            )*
        }

        impl CountKind {
            /// The family it names.
            pub fn kind(self) -> Kind {
                match self {
                    $(CountKind::$c => Kind::$c,)*
                }
            }
        }

        impl $crate::choice::Choice for CountKind {
            const ALL: &'static [Self] = &[$(CountKind::$c),*];
            fn name(self) -> &'static str {
                self.kind().name()
            }
        }

        impl serde::Serialize for CountKind {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str($crate::choice::Choice::name(*self))
            }
        }

        impl<'de> serde::Deserialize<'de> for CountKind {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let name = String::deserialize(d)?;
                <CountKind as $crate::choice::Choice>::from_name(&name).ok_or_else(|| {
                    serde::de::Error::custom(format!("'{name}' is not a family that counts a scene"))
                })
            }
        }
    };
}

families!(__family_kinds);

/// The conformance kit's entry points (`crate::kit`): each listed family's `kit.rs`'s public items,
/// re-exported, from [`families!`].
#[doc(hidden)]
#[macro_export]
macro_rules! __kit_entries {
    ([] { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } kit { $($km:ident),* } $($rest:tt)*) => {
        $(pub use $crate::family::$km::kit::*;)*
    };
}

/// Run `$body` with `$F` the family type a [`Kind`] names.
#[doc(hidden)]
#[macro_export]
macro_rules! with_family {
    ($kind:expr, $F:ident => $body:expr) => {
        $crate::families!(__kind_match, Kind, $kind, $F, $body)
    };
}

/// Run `$body` with `$F` the counted family a [`CountKind`] names.
#[doc(hidden)]
#[macro_export]
macro_rules! with_counted {
    ($kind:expr, $F:ident => $body:expr) => {
        $crate::families!(__kind_match, CountKind, $kind, $F, $body)
    };
}

/// [`with_family!`]'s and [`with_counted!`]'s match, from [`families!`]: over every family for a
/// [`Kind`], over the counted ones for a [`CountKind`].
#[doc(hidden)]
#[macro_export]
macro_rules! __kind_match {
    ([Kind, $kind:expr, $F:ident, $body:expr]
        { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {
        $crate::__kind_match!(@ Kind, $kind, $F, $body, $($v)*)
    };
    ([CountKind, $kind:expr, $F:ident, $body:expr]
        { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {
        $crate::__kind_match!(@ CountKind, $kind, $F, $body, $($c)*)
    };
    (@ $enum:ident, $kind:expr, $F:ident, $body:expr, $($v:ident)*) => {
        match $kind {
            $(
                $crate::family::$enum::$v => {
                    type $F = $crate::family::of::$v;
                    $body
                }
            )*
        }
    };
}

/// The family whose case a JSON object holds, by its keys.
pub fn owner(obj: &Map<String, Value>) -> Kind {
    use crate::choice::Choice;
    Kind::ALL
        .iter()
        .copied()
        .find(|&k| crate::with_family!(k, F => F::owns(obj)))
        .unwrap_or(Kind::ExitFace)
}

/// An answer given from outside, its fields checked as strictly as a case's: only the keys
/// `allowed` for this kind of case (and `line`), each of `required` present (null allowed where the
/// kind allows no answer).
pub(crate) fn given_fields<'a>(
    o: &'a Map<String, Value>,
    kind: &str,
    allowed: &[&str],
    required: &[&str],
) -> Result<&'a Map<String, Value>, String> {
    let shape = || {
        let keys: Vec<String> = allowed.iter().map(|k| format!("\"{k}\"")).collect();
        format!("an answer to {kind} holds \"line\" and {}", keys.join(", "))
    };
    if let Some(k) = o
        .keys()
        .find(|k| *k != "line" && !allowed.contains(&k.as_str()))
    {
        return Err(format!("unknown field \"{k}\": {}", shape()));
    }
    if let Some(k) = required.iter().find(|k| !o.contains_key(**k)) {
        return Err(format!("missing field \"{k}\": {}", shape()));
    }
    Ok(o)
}
