//! One tetrahedron's exit face (seeds 000 and 003): a tetrahedron, a ray and the face it entered
//! through; the answer a face, judged against every exact exit face.

use super::{Family, Verdict, given_fields};
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
});

/// A stress row of tetrahedron cases, as its report's row writes it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ExitRow {
    pub row: TetRow,
}

/// What shapes a stress run of tetrahedron cases.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ExitRows {
    pub rows: Vec<TetRow>,
    /// Flatness of the degenerate shapes (well-shaped ones use 1).
    pub flatness: f32,
    /// Largest ulp offset of the near-* rows.
    pub ulps: i32,
    /// How every case's tetrahedron is relabelled before the methods see it (new vertex `i` is old
    /// vertex `relabel[i]`; answers are mapped back): one of [`EVEN_PERMUTATIONS`].
    pub relabel: [usize; 4],
}

impl Default for ExitRows {
    fn default() -> Self {
        ExitRows {
            rows: <TetRow as crate::choice::Choice>::ALL.to_vec(),
            flatness: 1e-3,
            ulps: 4,
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
}

impl super::Summed for ExitTally {
    fn add(&mut self, o: &Self) {
        self.judged += o.judged;
        self.wrong_face += o.wrong_face;
        self.no_exit_face += o.no_exit_face;
    }
}

/// The face (0..3, in the case's own numbering) a method answers, or none.
pub type Face = Option<u8>;

/// Case `i` of `row`: a pure function of `(seed, row, i)`.
fn generate(rows: &ExitRows, row: TetRow, seed: u64, i: usize) -> Option<(crate::tet::Tet, Ray)> {
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
            let d = 10f32.powf(r.random_range(4.0..6.0));
            let dir = Vec3::new(
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
            );
            tets::translated(&t, &ray, dir.normalize_or(Vec3::X) * d)
        }
        TetRow::NearEdge => tets::near(shape, flat(shape), Target::Edge, rows.ulps, &mut r),
        TetRow::NearVertex => tets::near(shape, flat(shape), Target::Vertex, rows.ulps, &mut r),
        TetRow::ThroughEdge => tets::through(shape, flat(shape), Target::Edge, &mut r),
        TetRow::ThroughVertex => tets::through(shape, flat(shape), Target::Vertex, &mut r),
    }
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
    const BYTES_PER_CASE: u128 = 112;
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
        let v = serde_json::json!({
            "tet": c.tet.map(|p| p.to_array()),
            "org": c.org.to_array(),
            "dir": c.dir.to_array(),
            "entry": c.entry,
        });
        match v {
            Value::Object(m) => m,
            _ => Map::new(),
        }
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

    /// The exact line meets the tetrahedron, but the oracle's symbolically perturbed line (as the
    /// `exact` walk perturbs it) misses it: the line grazes an edge or vertex, or runs along a face.
    fn touch_only(c: &Case) -> bool {
        let (tet, _) = normalize(&c.tet);
        perturbed_exit(&tet, &c.ray()).is_ok_and(|(face, x)| face.is_none() && x.meets())
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

    /// Even-numbered cases carry the exact entry face (as a walk has it), odd ones none (a starting
    /// tetrahedron).
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
}
