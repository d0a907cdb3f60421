//! Verdict lines: one JSON line per case and method, the method's answer beside the exact one, as
//! `exit`, `hit`, `box-exit` and `judge` write them.

use crate::exact::Classification;
use crate::exact::boxes::BoxExit;
use crate::exact::hit::HitTruth;
use crate::family::exit_face::Face;
use crate::family::octree::CellExit;
use crate::family::triangle::Hits;
use crate::family::walk::WalkTruth;
use crate::family::{ExitFace, Family, OctreeCells, Triangle, Verdict, Walks};
use crate::octree::cell::FACE_NAMES;
use crate::walk::Walk;
use serde_json::{Map, Value, json};

/// What a verdict line says of an answer: right, wrong, or not judged (`None`), whether it leaks,
/// whether the ray first meets a back face there ([`HitTruth::back_face`]), and whether a hit is wrong
/// for its `t` alone (its triangle right).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Said {
    pub correct: Option<bool>,
    /// A cell's case (a tetrahedron's or an octree cell's), whose line may miss the cell.
    pub cell: bool,
    /// A triangle case (leaks, back faces and `t` are counted).
    pub triangle: bool,
    /// A tetrahedron's case: how it was answered.
    pub tet: Option<TetSaid>,
    pub leak: bool,
    pub back_face: bool,
    pub t_alone: bool,
    /// What a wrong closed-mesh answer is ([`HitTruth::wrong_kind`]).
    pub kind: Option<&'static str>,
}

/// What a tetrahedron case's verdict line says besides right or wrong.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TetSaid {
    /// Wrong with a face (`wrong_face`) or with none (`no_exit_face`).
    pub wrong: Option<&'static str>,
    /// More than one face is right: the line leaves through an edge or vertex.
    pub tie: bool,
    /// The line only touches the tetrahedron (an edge, a vertex, along a face).
    pub touch_only: bool,
}

/// How a family's verdict lines read.
pub trait Lines: Family {
    /// The fields after `line`, `method` and `backend`: the answer beside the exact one, and
    /// `correct`. A hit's `t` is right within `t_ulps` ulps of the exact `t`.
    fn verdict_line(
        case: &Self::Case,
        truth: &Self::Truth,
        answer: &Self::Answer,
        t_ulps: f64,
    ) -> (Map<String, Value>, Said);
}

/// The object of `v`.
fn fields(v: Value) -> Map<String, Value> {
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

/// The verdict's `correct`: `null` where the case is not judged.
fn correct(v: Verdict) -> Option<bool> {
    match v {
        Verdict::Right => Some(true),
        Verdict::Wrong(_) => Some(false),
        Verdict::NotJudged => None,
    }
}

impl Lines for ExitFace {
    fn verdict_line(
        c: &crate::tet::Case,
        x: &Classification,
        face: &Face,
        _: f64,
    ) -> (Map<String, Value>, Said) {
        let v = Self::verdict(c, x, face);
        let ok = correct(v);
        let said = TetSaid {
            wrong: match v {
                Verdict::Wrong(_) if face.is_some() => Some("wrong_face"),
                Verdict::Wrong(_) => Some("no_exit_face"),
                _ => None,
            },
            tie: Self::tie(x),
            touch_only: x.meets() && Self::touch_only(c),
        };
        let verdict = match v {
            Verdict::Right => "right",
            Verdict::NotJudged => "not_judged",
            Verdict::Wrong(_) => said.wrong.unwrap_or_default(),
        };
        let line = json!({
            "face": face, "exact_exit": x.exit.to_vec(), "exact_entry": x.entry.to_vec(),
            "correct": ok, "verdict": verdict, "tie": said.tie, "touch_only": said.touch_only,
        });
        (
            fields(line),
            Said {
                correct: ok,
                cell: true,
                tet: Some(said),
                ..Said::default()
            },
        )
    }
}

impl Lines for Walks {
    fn verdict_line(
        c: &crate::cases::WalkCase,
        t: &WalkTruth,
        got: &Walk,
        _: f64,
    ) -> (Map<String, Value>, Said) {
        let ok = correct(Self::verdict(c, t, got));
        let line = json!({
            "walk": got.outcome, "steps": got.steps, "exact_walk": t.exact.outcome, "correct": ok,
        });
        (
            fields(line),
            Said {
                correct: ok,
                ..Said::default()
            },
        )
    }
}

/// A rational as `p/q`.
fn ratio(q: &rug::Rational) -> String {
    format!("{}/{}", q.numer(), q.denom())
}

impl Lines for Triangle {
    /// Judged by the family's one rule ([`HitTruth::judge`]: the triangle and, for a hit, its `t`);
    /// on a closed mesh, every triangle the method reports says whether the ray leaks.
    fn verdict_line(
        case: &crate::cases::HitCase,
        truth: &HitTruth,
        hits: &Hits,
        t_ulps: f64,
    ) -> (Map<String, Value>, Said) {
        let g = hits.nearest();
        let judged = truth.judge(g, t_ulps);
        let (t, triangle_right, ok) = (judged.t, judged.triangle, judged.right);
        let first = truth.first();
        let mut o = fields(json!({
            "hit": g.is_some(), "t": g.map(|(_, t)| t), "t_ulps": t.and_then(|t| t.ulps),
            "exact_hit": first.is_some(), "exact_t": first.map(|p| ratio(&p.t)),
        }));
        let mut leak = false;
        let mut kind = None;
        if case.closed {
            leak = truth.leaks(&hits.ids());
            o.insert("tri".into(), json!(g.map(|(i, _)| i)));
            let holding = first.map_or(vec![], |p| p.holding.clone());
            let boundary = holding.iter().any(|&i| truth.each[i as usize].on_boundary);
            o.insert("exact_tris".into(), json!(holding));
            o.insert("on_boundary".into(), Value::Bool(boundary));
            o.insert("crosses".into(), json!(first.map(|p| p.crosses)));
            o.insert("leak".into(), Value::Bool(leak));
            kind = truth.wrong_kind(&hits.ids(), g.map(|(i, _)| i));
            o.insert(
                "kind".into(),
                json!(kind.unwrap_or(if ok { "right" } else { "t" })),
            );
            if crate::exact::hit::inside_out(case.tris()) {
                o.insert("inside_out".into(), Value::Bool(true));
            }
        } else {
            o.insert("on_boundary".into(), Value::Bool(truth.each[0].on_boundary));
        }
        if truth.back_face() {
            o.insert("back_face".into(), Value::Bool(true));
        }
        o.insert("correct".into(), Value::Bool(ok));
        (
            o,
            Said {
                correct: Some(ok),
                triangle: true,
                leak,
                back_face: truth.back_face(),
                t_alone: triangle_right && !ok,
                kind,
                ..Said::default()
            },
        )
    }
}

impl Lines for OctreeCells {
    fn verdict_line(
        c: &crate::cases::BoxCase,
        x: &BoxExit,
        a: &CellExit,
        _: f64,
    ) -> (Map<String, Value>, Said) {
        let ok = correct(Self::verdict(c, x, a));
        let mut quarters = Map::new();
        for (f, q) in x.faces.iter().zip(&x.quarters) {
            quarters.insert(FACE_NAMES[*f].into(), json!(q));
        }
        let line = json!({
            "face": a.map(|(f, _)| FACE_NAMES[f as usize]),
            "quarter": a.map(|(_, q)| q),
            "exact_faces": x.faces.iter().map(|&f| FACE_NAMES[f]).collect::<Vec<_>>(),
            "exact_quarters": quarters,
            "correct": ok,
        });
        (
            fields(line),
            Said {
                correct: ok,
                cell: true,
                ..Said::default()
            },
        )
    }
}
