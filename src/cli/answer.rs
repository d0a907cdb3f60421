//! The commands that answer case lines (`exit`, `hit`, `box-exit`, `judge`), wired to the engine's
//! answering (`crate::engine::answering`): their shared arguments, where the lines come from and the
//! verdict lines and summary go, and the exit status.

use super::{BackendArg, FailArg, JsonOut, Status};
use crate::engine::answering::{
    AnswerSummary, AnswerTally, Answered, Line, Part, Takes, answer, batches, open_lines,
    outside_standing, standing,
};
use crate::engine::standing::Standing;
use crate::family::{Family, Kind};
use crate::registry::Named;
use crate::report::lines::{Lines, failures, per_method};
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;

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
    pub(crate) file: Option<&'a std::path::Path>,
    pub(crate) json: Option<&'a std::path::Path>,
    pub(crate) fail: FailArg,
}

/// A command answering JSON Lines: its name, its methods' names, what their tallies count, where the
/// lines come from and the summary goes, and how a tally stands under `--fail-on`.
pub(crate) struct Answering<'a> {
    pub(crate) command: &'static str,
    pub(crate) names: Vec<String>,
    /// The tallies count lines missing the cell.
    pub(crate) missed: bool,
    /// The tallies count leaks.
    pub(crate) leaks: bool,
    pub(crate) backend: String,
    pub(crate) file: Option<&'a std::path::Path>,
    /// `file` already open (read once: a pipe cannot be read twice), or `None` to open it here.
    pub(crate) input: Option<Box<dyn BufRead + Send>>,
    pub(crate) json: Option<&'a std::path::Path>,
    pub(crate) fail: FailArg,
    pub(crate) standing: &'a dyn Fn(&AnswerTally) -> Standing,
    /// Most lines answered at once (an answerer's `--answerer-batch`).
    pub(crate) batch: usize,
}

impl<'a> Answering<'a> {
    /// `command`'s answers by `names` on `backend` to the lines of `input`, each tally standing as
    /// `standing` says; the tallies count neither misses nor leaks.
    pub(crate) fn new(
        command: &'static str,
        names: Vec<String>,
        backend: String,
        input: Input<'a>,
        standing: &'a dyn Fn(&AnswerTally) -> Standing,
    ) -> Self {
        Answering {
            command,
            names,
            missed: false,
            leaks: false,
            backend,
            file: input.file,
            input: None,
            json: input.json,
            fail: input.fail,
            standing,
            batch: crate::engine::answering::BATCH,
        }
    }

    /// tetwalk's own methods of family `F` on `backend` answering `input` (`exit`, `hit`, `box-exit`),
    /// standing as `F`'s claim says.
    pub(crate) fn own<F: Family>(
        command: &'static str,
        methods: &[&'static F::Method],
        backend: &crate::backend::Backend,
        input: Input<'a>,
    ) -> Self {
        let names = methods.iter().map(|m| m.name().to_string()).collect();
        Self::new(command, names, backend.describe(), input, &standing::<F>)
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
            |batch, summary| Ok(answer(batch, &mut parts(), refuse, None, summary)?),
            || Ok(()),
        )
    }

    /// Answer the lines with `answer` (given each batch and the summary); then `after` checks what
    /// only the whole input tells (an error there writes no summary); then the summary goes to
    /// `--json`, and a line per method to standard error (cases answered, right, wrong, not judged).
    /// Exit status 1 when a line could not be answered, or under `--fail-on`.
    pub(crate) fn run(
        self,
        mut answer: impl FnMut(&[Line], &mut AnswerSummary) -> Result<String, super::Error>,
        after: impl FnOnce() -> Result<(), super::Error>,
    ) -> Status {
        let out = JsonOut::new(self.json)?;
        let mut summary = AnswerSummary::new(self.backend, self.names, self.missed, self.leaks);
        let input: Box<dyn BufRead + Send> = match (self.input, self.file) {
            (Some(input), _) => input,
            (None, Some(p)) => open_lines(p)?,
            (None, None) => Box::new(std::io::BufReader::new(std::io::stdin())),
        };
        let mut w = std::io::BufWriter::new(std::io::stdout().lock());
        batches(input, self.batch, |batch| -> Result<(), super::Error> {
            w.write_all(answer(batch, &mut summary)?.as_bytes())?;
            Ok(w.flush()?)
        })?;
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
        for l in per_method(self.command, &summary) {
            eprintln!("{l}");
        }
        let standings: Vec<Standing> = summary.methods.iter().map(|t| (self.standing)(t)).collect();
        let status = self.fail.status(self.command, &standings);
        let failed = failures(self.command, &summary);
        for l in &failed {
            eprintln!("{l}");
        }
        if !failed.is_empty() {
            return Ok(ExitCode::FAILURE);
        }
        Ok(status)
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
    let standing = |t: &AnswerTally| outside_standing::<F>(x, t);
    let answering = Answering {
        batch: x.batch,
        ..Answering::new(
            command,
            vec![x.name.clone()],
            "outside".into(),
            a.input(),
            &standing,
        )
    };
    answering.run(
        |batch, summary| {
            let mut parts: Vec<Box<dyn Takes>> = vec![Box::new(Part::<F>::new(
                Answered::Outside(x),
                F::verdict_line,
                t_ulps,
            ))];
            Ok(answer(batch, &mut parts, refuse, None, summary)?)
        },
        || Ok(x.finish()?),
    )
}

/// Family `F`'s part answered by `methods` on `backend`, its lines printed as `F`'s read, a hit's
/// `t` right within `t_ulps` ulps.
pub(crate) fn methods_part<'a, F: Lines>(
    methods: &'a [&'static F::Method],
    backend: &'a crate::backend::Backend,
    t_ulps: f64,
) -> Part<'a, F> {
    Part::new(Answered::Methods(methods, backend), F::verdict_line, t_ulps)
}

/// A part for each family whose answers given from outside `judge` reads ([`Family::GIVEN`]),
/// from the families' list: `families!(__given_parts, NAME, T_ULPS)`.
#[doc(hidden)]
#[macro_export]
macro_rules! __given_parts {
    ([$name:expr, $t_ulps:expr] { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {{
        let mut parts: Vec<Box<dyn $crate::engine::answering::Takes + '_>> = Vec::new();
        $(
            if <$ty as $crate::family::Family>::GIVEN {
                parts.push(Box::new($crate::engine::answering::Part::<$ty>::new(
                    $crate::engine::answering::Answered::Given($name),
                    <$ty as $crate::report::lines::Lines>::verdict_line,
                    $t_ulps,
                )));
            }
        )*
        parts
    }};
}
