//! `tetwalk stress`: the failure table over a family's stress rows, a campaign over them, or the
//! backends compared, for every family.

use super::{
    AnswererArg, BackendArg, ContractArg, Error, FailArg, JsonOut, Status, WgslArg, choice,
};
use crate::backend::BackendKind;
use crate::choice::Choice;
use crate::engine::filing::Filing;
use crate::engine::standing::Standings;
use crate::engine::stress::{self, StressSettings, Who};
use crate::family::{self, Kind, Scale};
use crate::report::Formats;
use crate::report::stress::{disagreements, filed};
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Which family: `exit-face` (one tetrahedron's exit face, seeds 000 and 003), `walk` (walks
    /// through the lattice-tie scenes: Kuhn and jittered grids, an edge fan, near and far), `triangle`
    /// (closed triangle meshes, seed 004: leaks, double hits, wrong first hits) or `octree` (octree
    /// cells, seed 001: wrong exit faces and quarters).
    #[arg(long, value_parser = choice::<Kind>(), default_value = "exit-face")]
    family: Kind,
    /// Cases per row [default: 100000, 10000 for walk, 2000 for triangle].
    #[arg(long, allow_negative_numbers = true)]
    cases: Option<i64>,
    #[command(flatten)]
    rows: RowFlags,
    /// Methods (comma-separated, or all) [default: all; none beside an --answerer].
    #[arg(long)]
    methods: Option<String>,
    /// Seed of the generated cases.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    wgsl: WgslArg,
    #[command(flatten)]
    answerer: AnswererArg,
    #[command(flatten)]
    contract: ContractArg,
    #[command(flatten)]
    fail: FailArg,
    /// Instead of judging, count how often the GPU answers otherwise than each CPU backend (needs a GPU).
    #[arg(long)]
    compare: bool,
    /// Exit-face and triangle rows: flatness of the degenerate shapes, in (0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1e-3)]
    flatness: f32,
    /// Largest offset of the near-edge and near-vertex rows, in ulps of each case's largest
    /// coordinate.
    #[arg(long, allow_negative_numbers = true, default_value_t = 4)]
    ulps: i32,
    /// `all`: run again under each orientation-preserving relabelling of every case's tetrahedron
    /// (exit-face: 12) and give each row's and method's wrong answers with the cases' own labelling
    /// beside their min / median / max.
    #[arg(long, value_parser = ["all"])]
    relabel: Option<String>,
    /// A differential campaign: rounds of new cases (seed, seed + 1, …) until this many seconds have
    /// passed, the tallies summed, every new failure filed under `--found`.
    #[arg(long, allow_negative_numbers = true)]
    seconds: Option<f64>,
    /// Where a campaign files its failures as found cases (one folder per method), replayed by
    /// `cargo test` [default: corpora/found; with --answerer it must be given: its cases need the
    /// program to replay].
    #[arg(long)]
    found: Option<PathBuf>,
    /// A campaign files at most this many new failures per method, row and kind of wrong answer.
    #[arg(long, default_value_t = 3)]
    keep: usize,
    /// Every case at a power-of-two scale: `E` multiplies its points, origin and direction by 2^E,
    /// `E/D` its points and origin by 2^E and its direction by 2^D (exact where nothing underflows or
    /// overflows; each scaled case judged as it is). Not for walks, whose meshes are generated.
    #[arg(long, allow_hyphen_values = true, value_parser = Scale::parse, default_value = "0")]
    scale: Scale,
    /// Also write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .input("--wgsl", self.wgsl.wgsl.as_deref())
            .output("--json", self.json.as_deref())
    }
}

/// The stress rows a family's flags choose (its folder's `cli.rs`).
pub(crate) trait Rows: Formats {
    /// Its own flags, from among every family's.
    type Flags;
    fn own(all: &RowFlags) -> &Self::Flags;
    /// The flags of its own that were given (a family's flags given with another family are refused).
    fn given(own: &Self::Flags) -> Vec<&'static str>;
    /// The rows chosen, with the flags every family's rows share.
    fn chosen(own: &Self::Flags, shape: Shape) -> Self::Rows;
}

/// What the rows of several families share: flatness and ulps.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    pub(crate) flatness: f32,
    pub(crate) ulps: i32,
}

/// `given`, or every value when none is.
pub(crate) fn or_all<T: Choice>(given: &[T]) -> Vec<T> {
    if given.is_empty() {
        T::ALL.to_vec()
    } else {
        given.to_vec()
    }
}

/// Every family's row flags, each family's from its folder (`src/family/NAME/cli.rs`), from the
/// families' list.
#[doc(hidden)]
#[macro_export]
macro_rules! __stress_row_flags {
    ([] { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {
        /// Every family's row flags.
        #[derive(clap::Args)]
        pub(crate) struct RowFlags {
            $(
                #[command(flatten)]
                pub $m: $crate::family::$m::cli::StressFlags,
            )*
        }

        impl RowFlags {
            /// Each family's flags that were given, and the family.
            fn given(&self) -> Vec<(&'static str, $crate::family::Kind)> {
                let mut out = Vec::new();
                $(
                    out.extend(
                        <$ty as $crate::cli::stress::Rows>::given(&self.$m)
                            .into_iter()
                            .map(|f| (f, $crate::family::Kind::$v)),
                    );
                )*
                out
            }
        }
    };
}
crate::families!(__stress_row_flags);

/// Each family's own row flags, whether given: one given with another family is refused.
fn foreign(a: &Args) -> Result<(), Error> {
    match a.rows.given().into_iter().find(|(_, of)| *of != a.family) {
        Some((flag, of)) => Err(format!(
            "{flag} chooses {} rows; add --family {} (this run is --family {})",
            of.name(),
            of.name(),
            a.family.name()
        )
        .into()),
        None => Ok(()),
    }
}

pub(crate) fn run(a: Args) -> Status {
    super::generator(a.flatness, a.ulps)?;
    if let Some(seconds) = a.seconds
        && !(seconds.is_finite() && seconds >= 0.0)
    {
        return Err(format!("--seconds {seconds} is not a number of seconds").into());
    }
    foreign(&a)?;
    crate::with_family!(a.family, F => stress::<F>(a))
}

/// An error where the run judged no case at all (a contract or tolerance that leaves every row
/// none, cases that all leave f32's range at the scale): a table of zeros says nothing.
fn judged_something<F: family::Family>(report: &stress::StressReport<F>) -> Result<(), Error> {
    if report.standings().iter().any(|s| s.judged > 0) {
        return Ok(());
    }
    let s = &report.settings;
    Err(format!(
        "no case was judged: none of the {} rows' cases could be made{}{} (a run that judges nothing is an error, not a table of zeros)",
        report.rows.len(),
        if s.contract.is_default() {
            String::new()
        } else {
            format!(" within the contract ({})", s.contract.describe())
        },
        if s.scale.is_one() {
            String::new()
        } else {
            format!(" at scale {}", s.scale)
        }
    )
    .into())
}

/// The stress table of family `F`, its campaign, or its backends compared.
fn stress<F: Rows>(a: Args) -> Status {
    let cases = a.cases.unwrap_or(F::STRESS_CASES as i64);
    if cases <= 0 {
        return Err(
            format!("--cases {cases}: a stress run needs at least one case per row").into(),
        );
    }
    let cases = cases as usize;
    if a.wgsl.wgsl.is_some() && (F::user_wgsl().is_none() || a.seconds.is_some()) {
        return Err("--wgsl judges an exit-face function in a stress table of exit faces or walks (a campaign files found cases for tetwalk's own methods: fuzz a --wgsl function with TETWALK_FUZZ_WGSL)".into());
    }
    if a.relabel.is_some() && F::LABELLINGS == 1 {
        return Err(format!(
            "--relabel all: a {} case has one labelling (the exit-face family's tetrahedra have 12)",
            F::NAME
        )
        .into());
    }
    if a.relabel.is_some() && (a.compare || a.seconds.is_some()) {
        return Err("--relabel reruns one stress table; leave out --compare and --seconds".into());
    }
    if a.compare && a.fail.fail_on.is_some() {
        return Err("--compare counts disagreements between backends and judges nothing: leave out --fail-on".into());
    }
    if a.compare && a.wgsl.wgsl.is_some() {
        return Err("--compare runs every method on cpu and cpu-fma too; a --wgsl function runs on the GPU only".into());
    }
    let contract = a.contract.contract::<F>()?;
    a.contract.at_scale(a.scale)?;
    if a.answerer.answerer.is_some() {
        if !F::GIVEN {
            return Err("--answerer answers one cell's cases here; a program's walks are judged by count --answerer (every step asked) or judge (whole walks given)".into());
        }
        if a.compare || a.wgsl.wgsl.is_some() {
            return Err(
                "--answerer judges a program outside tetwalk: leave out --compare and --wgsl"
                    .into(),
            );
        }
        if a.seconds.is_some() && a.found.is_none() {
            return Err("a campaign with --answerer files its found cases where --found says (corpora/found holds tetwalk's own methods', replayed by cargo test)".into());
        }
    }
    // A row's cases, their truths and one method's answers are held at once.
    super::fits(
        &format!("--cases {cases}"),
        cases as u128 * F::BYTES_PER_CASE,
    )?;
    let out = JsonOut::new(a.json.as_deref())?;
    let (backend, methods) = if a.compare {
        if a.backend.backend != BackendKind::Cpu {
            return Err(
                "--compare runs the GPU and every CPU backend itself; leave out --backend".into(),
            );
        }
        let gpu = BackendArg {
            backend: BackendKind::Gpu,
            ..a.backend
        };
        (
            gpu.open()?,
            family::parse_list::<F>(a.methods.as_deref().unwrap_or("all"))?,
        )
    } else {
        a.wgsl
            .open::<F>(a.backend, a.methods.as_deref().unwrap_or("all"))?
    };
    let answerer = a.answerer.start::<F>(&contract)?;
    // The answerer first, then the methods asked for beside it.
    let who: Vec<Who<F>> = match &answerer {
        Some(x) if a.methods.is_none() => vec![Who::Outside(x)],
        Some(x) => [vec![Who::Outside(x)], Who::methods(&methods)].concat(),
        None => Who::methods(&methods),
    };
    let settings = StressSettings::<F> {
        contract,
        cases,
        rows: F::chosen(
            F::own(&a.rows),
            Shape {
                flatness: a.flatness,
                ulps: a.ulps,
            },
        ),
        seed: a.seed,
        backend: backend.ran(),
        scale: a.scale,
    };
    if a.compare {
        let d = stress::compare(&settings, &methods, &backend)?;
        return out.done(&disagreements(&d), &d);
    }
    let Some(seconds) = a.seconds else {
        let rows = F::rows(&settings.rows).len();
        let bar = super::progress("stress", (settings.cases * rows) as u64, "cases");
        let mut report = stress::run(&settings, &who, &backend, &|n| bar.inc(n), &mut |_| {})?;
        if a.relabel.is_some() {
            report.relabel_all(&who, &backend)?;
        }
        if let Some(x) = &answerer {
            x.finish()?;
        }
        bar.finish_and_clear();
        judged_something(&report)?;
        print!("{}", F::stress_table(&report));
        out.finish(&report)?;
        return Ok(a
            .fail
            .status("stress", &report.standings_with(answerer.as_ref())));
    };
    let found = a.found.unwrap_or_else(|| PathBuf::from("corpora/found"));
    let mut filing = Filing::new(found, a.keep, contract);
    let report = stress::campaign(&settings, &who, &backend, seconds, &|_| {}, &mut |w| {
        filing.file::<F>(w)
    })?;
    if let Some(e) = filing.error {
        return Err(e.into());
    }
    if let Some(x) = &answerer {
        x.finish()?;
    }
    judged_something(&report)?;
    print!("{}", F::stress_table(&report));
    print!("{}", filed(&filing, report.rounds));
    out.finish(&report)?;
    Ok(a.fail
        .status("stress", &report.standings_with(answerer.as_ref())))
}
