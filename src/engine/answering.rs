//! Answering case lines, for `exit`, `hit`, `box-exit` and `judge`: lines read as they come (a reader
//! thread; whatever has arrived is answered as one batch), so a stream gets its answers as it goes and
//! memory stays bounded; each line's family (by its keys) takes it, if the command answers that
//! family, and answers it with the command's methods, or with answers given from outside; each
//! answer's verdict ([`Family::said`]) is counted per method and written by the family's printer.

use crate::backend::{Backend, BackendError};
use crate::cases::object;
use crate::choice::Choice;
use crate::engine::answerer::{Answerer, AnswererError};
use crate::engine::found::Found;
use crate::engine::standing::Standing;
use crate::family::{Family, Kind, Said, owner};
use crate::registry::Named;
use serde_json::{Map, Value, json};
use std::collections::{BTreeMap, HashMap};
use std::io::BufRead;
use std::path::Path;
use std::sync::mpsc;

/// Why lines could not be answered.
#[derive(Debug, thiserror::Error)]
pub(crate) enum AnsweringError {
    /// The file of lines cannot be opened.
    #[error("{file}: {why}")]
    File {
        /// The file, as given.
        file: String,
        /// Why.
        why: String,
    },
    /// A backend could not answer a batch.
    #[error(transparent)]
    Backend(#[from] BackendError),
    /// A program outside tetwalk could not answer a batch.
    #[error(transparent)]
    Answerer(#[from] AnswererError),
}

/// A file of JSON lines opened for reading (a pipe too: `/dev/stdin`; `-` is standard input); a
/// folder is refused.
pub(crate) fn open_lines(p: &Path) -> Result<Box<dyn BufRead + Send>, AnsweringError> {
    if p == Path::new("-") {
        return Ok(Box::new(std::io::BufReader::new(std::io::stdin())));
    }
    let refused = |why: String| AnsweringError::File {
        file: p.display().to_string(),
        why,
    };
    if p.is_dir() {
        return Err(refused("is a folder, not a file of JSON lines".into()));
    }
    Ok(Box::new(std::io::BufReader::new(
        std::fs::File::open(p).map_err(|e| refused(e.to_string()))?,
    )))
}

/// Most characters of a line's error kept (what it echoes of the input is cut there).
const BRIEF: usize = 300;

/// `why`, cut to [`BRIEF`] characters (an echoed million-digit number is not repeated whole).
fn brief(why: String) -> String {
    if why.chars().count() <= BRIEF {
        return why;
    }
    let kept: String = why.chars().take(BRIEF).collect();
    format!("{kept}… ({} characters in all)", why.chars().count())
}

/// The key under which an answer line that is not JSON keeps why, for its case line (`judge`).
pub(crate) const NOT_JSON: &str = "not JSON";

/// Longest line read, in bytes; a longer one is an error for that line.
pub(crate) const MAX_LINE: u64 = 1 << 20;
/// Most lines answered as one batch by tetwalk's own methods.
pub(crate) const BATCH: usize = 4096;

/// One input line: its number and its text, or why it could not be read.
pub(crate) type Line = (usize, Result<String, String>);

/// Read lines on a thread, each at most [`MAX_LINE`] bytes, invalid UTF-8 an error for its line.
pub(crate) fn reader(mut input: Box<dyn BufRead + Send>) -> mpsc::Receiver<Line> {
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

/// The lines of `input` batch by batch as they arrive: block for one line, take whatever else has
/// arrived (at most `most`), hand them to `each`.
pub(crate) fn batches<E>(
    input: Box<dyn BufRead + Send>,
    most: usize,
    mut each: impl FnMut(&[Line]) -> Result<(), E>,
) -> Result<(), E> {
    let rx = reader(input);
    while let Ok(first) = rx.recv() {
        let mut batch = vec![first];
        while batch.len() < most.max(1) {
            match rx.try_recv() {
                Ok(l) => batch.push(l),
                Err(_) => break,
            }
        }
        each(&batch)?;
    }
    Ok(())
}

/// Per method: lines judged right, wrong, (`exit`, `box-exit`) whose line missed the cell, and (`hit`,
/// `judge` on closed meshes) leaks.
#[derive(Clone, Default, serde::Serialize)]
pub(crate) struct AnswerTally {
    /// The method's name (or the answers' given from outside).
    pub(crate) method: String,
    /// Answers judged right.
    pub(crate) right: u64,
    /// Answers judged wrong.
    pub(crate) wrong: u64,
    /// Lines that miss the cell (not judged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) missed: Option<u64>,
    /// Wrong answers on closed meshes where the ray passes through the surface.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) leaks: Option<u64>,
    /// Wrong answers where the ray first meets a back face
    /// ([`crate::exact::hit::HitTruth::back_face`]), which a method that culls back faces passes by
    /// design.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) back_faces: Option<u64>,
    /// Wrong answers on closed meshes by kind ([`crate::exact::hit::HitTruth::wrong_kind`]), the stress
    /// rows' classification.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub(crate) kinds: BTreeMap<&'static str, u64>,
    /// Tetrahedra: wrong answers that are a face.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) wrong_face: Option<u64>,
    /// Tetrahedra: wrong answers that are none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) no_exit_face: Option<u64>,
    /// Tetrahedra: answers to ties (more than one face right).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) at_tie: Option<u64>,
    /// Tetrahedra: wrong answers to ties.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) wrong_at_tie: Option<u64>,
    /// Tetrahedra: wrong answers on lines that only touch the tetrahedron.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) touch_only: Option<u64>,
    /// Hits wrong for their `t` alone: the triangle right, `t` beyond `--t-ulps`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) t_alone: Option<u64>,
    /// With `hit --wide`, for a method with a 4-wide version: the cases it answered otherwise than
    /// the scalar version.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) wide_differs: Option<u64>,
    /// With `hit --wide`: the cases compared.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) wide_compared: Option<u64>,
}

impl AnswerTally {
    /// Count one verdict.
    fn count(&mut self, said: Said) {
        self.right += (said.correct == Some(true)) as u64;
        self.wrong += (said.correct == Some(false)) as u64;
        // Each family's fields, once a line of it is counted.
        if said.cell {
            self.missed.get_or_insert(0);
        }
        if said.triangle {
            self.leaks.get_or_insert(0);
            self.back_faces.get_or_insert(0);
            self.t_alone.get_or_insert(0);
        }
        if let Some(t) = said.tet {
            let wrong = said.correct == Some(false);
            *self.wrong_face.get_or_insert(0) += (t.wrong == Some("wrong_face")) as u64;
            *self.no_exit_face.get_or_insert(0) += (t.wrong == Some("no_exit_face")) as u64;
            *self.at_tie.get_or_insert(0) += t.tie as u64;
            *self.wrong_at_tie.get_or_insert(0) += (t.tie && wrong) as u64;
            *self.touch_only.get_or_insert(0) += (t.touch_only && wrong) as u64;
        }
        if let Some(m) = self.missed.as_mut() {
            *m += said.correct.is_none() as u64;
        }
        if let Some(l) = self.leaks.as_mut() {
            *l += said.leak as u64;
        }
        if let Some(b) = self.back_faces.as_mut() {
            *b += (said.correct == Some(false) && said.back_face && !said.t_alone) as u64;
        }
        if let Some(n) = self.t_alone.as_mut() {
            *n += said.t_alone as u64;
        }
        if let Some(k) = said.kind {
            *self.kinds.entry(k).or_default() += 1;
        }
    }
}

/// What a command answering JSON Lines counted (`--json` writes it).
#[derive(serde::Serialize)]
pub(crate) struct AnswerSummary {
    backend: String,
    /// Lines read, blank ones left out.
    pub(crate) lines: u64,
    /// Lines that could not be answered.
    pub(crate) errors: u64,
    /// Each method's tally.
    pub(crate) methods: Vec<AnswerTally>,
}

impl AnswerSummary {
    /// Nothing counted yet for the methods `names` on `backend`; their tallies count lines missing
    /// the cell (`missed`) and leaks (`leaks`) from the start.
    pub(crate) fn new(
        backend: String,
        names: Vec<String>,
        missed: bool,
        leaks: bool,
    ) -> AnswerSummary {
        AnswerSummary {
            backend,
            lines: 0,
            errors: 0,
            methods: names
                .into_iter()
                .map(|method| AnswerTally {
                    method,
                    missed: missed.then_some(0),
                    leaks: leaks.then_some(0),
                    back_faces: leaks.then_some(0),
                    t_alone: leaks.then_some(0),
                    ..AnswerTally::default()
                })
                .collect(),
        }
    }

    /// Lines answered (read, less those that could not be).
    pub(crate) fn answered(&self) -> u64 {
        self.lines - self.errors
    }

    /// Cases a 4-wide version answered otherwise than its scalar version.
    pub(crate) fn wide_differs(&self) -> u64 {
        self.methods.iter().filter_map(|t| t.wide_differs).sum()
    }
}

/// Who answers a family's lines: methods on a backend, or answers given from outside (`judge`),
/// named.
pub(crate) enum Answered<'a, F: Family> {
    /// tetwalk's methods, on a backend.
    Methods(&'a [&'static F::Method], &'a Backend),
    /// Answers given with the cases (`judge`), under this name.
    Given(&'a str),
    /// A program outside tetwalk, asked each batch (`--answerer`).
    Outside(&'a Answerer),
}

/// The fields of a verdict line after `line`, `method` and `backend`: the answer beside the exact
/// one, as the family's printer writes them for the verdict it is given.
pub(crate) type Printer<F> = fn(
    &<F as Family>::Case,
    &<F as Family>::Truth,
    &<F as Family>::Answer,
    &Said,
) -> Map<String, Value>;

/// A case line taken: its number, the case, its truth, and the answer given for it (`judge`).
type Taken<F> = (
    usize,
    <F as Family>::Case,
    <F as Family>::Truth,
    Option<<F as Family>::Answer>,
);

/// One family's part of a command: who answers its cases, how its verdict lines are printed, the
/// bound on a hit's `t`, whether methods with a 4-wide version are answered by it too and compared
/// (`hit --wide`), and the cases of a batch taken so far.
pub(crate) struct Part<'a, F: Family> {
    answered: Answered<'a, F>,
    printer: Printer<F>,
    t_ulps: f64,
    /// Answer with each method's 4-wide version too and compare (`hit --wide`).
    pub(crate) wide: bool,
    taken: Vec<Taken<F>>,
}

impl<'a, F: Family> Part<'a, F> {
    /// A part answered as `answered` says, its lines printed by `printer`, a hit's `t` right within
    /// `t_ulps` ulps.
    pub(crate) fn new(answered: Answered<'a, F>, printer: Printer<F>, t_ulps: f64) -> Self {
        Part {
            answered,
            printer,
            t_ulps,
            wide: false,
            taken: Vec::new(),
        }
    }

    /// A verdict line's fields and what they say.
    fn judged(
        &self,
        case: &F::Case,
        truth: &F::Truth,
        a: &F::Answer,
    ) -> (Map<String, Value>, Said) {
        let said = F::said(case, truth, a, self.t_ulps);
        ((self.printer)(case, truth, a, &said), said)
    }
}

/// A family's part, whatever the family.
pub(crate) trait Takes {
    /// The family's name.
    fn name(&self) -> &'static str;
    /// Take line `n`'s object (a case of this family), with its answer given from outside where the
    /// command has such answers (`Some(None)`: none given for it): an error for the line, or `Ok` once
    /// taken.
    fn take(
        &mut self,
        n: usize,
        obj: Map<String, Value>,
        given: Option<Option<Value>>,
    ) -> Result<(), String>;
    /// The verdict lines of the cases taken (by line number), each method's counted in `summary`.
    fn answer(
        &mut self,
        summary: &mut AnswerSummary,
    ) -> Result<Vec<(usize, Value)>, AnsweringError>;
}

impl<F: Family> Takes for Part<'_, F> {
    fn name(&self) -> &'static str {
        F::NAME
    }

    fn take(
        &mut self,
        n: usize,
        obj: Map<String, Value>,
        given: Option<Option<Value>>,
    ) -> Result<(), String> {
        let case = Found::<F>::from_object(obj)
            .map_err(|e| e.to_string())?
            .case;
        let given = match given {
            None => None,
            Some(a) => Some(a.ok_or("no answer for this line in the answers")?),
        };
        let truth = F::truth(&case).map_err(|e| e.to_string())?;
        let given = match given {
            None => None,
            Some(a) => {
                let o = a.as_object().ok_or("an answer is a JSON object")?;
                if let Some(why) = o.get(NOT_JSON).and_then(Value::as_str) {
                    return Err(why.to_string());
                }
                Some(F::given(o, &case)?)
            }
        };
        self.taken.push((n, case, truth, given));
        Ok(())
    }

    fn answer(
        &mut self,
        summary: &mut AnswerSummary,
    ) -> Result<Vec<(usize, Value)>, AnsweringError> {
        let taken = std::mem::take(&mut self.taken);
        let mut out = Vec::new();
        match &self.answered {
            Answered::Given(name) => {
                for (n, case, truth, given) in &taken {
                    let a = given
                        .as_ref()
                        .expect("a given answer was taken with its case");
                    let (fields, said) = self.judged(case, truth, a);
                    summary.methods[0].count(said);
                    out.push((*n, line(*n, name, "given", fields)));
                }
            }
            Answered::Outside(x) => {
                let cases: Vec<F::Case> = taken.iter().map(|(_, c, ..)| *c).collect();
                let answers = x.answers::<F>(&cases)?;
                for ((n, case, truth, _), a) in taken.iter().zip(&answers) {
                    let (fields, said) = self.judged(case, truth, a);
                    summary.methods[0].count(said);
                    out.push((*n, line(*n, &x.name, "outside", fields)));
                }
            }
            Answered::Methods(methods, backend) => {
                let cases: Vec<F::Case> = taken.iter().map(|(_, c, ..)| *c).collect();
                let mut answers = Vec::new();
                let mut wide = Vec::new();
                for m in methods.iter() {
                    answers.push(F::answers(backend, m, &cases)?);
                    wide.push(self.wide.then(|| F::wide_answers(m, &cases)).flatten());
                }
                for (k, (n, case, truth, _)) in taken.iter().enumerate() {
                    for (i, m) in methods.iter().enumerate() {
                        let (mut fields, said) = self.judged(case, truth, &answers[i][k]);
                        let tally = summary
                            .methods
                            .iter_mut()
                            .find(|t| t.method == m.name())
                            .expect("every method has a tally");
                        tally.count(said);
                        if let Some(w) = &wide[i] {
                            // Hits are compared by value: each `t` a method reports is finite and
                            // above zero, where equal values are equal bits.
                            let same = w[k] == answers[i][k];
                            fields.insert("wide_same".into(), json!(same));
                            if !same {
                                fields.insert("wide_answer".into(), F::answer_json(&w[k]));
                            }
                            *tally.wide_compared.get_or_insert(0) += 1;
                            *tally.wide_differs.get_or_insert(0) += !same as u64;
                        }
                        let on = backend.for_method(*m).ran().kind.name();
                        out.push((*n, line(*n, m.name(), on, fields)));
                    }
                }
            }
        }
        Ok(out)
    }
}

/// A verdict line: `line`, `method`, `backend`, then the family's fields.
fn line(n: usize, method: &str, backend: &str, fields: Map<String, Value>) -> Value {
    let mut o = Map::new();
    o.insert("line".into(), json!(n));
    o.insert("method".into(), json!(method));
    o.insert("backend".into(), json!(backend));
    o.extend(fields);
    Value::Object(o)
}

/// The output lines for a batch of input lines: each line's family's part takes it (or `refuse`
/// says why no part answers that family here), with its answer taken out of `given` where the command
/// judges answers given from outside; then each part answers what it took, the lines in input order.
pub(crate) fn answer(
    batch: &[Line],
    parts: &mut [Box<dyn Takes + '_>],
    refuse: fn(Kind) -> String,
    given: Option<&mut HashMap<usize, Value>>,
    summary: &mut AnswerSummary,
) -> Result<String, AnsweringError> {
    let mut given = given;
    let mut out: Vec<(usize, Value)> = Vec::new();
    for (n, l) in batch {
        if l.as_ref().is_ok_and(|t| t.trim().is_empty()) {
            continue;
        }
        summary.lines += 1;
        let answer = given.as_mut().map(|g| g.remove(n));
        let taken = l.clone().and_then(|text| {
            let obj = object(&text).map_err(|e| e.to_string())?;
            let kind = owner(&obj);
            match parts.iter_mut().find(|p| p.name() == kind.name()) {
                Some(p) => p.take(*n, obj, answer),
                None => Err(refuse(kind)),
            }
        });
        if let Err(e) = taken {
            summary.errors += 1;
            out.push((*n, json!({"line": n, "error": brief(e)})));
        }
    }
    for p in parts.iter_mut() {
        out.extend(p.answer(summary)?);
    }
    out.sort_by_key(|(n, _)| *n);
    let mut s = String::new();
    for (_, v) in out {
        s += &v.to_string();
        s.push('\n');
    }
    Ok(s)
}

/// Each method's tally's standing, as `F`'s claims have it ([`AnswerTally::refuting`]).
pub(crate) fn standing<F: Family>(t: &AnswerTally) -> Standing {
    Standing::named::<F>(&t.method, t.right + t.wrong, t.wrong, |c| t.refuting(c))
}

/// A program's tally's standing, with the claim it makes (`--answerer-claims`), if it makes one, held
/// to its answers as `F`'s claim is ([`AnswerTally::refuting`]; leaks not counted refute nothing).
pub(crate) fn outside_standing<F: Family>(
    x: &crate::engine::answerer::Answerer,
    t: &AnswerTally,
) -> Standing {
    let mut s = vec![standing::<F>(t)];
    x.claim::<F>(&mut s, t.refuting(F::CLAIM).unwrap_or(0));
    s.remove(0)
}

impl AnswerTally {
    /// The answers that refute `claim`: a robust method's every wrong answer, a watertight one's
    /// leaks (where they are counted).
    pub(crate) fn refuting(&self, claim: crate::registry::Claim) -> Option<u64> {
        match claim {
            crate::registry::Claim::Robust => Some(self.wrong),
            crate::registry::Claim::NoLeak => self.leaks,
        }
    }
}

/// The cases file opened once (a pipe, `/dev/stdin`, cannot be read twice): its first line read to
/// see whether it is a `count --rays-out` header, then put back in front of the rest.
pub(crate) fn open_cases(
    path: &Path,
) -> Result<(Option<Value>, Box<dyn BufRead + Send>), AnsweringError> {
    let file = path.display().to_string();
    let mut input = open_lines(path)?;
    // The first line only, at most a line's length bound (a longer one is no header).
    let mut first = Vec::new();
    std::io::Read::take(&mut input, MAX_LINE)
        .read_until(b'\n', &mut first)
        .map_err(|e| AnsweringError::File {
            file: file.clone(),
            why: e.to_string(),
        })?;
    let header = match serde_json::from_slice::<Value>(&first) {
        Ok(v) if v.get("scene").is_some() => Some(v),
        _ => None,
    };
    let again = std::io::Read::chain(std::io::Cursor::new(first), input);
    Ok((header, Box::new(std::io::BufReader::new(again))))
}

/// Why an answers file cannot be read.
#[derive(Debug, thiserror::Error)]
pub(crate) enum AnswersError {
    #[error("{file}:{line}: {why}")]
    Answer {
        file: String,
        line: usize,
        why: String,
    },
    #[error("{file}: {why}")]
    File { file: String, why: String },
}

/// Each non-blank line of an answers file as a JSON value, with its line number, handed to `take`,
/// read through `exit`'s reader (each line at most its length bound); an error names file and line.
pub(crate) fn each_answer(
    path: &Path,
    mut take: impl FnMut(usize, Value) -> Result<(), String>,
) -> Result<(), AnswersError> {
    let file = path.display().to_string();
    let f = open_lines(path).map_err(|e| AnswersError::File {
        file: file.clone(),
        why: match e {
            AnsweringError::File { why, .. } => why,
            e => e.to_string(),
        },
    })?;
    for (i, l) in reader(f) {
        let at = |why: String| AnswersError::Answer {
            file: file.clone(),
            line: i,
            why,
        };
        let l = l.map_err(at)?;
        if l.trim().is_empty() {
            continue;
        }
        let v = match serde_json::from_str::<Value>(&l) {
            Ok(v) => v,
            // Not JSON, but naming its case line: an error for that line, the run goes on.
            Err(e) => match line_number(&l) {
                Some(n) => serde_json::json!({ "line": n, NOT_JSON: not_json(&e) }),
                None => return Err(at(not_json(&e))),
            },
        };
        take(i, v).map_err(at)?;
    }
    Ok(())
}

/// Why an answer line is not JSON, naming the forms that are (Python's `json.dumps` writes NaN and
/// Infinity, which JSON has not).
fn not_json(e: &serde_json::Error) -> String {
    format!(
        "not JSON ({e}); NaN and Infinity are not JSON numbers (Python's json.dumps writes them): a miss is \"tri\": null, \"hit\": false or \"face\": null, without \"t\""
    )
}

/// The case line an answer line names in its `"line": N`, read from text that is not JSON.
fn line_number(text: &str) -> Option<usize> {
    let rest = &text[text.find("\"line\"")? + 6..];
    let rest = rest.trim_start().strip_prefix(':')?.trim_start();
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok().filter(|&n| n >= 1)
}

/// The answers by case line, read whole (each a JSON object with a `line`).
pub(crate) fn read_answers(path: &Path) -> Result<HashMap<usize, Value>, AnswersError> {
    let mut out = HashMap::new();
    each_answer(path, |_, v| {
        let n = v
            .get("line")
            .and_then(Value::as_u64)
            .filter(|&n| n >= 1)
            .ok_or("needs \"line\", the case's line number (1-based)")? as usize;
        match out.insert(n, v) {
            Some(_) => Err(format!("a second answer for case line {n}")),
            None => Ok(()),
        }
    })?;
    Ok(out)
}
