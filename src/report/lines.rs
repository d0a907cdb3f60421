//! Verdict lines: one JSON line per case and method, the method's answer beside the exact one, as
//! `exit`, `hit`, `box-exit` and `judge` write them.

use crate::family::{Family, Verdict};
use serde_json::{Map, Value};

/// What a verdict line says of an answer: right, wrong, or not judged (`None`), whether it leaks,
/// whether the ray first meets a back face there ([`crate::exact::hit::HitTruth::back_face`]), and whether a hit is wrong
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
    /// What a wrong closed-mesh answer is ([`crate::exact::hit::HitTruth::wrong_kind`]).
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
pub fn fields(v: Value) -> Map<String, Value> {
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

/// The verdict's `correct`: `null` where the case is not judged.
pub fn correct(v: Verdict) -> Option<bool> {
    match v {
        Verdict::Right => Some(true),
        Verdict::Wrong(_) => Some(false),
        Verdict::NotJudged => None,
    }
}
