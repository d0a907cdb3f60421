//! What commands write: the files each reads and writes, checked apart before any work ([`Io`]),
//! outputs staged and written whole ([`Staged`], [`JsonOut`]), and progress on standard error.

use super::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The files a command reads and writes, declared beside its arguments ([`Io`]) and checked in
/// [`main`](super::main) before any work: no output is one of the run's inputs or another of its
/// outputs (the same file by identity: links followed, hard links and other spellings alike;
/// standard input and output, devices and pipes aside), so that nothing the user gave is overwritten
/// and no output is lost.
#[derive(Default)]
pub(crate) struct Files {
    inputs: Vec<(String, PathBuf)>,
    outputs: Vec<(String, PathBuf)>,
}

impl Files {
    /// An input, named as the user gave it (`CASES`, `--wgsl`); `-` is standard input.
    pub(crate) fn input(mut self, what: &str, p: Option<&Path>) -> Files {
        if let Some(p) = p.filter(|p| *p != Path::new("-")) {
            self.inputs.push((what.to_string(), p.to_path_buf()));
        }
        self
    }

    /// Several inputs under one name (`REPORTS`, `FILES`).
    pub(crate) fn inputs(self, what: &str, ps: &[PathBuf]) -> Files {
        ps.iter().fold(self, |f, p| f.input(what, Some(p)))
    }

    /// The files the scene `name` is read from (none for a built-in or generated one).
    pub(crate) fn scene(self, what: &str, name: &str) -> Files {
        self.inputs(what, &crate::scenes::files_of(name))
    }

    /// An output (`--json`, `--dump`, `--out`).
    pub(crate) fn output(mut self, what: &str, p: Option<&Path>) -> Files {
        if let Some(p) = p {
            self.outputs.push((what.to_string(), p.to_path_buf()));
        }
        self
    }

    /// Every file below the folder `dir` (a corpus the run reads), as inputs.
    pub(crate) fn folder(self, what: &str, dir: &Path) -> Files {
        let mut files = Vec::new();
        let mut todo = vec![dir.to_path_buf()];
        while let Some(d) = todo.pop() {
            for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
                match e.file_type() {
                    Ok(t) if t.is_dir() => todo.push(e.path()),
                    Ok(_) => files.push(e.path()),
                    Err(_) => {}
                }
            }
        }
        self.inputs(what, &files)
    }

    /// An error naming the first output that is an input (standard input too, whatever the command
    /// reads: a file given there is the user's), where standard output or error goes while not named
    /// as such (renamed over, it would lose what was printed: `/dev/stdout` is written into), or
    /// another output.
    pub(crate) fn check(&self) -> Result<(), Error> {
        for (what, out) in &self.outputs {
            #[cfg(unix)]
            if let Some(fd) = crate::staged::descriptor(out) {
                if fd == 0 && crate::staged::identity_of_fd(0).is_some_and(|(_, _, file)| file) {
                    return Err(format!(
                        "{what} {} is standard input, a file the run is given: an output never overwrites it; nothing was written",
                        out.display()
                    )
                    .into());
                }
                continue;
            }
            #[cfg(unix)]
            for (fd, stream, name) in [
                (0, "standard input", "/dev/stdin"),
                (1, "standard output", "/dev/stdout"),
                (2, "standard error", "/dev/stderr"),
            ] {
                let given = crate::staged::identity_of_fd(fd);
                let here = crate::staged::identity(out);
                if let (Some((d, i, true)), Some((d2, i2, true))) = (given, here)
                    && (d, i) == (d2, i2)
                {
                    return Err(format!(
                        "{what} {} is the file {stream} is; {}; nothing was written",
                        out.display(),
                        if fd == 0 {
                            "an output never overwrites what the run is given".to_string()
                        } else {
                            format!("renamed over, it would lose what is printed there: give {name} to write into it")
                        }
                    )
                    .into());
                }
            }
        }
        for (i, (what, out)) in self.outputs.iter().enumerate() {
            let clash = self
                .inputs
                .iter()
                .map(|(w, p)| (w, p, "the run's input"))
                .chain(
                    self.outputs[..i]
                        .iter()
                        .map(|(w, p)| (w, p, "another output,")),
                )
                .find(|(_, p, _)| crate::staged::same_file(out, p));
            if let Some((w, p, role)) = clash {
                return Err(format!(
                    "{what} {} is the same file as {role} {w} {}: an output never overwrites what the run reads or another output; nothing was written",
                    out.display(),
                    p.display()
                )
                .into());
            }
        }
        Ok(())
    }
}

/// A command's arguments declare the files it reads and writes.
pub(crate) trait Io {
    fn io(&self) -> Files;
}

/// A file written under a temporary name beside its target, made when the command starts (so an
/// unwritable place fails before any work) and renamed onto the target when it is complete (so nothing
/// half-written is left). Every error writing it names its flag and place.
pub(crate) struct Staged {
    tmp: crate::staged::Staging,
    flag: String,
    path: PathBuf,
}

impl Staged {
    pub(crate) fn new(flag: &str, p: &Path) -> Result<Staged, Error> {
        let tmp = crate::staged::beside(p)
            .map_err(|e| format!("{flag} {}: cannot write there: {e}", p.display()))?;
        Ok(Staged {
            tmp,
            flag: flag.to_string(),
            path: p.to_path_buf(),
        })
    }

    /// `e`, with the flag and the place.
    pub(crate) fn named(&self, e: std::io::Error) -> std::io::Error {
        let place = format!("{} {}: {e}", self.flag, self.path.display());
        std::io::Error::new(e.kind(), place)
    }

    pub(crate) fn finish(self) -> Result<(), Error> {
        let place = format!("{} {}", self.flag, self.path.display());
        self.tmp.persist().map_err(|e| format!("{place}: {e}"))?;
        Ok(())
    }
}

impl Write for Staged {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.tmp.write(buf).map_err(|e| self.named(e))
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.tmp.flush().map_err(|e| self.named(e))
    }
}

/// Where a report's JSON goes (`--json FILE`), staged.
pub(crate) struct JsonOut(Option<Staged>);

/// The JSON reports in `paths` (`--json` files of the shards of a run), each with its file's name; a
/// bad one named with its field.
pub(crate) fn read_reports<T: serde::de::DeserializeOwned>(
    paths: &[PathBuf],
) -> Result<Vec<(String, T)>, Error> {
    paths
        .iter()
        .map(|p| {
            let name = p.display().to_string();
            let text = std::fs::read_to_string(p).map_err(|e| format!("{name}: {e}"))?;
            let mut de = serde_json::Deserializer::from_str(&text);
            let value = serde_path_to_error::deserialize(&mut de)
                .map_err(|e| format!("{name}: {}: {}", e.path(), e.inner()))?;
            Ok((name, value))
        })
        .collect()
}

impl JsonOut {
    pub(crate) fn new(path: Option<&Path>) -> Result<JsonOut, Error> {
        Ok(JsonOut(path.map(|p| Staged::new("--json", p)).transpose()?))
    }

    pub(crate) fn finish(self, value: &impl serde::Serialize) -> Result<(), Error> {
        let Some(mut staged) = self.0 else {
            return Ok(());
        };
        serde_json::to_writer_pretty(&mut staged, value).map_err(std::io::Error::from)?;
        staged.write_all(b"\n")?;
        staged.finish()
    }

    /// `printed` on standard output, then the JSON written: the command done.
    pub(crate) fn done(self, printed: &str, value: &impl serde::Serialize) -> super::Status {
        print!("{printed}");
        self.finish(value)?;
        Ok(std::process::ExitCode::SUCCESS)
    }
}

/// Progress of a long run on standard error: a bar where standard error is a terminal; elsewhere (a CI
/// log, a file) a line every [`PROGRESS_EVERY`] seconds (`TETWALK_PROGRESS_SECONDS` sets another),
/// so that a run of hours shows it is alive and how far it is.
pub(crate) struct Progress {
    bar: indicatif::ProgressBar,
    log: Option<ProgressLog>,
}

/// The lines of [`Progress`] where there is no terminal.
struct ProgressLog {
    what: String,
    len: u64,
    done: std::sync::atomic::AtomicU64,
    start: std::time::Instant,
    /// Seconds since `start` of the last line.
    last: std::sync::atomic::AtomicU64,
    every: u64,
}

/// Seconds between progress lines where standard error is not a terminal.
const PROGRESS_EVERY: u64 = 30;

impl Progress {
    /// Count `n` more done (from any thread).
    pub(crate) fn inc(&self, n: u64) {
        self.bar.inc(n);
        let Some(log) = &self.log else {
            return;
        };
        use std::sync::atomic::Ordering::Relaxed;
        let done = log.done.fetch_add(n, Relaxed) + n;
        let now = log.start.elapsed().as_secs();
        let last = log.last.load(Relaxed);
        if now >= last + log.every
            && log
                .last
                .compare_exchange(last, now, Relaxed, Relaxed)
                .is_ok()
        {
            let left = (now as f64 * (log.len.saturating_sub(done)) as f64 / done.max(1) as f64)
                .round() as u64;
            eprintln!(
                "{}: {done} of {} ({:.0}%) after {now} s, about {left} s left",
                log.what,
                log.len,
                100.0 * done as f64 / log.len.max(1) as f64
            );
        }
    }

    pub(crate) fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
    }
}

/// Progress of `len` `unit` of `command`'s work ([`Progress`]).
pub(crate) fn progress(command: &str, len: u64, unit: &str) -> Progress {
    use std::io::IsTerminal;
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(len),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let style = format!("{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {unit} ({{eta}} left)");
    if let Ok(st) = indicatif::ProgressStyle::with_template(&style) {
        bar.set_style(st);
    }
    let every = std::env::var("TETWALK_PROGRESS_SECONDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(PROGRESS_EVERY);
    let log = (!std::io::stderr().is_terminal()).then(|| ProgressLog {
        what: format!("tetwalk {command}: {unit}"),
        len,
        done: 0.into(),
        start: std::time::Instant::now(),
        last: 0.into(),
        every,
    });
    Progress { bar, log }
}
