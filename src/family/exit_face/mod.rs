//! One tetrahedron's exit face (seeds 000 and 003): a tetrahedron, a ray and the face it entered
//! through; the answer a face, judged against every exact exit face.

#[cfg(feature = "cli")]
pub mod cli;
pub mod engine;
pub mod kit;
#[cfg(feature = "internals")]
mod report;

use super::contract::{self, Contract, EntryGiven, Orientation, Origin};
use super::{Family, Said, TetSaid, Verdict, given_fields};
use crate::backend::{Backend, BackendError};
use crate::cases::{CaseError, classify, field_error, vec3};
use crate::exact::{Classification, perturbed_exit};
use crate::registry::{METHODS, Method, USER_WGSL};
use crate::scenes::tets::{self, Target, TetShape};
use crate::tet::{Case, EVEN_PERMUTATIONS, Ray, normalize};
use crate::walk::OutcomeKind;
use glam::Vec3;
use rand::RngExt;
use serde_json::{Map, Value};

/// One tetrahedron's exit face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExitFace;

/// The stress rows of tetrahedron cases: a tetrahedron shape with stabbing rays, or a way of aiming
/// rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TetRow {
    Well,
    Sliver,
    Cap,
    Needle,
    Wedge,
    /// Well-shaped, moved 1e4 to 1e6 from the origin.
    FarOffset,
    /// Within k ulps of an edge (every shape in turn).
    NearEdge,
    /// Within k ulps of a vertex.
    NearVertex,
    /// Exactly through an edge.
    ThroughEdge,
    /// Exactly through a vertex.
    ThroughVertex,
    /// Every shape in turn, moved 10 to 1,000 from the origin: where a mesh in millimetres sits (last,
    /// so that the other rows' cases, seeded by their place, stay as they were).
    MmOffset,
}

crate::choice!(TetRow {
    Well => "well",
    Sliver => "sliver",
    Cap => "cap",
    Needle => "needle",
    Wedge => "wedge",
    FarOffset => "far-offset",
    NearEdge => "near-edge",
    NearVertex => "near-vertex",
    ThroughEdge => "through-edge",
    ThroughVertex => "through-vertex",
    MmOffset => "mm-offset",
});

/// A stress row of tetrahedron cases, as its report's row writes it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ExitRow {
    pub(crate) row: TetRow,
}

/// What shapes a stress run of tetrahedron cases.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ExitRows {
    pub(crate) rows: Vec<TetRow>,
    /// Flatness of the degenerate shapes (well-shaped ones use 1).
    pub(crate) flatness: f32,
    /// Largest ulp offset of the near-* rows.
    pub(crate) ulps: i32,
    /// Every case moved this far from the origin along (1, 1, 1) (`--offset`; each coordinate rounded
    /// to f32, the case judged as it then is); 0 for none.
    pub(crate) offset: f32,
    /// How every case's tetrahedron is relabelled before the methods see it (new vertex `i` is old
    /// vertex `relabel[i]`; answers are mapped back): one of [`EVEN_PERMUTATIONS`].
    pub(crate) relabel: [usize; 4],
}

impl Default for ExitRows {
    fn default() -> Self {
        ExitRows {
            rows: <TetRow as crate::choice::Choice>::ALL.to_vec(),
            flatness: 1e-3,
            ulps: 4,
            offset: 0.0,
            relabel: EVEN_PERMUTATIONS[0],
        }
    }
}

/// One method's counts on one row.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ExitTally {
    /// Cases whose line meets the tetrahedron (the others are not judged).
    pub judged: u64,
    pub wrong_face: u64,
    pub no_exit_face: u64,
    /// Of the wrong answers: at a tie (the line leaves through an edge or vertex, more than one face
    /// right), and on a line that only touches the tetrahedron.
    pub(crate) wrong_at_tie: u64,
    pub(crate) wrong_touch_only: u64,
}

impl super::Summed for ExitTally {
    fn add(&mut self, o: &Self) {
        self.judged += o.judged;
        self.wrong_face += o.wrong_face;
        self.no_exit_face += o.no_exit_face;
        self.wrong_at_tie += o.wrong_at_tie;
        self.wrong_touch_only += o.wrong_touch_only;
    }
}

/// The face (0..3, in the case's own numbering) a method answers, or none.
pub(crate) type Face = Option<u8>;

/// Case `i` of `row`: a pure function of `(seed, row, i)`, moved by the rows' offset.
fn generate(rows: &ExitRows, row: TetRow, seed: u64, i: usize) -> Option<(crate::tet::Tet, Ray)> {
    let (t, ray) = made(rows, row, seed, i)?;
    if rows.offset == 0.0 {
        return Some((t, ray));
    }
    tets::translated(&t, &ray, Vec3::splat(rows.offset / 3f32.sqrt()))
}

/// Case `i` of `row` where the row makes it.
fn made(rows: &ExitRows, row: TetRow, seed: u64, i: usize) -> Option<(crate::tet::Tet, Ray)> {
    let key = seed
        ^ (row as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ (i as u64).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let mut r = crate::scenes::rng(key);
    let shape = TetShape::ALL[i % TetShape::ALL.len()];
    let flat = |f: TetShape| {
        if f == TetShape::Well {
            1.0
        } else {
            rows.flatness
        }
    };
    let stab = |f: TetShape, r: &mut crate::scenes::Rng| {
        let t = tets::tet(f, flat(f), r);
        let ray = tets::stabbing_ray(&t, r);
        Some((t, ray))
    };
    match row {
        TetRow::Well => stab(TetShape::Well, &mut r),
        TetRow::Sliver => stab(TetShape::Sliver, &mut r),
        TetRow::Cap => stab(TetShape::Cap, &mut r),
        TetRow::Needle => stab(TetShape::Needle, &mut r),
        TetRow::Wedge => stab(TetShape::Wedge, &mut r),
        TetRow::FarOffset => {
            let (t, ray) = stab(TetShape::Well, &mut r)?;
            away(&t, &ray, 4.0..6.0, &mut r)
        }
        TetRow::MmOffset => {
            let (t, ray) = stab(shape, &mut r)?;
            away(&t, &ray, 1.0..3.0, &mut r)
        }
        TetRow::NearEdge => tets::near(shape, flat(shape), Target::Edge, rows.ulps, &mut r),
        TetRow::NearVertex => tets::near(shape, flat(shape), Target::Vertex, rows.ulps, &mut r),
        TetRow::ThroughEdge => tets::through(shape, flat(shape), Target::Edge, &mut r),
        TetRow::ThroughVertex => tets::through(shape, flat(shape), Target::Vertex, &mut r),
    }
}

/// The case moved 10^e from the origin (`e` drawn in `powers`) in a random direction.
fn away(
    t: &crate::tet::Tet,
    ray: &Ray,
    powers: std::ops::Range<f32>,
    r: &mut crate::scenes::Rng,
) -> Option<(crate::tet::Tet, Ray)> {
    let d = 10f32.powf(r.random_range(powers));
    let dir = Vec3::new(
        r.random_range(-1.0..1.0),
        r.random_range(-1.0..1.0),
        r.random_range(-1.0..1.0),
    );
    tets::translated(t, ray, dir.normalize_or(Vec3::X) * d)
}

/// A face number 0..3, or null.
fn face(v: &Value) -> Result<Face, String> {
    match v {
        Value::Null => Ok(None),
        f => Ok(Some(
            f.as_u64()
                .filter(|&f| f < 4)
                .ok_or_else(|| format!("{f} is not a face 0..3 or null"))? as u8,
        )),
    }
}

impl Family for ExitFace {
    const NAME: &'static str = "exit-face";
    const FUZZ_TARGET: &'static str = "exit_face";
    const BYTES_PER_CASE: u128 = 256;
    const LABELLINGS: usize = 12;

    type Method = Method;
    type Case = Case;
    type Truth = Classification;
    type Answer = Face;
    type Rows = ExitRows;
    type Row = ExitRow;
    type RowFacts = ();
    type Tally = ExitTally;

    fn methods() -> &'static [Method] {
        METHODS
    }

    fn owns(obj: &Map<String, Value>) -> bool {
        obj.contains_key("tet")
    }

    fn take_case(obj: &mut Map<String, Value>) -> Result<Case, CaseError> {
        let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
        let tet = field("tet")?;
        let tet = tet
            .as_array()
            .filter(|a| a.len() == 4)
            .ok_or_else(|| field_error("tet", "must hold four points"))?;
        let mut t = [Vec3::ZERO; 4];
        for (i, p) in tet.iter().enumerate() {
            t[i] = vec3(p).map_err(|e| field_error(format!("tet[{i}]"), e))?;
        }
        let org = vec3(&field("org")?).map_err(|e| field_error("org", e))?;
        let dir = vec3(&field("dir")?).map_err(|e| field_error("dir", e))?;
        let entry = match field("entry").unwrap_or(Value::Null) {
            Value::Null => None,
            e => Some(
                e.as_u64()
                    .filter(|&f| f < 4)
                    .ok_or_else(|| field_error("entry", format!("must be 0..3 or null, not {e}")))?
                    as u8,
            ),
        };
        Ok(Case {
            tet: t,
            org,
            dir,
            entry,
        })
    }

    fn case_json(c: &Case) -> Map<String, Value> {
        crate::cases::tet_case_json(c)
    }

    fn ray(c: &Case) -> Ray {
        c.ray()
    }

    fn with_ray(c: &Case, ray: Ray) -> Case {
        Case {
            org: ray.org,
            dir: ray.dir,
            ..*c
        }
    }

    const COMMAND: Option<&'static str> = Some("exit");

    /// The four vertices, then the origin and direction.
    fn numbers(c: &Case) -> Vec<f32> {
        super::points_numbers(c.tet.iter().chain([&c.org, &c.dir]))
    }

    fn with_numbers(c: &Case, n: &[f32]) -> Option<Case> {
        let p = super::numbers_points(n);
        Some(Case {
            tet: [p[0], p[1], p[2], p[3]],
            org: p[4],
            dir: p[5],
            entry: c.entry,
        })
    }

    fn truth(c: &Case) -> Result<Classification, CaseError> {
        classify(c)
    }

    fn verdict(_: &Case, x: &Classification, face: &Face) -> Verdict {
        match (x.meets(), face) {
            (false, _) => Verdict::NotJudged,
            (true, Some(f)) if x.exit.contains(*f as usize) => Verdict::Right,
            (true, f) => Verdict::Wrong(Self::kind(f)),
        }
    }

    /// Besides right or wrong: with a face or none, at a tie, on a line that only touches.
    fn said(c: &Case, x: &Classification, face: &Face, _: f64) -> Said {
        let v = Self::verdict(c, x, face);
        Said {
            correct: v.correct(),
            cell: true,
            tet: Some(TetSaid {
                wrong: match v {
                    Verdict::Wrong(_) if face.is_some() => Some("wrong_face"),
                    Verdict::Wrong(_) => Some("no_exit_face"),
                    _ => None,
                },
                tie: Self::tie(x),
                touch_only: x.meets() && Self::touch_only(c),
            }),
            ..Said::default()
        }
    }

    /// The exact line meets the tetrahedron, but the oracle's symbolically perturbed line (as the
    /// `exact` walk perturbs it) misses it: the line grazes an edge or vertex, or runs along a face.
    fn touch_only(c: &Case) -> bool {
        let (tet, _) = normalize(&c.tet);
        perturbed_exit(&tet, &c.ray()).is_ok_and(|(face, x)| face.is_none() && x.meets())
    }

    fn tie(x: &Classification) -> bool {
        x.exit.iter().count() > 1
    }

    /// The same exact exit faces.
    fn same_truth(a: &Classification, b: &Classification) -> bool {
        a.exit == b.exit
    }

    /// The exact exit point's least barycentric coordinate in its exit face (0 at a tie: through an
    /// edge or vertex), computed in f64.
    fn clearance(c: &Case, x: &Classification) -> f64 {
        let Some(f) = x.exit.first() else {
            return 0.0;
        };
        let [a, b, v] = crate::tet::FACE_VERTICES[f].map(|i| c.tet[i].as_dvec3());
        let (o, d) = (c.org.as_dvec3(), c.dir.as_dvec3());
        let n = (b - a).cross(v - a);
        let p = o + d * (n.dot(a - o) / n.dot(d));
        let area = |p: glam::DVec3, q: glam::DVec3, r: glam::DVec3| (q - p).cross(r - p).dot(n);
        let whole = area(a, b, v);
        let least = [area(p, b, v), area(a, p, v), area(a, b, p)]
            .into_iter()
            .map(|s| s / whole)
            .fold(f64::INFINITY, f64::min);
        if least.is_finite() {
            least.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    fn right_answers(_: &Case, x: &Classification) -> String {
        format!(
            "exit faces {:?} (entry faces {:?})",
            x.exit.to_vec(),
            x.entry.to_vec()
        )
    }

    fn answers(backend: &Backend, m: &Method, cases: &[Case]) -> Result<Vec<Face>, BackendError> {
        Ok(backend
            .exit_faces(m, cases)?
            .into_iter()
            .map(|f| f.map(|f| f as u8))
            .collect())
    }

    fn kind(face: &Face) -> OutcomeKind {
        match face {
            Some(_) => OutcomeKind::Hit,
            None => OutcomeKind::NoExitFace,
        }
    }

    fn answer_json(face: &Face) -> Value {
        serde_json::json!(face)
    }

    fn parse_answer(v: &Value, _: &Case) -> Result<Face, String> {
        face(v)
    }

    fn given(obj: &Map<String, Value>, _: &Case) -> Result<Face, String> {
        let o = given_fields(obj, "a tetrahedron case", &["face"], &["face"])?;
        match &o["face"] {
            Value::Null => Ok(None),
            f => Ok(Some(
                f.as_u64()
                    .filter(|&f| f < 4)
                    .ok_or_else(|| match f.as_i64() {
                        Some(..0) => {
                            format!("the answer's face {f}: no exit face is written \"face\": null")
                        }
                        _ => format!("the answer's face {f} is not 0..3 or null"),
                    })? as u8,
            )),
        }
    }

    fn describe(face: &Face) -> String {
        match face {
            Some(f) => format!("exit face {f}"),
            None => "no exit face".into(),
        }
    }

    fn user_wgsl() -> Option<&'static Method> {
        Some(&USER_WGSL)
    }

    fn rows(rows: &ExitRows) -> Vec<ExitRow> {
        rows.rows.iter().map(|&row| ExitRow { row }).collect()
    }

    fn row_name(row: &ExitRow) -> String {
        crate::choice::Choice::name(row.row).to_string()
    }

    /// Under a unit direction the through-* rows' lines, their directions rounded, pass beside the
    /// edge or vertex by a fraction of an ulp (a tie only where the rounding is exact): near rows.
    fn row_label(row: &ExitRow, k: &Contract) -> String {
        let name = Self::row_name(row);
        match row.row {
            TetRow::ThroughEdge | TetRow::ThroughVertex if k.unit_direction => {
                format!("{name} (unit direction: near, by its rounding)")
            }
            _ => name,
        }
    }

    /// Even-numbered cases carry the exact entry face (as a walk has it), odd ones none (a starting
    /// tetrahedron). What the rows promise besides (the line crossing, the origin inside or before,
    /// positive orientation) is held where their cases are taken ([`contract::cases_within`]).
    fn case(rows: &ExitRows, row: ExitRow, seed: u64, i: usize) -> Option<(Case, Classification)> {
        let (tet, ray) = generate(rows, row.row, seed, i)?;
        let mut c = Case {
            tet,
            org: ray.org,
            dir: ray.dir,
            entry: None,
        };
        let x = classify(&c).ok()?;
        if i.is_multiple_of(2) {
            c.entry = x.entry.first().map(|f| f as u8);
        }
        Some((c, x))
    }

    fn tally(t: &mut ExitTally, c: &Case, x: &Classification, face: &Face) {
        match Self::verdict(c, x, face) {
            Verdict::NotJudged => {}
            Verdict::Right => t.judged += 1,
            Verdict::Wrong(_) => {
                t.judged += 1;
                t.wrong_face += face.is_some() as u64;
                t.no_exit_face += face.is_none() as u64;
                t.wrong_at_tie += Self::tie(x) as u64;
                t.wrong_touch_only += Self::touch_only(c) as u64;
            }
        }
    }

    fn judged(_: &(), t: &ExitTally) -> u64 {
        t.judged
    }

    fn wrong(t: &ExitTally) -> u64 {
        t.wrong_face + t.no_exit_face
    }

    fn relabelled(rows: &ExitRows, k: usize) -> ExitRows {
        ExitRows {
            relabel: EVEN_PERMUTATIONS[k],
            ..rows.clone()
        }
    }

    fn relabel(rows: &ExitRows, c: &Case) -> Case {
        c.relabelled(rows.relabel)
    }

    fn unrelabel(rows: &ExitRows, face: Face) -> Face {
        face.map(|f| rows.relabel[f as usize] as u8)
    }

    fn arbitrary(u: &mut arbitrary::Unstructured) -> Option<Case> {
        crate::scenes::from_bytes::exit_case(u).ok().flatten()
    }

    /// 76 bytes after the case's number: the four vertices, the origin and the direction (18 f32),
    /// the entry face (i32, -1 for none).
    fn case_record(c: &Case) -> Option<Vec<u8>> {
        let mut b: Vec<u8> = Self::numbers(c)
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        b.extend(c.entry.map_or(-1, |e| e as i32).to_le_bytes());
        Some(b)
    }

    /// 4 bytes after the case's number: the exit face (i32, -1 for none).
    const ANSWER_RECORD: usize = 4;

    fn answer_record(b: &[u8], _: &Case) -> Result<Face, String> {
        match i32::from_le_bytes(b.try_into().map_err(|_| "a short record")?) {
            -1 => Ok(None),
            f @ 0..=3 => Ok(Some(f as u8)),
            f => Err(format!("answered face {f}, not 0..3 or -1 (none)")),
        }
    }

    const FACES: bool = true;
    /// The `well` stress row's cases.
    fn numbering_cases(k: &Contract, count: usize) -> Vec<(Case, Classification)> {
        let rows = ExitRows {
            rows: vec![TetRow::Well],
            ..Default::default()
        };
        let row = ExitRow { row: TetRow::Well };
        contract::cases_within::<Self>(k, count, |i| Self::case(&rows, row, 0x5eed_face, i))
    }
    fn renumbered(face: Face, faces: &[u8; 4]) -> Face {
        face.map(|f| faces[f as usize])
    }
    /// The entry face in the program's numbering: its face `i` where `faces[i]` is the case's.
    fn for_program(c: &Case, faces: &[u8; 4]) -> Case {
        Case {
            entry: c
                .entry
                .and_then(|e| faces.iter().position(|&f| f == e).map(|i| i as u8)),
            ..*c
        }
    }

    const CONTRACTS: bool = true;

    /// Mirrored (vertices 0 and 1 swapped) where the contract takes the negative orientation, or
    /// either and `key`'s bit 1 is set; the direction made a unit one; the origin made for one of the
    /// contract's placements in turn (by `key`'s higher bits): kept where it already lies there, else
    /// moved along the line (inside, before: rounded to f32; entry: [`contract::entry_origin`]) and
    /// the case judged again as it then is; the entry face given or left out. `None` where the line
    /// misses the tetrahedron (every row promises a crossing).
    fn contracted(k: &Contract, c: &Case, key: u64) -> Option<Case> {
        let mut c = *c;
        if k.orientation == Orientation::Negative
            || (k.orientation == Orientation::Any && key & 2 != 0)
        {
            c.tet.swap(0, 1);
            c.entry = c.entry.map(|e| [1, 0, 2, 3][e as usize]);
        }
        if k.unit_direction {
            c.dir = contract::unit(c.dir)?;
        }
        let x = classify(&c).ok()?;
        if !x.meets() {
            return None;
        }
        let target = k.origin.for_key(key >> 2);
        if !origin_holds(target, &c, &x) {
            let (t_in, t_out) = span(&c.tet, c.org, c.dir)?;
            let at = |t: f64| c.org.as_dvec3() + c.dir.as_dvec3() * t;
            c.org = match target {
                Origin::Anywhere => return None,
                Origin::Inside => at(0.5 * (t_in + t_out)).as_vec3(),
                Origin::Entry => contract::entry_origin(&c.tet, at(t_in), x.entry.first()?, c.dir)?,
                Origin::Before => at(t_in - 0.5 * (t_out - t_in)).as_vec3(),
            };
        }
        let x = classify(&c).ok()?;
        c.entry = match k.entry {
            EntryGiven::Any => c.entry.filter(|&e| x.entry.contains(e as usize)),
            EntryGiven::Given => Some(x.entry.first()? as u8),
            EntryGiven::None => None,
        };
        Some(c)
    }

    fn holds(k: &Contract, c: &Case, x: &Classification) -> bool {
        let meets = x.meets();
        let entry = match (k.entry, c.entry) {
            (EntryGiven::None, e) => e.is_none(),
            (EntryGiven::Given, None) => false,
            (_, e) => e.is_none_or(|e| x.entry.contains(e as usize)),
        };
        meets
            && entry
            && match k.orientation {
                Orientation::Positive => crate::tet::orientation(&c.tet) > 0,
                Orientation::Negative => crate::tet::orientation(&c.tet) < 0,
                Orientation::Any => true,
            }
            && (!k.unit_direction || contract::is_unit(c.dir))
            && k.origin.placements().iter().any(|&o| origin_holds(o, c, x))
            && (k.tolerance == 0.0 || contract::edge_distance(&c.tet, c.org, c.dir) >= k.tolerance)
    }
}

/// Whether the case's origin lies where `origin` says, for a line whose exact faces are `x`, each
/// decided exactly: anywhere, as the rows place it (in the closed tetrahedron or before it on the
/// line, never past its exit); strictly inside; strictly outside the plane of every entry face
/// (before the line enters); on an entry face, or as near one inside as f32 allows
/// ([`contract::holds_entry`]).
fn origin_holds(origin: Origin, c: &Case, x: &Classification) -> bool {
    let (tet, o) = (&c.tet, c.org);
    match origin {
        Origin::Anywhere => !contract::past_exit(tet, o, c.dir),
        Origin::Inside => contract::strictly_inside(tet, o),
        Origin::Before => {
            !x.entry.is_empty() && x.entry.iter().all(|f| contract::face_side(tet, f, o) < 0)
        }
        Origin::Entry => contract::holds_entry(tet, o, c.dir),
    }
}

/// The parameters where the line `o + t·d` enters and leaves the tetrahedron, in f64; `None` where
/// it misses it there.
fn span(tet: &crate::tet::Tet, o: Vec3, d: Vec3) -> Option<(f64, f64)> {
    let (o, d) = (o.as_dvec3(), d.as_dvec3());
    let (mut t_in, mut t_out) = (f64::NEG_INFINITY, f64::INFINITY);
    for (f, v) in crate::tet::FACE_VERTICES.iter().enumerate() {
        let [a, b, c] = v.map(|i| tet[i].as_dvec3());
        let mut n = (b - a).cross(c - a);
        // Outward: away from the opposite vertex.
        if n.dot(tet[f].as_dvec3() - a) > 0.0 {
            n = -n;
        }
        let (num, den) = (n.dot(a - o), n.dot(d));
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
            continue;
        }
        let t = num / den;
        if den < 0.0 {
            t_in = t_in.max(t);
        } else {
            t_out = t_out.min(t);
        }
    }
    (t_in.is_finite() && t_out.is_finite() && t_in <= t_out).then_some((t_in, t_out))
}
