//! The answerer protocol: a user's program (C, CUDA host, Python, anything) started once and asked
//! batches of cases over its standard input, answering on its standard output — in JSON Lines, or in
//! fixed little-endian binary records (docs/answerers.md). Each batch is held to a time limit; the
//! program runs in a process group of its own, ended with tetwalk (`crate::child`); its answers are
//! checked as strictly as `tetwalk judge` checks an answers file, each against the case it names (a
//! JSON line's `"line"`, a binary record's first `uint32`), so that a stream with an answer too many
//! or too few is refused where it shifts, and read to its end once the run is done ([`Answerer::finish`]).

use crate::family::Family;
use crate::family::contract::Contract;
use serde_json::Value;
use std::io::{Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, RecvTimeoutError, sync_channel};
use std::time::{Duration, Instant};

/// How cases and answers travel.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum WireFormat {
    /// A case line as `exit`, `hit` and `box-exit` read it, with `"line": n` (cases numbered from 1
    /// over the whole run); an empty line ends each batch. One answer line per case, as `judge` reads
    /// them, with the case's `"line"`.
    #[default]
    Json,
    /// Per batch a `u32` count, then that many case records, each its case's number (`u32`, the
    /// JSON `"line"`) and the family's fields ([`Family::case_record`]); the answers, that many
    /// records, each the case's number and the family's answer fields, in the cases' order.
    Binary,
}

crate::choice!(WireFormat { Json => "json", Binary => "binary" });

/// Longest answer line read, in bytes.
const MAX_LINE: usize = 1 << 16;

/// Bytes of the case number that begins every binary case and answer record.
const NUMBER: usize = 4;

/// Most characters of a program's output quoted in a message.
const QUOTED: usize = 60;

/// How long an answerer whose output has closed is given to exit, so that its exit status is said,
/// and how long one whose input has closed at the end of the run is given to end its output.
const EXIT_GRACE: Duration = Duration::from_secs(2);

/// Why an answerer gave no answers.
#[derive(Debug, thiserror::Error)]
#[error("answerer {name} ({cmd}): {why}")]
pub(crate) struct AnswererError {
    pub(crate) name: String,
    pub(crate) cmd: String,
    pub(crate) why: String,
}

/// What the reader thread hands over: the program's output as it arrives, or its end.
enum Chunk {
    Bytes(Vec<u8>),
    /// Its output ended (closed, or reading it failed: why).
    End(Option<String>),
}

/// The running program.
struct Running {
    child: Child,
    stdin: Option<ChildStdin>,
    from: Receiver<Chunk>,
    /// Output read and not yet taken as answers.
    pending: Vec<u8>,
    /// Cases sent so far (each case's number is one more than the cases before it).
    sent: u64,
    /// Why it can answer no more, once it cannot.
    broken: Option<String>,
    /// Whether the run's end was seen ([`Answerer::finish`]).
    finished: bool,
}

/// A user's program answering cases (module docs).
pub struct Answerer {
    /// Its name in reports and found cases.
    pub(crate) name: String,
    /// The shell command that starts it.
    pub(crate) cmd: String,
    pub(crate) format: WireFormat,
    /// Seconds one batch may take.
    pub(crate) limit: Duration,
    /// Cases per batch.
    pub(crate) batch: usize,
    /// Whether it claims what its family's claim is ([`Family::CLAIM`]): `--fail-on claims` then
    /// holds it to that.
    pub(crate) claims: bool,
    /// Answered face `i` is the case's face `faces[i]` (exit faces; the identity unless a numbering
    /// was found or given, [`find_numbering`]); cases are sent in it too ([`Family::for_program`]).
    pub(crate) faces: [u8; 4],
    running: Mutex<Running>,
}

/// Who answered, as a report records it: `count merge` adds up only shards asked of the same program,
/// in the same way.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Asked {
    pub(crate) name: String,
    /// The shell command that started it.
    pub(crate) program: String,
    pub(crate) format: WireFormat,
    /// Its face `i` is the case's face `faces[i]`.
    pub(crate) faces: [u8; 4],
    /// The contract its cases were made under ([`Contract::describe`]), where not the default one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) contract: Option<String>,
}

/// The first [`QUOTED`] characters of `bytes` as text (invalid UTF-8 replaced), on one line.
fn quoted(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let text = text.trim();
    let mut q: String = text.chars().take(QUOTED).collect();
    if q.len() < text.len() {
        q.push('…');
    }
    q.replace('\n', "\\n")
}

/// Where output read as JSON Lines is not text: the offset of its first byte that no answer line
/// holds (a control character other than tab and carriage return, or invalid UTF-8; a multi-byte
/// character cut at the end is not yet invalid).
fn not_text(bytes: &[u8]) -> Option<usize> {
    let control = bytes
        .iter()
        .position(|&b| (b < 0x20 && !matches!(b, b'\t' | b'\r' | b'\n')) || b == 0x7f);
    let invalid = match std::str::from_utf8(bytes) {
        Err(e) if e.error_len().is_some() => Some(e.valid_up_to()),
        _ => None,
    };
    match (control, invalid) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Whether a binary record's first bytes read as text (printable ASCII or white space): a program
/// that prints where it should write records.
fn looks_like_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .all(|&b| (0x20..0x7f).contains(&b) || matches!(b, b'\t' | b'\r' | b'\n'))
}

/// Cases `first` to `first + n - 1` in words.
fn lines(first: u64, n: usize) -> String {
    match n {
        1 => format!("line {first}"),
        _ => format!("lines {first} to {}", first + n as u64 - 1),
    }
}

impl Answerer {
    /// Start `cmd` (through `sh -c`) in a process group of its own.
    pub(crate) fn start(
        name: &str,
        cmd: &str,
        format: WireFormat,
        limit: Duration,
        batch: usize,
    ) -> Result<Answerer, AnswererError> {
        let fail = |why: String| AnswererError {
            name: name.into(),
            cmd: cmd.into(),
            why,
        };
        let mut child = crate::child::spawn(
            Command::new("sh")
                .args(["-c", cmd])
                .stdin(Stdio::piped())
                .stdout(Stdio::piped()),
        )
        .map_err(|e| fail(e.to_string()))?;
        let mut out = child
            .stdout
            .take()
            .ok_or_else(|| fail("no standard output".into()))?;
        let (tx, from) = sync_channel(1024);
        std::thread::spawn(move || {
            loop {
                let mut buf = vec![0; 1 << 16];
                let chunk = match out.read(&mut buf) {
                    Ok(0) => Chunk::End(None),
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(e) => Chunk::End(Some(format!("reading its output: {e}"))),
                    Ok(n) => {
                        buf.truncate(n);
                        Chunk::Bytes(buf)
                    }
                };
                let end = matches!(chunk, Chunk::End(_));
                if tx.send(chunk).is_err() || end {
                    return;
                }
            }
        });
        let stdin = child.stdin.take();
        Ok(Answerer {
            name: name.into(),
            cmd: cmd.into(),
            format,
            limit,
            batch: batch.max(1),
            claims: false,
            faces: [0, 1, 2, 3],
            running: Mutex::new(Running {
                child,
                stdin,
                from,
                pending: Vec::new(),
                sent: 0,
                broken: None,
                finished: false,
            }),
        })
    }

    /// Who it is, as a report records it.
    /// Who answered, asked under contract `k`.
    pub(crate) fn asked(&self, k: &Contract) -> Asked {
        Asked {
            name: self.name.clone(),
            program: self.cmd.clone(),
            format: self.format,
            faces: self.faces,
            contract: (!k.is_default()).then(|| k.describe()),
        }
    }

    fn error(&self, why: String) -> AnswererError {
        AnswererError {
            name: self.name.clone(),
            cmd: self.cmd.clone(),
            why,
        }
    }

    /// Its answers to `cases`, batch by batch, each answer checked as `judge` checks one and read in
    /// the case's own numbering ([`Answerer::faces`]).
    pub(crate) fn answers<F: Family>(
        &self,
        cases: &[F::Case],
    ) -> Result<Vec<F::Answer>, AnswererError> {
        let mut out = Vec::with_capacity(cases.len());
        for batch in cases.chunks(self.batch) {
            out.extend(
                self.raw::<F>(batch, &self.faces)?
                    .into_iter()
                    .map(|a| F::renumbered(a, &self.faces)),
            );
        }
        Ok(out)
    }

    /// One batch's answers, as the program numbers faces, the cases sent in the numbering `faces`.
    fn raw<F: Family>(
        &self,
        batch: &[F::Case],
        faces: &[u8; 4],
    ) -> Result<Vec<F::Answer>, AnswererError> {
        let mut r = self
            .running
            .lock()
            .map_err(|_| self.error("a thread asking it failed".into()))?;
        if let Some(why) = &r.broken {
            return Err(self.error(why.clone()));
        }
        if r.finished {
            return Err(self.error("asked after the run's end".into()));
        }
        let first = r.sent + 1;
        let last = first + batch.len() as u64 - 1;
        let mut bytes = Vec::new();
        match self.format {
            WireFormat::Json => {
                for (k, c) in batch.iter().enumerate() {
                    let mut obj = F::case_json(&F::for_program(c, faces));
                    obj.insert("line".into(), Value::from(first + k as u64));
                    bytes.extend(Value::Object(obj).to_string().into_bytes());
                    bytes.push(b'\n');
                }
                bytes.push(b'\n');
            }
            WireFormat::Binary => {
                if last > u32::MAX as u64 {
                    return Err(self.error(format!(
                        "binary records number cases with a uint32: case {last} is past {}; ask fewer cases in one run",
                        u32::MAX
                    )));
                }
                bytes.extend((batch.len() as u32).to_le_bytes());
                for (k, c) in batch.iter().enumerate() {
                    let rec = F::case_record(&F::for_program(c, faces)).ok_or_else(|| {
                        self.error(format!(
                            "the {} family's case {} has no binary record (docs/answerers.md lists them): use --answerer-format json",
                            F::NAME,
                            Value::Object(F::case_json(c))
                        ))
                    })?;
                    bytes.extend(((first + k as u64) as u32).to_le_bytes());
                    bytes.extend(rec);
                }
            }
        }
        r.sent = last;
        let deadline = Instant::now() + self.limit;
        let result = std::thread::scope(|s| {
            let mut stdin = r.stdin.take();
            let writer = s.spawn(move || {
                let w = stdin
                    .as_mut()
                    .map(|i| i.write_all(&bytes).and_then(|_| i.flush()));
                (stdin, w)
            });
            let got = self.collect::<F>(&mut r, batch, first, deadline);
            // On an error: whether it was still running with its input's writer already ended,
            // and then it is stopped, so that a writer blocked by a program that reads no more
            // ends too.
            let alive_writer_ended = got.is_err().then(|| {
                let alive = matches!(r.child.try_wait(), Ok(None));
                let ended = writer.is_finished();
                crate::child::kill(&mut r.child);
                alive && ended
            });
            let (stdin, written) = writer.join().unwrap_or((None, None));
            r.stdin = stdin;
            match (got, written, alive_writer_ended) {
                (Ok(a), ..) => Ok(a),
                (Err(e), Some(Err(w)), Some(true))
                    if w.kind() == std::io::ErrorKind::BrokenPipe =>
                {
                    Err(format!("{e} (it stopped reading its input)"))
                }
                (Err(e), ..) => Err(e),
            }
        });
        result.map_err(|why| {
            r.broken = Some(why.clone());
            crate::child::kill(&mut r.child);
            self.error(why)
        })
    }

    /// The batch's answers as they arrive, until `deadline`.
    fn collect<F: Family>(
        &self,
        r: &mut Running,
        batch: &[F::Case],
        first: u64,
        deadline: Instant,
    ) -> Result<Vec<F::Answer>, String> {
        let n = batch.len();
        let mut answers: Vec<Option<F::Answer>> = vec![None; n];
        let mut got = 0;
        loop {
            match self.format {
                WireFormat::Json => {
                    self.json_answers::<F>(r, batch, first, &mut answers, &mut got)?
                }
                WireFormat::Binary => {
                    binary_answers::<F>(r, batch, first, &mut answers, &mut got)?;
                    if got == n && !r.pending.is_empty() {
                        return Err(format!(
                            "{} bytes more than the {n} answer records of {} bytes asked ({}): an answer too many, or records of another size",
                            r.pending.len(),
                            NUMBER + F::ANSWER_RECORD,
                            lines(first, n)
                        ));
                    }
                }
            }
            if got == n {
                return Ok(answers.into_iter().flatten().collect());
            }
            let wait = deadline.saturating_duration_since(Instant::now());
            match r.from.recv_timeout(wait) {
                Ok(Chunk::Bytes(b)) => r.pending.extend(b),
                Err(RecvTimeoutError::Timeout) => {
                    return Err(format!(
                        "answered {got} of a batch's {n} cases ({}) within its time limit of {:?} (--answerer-seconds); stopped, with everything it started",
                        lines(first, n),
                        self.limit
                    ));
                }
                Ok(Chunk::End(why)) => return Err(ended(r, why, got, n, first, deadline)),
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(ended(r, None, got, n, first, deadline));
                }
            }
        }
    }

    /// The whole answer lines among `r.pending`, each taken as the answer to the case it names.
    fn json_answers<F: Family>(
        &self,
        r: &mut Running,
        batch: &[F::Case],
        first: u64,
        answers: &mut [Option<F::Answer>],
        got: &mut usize,
    ) -> Result<(), String> {
        let n = batch.len();
        if let Some(at) = not_text(&r.pending) {
            return Err(format!(
                "its output is not JSON Lines: byte {at} of what it wrote is 0x{:02x} ('{}'), not text — does it answer in binary records (--answerer-format binary)?",
                r.pending[at],
                quoted(&r.pending[at.saturating_sub(8)..(at + 8).min(r.pending.len())])
            ));
        }
        while *got < n {
            let Some(end) = r.pending.iter().position(|&b| b == b'\n') else {
                if r.pending.len() > MAX_LINE {
                    return Err(format!(
                        "an answer line longer than {MAX_LINE} bytes ('{}')",
                        quoted(&r.pending)
                    ));
                }
                return Ok(());
            };
            let bytes: Vec<u8> = r.pending.drain(..=end).collect();
            let line = String::from_utf8_lossy(&bytes);
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let v: Value = serde_json::from_str(line).map_err(|e| {
                format!(
                    "answered '{}', not a JSON line ({e})",
                    quoted(line.as_bytes())
                )
            })?;
            let obj = v.as_object().ok_or_else(|| {
                format!("answered '{}', not a JSON object", quoted(line.as_bytes()))
            })?;
            let k = obj.get("line").and_then(Value::as_u64).ok_or_else(|| {
                format!(
                    "answered '{}' without \"line\", the case's number",
                    quoted(line.as_bytes())
                )
            })?;
            if (1..first).contains(&k) {
                return Err(format!(
                    "a second answer for line {k} ('{}'), whose batch was answered already",
                    quoted(line.as_bytes())
                ));
            }
            if !(first..first + n as u64).contains(&k) {
                return Err(format!(
                    "answered '{}' for line {k}, which is not in the batch asked ({})",
                    quoted(line.as_bytes()),
                    lines(first, n)
                ));
            }
            let i = (k - first) as usize;
            if answers[i].is_some() {
                return Err(format!(
                    "a second answer for line {k} in its batch ({}): '{}'",
                    lines(first, n),
                    quoted(line.as_bytes())
                ));
            }
            answers[i] =
                Some(F::given(obj, &batch[i]).map_err(|e| {
                    format!("line {k}: {e} (answered '{}')", quoted(line.as_bytes()))
                })?);
            *got += 1;
        }
        Ok(())
    }

    /// The end of the run: its input closed, and its output read to the end (for at most
    /// [`EXIT_GRACE`]), so that an answer past the last batch's — a second answer for its last case, a
    /// record too many — is an error, not a thing left unread. Once; a broken run's error stands.
    pub(crate) fn finish(&self) -> Result<(), AnswererError> {
        let Ok(mut r) = self.running.lock() else {
            return Err(self.error("a thread asking it failed".into()));
        };
        if r.finished || r.broken.is_some() {
            return Ok(());
        }
        r.finished = true;
        drop(r.stdin.take());
        let deadline = Instant::now() + EXIT_GRACE;
        loop {
            let extra = match self.format {
                WireFormat::Json => r.pending.iter().any(|b| !b.is_ascii_whitespace()),
                WireFormat::Binary => !r.pending.is_empty(),
            };
            if extra {
                break;
            }
            match r
                .from
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
            {
                Ok(Chunk::Bytes(b)) => r.pending.extend(b),
                Ok(Chunk::End(_)) | Err(_) => return Ok(()),
            }
        }
        // More arrived, or is arriving: what it says, read for a moment longer.
        while let Ok(Chunk::Bytes(b)) = r.from.recv_timeout(Duration::from_millis(50)) {
            r.pending.extend(b);
            if r.pending.len() > MAX_LINE {
                break;
            }
        }
        let why = match self.format {
            WireFormat::Json => {
                let text = String::from_utf8_lossy(&r.pending);
                let line = text
                    .lines()
                    .map(str::trim)
                    .find(|l| !l.is_empty())
                    .unwrap_or("");
                let numbered = serde_json::from_str::<Value>(line)
                    .ok()
                    .and_then(|v| v.get("line").and_then(Value::as_u64));
                match numbered {
                    Some(k) if k <= r.sent => format!(
                        "a second answer for line {k} after the run's last batch was answered ('{}')",
                        quoted(line.as_bytes())
                    ),
                    _ => format!(
                        "answered '{}' after the run's last batch was answered (every case's answer was read)",
                        quoted(line.as_bytes())
                    ),
                }
            }
            WireFormat::Binary => format!(
                "{} bytes after the run's last batch was answered (every case's answer record was read){}: an answer too many",
                r.pending.len(),
                if looks_like_text(&r.pending[..r.pending.len().min(NUMBER)]) {
                    format!(", text: '{}'", quoted(&r.pending))
                } else {
                    String::new()
                }
            ),
        };
        r.broken = Some(why.clone());
        crate::child::kill(&mut r.child);
        Err(self.error(why))
    }
}

/// The whole answer records among `r.pending`, each checked to carry its case's number.
fn binary_answers<F: Family>(
    r: &mut Running,
    batch: &[F::Case],
    first: u64,
    answers: &mut [Option<F::Answer>],
    got: &mut usize,
) -> Result<(), String> {
    let n = batch.len();
    let size = NUMBER + F::ANSWER_RECORD;
    while *got < n && r.pending.len() >= size {
        let want = first + *got as u64;
        let number = u32::from_le_bytes([r.pending[0], r.pending[1], r.pending[2], r.pending[3]]);
        if looks_like_text(&r.pending[..NUMBER]) {
            return Err(format!(
                "its output holds text ('{}') where the binary answer record of line {want} was expected: does it print to its standard output?",
                quoted(&r.pending)
            ));
        }
        if number as u64 != want {
            return Err(format!(
                "answer record {} of the batch ({}) carries case number {number} where {want} was expected: the answer stream shifted (an answer too many or too few before it, or records of another size than {size} bytes)",
                *got + 1,
                lines(first, n)
            ));
        }
        let rec: Vec<u8> = r.pending.drain(..size).collect();
        answers[*got] = Some(
            F::answer_record(&rec[NUMBER..], &batch[*got])
                .map_err(|e| format!("line {want}: {e}"))?,
        );
        *got += 1;
    }
    Ok(())
}

/// Why the batch got no more answers once the program's output ended: its exit status waited for
/// (within [`EXIT_GRACE`] and the deadline), to be said whether or not it came first.
fn ended(
    r: &mut Running,
    why: Option<String>,
    got: usize,
    n: usize,
    first: u64,
    deadline: Instant,
) -> String {
    let grace = deadline
        .saturating_duration_since(Instant::now())
        .min(EXIT_GRACE);
    let status = crate::child::wait(&mut r.child, grace).ok();
    format!(
        "{} after {got} of a batch's {n} answers ({}){}",
        why.unwrap_or_else(|| "its output ended".into()),
        lines(first, n),
        status.map_or(String::new(), |s| format!("; {}", crate::child::said(s)))
    )
}

impl Answerer {
    /// Its standing in `standings` given the claim it makes, if it makes one: `refuted` answers of this
    /// run refute it.
    pub(crate) fn claim<F: Family>(
        &self,
        standings: &mut [crate::engine::standing::Standing],
        refuted: u64,
    ) {
        if !self.claims {
            return;
        }
        for s in standings.iter_mut().filter(|s| s.method == self.name) {
            s.claim = Some(crate::engine::standing::Held {
                claim: F::CLAIM.name(),
                refuted: Some(refuted),
            });
        }
    }
}

impl Drop for Answerer {
    /// Its input closed (its end of the run), then it and everything it started ended.
    fn drop(&mut self) {
        if let Ok(r) = self.running.get_mut() {
            drop(r.stdin.take());
            let _ = crate::child::wait(&mut r.child, Duration::from_secs(2));
        }
    }
}

/// The face numbering under which `a` answers well-shaped cases of family `F` holding contract `k`
/// rightly ([`crate::engine::numbering::find`]), with the number of cases asked; where none fits, an
/// error saying what was found.
pub(crate) fn find_numbering<F: Family>(
    a: &Answerer,
    k: &crate::family::contract::Contract,
) -> Result<([u8; 4], usize), AnswererError> {
    use crate::choice::Choice;
    use crate::engine::numbering::{Numbering, find};
    let ask = |cases: &[F::Case], p: &[u8; 4]| {
        let mut raw = Vec::with_capacity(cases.len());
        for batch in cases.chunks(a.batch) {
            raw.extend(a.raw::<F>(batch, p)?);
        }
        Ok(raw)
    };
    let (miss, asked) = match find::<F, AnswererError>(k, ask)? {
        (Numbering::Fits(p), asked) => return Ok((p, asked)),
        miss => miss,
    };
    // Where it answered faces but none fits, whether the tetrahedra mirrored fit.
    let mirrored = match (&miss, k.mirrored()) {
        (Numbering::NoFit { no_face: false, .. }, Some(other)) => {
            let fits = match find::<F, AnswererError>(&other, ask)?.0 {
                Numbering::Fits(p) => Some(p),
                Numbering::NoFit { .. } => None,
            };
            Some((other.orientation, fits))
        }
        _ => None,
    };
    Err(a.error(miss.why(k, asked, mirrored, |o, p| {
        format!(
            "give --orientation {} --faces {}",
            o.name(),
            p.map(|f| f.to_string()).join(",")
        )
    })))
}
