//! The answerer protocol: a user's program (C, CUDA host, Python, anything) started once and asked
//! batches of cases over its standard input, answering on its standard output — in JSON Lines, or in
//! fixed little-endian binary records (docs/answerers.md). Each batch is held to a time limit; the
//! program runs in a process group of its own, ended with tetwalk (`crate::child`); its answers are
//! checked as strictly as `tetwalk judge` checks an answers file.

use crate::family::{Family, Verdict};
use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, RecvTimeoutError, sync_channel};
use std::time::{Duration, Instant};

/// How cases and answers travel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum WireFormat {
    /// A case line as `exit`, `hit` and `box-exit` read it, with `"line": n` (cases numbered from 1
    /// over the whole run); an empty line ends each batch. One answer line per case, as `judge` reads
    /// them.
    #[default]
    Json,
    /// Per batch a `u32` count, then that many case records; the answers, that many answer records
    /// in the cases' order ([`Family::case_record`]).
    Binary,
}

crate::choice!(WireFormat { Json => "json", Binary => "binary" });

/// Longest answer line read, in bytes.
const MAX_LINE: u64 = 1 << 16;

/// How long an answerer whose output has closed is given to exit, so that its exit status is said.
const EXIT_GRACE: Duration = Duration::from_secs(2);

/// Why an answerer gave no answers.
#[derive(Debug, thiserror::Error)]
#[error("answerer {name} ({cmd}): {why}")]
pub(crate) struct AnswererError {
    pub(crate) name: String,
    pub(crate) cmd: String,
    pub(crate) why: String,
}

/// What the reader thread hands over.
enum Chunk {
    Line(Result<String, String>),
    Bytes(Vec<u8>),
    End,
}

/// The running program.
struct Running {
    child: Child,
    stdin: Option<ChildStdin>,
    from: Receiver<Chunk>,
    /// Bytes read of binary answers not yet taken.
    pending: Vec<u8>,
    /// Cases sent so far (JSON lines are numbered on from it).
    sent: u64,
    /// Why it can answer no more, once it cannot.
    broken: Option<String>,
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
    /// was found or given, [`find_numbering`]).
    pub(crate) faces: [u8; 4],
    running: Mutex<Running>,
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
        let out = child
            .stdout
            .take()
            .ok_or_else(|| fail("no standard output".into()))?;
        let (tx, from) = sync_channel(1024);
        std::thread::spawn(move || {
            let mut out = BufReader::new(out);
            loop {
                let chunk = match format {
                    WireFormat::Json => {
                        let mut buf = Vec::new();
                        match (&mut out).take(MAX_LINE).read_until(b'\n', &mut buf) {
                            Ok(0) => Chunk::End,
                            Err(e) => Chunk::Line(Err(format!("reading its output: {e}"))),
                            Ok(_) if buf.last() != Some(&b'\n') && buf.len() as u64 == MAX_LINE => {
                                Chunk::Line(Err(format!(
                                    "an answer line longer than {MAX_LINE} bytes"
                                )))
                            }
                            Ok(_) => Chunk::Line(
                                String::from_utf8(buf)
                                    .map_err(|_| "an answer line is not UTF-8".into()),
                            ),
                        }
                    }
                    WireFormat::Binary => {
                        let mut buf = vec![0; 1 << 16];
                        match out.read(&mut buf) {
                            Ok(0) | Err(_) => Chunk::End,
                            Ok(n) => {
                                buf.truncate(n);
                                Chunk::Bytes(buf)
                            }
                        }
                    }
                };
                let end = matches!(chunk, Chunk::End | Chunk::Line(Err(_)));
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
            }),
        })
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
                self.raw::<F>(batch)?
                    .into_iter()
                    .map(|a| F::renumbered(a, &self.faces)),
            );
        }
        Ok(out)
    }

    /// One batch's answers, as the program numbers faces.
    fn raw<F: Family>(&self, batch: &[F::Case]) -> Result<Vec<F::Answer>, AnswererError> {
        let mut r = self
            .running
            .lock()
            .map_err(|_| self.error("a thread asking it failed".into()))?;
        if let Some(why) = &r.broken {
            return Err(self.error(why.clone()));
        }
        let first = r.sent + 1;
        let mut bytes = Vec::new();
        match self.format {
            WireFormat::Json => {
                for (k, c) in batch.iter().enumerate() {
                    let mut obj = F::case_json(c);
                    obj.insert("line".into(), Value::from(first + k as u64));
                    bytes.extend(Value::Object(obj).to_string().into_bytes());
                    bytes.push(b'\n');
                }
                bytes.push(b'\n');
            }
            WireFormat::Binary => {
                bytes.extend((batch.len() as u32).to_le_bytes());
                for c in batch {
                    let rec = F::case_record(c).ok_or_else(|| {
                        self.error(format!(
                            "the {} family's case {} has no binary record (docs/answerers.md lists them): use --answerer-format json",
                            F::NAME,
                            Value::Object(F::case_json(c))
                        ))
                    })?;
                    bytes.extend(rec);
                }
            }
        }
        r.sent += batch.len() as u64;
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
        let lines = || format!("lines {first}..={}", first + n as u64 - 1);
        while got < n {
            let wait = deadline.saturating_duration_since(Instant::now());
            let chunk = match r.from.recv_timeout(wait) {
                Ok(c) => c,
                Err(RecvTimeoutError::Timeout) => {
                    return Err(format!(
                        "answered {got} of a batch's {n} cases ({}) within its time limit of {:?} (--answerer-seconds); stopped, with everything it started",
                        lines(),
                        self.limit
                    ));
                }
                Err(RecvTimeoutError::Disconnected) => Chunk::End,
            };
            match chunk {
                Chunk::End => {
                    // Its output closed: it is ending, so its exit status is waited for (within
                    // `EXIT_GRACE` and the deadline), to be said whether or not it came first.
                    let grace = deadline
                        .saturating_duration_since(Instant::now())
                        .min(EXIT_GRACE);
                    let status = crate::child::wait(&mut r.child, grace).ok();
                    return Err(format!(
                        "its output ended after {got} of a batch's {n} answers ({}){}",
                        lines(),
                        status.map_or(String::new(), |s| format!("; it exited with {s}"))
                    ));
                }
                Chunk::Line(line) => {
                    let line = line?;
                    if line.trim().is_empty() {
                        continue;
                    }
                    let v: Value = serde_json::from_str(&line).map_err(|e| {
                        format!("answered '{}', not a JSON line ({e})", line.trim())
                    })?;
                    let obj = v
                        .as_object()
                        .ok_or_else(|| format!("answered '{}', not a JSON object", line.trim()))?;
                    let k = obj.get("line").and_then(Value::as_u64).ok_or_else(|| {
                        format!(
                            "answered '{}' without \"line\", the case's number",
                            line.trim()
                        )
                    })?;
                    if (1..first).contains(&k) {
                        return Err(format!(
                            "a second answer for line {k} ('{}'), whose batch was answered already",
                            line.trim()
                        ));
                    }
                    if !(first..first + n as u64).contains(&k) {
                        return Err(format!(
                            "answered '{}' for line {k}, which is not in the batch asked ({})",
                            line.trim(),
                            lines()
                        ));
                    }
                    let i = (k - first) as usize;
                    if answers[i].is_some() {
                        return Err(format!("a second answer for line {k}"));
                    }
                    answers[i] = Some(
                        F::given(obj, &batch[i])
                            .map_err(|e| format!("line {k}: {e} (answered '{}')", line.trim()))?,
                    );
                    got += 1;
                }
                Chunk::Bytes(b) => {
                    r.pending.extend(b);
                    let size = F::ANSWER_RECORD;
                    while got < n && r.pending.len() >= size {
                        let rec: Vec<u8> = r.pending.drain(..size).collect();
                        answers[got] = Some(F::answer_record(&rec, &batch[got]).map_err(|e| {
                            format!("case {} (line {}): {e}", got + 1, first + got as u64)
                        })?);
                        got += 1;
                    }
                    if got == n && !r.pending.is_empty() {
                        return Err(format!(
                            "{} bytes more than a batch's {n} answer records of {size} bytes",
                            r.pending.len()
                        ));
                    }
                }
            }
        }
        Ok(answers.into_iter().flatten().collect())
    }
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

/// The face numbering under which `a` answers well-shaped cases of family `F` rightly
/// ([`Family::numbering_cases`]): every relabelling of the four faces tried ([`Family::renumbered`]),
/// the one it answers rightly on at least 99% of judged cases, and no other within 1%; an error
/// saying the best where none fits.
pub(crate) fn find_numbering<F: Family>(
    a: &Answerer,
    cases: &[(F::Case, F::Truth)],
) -> Result<[u8; 4], AnswererError> {
    let plain: Vec<F::Case> = cases.iter().map(|(c, _)| *c).collect();
    let raw = a.raw_all::<F>(&plain)?;
    let mut scored: Vec<([u8; 4], usize)> = permutations()
        .into_iter()
        .map(|p| {
            let right = cases
                .iter()
                .zip(&raw)
                .filter(|((c, x), f)| F::verdict(c, x, &F::renumbered(**f, &p)) == Verdict::Right)
                .count();
            (p, right)
        })
        .collect();
    scored.sort_by_key(|&(_, r)| std::cmp::Reverse(r));
    let judged = cases
        .iter()
        .zip(&raw)
        .filter(|((c, x), f)| F::verdict(c, x, f) != Verdict::NotJudged)
        .count()
        .max(1);
    let (best, right) = scored[0];
    let second = scored[1].1;
    if right * 100 >= judged * 99 && (right - second) * 100 >= judged {
        return Ok(best);
    }
    Err(a.error(format!(
        "no face numbering fits its answers: the best, answered face i = case face {best:?}[i], is right on {right} of {judged} well-shaped cases (the next {second})"
    )))
}

impl Answerer {
    /// Answers as the program numbers faces, batch by batch.
    fn raw_all<F: Family>(&self, cases: &[F::Case]) -> Result<Vec<F::Answer>, AnswererError> {
        let mut out = Vec::with_capacity(cases.len());
        for batch in cases.chunks(self.batch) {
            out.extend(self.raw::<F>(batch)?);
        }
        Ok(out)
    }
}

/// The 24 orderings of four faces.
fn permutations() -> Vec<[u8; 4]> {
    let mut out = Vec::new();
    for a in 0..4u8 {
        for b in 0..4u8 {
            for c in 0..4u8 {
                // The fourth is the one left: 0 + 1 + 2 + 3 = 6 (checked: the first three may sum
                // past 6).
                let Some(d) = 6u8.checked_sub(a + b + c) else {
                    continue;
                };
                if a != b && a != c && b != c && d < 4 && d != a && d != b && d != c {
                    out.push([a, b, c, d]);
                }
            }
        }
    }
    out
}

/// A face numbering `--faces` gives: four distinct faces, `a,b,c,d` (answered face i is case face
/// the i-th).
pub(crate) fn parse_faces(s: &str) -> Result<[u8; 4], String> {
    let f: Vec<u8> = s
        .split(',')
        .map(|x| x.trim().parse::<u8>().ok().filter(|&f| f < 4))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("'{s}' is not four faces 0..3, comma-separated"))?;
    match f[..] {
        [a, b, c, d] if permutations().contains(&[a, b, c, d]) => Ok([a, b, c, d]),
        _ => Err(format!("'{s}' is not an ordering of the faces 0,1,2,3")),
    }
}

#[cfg(test)]
mod tests {
    /// The 24 orderings, each once (in a debug build the sum of three faces past 6 overflowed).
    #[test]
    fn the_face_orderings_are_the_24_permutations() {
        let p = super::permutations();
        let distinct: std::collections::HashSet<_> = p.iter().collect();
        assert_eq!((p.len(), distinct.len()), (24, 24));
        for q in &p {
            let mut sorted = *q;
            sorted.sort();
            assert_eq!(sorted, [0, 1, 2, 3], "{q:?}");
        }
    }
}
