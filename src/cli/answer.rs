//! Answering case lines, for `exit`, `hit`, `box-exit` and `judge`: lines read as they come (a reader
//! thread; whatever has arrived is answered as one batch), so a stream gets its answers as it goes and
//! memory stays bounded; each line's family (by its keys) takes it, if the command answers that
//! family, and answers it with the command's methods, or with answers given from outside.

use super::{BackendArg, FailArg, JsonOut, Status};
use crate::backend::Backend;
use crate::cases::object;
use crate::choice::Choice;
use crate::engine::found::Found;
use crate::engine::standing::Standing;
use crate::family::{Family, Kind, owner};
use crate::registry::Named;
use crate::report::counted;
use crate::report::lines::{Lines, Said};
use serde_json::{Map, Value, json};
use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::mpsc;

/// The arguments `exit` and `hit` share.
#[derive(clap::Args)]
pub(crate) struct Common {
    /// A method name, a comma-separated list, or `all`.
    #[arg(long, default_value = "all")]
    pub(crate) method: String,
    #[command(flatten)]
    pub(crate) backend: BackendArg,
    #[command(flatten)]
    pub(crate) fail: FailArg,
    /// Also write a summary (lines, errors, per method right / wrong, and for `exit` lines missing the
    /// tetrahedron) as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
    /// JSON Lines file of cases (found cases too); standard input when absent or `-`.
    pub(crate) file: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) answerer: super::AnswererArg,
}

impl Common {
    /// The cases read and the summary written.
    pub(crate) fn io(&self) -> super::Files {
        super::Files::default()
            .input("FILE", self.file.as_deref())
            .output("--json", self.json.as_deref())
    }

    /// Where the cases come from and the summary goes.
    pub(crate) fn input(&self) -> Input<'_> {
        Input {
            file: self.file.as_deref(),
            json: self.json.as_deref(),
            fail: self.fail,
        }
    }
}

/// Where a command's cases come from (standard input when `None`) and its summary goes, and how its
/// tallies stand under `--fail-on`.
#[derive(Clone, Copy)]
pub(crate) struct Input<'a> {
    pub file: Option<&'a std::path::Path>,
    pub json: Option<&'a std::path::Path>,
    pub fail: FailArg,
}

/// A file of JSON lines opened for reading (a pipe too: `/dev/stdin`; `-` is standard input); a
/// folder is refused.
pub(crate) fn open_lines(p: &std::path::Path) -> Result<Box<dyn BufRead + Send>, super::Error> {
    if p == std::path::Path::new("-") {
        return Ok(Box::new(std::io::BufReader::new(std::io::stdin())));
    }
    if p.is_dir() {
        return Err(format!("{}: is a folder, not a file of JSON lines", p.display()).into());
    }
    Ok(Box::new(std::io::BufReader::new(
        std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?,
    )))
}

/// The key under which an answer line that is not JSON keeps why, for its case line (`judge`).
pub(crate) const NOT_JSON: &str = "not JSON";

/// Longest line read, in bytes; a longer one is an error for that line.
pub(crate) const MAX_LINE: u64 = 1 << 20;
/// Most lines answered as one batch.
const BATCH: usize = 4096;

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

/// Answer the JSON Lines of `file` (standard input when `None`) batch by batch as they arrive: block
/// for one line, take whatever else has arrived, write `answer`'s text for them to standard output.
pub(crate) fn answer_lines(
    file: Option<&std::path::Path>,
    open: Option<Box<dyn BufRead + Send>>,
    mut answer: impl FnMut(&[Line]) -> Result<String, super::Error>,
) -> Result<(), super::Error> {
    let input: Box<dyn BufRead + Send> = match (open, file) {
        (Some(input), _) => input,
        (None, Some(p)) => open_lines(p)?,
        (None, None) => Box::new(std::io::BufReader::new(std::io::stdin())),
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
pub(crate) struct AnswerTally {
    pub method: String,
    pub right: u64,
    pub wrong: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub missed: Option<u64>,
    /// Wrong answers on closed meshes where the ray passes through the surface.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub leaks: Option<u64>,
    /// Wrong answers where the ray first meets a back face
    /// ([`crate::exact::hit::HitTruth::back_face`]), which a method that culls back faces passes by
    /// design.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub back_faces: Option<u64>,
    /// Wrong answers on closed meshes by kind ([`crate::exact::hit::HitTruth::wrong_kind`]), the stress
    /// rows' classification.
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub kinds: std::collections::BTreeMap<&'static str, u64>,
    /// Tetrahedra: wrong answers that are a face, and that are none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrong_face: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_exit_face: Option<u64>,
    /// Tetrahedra: answers to ties (more than one face right), and of them wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at_tie: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrong_at_tie: Option<u64>,
    /// Tetrahedra: wrong answers on lines that only touch the tetrahedron.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub touch_only: Option<u64>,
    /// Hits wrong for their `t` alone: the triangle right, `t` beyond `--t-ulps`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_alone: Option<u64>,
    /// With `hit --wide`, for a method with a 4-wide version: the cases it answered otherwise than
    /// the scalar version, and the cases compared.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wide_differs: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wide_compared: Option<u64>,
}

/// What a command answering JSON Lines writes with `--json`.
#[derive(serde::Serialize)]
pub(crate) struct Summary {
    backend: String,
    pub lines: u64,
    pub errors: u64,
    pub methods: Vec<AnswerTally>,
}

/// A command answering JSON Lines: its name, its methods' names, what their tallies count, where the
/// lines come from and the summary goes, and how a tally stands under `--fail-on`.
pub(crate) struct Answering<'a> {
    pub command: &'static str,
    pub names: Vec<String>,
    /// The tallies count lines missing the cell.
    pub missed: bool,
    /// The tallies count leaks.
    pub leaks: bool,
    pub backend: String,
    pub file: Option<&'a std::path::Path>,
    /// `file` already open (read once: a pipe cannot be read twice), or `None` to open it here.
    pub input: Option<Box<dyn BufRead + Send>>,
    pub json: Option<&'a std::path::Path>,
    pub fail: FailArg,
    pub standing: &'a dyn Fn(&AnswerTally) -> Standing,
}

impl<'a> Answering<'a> {
    /// tetwalk's own methods of family `F` on `backend` answering `input` (`exit`, `hit`, `box-exit`),
    /// standing as `F`'s claim says; the tallies count neither misses nor leaks.
    pub(crate) fn own<F: Family>(
        command: &'static str,
        methods: &[&'static F::Method],
        backend: &crate::backend::Backend,
        input: Input<'a>,
    ) -> Self {
        Answering {
            command,
            names: methods.iter().map(|m| m.name().to_string()).collect(),
            missed: false,
            leaks: false,
            backend: backend.describe(),
            file: input.file,
            input: None,
            json: input.json,
            fail: input.fail,
            standing: &standing::<F>,
        }
    }

    /// The tallies count lines missing the cell.
    pub(crate) fn missing(self) -> Self {
        Answering {
            missed: true,
            ..self
        }
    }

    /// The tallies count leaks.
    pub(crate) fn leaking(self) -> Self {
        Answering {
            leaks: true,
            ..self
        }
    }

    /// [`Answering::run`] with each batch answered by the parts `parts` makes, lines of a family no
    /// part takes refused as `refuse` says, and nothing checked after.
    pub(crate) fn by_parts<'p>(
        self,
        mut parts: impl FnMut() -> Vec<Box<dyn Takes + 'p>>,
        refuse: fn(Kind) -> String,
    ) -> Status {
        self.run(
            |batch, summary| answer(batch, &mut parts(), refuse, None, summary),
            || Ok(()),
        )
    }

    /// Answer the lines with `answer` (given each batch and the summary); then `after` checks what
    /// only the whole input tells (an error there writes no summary); then the summary goes to
    /// `--json`, and a line per method to standard error (cases answered, right, wrong, not judged).
    /// Exit status 1 when a line could not be answered, or under `--fail-on`.
    pub(crate) fn run(
        self,
        mut answer: impl FnMut(&[Line], &mut Summary) -> Result<String, super::Error>,
        after: impl FnOnce() -> Result<(), super::Error>,
    ) -> Status {
        let out = JsonOut::new(self.json)?;
        let mut summary = Summary {
            backend: self.backend,
            lines: 0,
            errors: 0,
            methods: self
                .names
                .into_iter()
                .map(|method| AnswerTally {
                    method,
                    missed: self.missed.then_some(0),
                    leaks: self.leaks.then_some(0),
                    back_faces: self.leaks.then_some(0),
                    t_alone: self.leaks.then_some(0),
                    ..AnswerTally::default()
                })
                .collect(),
        };
        answer_lines(self.file, self.input, |batch| answer(batch, &mut summary))?;
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
        let answered = summary.lines - summary.errors;
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
                (Some(n), Some(d)) => format!(
                    "; its 4-wide version answered {d} of {n} otherwise than the scalar one"
                ),
                _ => String::new(),
            };
            eprintln!(
                "tetwalk {}: {}: {}, {} right, {} wrong{back}, {not} not judged{}{wide}",
                self.command,
                t.method,
                counted(answered, "case", "cases"),
                t.right,
                t.wrong,
                if t.missed.is_some() && not > 0 {
                    " (the line misses the cell)"
                } else {
                    ""
                }
            );
        }
        let standings: Vec<Standing> = summary.methods.iter().map(|t| (self.standing)(t)).collect();
        let status = self.fail.status(self.command, &standings);
        let differ: u64 = summary.methods.iter().filter_map(|t| t.wide_differs).sum();
        if differ > 0 {
            eprintln!(
                "tetwalk {}: a 4-wide version answered {} otherwise than its scalar version (the lines' \"wide_same\": false)",
                self.command,
                counted(differ, "case", "cases")
            );
        }
        if summary.errors > 0 {
            eprintln!(
                "tetwalk {}: {} could not be answered",
                self.command,
                counted(summary.errors, "line", "lines")
            );
        }
        if differ > 0 || summary.errors > 0 {
            return Ok(ExitCode::FAILURE);
        }
        Ok(status)
    }
}

/// Who answers a family's lines: methods on a backend, or answers given from outside (`judge`),
/// named.
pub(crate) enum Answered<'a, F: Family> {
    Methods(&'a [&'static F::Method], &'a Backend),
    Given(&'a str),
    /// A program outside tetwalk, asked each batch (`--answerer`).
    Outside(&'a crate::engine::answerer::Answerer),
}

/// A case line taken: its number, the case, its truth, and the answer given for it (`judge`).
type Taken<F> = (
    usize,
    <F as Family>::Case,
    <F as Family>::Truth,
    Option<<F as Family>::Answer>,
);

/// One family's part of a command: who answers its cases, whether methods with a 4-wide version are
/// answered by it too and compared (`hit --wide`), and the cases of a batch taken so far.
pub(crate) struct Part<'a, F: Family> {
    pub answered: Answered<'a, F>,
    pub t_ulps: f64,
    pub wide: bool,
    taken: Vec<Taken<F>>,
}

impl<'a, F: Lines> Part<'a, F> {
    pub(crate) fn new(answered: Answered<'a, F>, t_ulps: f64) -> Self {
        Part {
            answered,
            t_ulps,
            wide: false,
            taken: Vec::new(),
        }
    }
}

/// A part for each family whose answers given from outside `judge` reads ([`Family::GIVEN`]),
/// from the families' list: `families!(__given_parts, NAME, T_ULPS)`.
#[doc(hidden)]
#[macro_export]
macro_rules! __given_parts {
    ([$name:expr, $t_ulps:expr] { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {{
        let mut parts: Vec<Box<dyn $crate::cli::answer::Takes + '_>> = Vec::new();
        $(
            if <$ty as $crate::family::Family>::GIVEN {
                parts.push(Box::new($crate::cli::answer::Part::<$ty>::new(
                    $crate::cli::answer::Answered::Given($name),
                    $t_ulps,
                )));
            }
        )*
        parts
    }};
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
    fn answer(&mut self, summary: &mut Summary) -> Result<Vec<(usize, Value)>, super::Error>;
}

impl<F: Lines> Takes for Part<'_, F> {
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

    fn answer(&mut self, summary: &mut Summary) -> Result<Vec<(usize, Value)>, super::Error> {
        let taken = std::mem::take(&mut self.taken);
        let mut out = Vec::new();
        match &self.answered {
            Answered::Given(name) => {
                for (n, case, truth, given) in &taken {
                    let a = given
                        .as_ref()
                        .expect("a given answer was taken with its case");
                    let (fields, said) = F::verdict_line(case, truth, a, self.t_ulps);
                    summary.methods[0].count(said);
                    out.push((*n, line(*n, name, "given", fields)));
                }
            }
            Answered::Outside(x) => {
                let cases: Vec<F::Case> = taken.iter().map(|(_, c, ..)| *c).collect();
                let answers = x.answers::<F>(&cases)?;
                for ((n, case, truth, _), a) in taken.iter().zip(&answers) {
                    let (fields, said) = F::verdict_line(case, truth, a, self.t_ulps);
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
                        let (mut fields, said) =
                            F::verdict_line(case, truth, &answers[i][k], self.t_ulps);
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

/// `exit` or `hit` with `--answerer`: each batch of family `F`'s lines asked of the program, its
/// answers judged (the other families' lines refused as `refuse` says).
pub(crate) fn outside<F: Lines>(
    command: &'static str,
    x: &crate::engine::answerer::Answerer,
    a: &Common,
    refuse: fn(Kind) -> String,
    t_ulps: f64,
) -> Status {
    Answering {
        command,
        names: vec![x.name.clone()],
        missed: false,
        leaks: false,
        backend: "outside".into(),
        file: a.file.as_deref(),
        input: None,
        json: a.json.as_deref(),
        fail: a.fail,
        standing: &|t| {
            // The claim it makes, if it makes one: robust refuted by every wrong answer, no leak by leaks.
            let mut s = vec![standing::<F>(t)];
            let refuted = match F::CLAIM {
                crate::registry::Claim::Robust => t.wrong,
                crate::registry::Claim::NoLeak => t.leaks.unwrap_or(0),
            };
            x.claim::<F>(&mut s, refuted);
            s.remove(0)
        },
    }
    .by_parts(
        || vec![Box::new(Part::<F>::new(Answered::Outside(x), t_ulps))],
        refuse,
    )
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

impl AnswerTally {
    /// Count one verdict line.
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

/// The output lines for a batch of input lines: each line's family's part takes it (or `refuse`
/// says why no part answers that family here), with its answer taken out of `given` where the command
/// judges answers given from outside; then each part answers what it took, the lines in input order.
pub(crate) fn answer(
    batch: &[Line],
    parts: &mut [Box<dyn Takes + '_>],
    refuse: fn(Kind) -> String,
    given: Option<&mut HashMap<usize, Value>>,
    summary: &mut Summary,
) -> Result<String, super::Error> {
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
            out.push((*n, json!({"line": n, "error": e})));
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

/// Each method's tally's standing, as `F`'s claims have it: a robust method's claim refuted by every
/// wrong answer, a watertight one's by its leaks.
pub(crate) fn standing<F: Family>(t: &AnswerTally) -> Standing {
    Standing::named::<F>(&t.method, t.right + t.wrong, t.wrong, |c| match c {
        crate::registry::Claim::Robust => Some(t.wrong),
        crate::registry::Claim::NoLeak => t.leaks,
    })
}
