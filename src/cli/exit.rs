//! `tetwalk exit`: one JSON line per case and method, with the exact answer beside it. Lines are read
//! as they come (a reader thread; whatever has arrived is answered as one batch), so a stream gets its
//! answers as it goes and memory stays bounded.

use super::{BackendArg, FailArg, JsonOut, Outcome, WgslArg};
use crate::backend::Backend;
use crate::cases::{Subject, classify, judged};
use crate::choice::Choice;
use crate::exact::Classification;
use crate::found::{Record, WalkSetup};
use crate::registry::{Method, reference};
use crate::report::standing::Standing;
use crate::tet::Case;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::mpsc;

/// The arguments of `exit` and `hit`.
#[derive(clap::Args)]
pub struct Args {
    /// A method name, a comma-separated list, or `all` [default: all].
    #[arg(long, default_value = "all")]
    pub(super) method: String,
    #[command(flatten)]
    pub(super) backend: BackendArg,
    #[command(flatten)]
    pub(super) wgsl: WgslArg,
    #[command(flatten)]
    pub(super) fail: FailArg,
    /// `hit`: a hit's `t` is right within this many ulps of the exact `t` (of the f32 nearest it),
    /// and always needs `0 < t < ∞` [default: 4096].
    #[arg(long, value_name = "ULPS", allow_negative_numbers = true)]
    pub(super) t_ulps: Option<f64>,
    /// Also write a summary (lines, errors, per method right / wrong, and for `exit` lines missing the
    /// tetrahedron) as JSON here.
    #[arg(long)]
    pub(super) json: Option<PathBuf>,
    /// JSON Lines file of cases (found cases too); standard input when absent.
    pub(super) file: Option<PathBuf>,
}

/// Longest line read, in bytes; a longer one is an error for that line.
pub(super) const MAX_LINE: u64 = 1 << 20;
/// Most lines answered as one batch.
const BATCH: usize = 4096;

/// One input line: its number and its text, or why it could not be read.
pub(super) type Line = (usize, Result<String, String>);

/// Read lines on a thread, each at most [`MAX_LINE`] bytes, invalid UTF-8 an error for its line.
pub(super) fn reader(mut input: Box<dyn BufRead + Send>) -> mpsc::Receiver<Line> {
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

/// Answer the JSON Lines of `file` (standard input when `None`) batch by batch as they arrive: block
/// for one line, take whatever else has arrived, write `answer`'s text for them to standard output.
pub(super) fn answer_lines(
    file: Option<&std::path::Path>,
    mut answer: impl FnMut(&[Line]) -> Result<String, super::Error>,
) -> Result<(), super::Error> {
    if let Some(p) = file.filter(|p| p.is_dir()) {
        return Err(format!("{}: is a folder, not a file of JSON lines", p.display()).into());
    }
    let input: Box<dyn BufRead + Send> = match file {
        Some(p) => Box::new(std::io::BufReader::new(
            std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?,
        )),
        None => Box::new(std::io::BufReader::new(std::io::stdin())),
    };
    let rx = reader(input);
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    while let Ok(first) = rx.recv() {
        let mut batch = vec![first];
        while batch.len() < BATCH {
            match rx.try_recv() {
                Ok(l) => batch.push(l),
                Err(_) => break,
            }
        }
        let text = answer(&batch)?;
        w.write_all(text.as_bytes())?;
        w.flush()?;
    }
    Ok(())
}

/// Per method: lines judged right, wrong, (`exit`, `box-exit`) whose line missed the cell, and (`hit`,
/// `judge` on closed meshes) leaks.
#[derive(Clone, Default, serde::Serialize)]
pub(super) struct Tally {
    pub method: String,
    pub right: u64,
    pub wrong: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub missed: Option<u64>,
    /// Wrong answers on closed meshes where the ray passes through the surface.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub leaks: Option<u64>,
}

/// What a command answering JSON Lines writes with `--json`.
#[derive(serde::Serialize)]
pub(super) struct Summary {
    backend: String,
    pub lines: u64,
    pub errors: u64,
    pub methods: Vec<Tally>,
}

/// A command answering JSON Lines: its name, its methods' names, what their tallies count, where the
/// lines come from and the summary goes, and how a tally stands under `--fail-on`.
pub(super) struct Answering<'a> {
    pub command: &'static str,
    pub names: Vec<String>,
    /// The tallies count lines missing the cell.
    pub missed: bool,
    /// The tallies count leaks.
    pub leaks: bool,
    pub backend: String,
    pub file: Option<&'a std::path::Path>,
    pub json: Option<&'a std::path::Path>,
    pub fail: FailArg,
    pub standing: fn(&Tally) -> Standing,
}

impl Answering<'_> {
    /// Answer the lines with `answer` (given each batch and the summary); then `after` checks what
    /// only the whole input tells (an error there writes no summary); then the summary goes to
    /// `--json`. Exit status 1 when a line could not be answered, or under `--fail-on`.
    pub(super) fn run(
        self,
        mut answer: impl FnMut(&[Line], &mut Summary) -> Result<String, super::Error>,
        after: impl FnOnce() -> Result<(), super::Error>,
    ) -> Outcome {
        let out = JsonOut::new(self.json)?;
        let mut summary = Summary {
            backend: self.backend,
            lines: 0,
            errors: 0,
            methods: self
                .names
                .into_iter()
                .map(|method| Tally {
                    method,
                    missed: self.missed.then_some(0),
                    leaks: self.leaks.then_some(0),
                    ..Tally::default()
                })
                .collect(),
        };
        answer_lines(self.file, |batch| answer(batch, &mut summary))?;
        after()?;
        if summary.lines == 0 {
            return Err(format!(
                "{}: no case to answer (the input holds no line but blank ones)",
                self.file
                    .map_or("standard input".into(), |p| p.display().to_string())
            )
            .into());
        }
        out.finish(&summary)?;
        let standings: Vec<Standing> = summary.methods.iter().map(self.standing).collect();
        let status = self.fail.status(self.command, &standings);
        if summary.errors > 0 {
            eprintln!(
                "tetwalk {}: {} line(s) could not be answered",
                self.command, summary.errors
            );
            return Ok(ExitCode::FAILURE);
        }
        Ok(status)
    }
}

pub fn run(a: Args) -> Outcome {
    if a.t_ulps.is_some() {
        return Err("--t-ulps judges a hit's t: it is for tetwalk hit (and judge)".into());
    }
    let (backend, methods) = a.wgsl.open(a.backend, &a.method)?;
    Answering {
        command: "exit",
        names: methods.iter().map(|m| m.name.to_string()).collect(),
        missed: true,
        leaks: false,
        backend: backend.describe(),
        file: a.file.as_deref(),
        json: a.json.as_deref(),
        fail: a.fail,
        standing: |t| Standing::exit_face(&t.method, t.right + t.wrong, t.wrong),
    }
    .run(
        |batch, summary| answer(batch, &methods, &backend, summary),
        || Ok(()),
    )
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
                    Subject::Hit(_) => {
                        Err("a ray-triangle case: tetwalk hit answers it".to_string())
                    }
                    Subject::Box(_) => {
                        Err("an octree cell case: tetwalk box-exit answers it".to_string())
                    }
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
                        let on = backend.for_method(*m).kind().name();
                        exit_verdict(*n, m.name, on, c, f[k], t)
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

/// An exit-face verdict line: `face` (in the case's numbering) beside the exact answer, counted in
/// `tally`.
pub(super) fn exit_verdict(
    n: usize,
    method: &str,
    backend: &str,
    c: &Classification,
    face: Option<usize>,
    tally: &mut Tally,
) -> serde_json::Value {
    let j = judged(c, face);
    tally.right += (j.correct == Some(true)) as u64;
    tally.wrong += (j.correct == Some(false)) as u64;
    if let Some(m) = tally.missed.as_mut() {
        *m += j.correct.is_none() as u64;
    }
    serde_json::json!({
        "line": n, "method": method, "backend": backend,
        "face": j.face, "exact_exit": j.exact_exit, "exact_entry": j.exact_entry,
        "correct": j.correct,
    })
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
            "line": n, "method": m.name, "backend": backend.for_method(*m).kind().name(),
            "walk": got.outcome, "steps": got.steps, "exact_walk": exact.outcome, "correct": right,
        }));
    }
    Ok(out)
}
