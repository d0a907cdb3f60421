//! `replay`'s lines: each found case or dumped wrong ray as it replays now, one JSON line, and the
//! summary.

use crate::engine::count::Rerun;
use crate::engine::found::{Replay, ReplayTally};
use crate::walk::Outcome;
use serde_json::{Value, json};

/// A found case at `line` of `file`, failed by `method`, as it replays now.
pub(crate) fn found_line(file: &str, line: usize, method: Option<&str>, now: &Replay) -> Value {
    let replay = match now {
        Replay::Holds => "holds".to_string(),
        Replay::Skipped(_) => "skipped".to_string(),
        Replay::Right => "right now".to_string(),
        Replay::OtherAnswer(x) => format!("other answer {x}"),
    };
    json!({"file": file, "line": line, "method": method, "replay": replay})
}

/// A dumped wrong ray at `line` of `file`, answered again on `backend`, beside where it was recorded
/// to stop.
pub(crate) fn dumped_line(
    file: &str,
    line: usize,
    r: &Rerun,
    backend: &str,
    recorded: &Outcome,
) -> Value {
    json!({
        "file": file, "line": line, "method": r.method, "backend": backend, "still_wrong": r.still_wrong,
        "same": r.same, "now": r.now.outcome, "recorded": recorded,
    })
}

/// The summary line: how many of the lines `what` (fail again …), changed and skipped.
pub(crate) fn summary(t: &ReplayTally, what: &str) -> String {
    format!(
        "{} of {} {what} ({} changed, {} skipped)",
        t.same, t.lines, t.changed, t.skipped
    )
}
