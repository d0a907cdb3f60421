//! `tetwalk shrink`: found cases, and the wrong rays of a `count --dump` (the one-tetrahedron case of
//! each walk's diverging step), shrunk to the simplest case the same method still fails the same way
//! on the same backend (`crate::engine::shrink`); each printed with the line that reproduces it, and
//! with `--in-place` written back over its file, the original kept in the line.

use super::{JsonOut, Status};
use crate::backend::{Backend, BackendKind};
use crate::cases::object;
use crate::choice::Choice;
use crate::engine::answerer::{Answerer, Format};
use crate::engine::found::{Failure, Found, FoundError};
use crate::engine::shrink::{CHECKS, Shrunk, bits, reproduce, shrink_on};
use crate::family::wrong::WrongRay;
use crate::family::{self, Family, Kind, owner};
use std::collections::HashMap;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Files of found cases (`corpora/found/`, one JSON line each or more), or a `count --dump`.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Write each file of found cases back with its cases shrunk, the case as found kept in each
    /// line's `original` (a dump is never rewritten: its shrunk cases are printed).
    #[arg(long)]
    in_place: bool,
    /// Shrink for a program outside tetwalk instead (--answerer CMD, docs/answerers.md): each line
    /// of FILE is a case (a found case too), asked of the program as `stress --answerer` asks; the
    /// simplest case it still answers wrongly the same way, inside its contract, is printed (a leak
    /// stays a leak, a failure that is no tie does not become one), with the line that reproduces it.
    #[command(flatten)]
    answerer: super::AnswererArg,
    #[command(flatten)]
    contract: super::ContractArg,
    /// Checks (exact judgements of a candidate case) one shrink may make at most.
    #[arg(long, default_value_t = CHECKS)]
    checks: usize,
    /// Also write what was done to each case (significant bits before and after, checks, the shrunk
    /// line, the line that reproduces it) and the totals as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .inputs("FILES", &self.files)
            .output("--json", self.json.as_deref())
    }
}

/// One case shrunk.
#[derive(serde::Serialize)]
struct Done {
    file: String,
    line: usize,
    method: String,
    /// Where it ran: a backend, or `outside` (`--answerer`).
    backend: String,
    /// How many numbers the case has, and their significant bits summed, before and after.
    numbers: usize,
    bits_before: u32,
    bits_after: u32,
    /// The most significant bits of any one number, before and after.
    largest_before: u32,
    largest_after: u32,
    checks: usize,
    /// Whether the check budget ran out first (a simpler case may exist).
    exhausted: bool,
    /// The shrunk found case, its original in `original`.
    shrunk: serde_json::Value,
    /// One shell line that reproduces it.
    reproduce: Option<String>,
}

impl Done {
    /// What a shrink of `before` to `s` did at `at`, its answerer and lines left to fill in.
    fn measured<F: Family>(at: &Place, before: &F::Case, s: &Shrunk<F>) -> Done {
        let (bits_before, largest_before) = bits::<F>(before);
        let (bits_after, largest_after) = bits::<F>(&s.case);
        Done {
            file: at.file.clone(),
            line: at.line,
            method: String::new(),
            backend: String::new(),
            numbers: F::numbers(before).len(),
            bits_before,
            bits_after,
            largest_before,
            largest_after,
            checks: s.checks,
            exhausted: s.exhausted,
            shrunk: serde_json::Value::Null,
            reproduce: None,
        }
    }

    /// Whether the search found a simpler case (fewer significant bits in all, or in the largest).
    fn simpler(&self) -> bool {
        self.bits_after < self.bits_before || self.largest_after < self.largest_before
    }
}

/// Where a case is: its file and 1-based line.
#[derive(Clone, serde::Serialize)]
struct Place {
    file: String,
    line: usize,
}

#[derive(Default, serde::Serialize)]
struct Report {
    cases: Vec<Done>,
    /// Cases left as they were, and why (found on a GPU not here, a dump line without a diverging
    /// step).
    left: Vec<(Place, String)>,
}

/// Backends opened once each.
struct Backends(HashMap<BackendKind, Result<Backend, String>>);

impl Backends {
    /// Where `f` was found, opened here (a GPU finding only on its own adapter), or why not.
    fn get<F: Family>(&mut self, f: &Failure<F>) -> Result<&Backend, String> {
        let b = self
            .0
            .entry(f.backend)
            .or_insert_with(|| Backend::open(f.backend).map_err(|e| e.to_string()))
            .as_ref()
            .map_err(Clone::clone)?;
        f.runs_on(b)?;
        Ok(b)
    }
}

/// Shrink one found case of family `F`, or say why it is left as it is.
fn shrink_one<F: Family>(
    found: &Found<F>,
    at: &Place,
    backends: &mut Backends,
    checks: usize,
) -> Result<Result<Done, String>, FoundError> {
    let f = found.failed("shrink")?;
    let backend = match backends.get(f) {
        Ok(b) => b,
        Err(why) => return Ok(Err(why)),
    };
    let m = family::by_name::<F>(&f.method)?;
    let (shrunk, s) = shrink_on(found, m, backend, checks)?;
    Ok(Ok(Done {
        method: f.method.clone(),
        backend: f.backend.name().to_string(),
        shrunk: serde_json::from_str(&shrunk.to_json()).expect("a found case's line is JSON"),
        reproduce: reproduce(&shrunk),
        ..Done::measured(at, &found.case, &s)
    }))
}

/// A case shrunk for a program outside tetwalk, inside its contract.
fn shrink_outside<F: Family>(
    found: &Found<F>,
    a: &Answerer,
    contract: &super::ContractArg,
    at: &Place,
    checks: usize,
) -> Result<Result<Done, String>, FoundError> {
    let contract = contract.contract::<F>().map_err(|e| FoundError::Field {
        field: "contract",
        why: e.to_string(),
    })?;
    let s = match crate::engine::shrink::shrink_outside::<F>(a, &found.case, checks, &contract) {
        Ok(s) => s,
        Err(FoundError::Field { field: "case", why }) => return Ok(Err(why)),
        Err(e) => return Err(e),
    };
    let mut asked = F::case_json(&s.case);
    let line = serde_json::Value::Object(asked.clone()).to_string();
    asked.insert("line".into(), 1.into());
    let quoted = |t: &str| format!("'{}'", t.replace('\'', "'\\''"));
    Ok(Ok(Done {
        method: a.name.clone(),
        backend: "outside".into(),
        shrunk: serde_json::Value::Object(F::case_json(&s.case)),
        reproduce: (a.format == Format::Json).then(|| {
            format!(
                "printf '%s\\n\\n' {} | {} > answer.jsonl && echo {} | tetwalk judge - answer.jsonl",
                quoted(&serde_json::Value::Object(asked).to_string()),
                a.cmd,
                quoted(&line),
            )
        }),
        ..Done::measured(at, &found.case, &s)
    }))
}

/// A dump line's diverging step as a found case (of the family whose case the dump holds: a walk's
/// step, one tetrahedron), its answer the divergence's in that family's form, or why it has none.
fn from_dump<F: Family>(
    method: &str,
    case: serde_json::Map<String, serde_json::Value>,
    answer: &serde_json::Value,
    backend: BackendKind,
) -> Result<Found<F>, String> {
    let case = Found::<F>::from_object(case).map_err(|e| e.to_string())?;
    let method = family::by_name::<F>(method).map_err(|e| e.to_string())?;
    let answer = F::parse_answer(answer, &case.case)?;
    Ok(Found::of(
        case.case,
        Failure {
            method: crate::registry::Named::name(method).to_string(),
            backend,
            adapter: None,
            answer,
        },
    ))
}

/// A dump line shrunk: the found case of its diverging step ([`from_dump`]), or why it has none.
fn shrink_dump(
    obj: serde_json::Map<String, serde_json::Value>,
    at: &Place,
    backends: &mut Backends,
    checks: usize,
) -> Result<Result<Done, String>, FoundError> {
    let w: WrongRay = match serde_json::from_value(serde_json::Value::Object(obj)) {
        Ok(w) => w,
        Err(e) => {
            return Err(FoundError::Field {
                field: "wrong ray",
                why: e.to_string(),
            });
        }
    };
    let WrongRay {
        case: Some(case),
        divergence: Some(d),
        backend: Some(backend),
        method,
        ..
    } = w
    else {
        return Ok(Err(
            "no diverging step was observed (a GPU walk, or walks given from outside)".into(),
        ));
    };
    let answer = serde_json::json!(d.face);
    crate::with_family!(owner(&case), F => match from_dump::<F>(&method, case, &answer, backend) {
        Ok(found) => shrink_one::<F>(&found, at, backends, checks),
        Err(why) => Ok(Err(why)),
    })
}

pub(crate) fn run(a: Args) -> Status {
    let out = JsonOut::new(a.json.as_deref())?;
    if a.checks == 0 {
        return Err("--checks 0 would shrink nothing".into());
    }
    if a.answerer.answerer.is_some() && a.in_place {
        return Err("--answerer prints the shrunk cases; a user's file is not rewritten (leave out --in-place)".into());
    }
    // Started once, before the first line, as the family whose faces it may number starts it (its
    // numbering found then); each case's family checks the contract again as it is shrunk.
    let faces = Kind::ALL
        .iter()
        .copied()
        .find(|&k| crate::with_family!(k, F => F::FACES))
        .ok_or("no family numbers faces")?;
    let answerer = crate::with_family!(faces, F => {
        let contract = a.contract.contract::<F>()?;
        if a.answerer.answerer.is_none() && contract != Default::default() {
            return Err("--origin, --unit-direction, --entry, --orientation and --tolerance state an --answerer's contract; tetwalk's own methods are shrunk as they fail".into());
        }
        a.answerer.start::<F>(&contract)?
    });
    let mut backends = Backends(HashMap::new());
    let mut report = Report::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    // Files to rewrite, each whole and only once every file's every line is shrunk.
    let mut rewrites: Vec<(PathBuf, String)> = Vec::new();
    for path in &a.files {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut rewritten = String::new();
        for (n, line) in text.lines().enumerate() {
            let at = Place {
                file: path.display().to_string(),
                line: n + 1,
            };
            let place = |e: &dyn std::fmt::Display| format!("{} line {}: {e}", at.file, at.line);
            if line.trim().is_empty() {
                rewritten += line;
                rewritten += "\n";
                continue;
            }
            let obj = object(line).map_err(|e| place(&e))?;
            let dump = obj.contains_key("pixel") && obj.contains_key("scene");
            if dump && a.in_place {
                return Err(place(
                    &"a count's dump is not rewritten: leave out --in-place (its shrunk cases are printed)",
                )
                .into());
            }
            let result = if let Some(x) = &answerer {
                if dump {
                    return Err(place(
                        &"--answerer shrinks cases (one per line), not a count's dump",
                    )
                    .into());
                }
                crate::with_family!(owner(&obj), F => Found::<F>::from_object(obj)
                    .and_then(|found| shrink_outside::<F>(&found, x, &a.contract, &at, a.checks)))
            } else if dump {
                shrink_dump(obj, &at, &mut backends, a.checks)
            } else {
                crate::with_family!(owner(&obj), F => Found::<F>::from_object(obj)
                    .and_then(|found| shrink_one::<F>(&found, &at, &mut backends, a.checks)))
            }
            .map_err(|e| place(&e))?;
            match result {
                Ok(done) => {
                    writeln!(
                        w,
                        "{}: {} on {}: {} -> {} significant bits in {} numbers (at most {} -> {} in one), {} checks{}{}",
                        place(&"case"),
                        done.method,
                        done.backend,
                        done.bits_before,
                        done.bits_after,
                        done.numbers,
                        done.largest_before,
                        done.largest_after,
                        done.checks,
                        if done.exhausted { ", budget spent" } else { "" },
                        if done.simpler() {
                            ""
                        } else {
                            ": already as simple as the search finds"
                        }
                    )?;
                    writeln!(w, "  {}", done.shrunk)?;
                    if let Some(r) = &done.reproduce {
                        writeln!(w, "  reproduce: {r}")?;
                    }
                    rewritten += &done.shrunk.to_string();
                    report.cases.push(done);
                }
                Err(why) => {
                    eprintln!("tetwalk shrink: {} left as it is: {why}", place(&"case"));
                    rewritten += line;
                    report.left.push((at.clone(), why));
                }
            }
            rewritten += "\n";
        }
        if a.in_place {
            rewrites.push((path.clone(), rewritten));
        }
    }
    w.flush()?;
    if report.cases.is_empty() && report.left.is_empty() {
        return Err("no case to shrink in the files given".into());
    }
    for (path, text) in &rewrites {
        crate::staged::write(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let numbers: usize = report.cases.iter().map(|d| d.numbers).sum();
    let mean = |f: fn(&Done) -> u32| {
        report.cases.iter().map(|d| f(d) as f64).sum::<f64>() / numbers.max(1) as f64
    };
    let simpler = report.cases.iter().filter(|d| d.simpler()).count();
    let bits = match numbers {
        0 => String::new(),
        _ => format!(
            "; significant bits per number, mean {:.1} -> {:.1}",
            mean(|d| d.bits_before),
            mean(|d| d.bits_after)
        ),
    };
    eprintln!(
        "tetwalk shrink: {} shrunk{}, {} already as simple as the search finds, {} left as they were (each with its reason above){bits}",
        crate::report::counted(simpler as u64, "case", "cases"),
        if a.in_place { " and written back" } else { "" },
        report.cases.len() - simpler,
        report.left.len(),
    );
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}
