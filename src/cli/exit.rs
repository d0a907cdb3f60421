//! `tetwalk exit`: one JSON line per case and method, with the exact answer beside it. Lines are read
//! as they come (a reader thread; whatever has arrived is answered as one batch), so a stream gets its
//! answers as it goes and memory stays bounded.

use super::{BackendArg, JsonOut, Outcome};
use crate::backend::Backend;
use crate::cases::{Subject, classify, judged};
use crate::choice::Choice;
use crate::exact::Classification;
use crate::found::{Record, WalkSetup};
use crate::registry::{Method, parse_list, reference};
use crate::tet::Case;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::mpsc;

#[derive(clap::Args)]
pub struct Args {
    /// A method name, a comma-separated list, or `all` [default: all].
    #[arg(long, default_value = "all")]
    method: String,
    #[command(flatten)]
    backend: BackendArg,
    /// Also write a summary (lines, errors, per method right / wrong / missed) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// JSON Lines file of cases (found cases too); standard input when absent.
    file: Option<PathBuf>,
}

/// Longest line read, in bytes; a longer one is an error for that line.
const MAX_LINE: u64 = 1 << 20;
/// Most lines answered as one batch.
const BATCH: usize = 4096;

/// One input line: its number and its text, or why it could not be read.
type Line = (usize, Result<String, String>);

/// Read lines on a thread, each at most [`MAX_LINE`] bytes, invalid UTF-8 an error for its line.
fn reader(mut input: Box<dyn BufRead + Send>) -> mpsc::Receiver<Line> {
    let (tx, rx) = mpsc::sync_channel(BATCH);
    std::thread::spawn(move || {
        let mut n = 0;
        loop {
            n += 1;
            let mut buf = Vec::new();
            let got = std::io::Read::take(&mut *input, MAX_LINE).read_until(b'\n', &mut buf);
            let line = match got {
                Ok(0) => return,
                Err(e) => Err(format!("reading: {e}")),
                Ok(_) if buf.last() != Some(&b'\n') && buf.len() as u64 == MAX_LINE => {
                    // Skip the rest of an over-long line.
                    let mut rest = Vec::new();
                    while let Ok(k) =
                        std::io::Read::take(&mut *input, MAX_LINE).read_until(b'\n', &mut rest)
                    {
                        if k == 0 || rest.last() == Some(&b'\n') {
                            break;
                        }
                        rest.clear();
                    }
                    Err(format!("line longer than {MAX_LINE} bytes"))
                }
                Ok(_) => String::from_utf8(buf).map_err(|_| "not valid UTF-8".to_string()),
            };
            let stop = matches!(line, Err(ref e) if e.starts_with("reading"));
            if tx.send((n, line)).is_err() || stop {
                return;
            }
        }
    });
    rx
}

/// Per method: lines judged right, wrong, and whose line missed the tetrahedron.
#[derive(Clone, Default, serde::Serialize)]
struct Tally {
    method: String,
    right: u64,
    wrong: u64,
    missed: u64,
}

#[derive(serde::Serialize)]
struct Summary {
    backend: String,
    lines: u64,
    errors: u64,
    methods: Vec<Tally>,
}

pub fn run(a: Args) -> Outcome {
    let methods = parse_list(&a.method)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let backend = a.backend.open()?;
    let input: Box<dyn BufRead + Send> = match &a.file {
        Some(p) => Box::new(std::io::BufReader::new(
            std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?,
        )),
        None => Box::new(std::io::BufReader::new(std::io::stdin())),
    };
    let rx = reader(input);
    let mut summary = Summary {
        backend: backend.describe(),
        lines: 0,
        errors: 0,
        methods: methods
            .iter()
            .map(|m| Tally {
                method: m.name.into(),
                ..Tally::default()
            })
            .collect(),
    };
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    // Block for one line, then take whatever else has arrived.
    while let Ok(first) = rx.recv() {
        let mut batch = vec![first];
        while batch.len() < BATCH {
            match rx.try_recv() {
                Ok(l) => batch.push(l),
                Err(_) => break,
            }
        }
        let text = answer(&batch, &methods, &backend, &mut summary)?;
        w.write_all(text.as_bytes())?;
        w.flush()?;
    }
    out.finish(&summary)?;
    if summary.errors > 0 {
        eprintln!(
            "tetwalk exit: {} line(s) could not be answered",
            summary.errors
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}

/// What a line holds once read and judged by the oracle.
enum Parsed {
    Exit(Case, Classification),
    Walk(crate::scenes::from_bytes::WalkCase),
}

/// The output lines for a batch of input lines.
fn answer(
    batch: &[Line],
    methods: &[&'static Method],
    backend: &Backend,
    summary: &mut Summary,
) -> Result<String, super::Error> {
    let parsed: Vec<(usize, Result<Parsed, String>)> = batch
        .iter()
        .filter(|(_, l)| l.as_ref().map_or(true, |l| !l.trim().is_empty()))
        .map(|(n, l)| {
            let p = l.clone().and_then(|l| {
                let r = Record::parse(&l).map_err(|e| e.to_string())?;
                match r.subject {
                    Subject::Exit(c) => classify(&c)
                        .map(|x| Parsed::Exit(c, x))
                        .map_err(|e| e.to_string()),
                    Subject::Walk(w) => Ok(Parsed::Walk(w)),
                }
            });
            (*n, p)
        })
        .collect();
    let cases: Vec<Case> = parsed
        .iter()
        .filter_map(|(_, p)| match p {
            Ok(Parsed::Exit(c, _)) => Some(*c),
            _ => None,
        })
        .collect();
    let mut faces = Vec::new();
    for m in methods {
        faces.push(backend.exit_faces(m, &cases)?);
    }
    let mut s = String::new();
    let mut k = 0;
    for (n, p) in &parsed {
        summary.lines += 1;
        let lines: Vec<serde_json::Value> = match p {
            Err(e) => {
                summary.errors += 1;
                vec![serde_json::json!({"line": n, "error": e})]
            }
            Ok(Parsed::Exit(_, c)) => {
                let v = methods
                    .iter()
                    .zip(&faces)
                    .zip(&mut summary.methods)
                    .map(|((m, f), t)| {
                        let j = judged(c, f[k]);
                        t.right += (j.correct == Some(true)) as u64;
                        t.wrong += (j.correct == Some(false)) as u64;
                        t.missed += j.correct.is_none() as u64;
                        serde_json::json!({
                            "line": n, "method": m.name, "backend": backend.for_method(m).kind().name(),
                            "face": j.face, "exact_exit": j.exact_exit, "exact_entry": j.exact_entry,
                            "correct": j.correct,
                        })
                    })
                    .collect();
                k += 1;
                v
            }
            Ok(Parsed::Walk(w)) => match walk_lines(*n, w, methods, backend, summary) {
                Ok(v) => v,
                Err(e) => {
                    summary.errors += 1;
                    vec![serde_json::json!({"line": n, "error": e.to_string()})]
                }
            },
        };
        for l in lines {
            s += &l.to_string();
            s.push('\n');
        }
    }
    Ok(s)
}

/// A walk case: each method's walk beside the `exact` one.
fn walk_lines(
    n: usize,
    w: &crate::scenes::from_bytes::WalkCase,
    methods: &[&'static Method],
    backend: &Backend,
    summary: &mut Summary,
) -> Result<Vec<serde_json::Value>, super::Error> {
    let setup = WalkSetup::new(w)?;
    let exact = setup.walk(reference(), backend, w)?;
    let mut out = Vec::new();
    for (m, t) in methods.iter().zip(&mut summary.methods) {
        let got = setup.walk(m, backend, w)?;
        let right = setup.right(m, &w.ray(), &got, &exact);
        t.right += right as u64;
        t.wrong += !right as u64;
        out.push(serde_json::json!({
            "line": n, "method": m.name, "backend": backend.for_method(m).kind().name(),
            "walk": got.outcome, "steps": got.steps, "exact_walk": exact.outcome, "correct": right,
        }));
    }
    Ok(out)
}
