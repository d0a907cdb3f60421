//! `tetwalk box-exit`: octree cell cases (seed 001), one JSON line per case and method: the exit face
//! and quarter each method answers, beside every exact exit face and quarter. Read as `exit` reads its
//! cases: line by line as they come.

use super::Outcome;
use super::exit::{Answering, Line, Summary, Tally};
use crate::backend::Backend;
use crate::cases::{BoxCase, Subject};
use crate::choice::Choice;
use crate::exact::boxes::{BoxExit, box_exit};
use crate::found::Record;
use crate::octree::cell::{FACE_NAMES, quarter_signs};
use crate::registry::{OctreeMethod, parse_octree_list};
use crate::report::standing::Standing;
use serde_json::{Map, Value, json};

#[derive(clap::Args)]
pub struct Args {
    /// A method name, a comma-separated list, or `all` [default: all].
    #[arg(long, default_value = "all")]
    method: String,
    /// Where the methods run: `cpu` (plain f32), `cpu-fma` (as a GPU compiles them), `cpu-ftz`
    /// (subnormals flushed) or `gpu` (WGSL;
    /// the `exact` reference stays on the CPU).
    #[command(flatten)]
    backend: super::BackendArg,
    #[command(flatten)]
    fail: super::FailArg,
    /// Also write a summary (lines, errors, per method right / wrong / lines not crossing the open
    /// box) as JSON here.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// JSON Lines file of cases `{"box": [[lx, ly, lz], [hx, hy, hz]], "org", "dir"}` (found cases
    /// too); standard input when absent.
    file: Option<std::path::PathBuf>,
}

pub fn run(a: Args) -> Outcome {
    let methods = parse_octree_list(&a.method)?;
    let backend = a.backend.open()?;
    Answering {
        command: "box-exit",
        names: methods.iter().map(|m| m.name.to_string()).collect(),
        missed: true,
        leaks: false,
        backend: backend.describe(),
        file: a.file.as_deref(),
        json: a.json.as_deref(),
        fail: a.fail,
        standing: |t| Standing::cell(&t.method, t.right + t.wrong, t.wrong),
    }
    .run(
        |batch, summary| answer(batch, &methods, &backend, summary),
        || Ok(()),
    )
}

/// A line read and judged by the oracle, or why it could not be.
type Parsed = Result<(BoxCase, BoxExit), String>;

fn answer(
    batch: &[Line],
    methods: &[&OctreeMethod],
    backend: &Backend,
    summary: &mut Summary,
) -> Result<String, super::Error> {
    let parsed: Vec<(usize, Parsed)> = batch
        .iter()
        .filter(|(_, l)| l.as_ref().map_or(true, |t| !t.trim().is_empty()))
        .map(|(n, l)| {
            let case = l.clone().and_then(|text| {
                match Record::parse(&text).map_err(|e| e.to_string())?.subject {
                    Subject::Box(c) => {
                        let x = box_exit(c.lo, c.hi, &c.ray()).map_err(|e| e.to_string())?;
                        Ok((c, x))
                    }
                    _ => Err(
                        "not an octree cell case: box-exit answers {\"box\", \"org\", \"dir\"}"
                            .into(),
                    ),
                }
            });
            (*n, case)
        })
        .collect();
    let cases: Vec<BoxCase> = parsed
        .iter()
        .filter_map(|(_, p)| p.as_ref().ok().map(|(c, _)| *c))
        .collect();
    let mut answers = Vec::new();
    for m in methods {
        answers.push(backend.box_exits(m, &cases)?);
    }
    let mut s = String::new();
    let mut k = 0;
    for (n, p) in &parsed {
        summary.lines += 1;
        let lines: Vec<Value> = match p {
            Err(e) => {
                summary.errors += 1;
                vec![json!({"line": n, "error": e})]
            }
            Ok((_, x)) => {
                let v = methods
                    .iter()
                    .zip(&answers)
                    .zip(&mut summary.methods)
                    .map(|((m, a), t)| {
                        let on = backend.for_method(*m).kind().name();
                        let answer = a[k].map(|(f, q)| (f, quarter_signs(q)));
                        box_verdict(*n, m.name, on, x, answer, t)
                    })
                    .collect();
                k += 1;
                v
            }
        };
        for l in lines {
            s += &l.to_string();
            s.push('\n');
        }
    }
    Ok(s)
}

/// An octree cell verdict line: the exit face and quarter answered, beside every exact one, counted
/// in `tally`.
pub(super) fn box_verdict(
    n: usize,
    method: &str,
    backend: &str,
    x: &BoxExit,
    answer: Option<(usize, [i8; 2])>,
    tally: &mut Tally,
) -> Value {
    let correct = x.right(answer);
    tally.right += (correct == Some(true)) as u64;
    tally.wrong += (correct == Some(false)) as u64;
    if let Some(m) = tally.missed.as_mut() {
        *m += correct.is_none() as u64;
    }
    let mut quarters = Map::new();
    for (f, q) in x.faces.iter().zip(&x.quarters) {
        quarters.insert(FACE_NAMES[*f].into(), json!(q));
    }
    json!({
        "line": n, "method": method, "backend": backend,
        "face": answer.map(|(f, _)| FACE_NAMES[f]),
        "quarter": answer.map(|(_, q)| q),
        "exact_faces": x.faces.iter().map(|&f| FACE_NAMES[f]).collect::<Vec<_>>(),
        "exact_quarters": quarters,
        "correct": correct,
    })
}
