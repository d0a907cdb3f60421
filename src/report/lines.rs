//! Verdict lines: one JSON line per case and method, the method's answer beside the exact one, as
//! `exit`, `hit`, `box-exit` and `judge` write them, and the lines that sum them up per method.

use super::counted;
use crate::engine::answering::AnswerSummary;
use crate::family::{Family, Said};
use serde_json::{Map, Value};

/// How a family's verdict lines read.
pub trait Lines: Family {
    /// The fields after `line`, `method` and `backend`: the answer beside the exact one, and
    /// `correct`, as the family's verdict `said` has it ([`Family::said`]).
    fn verdict_line(
        case: &Self::Case,
        truth: &Self::Truth,
        answer: &Self::Answer,
        said: &Said,
    ) -> Map<String, Value>;
}

/// The object of `v`.
pub(crate) fn fields(v: Value) -> Map<String, Value> {
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

/// A line per method of what `command` answered: cases, right, wrong (of them, each kind counted),
/// not judged, and where a 4-wide version was compared, how it answered.
pub(crate) fn per_method(command: &str, summary: &AnswerSummary) -> Vec<String> {
    let answered = summary.answered();
    let mut out = Vec::new();
    for t in &summary.methods {
        let not = answered.saturating_sub(t.right + t.wrong);
        let mut of_them = Vec::new();
        if !t.kinds.is_empty() {
            let each: Vec<String> = t
                .kinds
                .iter()
                .map(|(k, &n)| match *k {
                    "leak" => counted(n, "leak", "leaks"),
                    "miss_beside" => counted(n, "miss beside", "misses beside"),
                    "neighbour" => counted(
                        n,
                        "hit on a neighbour of the crossing",
                        "hits on a neighbour of the crossing",
                    ),
                    _ => counted(n, "other wrong first hit", "other wrong first hits"),
                })
                .collect();
            of_them.push(format!("on closed meshes {}", each.join(", ")));
        }
        if let (Some(f), Some(n)) = (t.wrong_face, t.no_exit_face)
            && f + n > 0
        {
            of_them.push(format!(
                "{f} a wrong face, {n} no face, {} at a tie (of {} ties), {} on a line that only touches the tetrahedron",
                t.wrong_at_tie.unwrap_or(0),
                t.at_tie.unwrap_or(0),
                t.touch_only.unwrap_or(0)
            ));
        }
        if let Some(n @ 1..) = t.t_alone {
            of_them.push(format!(
                "{n} wrong for t alone: the triangle right, t further than --t-ulps from the exact t"
            ));
        }
        if let Some(b @ 1..) = t.back_faces {
            of_them.push(format!(
                "{b} where the ray first meets a back face: a method that culls back faces, as `mt` does by design, passes it"
            ));
        }
        let back = match of_them.is_empty() {
            true => String::new(),
            false => format!(" (of them {})", of_them.join("; ")),
        };
        let wide = match (t.wide_compared, t.wide_differs) {
            (Some(n), Some(0)) => {
                format!("; its 4-wide version answered all {n} the same, bit for bit")
            }
            (Some(n), Some(d)) => {
                format!("; its 4-wide version answered {d} of {n} otherwise than the scalar one")
            }
            _ => String::new(),
        };
        out.push(format!(
            "tetwalk {command}: {}: {}, {} right, {} wrong{back}, {not} not judged{}{wide}",
            t.method,
            counted(answered, "case", "cases"),
            t.right,
            t.wrong,
            if t.missed.is_some() && not > 0 {
                " (the line misses the cell)"
            } else {
                ""
            }
        ));
    }
    out
}

/// The lines that say why `command` fails whatever `--fail-on` says: a 4-wide version answering
/// otherwise than its scalar one, lines that could not be answered.
pub(crate) fn failures(command: &str, summary: &AnswerSummary) -> Vec<String> {
    let mut out = Vec::new();
    let differ = summary.wide_differs();
    if differ > 0 {
        out.push(format!(
            "tetwalk {command}: a 4-wide version answered {} otherwise than its scalar version (the lines' \"wide_same\": false)",
            counted(differ, "case", "cases")
        ));
    }
    if summary.errors > 0 {
        out.push(format!(
            "tetwalk {command}: {} could not be answered",
            counted(summary.errors, "line", "lines")
        ));
    }
    out
}
