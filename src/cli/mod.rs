//! The `tetwalk` command line: every command-line type lives here; each subcommand builds a report
//! value, prints it, and can write it as JSON (`--json FILE`, checked writable before the run starts).

pub(crate) mod answer;
pub(crate) mod bench;
mod check_filters;
pub(crate) mod count;
mod fuzz_import;
pub(crate) mod gen_cases;
pub(crate) mod judge;
mod paper;
pub(crate) mod render;
mod replay;
mod scene;
mod shrink;
pub(crate) mod stress;
mod verify;

use crate::backend::{Backend, BackendKind};
use crate::choice::Choice;
use crate::family::Family;
use crate::family::contract::{Contract, EntryGiven, Orientation, Origin};
use crate::registry::{Gpu, Named};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Any error a command reports; rendered once, by [`main`].
pub(crate) type Error = Box<dyn std::error::Error + Send + Sync>;
/// How a command ends: its exit status, or the error that stopped it.
pub(crate) type Status = Result<ExitCode, Error>;

#[derive(Parser)]
#[command(
    name = "tetwalk",
    version,
    about = "Finds out, with proof, when f32 ray traversal of tetrahedral meshes goes wrong"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the methods: family, paper and algorithm, claims, GPU version.
    Methods {
        /// Also write the list as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    #[command(flatten)]
    Answer(FamilyCommand),
    /// Judge answers computed anywhere (one JSON line per case) exactly, as exit and hit judge
    /// tetwalk's own methods.
    Judge(judge::Args),
    /// Write generated (tetrahedron, ray) cases as JSON Lines.
    GenCases(gen_cases::Args),
    /// Wrong exit faces and "no exit face" per million cases, per method and tetrahedron family.
    Stress(stress::Args),
    /// Wrong rays per image, per method, on a scene (seed 000 Table 4), judged exactly.
    Count(count::Args),
    /// The seeds' tables that tetwalk reproduces, ours beside theirs (printed; `--out` writes them,
    /// as in corpora/results/paper.md).
    Paper(paper::Args),
    /// Walk speed: rays and tetrahedra per second per method and backend, end to end and (on a GPU
    /// with timestamp queries) kernel alone.
    Bench(bench::Args),
    /// Shaded renders, failure maps, heat maps, predicate maps (PNG).
    Render(render::Args),
    /// Walk the wrong rays of a `count --dump` again: does each still fail the same way?
    Replay(replay::Args),
    /// Shrink found cases (and a count's dumped wrong rays) to the simplest case the same method
    /// still fails the same way, each with a line that reproduces it.
    Shrink(shrink::Args),
    /// Check the register of claims, as Embree's verify checks its kernels: one PASS / FAIL line per
    /// claim and backend; exit status 1 when one does not go as the register says.
    Verify(verify::Args),
    /// The GPU adapters wgpu finds.
    GpuInfo {
        /// Also write the list as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Every filtered sign (oracle filters, certified's f32 stage per model) beside the exact sign, on
    /// inputs from every exponent regime; exit status 1 when a decided sign is wrong.
    CheckFilters(check_filters::Args),
    /// Turn fuzzer crash files into readable found cases (corpora/found/METHOD/).
    FuzzImport(fuzz_import::Args),
    /// Build or describe scenes.
    #[command(subcommand)]
    Scene(scene::Scene),
}

crate::families!(__family_commands);

/// The commands that answer one family's cases with its methods (`exit`, `box-exit`, `hit`), each
/// its family's `cli::Args` and `cli::run`, from the families' list: `families!(__family_commands)`.
#[doc(hidden)]
#[macro_export]
macro_rules! __family_commands {
    ([] { $($line:tt)* } counted { $($c:tt)* } kit { $($k:tt)* } commands { $($m:ident: $v:ident),* } $($rest:tt)*) => {
        /// The commands that answer a family's cases (each documented in its family's folder).
        #[derive(Subcommand)]
        enum FamilyCommand {
            $($v($crate::family::$m::cli::Args),)*
        }

        impl Io for FamilyCommand {
            fn io(&self) -> Files {
                match self {
                    $(FamilyCommand::$v(a) => a.io(),)*
                }
            }
        }

        impl FamilyCommand {
            fn run(self) -> Status {
                match self {
                    $(FamilyCommand::$v(a) => $crate::family::$m::cli::run(a),)*
                }
            }
        }
    };
}

pub fn main() -> ExitCode {
    quiet_mesa();
    clean_on_interrupt();
    quiet_on_closed_output();
    let cli = Cli::parse();
    let io = match &cli.command {
        Command::Methods { json } | Command::GpuInfo { json } => {
            Files::default().output("--json", json.as_deref())
        }
        Command::Answer(a) => a.io(),
        Command::Judge(a) => a.io(),
        Command::GenCases(a) => a.io(),
        Command::Stress(a) => a.io(),
        Command::Scene(s) => s.io(),
        Command::Count(a) => a.io(),
        Command::Bench(a) => a.io(),
        Command::Paper(a) => a.io(),
        Command::FuzzImport(a) => a.io(),
        Command::CheckFilters(a) => a.io(),
        Command::Render(a) => a.io(),
        Command::Replay(a) => a.io(),
        Command::Shrink(a) => a.io(),
        Command::Verify(a) => a.io(),
    };
    let result = io.check().and_then(|()| match cli.command {
        Command::Methods { json } => methods(json),
        Command::Answer(a) => a.run(),
        Command::Judge(a) => judge::run(a),
        Command::GenCases(a) => gen_cases::run(a),
        Command::Stress(a) => stress::run(a),
        Command::Scene(s) => scene::run(s),
        Command::Count(a) => count::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Paper(a) => paper::run(a),
        Command::FuzzImport(a) => fuzz_import::run(a),
        Command::CheckFilters(a) => check_filters::run(a),
        Command::Render(a) => render::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Shrink(a) => shrink::run(a),
        Command::Verify(a) => verify::run(a),
        Command::GpuInfo { json } => gpu_info(json),
    });
    result.unwrap_or_else(|e| {
        if closed_output(&*e) {
            crate::staged::remove_all();
            return ExitCode::from(CLOSED_OUTPUT);
        }
        let mut msg = e.to_string();
        let mut src = e.source();
        while let Some(s) = src {
            let more = s.to_string();
            if !msg.contains(&more) {
                msg += &format!(": {more}");
            }
            src = s.source();
        }
        eprintln!("tetwalk: {msg}");
        ExitCode::from(2)
    })
}

/// The exit status of a run whose standard output was closed under it: that of a program SIGPIPE
/// ends (128 + 13), as `tetwalk methods | head -1` expects.
const CLOSED_OUTPUT: u8 = 141;

/// Whether an error is a write to a closed pipe.
fn closed_output(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut at = Some(e);
    while let Some(err) = at {
        if let Some(io) = err.downcast_ref::<std::io::Error>()
            && io.kind() == std::io::ErrorKind::BrokenPipe
        {
            return true;
        }
        at = err.source();
    }
    false
}

/// A closed or full standard output (`tetwalk methods | head -1`, `> /dev/full`) ends the command
/// quietly, with a non-zero status and its staging files removed: `print!` panics on such a write, and
/// this hook turns that panic into the exit (status [`CLOSED_OUTPUT`] for a closed pipe, else 2 with
/// one line saying why). Every other panic is reported as before.
fn quiet_on_closed_output() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let p = info.payload();
        let msg = p
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| p.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(why) = msg.strip_prefix("failed printing to stdout: ") {
            crate::staged::remove_all();
            if why.contains("Broken pipe") {
                std::process::exit(CLOSED_OUTPUT.into());
            }
            eprintln!("tetwalk: standard output: {why}");
            std::process::exit(2);
        }
        default(info);
    }));
}

/// Ctrl-C, SIGTERM or SIGHUP: stop the programs tetwalk runs (TetGen, an answerer) with everything
/// they started, remove the staging files of the outputs being written and the working folders
/// (nothing half-written is left behind), say so, and exit with status 130.
fn clean_on_interrupt() {
    let set = ctrlc::set_handler(|| {
        crate::child::kill_all();
        let n = crate::staged::remove_all();
        eprintln!(
            "tetwalk: interrupted; {} removed, nothing written",
            crate::report::counted(
                n as u64,
                "unfinished output file",
                "unfinished output files"
            )
        );
        std::process::exit(130);
    });
    if let Err(e) = set {
        eprintln!(
            "tetwalk: cannot watch for Ctrl-C ({e}): an interrupted run may leave .tetwalk-* files"
        );
    }
}

/// Mesa's drivers print "XDG_RUNTIME_DIR is invalid or not set" at every adapter query when the
/// variable is missing (as in CI and containers): give them a private directory of their own.
fn quiet_mesa() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return;
    }
    let dir = std::env::temp_dir().join("tetwalk-xdg-runtime");
    let made = std::fs::create_dir_all(&dir).and_then(|_| {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
    });
    if made.is_ok() {
        // SAFETY: called first thing in main, before any thread exists.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}

/// One registered method, as `tetwalk methods` lists it.
#[derive(serde::Serialize)]
struct Listed {
    name: &'static str,
    family: &'static str,
    claims_robust: bool,
    reference: bool,
    gpu: String,
    implements: &'static str,
}

/// The methods of family `F`.
fn listed<F: Family>() -> Vec<Listed> {
    F::methods()
        .iter()
        .map(|m| {
            let i = m.info();
            Listed {
                name: i.name,
                family: F::NAME,
                claims_robust: i.claim.is_some(),
                reference: i.reference,
                gpu: match i.gpu {
                    Gpu::Wgsl(_) => "yes".into(),
                    Gpu::CpuOnly(why) => format!("no: {why}"),
                },
                implements: i.source,
            }
        })
        .collect()
}

fn methods(json: Option<PathBuf>) -> Status {
    let out = JsonOut::new(json.as_deref())?;
    // Each registry once: families that share one (exit faces and walks) list it under the first.
    let mut seen: Vec<*const ()> = Vec::new();
    let mut rows: Vec<Listed> = Vec::new();
    for &k in crate::family::Kind::ALL {
        crate::with_family!(k, F => {
            let at = F::methods().as_ptr() as *const ();
            if !seen.contains(&at) {
                seen.push(at);
                rows.extend(listed::<F>());
            }
        });
    }
    println!("| method | family | claims robust | GPU | implements |\n|---|---|---|---|---|");
    for r in &rows {
        let yes = |b: bool| if b { "yes" } else { "no" };
        let claims = if r.reference {
            "reference".to_string()
        } else {
            yes(r.claims_robust).to_string()
        };
        println!(
            "| {} | {} | {} | {} | {} |",
            r.name, r.family, claims, r.gpu, r.implements
        );
    }
    out.finish(&rows)?;
    Ok(ExitCode::SUCCESS)
}

fn gpu_info(json: Option<PathBuf>) -> Status {
    let out = JsonOut::new(json.as_deref())?;
    let found = crate::gpu::adapters();
    if found.is_empty() {
        println!(
            "no GPU adapter found (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe)"
        );
    }
    for a in &found {
        println!("{a}");
    }
    out.finish(&serde_json::json!({ "adapters": found }))?;
    Ok(ExitCode::SUCCESS)
}

/// A clap value parser for a [`Choice`]: its names are the possible values.
pub(crate) fn choice<T: Choice>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|v| v.name()))
        .map(|s| T::from_name(&s).expect("clap checked the name"))
}

/// `--backend`, shared by every command that runs methods.
#[derive(clap::Args, Clone, Copy)]
pub(crate) struct BackendArg {
    /// Where the methods run: `cpu` (plain f32), `cpu-fma` (as a GPU compiles them: products
    /// contracted to fused multiply-adds), `cpu-ftz` (as a GPU that flushes subnormals computes them),
    /// `cpu-gpu` (both at once, as an NVIDIA GPU computes them) or `gpu` (WGSL through wgpu; the
    /// `exact` reference stays on the CPU).
    #[arg(long, value_parser = choice::<BackendKind>(), default_value = "cpu")]
    pub(crate) backend: BackendKind,
    /// Not an option: the FMA choice is spelled `--backend cpu-fma`.
    #[arg(long, hide = true)]
    fma: bool,
}

impl BackendArg {
    /// The backend asked for; the old `--fma` spelling is refused with the right one.
    pub(crate) fn open(self) -> Result<Backend, Error> {
        if self.fma {
            return Err(format!(
                "--fma is spelled --backend cpu-fma (asked for --backend {}; `gpu` runs whatever the GPU's compiler makes of the WGSL)",
                self.backend.name()
            )
            .into());
        }
        let b = Backend::open(self.backend)?;
        if let Backend::Gpu(_) = b {
            eprintln!("tetwalk: {}", b.describe());
        }
        Ok(b)
    }
}

/// What `--fail-on` fails on.
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
enum FailOn {
    /// Any method gave a wrong answer.
    Wrong,
    /// A method's claim was refuted (the register's claims: `exact` and `certified` never wrong, the
    /// octree's `exact` cell test never wrong, `woop-watertight` never leaks).
    Claims,
}

impl FailOn {
    fn name(self) -> &'static str {
        match self {
            FailOn::Wrong => "wrong",
            FailOn::Claims => "claims",
        }
    }
}

/// `--fail-on`, shared by every command that judges methods: an exit status for CI and nightly jobs.
#[derive(clap::Args, Clone, Copy, Debug)]
pub(crate) struct FailArg {
    /// Exit with status 1 when a method gave a wrong answer (`wrong`) or when a method's claim was
    /// refuted (`claims`: `exact` or `certified` wrong anywhere, the octree's `exact` too,
    /// `woop-watertight` leaking), after
    /// writing everything the run writes; one summary line per method on standard error. Without it
    /// the status says only whether the run could be made.
    #[arg(long, value_enum, value_name = "RULE")]
    fail_on: Option<FailOn>,
}

impl FailArg {
    /// The exit status `standings` earn under the rule, each method's summary line (and the verdict)
    /// on standard error.
    pub(crate) fn status(
        self,
        command: &str,
        standings: &[crate::engine::standing::Standing],
    ) -> ExitCode {
        let Some(rule) = self.fail_on else {
            return ExitCode::SUCCESS;
        };
        for s in standings {
            eprintln!("tetwalk {command}: {}", s.line());
        }
        let failed: Vec<&str> = standings
            .iter()
            .filter(|s| match rule {
                FailOn::Wrong => s.wrong > 0,
                FailOn::Claims => s.refuted(),
            })
            .map(|s| s.method.as_str())
            .collect();
        if rule == FailOn::Claims && standings.iter().all(|s| s.claim.is_none()) {
            eprintln!(
                "tetwalk {command}: --fail-on claims: no method judged here makes a claim (exact and certified claim robustness, as the octree's exact does, woop-watertight no leak)"
            );
        }
        if failed.is_empty() {
            return ExitCode::SUCCESS;
        }
        eprintln!(
            "tetwalk {command}: --fail-on {}: {}",
            rule.name(),
            failed.join(", ")
        );
        ExitCode::FAILURE
    }
}

use crate::exact::hit::T_ULPS;

/// `--t-ulps`: a number of ulps (0 or more, finite), or [`T_ULPS`].
pub(crate) fn t_ulps(given: Option<f64>) -> Result<f64, Error> {
    match given {
        None => Ok(T_ULPS),
        Some(u) if u.is_finite() && u >= 0.0 => Ok(u),
        Some(u) => Err(format!("--t-ulps {u} is not a number of ulps (0 or more)").into()),
    }
}

/// Most viewpoints a count or bench places (seed 000's runs have 1,282).
const MAX_VIEWS: usize = 1 << 20;

/// `--views N` of a count or bench (`what`): 1 to [`MAX_VIEWS`].
pub(crate) fn view_count(views: usize, what: &str) -> Result<usize, Error> {
    match views {
        0 => Err(format!("--views 0: a {what} needs at least one view").into()),
        v if v > MAX_VIEWS => Err(format!(
            "--views {v}: more than the {MAX_VIEWS} viewpoints a {what} places (seed 000 has 1,282)"
        )
        .into()),
        v => Ok(v),
    }
}

/// Most ulps a near-edge or near-vertex ray is moved (2^20: beyond that it is no longer near, and
/// offsets cross binades until the coordinates leave f32's range).
const MAX_ULPS: i32 = 1 << 20;

/// `--flatness` and `--ulps` of the generated families: flatness in `[2^-126, 1]` (below the smallest
/// normal f32 the flattest families' jitter underflows to nothing), ulps in `1..=2^20`.
fn generator(flatness: f32, ulps: i32) -> Result<(), Error> {
    if !(flatness > 0.0 && flatness <= 1.0) {
        return Err(format!("--flatness {flatness} is not in (0, 1]").into());
    }
    if flatness < f32::MIN_POSITIVE {
        return Err(format!(
            "--flatness {flatness:e} is below 2^-126 ({:e}), the smallest normal f32: the flattest families' jitter would underflow to nothing",
            f32::MIN_POSITIVE
        )
        .into());
    }
    if !(1..=MAX_ULPS).contains(&ulps) {
        return Err(format!(
            "--ulps {ulps} is not a number of ulps in 1..={MAX_ULPS} (a near ray moved further is no longer near)"
        )
        .into());
    }
    Ok(())
}

/// Largest WGSL file `--wgsl` reads.
const MAX_WGSL: u64 = 1 << 20;

/// `--answerer CMD` and its settings: a user's program answering cases over its standard input and
/// output (docs/answerers.md), shared by `stress` and `shrink`.
#[derive(clap::Args, Clone)]
pub(crate) struct AnswererArg {
    /// A program outside tetwalk that answers cases (a shell command, started once): batches of cases
    /// on its standard input, one answer per case on its standard output (docs/answerers.md), judged
    /// in place of --methods.
    #[arg(long, value_name = "CMD")]
    answerer: Option<String>,
    /// The answerer's name in tables and found cases.
    #[arg(
        long,
        value_name = "NAME",
        default_value = "answerer",
        requires = "answerer"
    )]
    answerer_name: String,
    /// How cases and answers travel: `json` (JSON Lines, every family) or `binary` (fixed
    /// little-endian records: exit faces, triangles, octree cells).
    #[arg(long, value_parser = choice::<crate::engine::answerer::Format>(), default_value = "json", requires = "answerer")]
    answerer_format: crate::engine::answerer::Format,
    /// Seconds the answerer may take on one batch; past them it is stopped, with everything it
    /// started, and the run fails saying so.
    #[arg(long, value_name = "S", default_value_t = 60.0)]
    answerer_seconds: f64,
    /// Cases per batch.
    #[arg(
        long,
        value_name = "N",
        default_value_t = 10_000,
        requires = "answerer"
    )]
    answerer_batch: usize,
    /// The answerer claims what its family's methods claim when they claim: never a wrong answer
    /// (exit faces, octree cells), no leak (triangles); `--fail-on claims` holds it to that.
    #[arg(long, requires = "answerer")]
    answerer_claims: bool,
    /// Exit faces: how the answerer numbers a tetrahedron's faces, `a,b,c,d` (its face i is the
    /// case's face the i-th), or `auto` (found on well-shaped cases, reported, applied; an error when
    /// none fits) [default: 0,1,2,3].
    #[arg(long, value_name = "FACES", requires = "answerer")]
    faces: Option<String>,
}

impl AnswererArg {
    /// The answerer started, if one is given, its face numbering set (found with `well` cases of
    /// the contract `k` under `auto`).
    pub(crate) fn start<F: Family>(
        &self,
        k: &Contract,
    ) -> Result<Option<crate::engine::answerer::Answerer>, Error> {
        use crate::engine::answerer::{Answerer, find_numbering, parse_faces};
        let Some(cmd) = &self.answerer else {
            return Ok(None);
        };
        if !(self.answerer_seconds > 0.0 && self.answerer_seconds <= 1e6) {
            return Err(format!(
                "--answerer-seconds {} is not in (0, 1e6]",
                self.answerer_seconds
            )
            .into());
        }
        if self.answerer_batch == 0 || self.answerer_batch > 1_000_000 {
            return Err(format!(
                "--answerer-batch {} is not 1 to 1,000,000 cases",
                self.answerer_batch
            )
            .into());
        }
        if crate::family::by_name::<F>(&self.answerer_name).is_ok() || self.answerer_name == "all" {
            return Err(format!(
                "--answerer-name {}: that names tetwalk's own; name the answerer otherwise",
                self.answerer_name
            )
            .into());
        }
        if self.faces.is_some() && !F::FACES {
            return Err(format!(
                "--faces numbers a tetrahedron's faces; {} cases have none",
                F::NAME
            )
            .into());
        }
        let mut a = Answerer::start(
            &self.answerer_name,
            cmd,
            self.answerer_format,
            std::time::Duration::from_secs_f64(self.answerer_seconds),
            self.answerer_batch,
        )?;
        a.claims = self.answerer_claims;
        match self.faces.as_deref() {
            None => {}
            Some("auto") => {
                let cases = F::numbering_cases(k, 2000);
                a.faces = find_numbering::<F>(&a, &cases)?;
                eprintln!(
                    "tetwalk: {}'s face i is the case's face {:?}[i] (found on {} well-shaped cases; give --faces {} to skip the search)",
                    a.name,
                    a.faces,
                    cases.len(),
                    a.faces.map(|f| f.to_string()).join(",")
                );
            }
            Some(f) => a.faces = parse_faces(f)?,
        }
        Ok(Some(a))
    }
}

/// What a kernel assumes of its cases (docs/answerers.md, "Contracts"), shared by `stress`,
/// `gen-cases` and `shrink`: every case made or tried holds it.
#[derive(clap::Args, Clone, Copy)]
struct ContractArg {
    /// Exit faces: where each ray's origin lies — `anywhere` (the rows' own), `before` the entry face,
    /// on the `entry` face (the entry point rounded to f32), or `inside` the tetrahedron.
    #[arg(long, value_parser = choice::<Origin>(), default_value = "anywhere")]
    origin: Origin,
    /// Directions of length 1 (rounded to f32; each case judged as it then is).
    #[arg(long)]
    unit_direction: bool,
    /// Exit faces: whether cases carry their entry face — `any` (every other case), `given` (all)
    /// or `none`.
    #[arg(long, value_parser = choice::<EntryGiven>(), default_value = "any")]
    entry: EntryGiven,
    /// Exit faces: `positive` tetrahedra only, or `any` orientation (half the cases mirrored).
    #[arg(long, value_parser = choice::<Orientation>(), default_value = "positive")]
    orientation: Orientation,
    /// Exit faces: lines within this distance of an edge, relative to the longest edge, are outside
    /// the contract (a kernel's epsilon); 0 for none.
    #[arg(long, value_name = "REL", default_value_t = 0.0)]
    tolerance: f64,
}

impl ContractArg {
    /// The contract, checked for family `F` (only exit faces hold more than a unit direction).
    fn contract<F: Family>(&self) -> Result<Contract, Error> {
        let k = Contract {
            origin: self.origin,
            unit_direction: self.unit_direction,
            entry: self.entry,
            orientation: self.orientation,
            tolerance: self.tolerance,
        };
        k.check()?;
        if !F::CONTRACTS && !k.is_general() {
            return Err(format!(
                "--origin, --entry, --orientation and --tolerance state what an exit-face kernel assumes; {} cases take --unit-direction only",
                F::NAME
            )
            .into());
        }
        Ok(k)
    }
}

/// `--wgsl FILE`: a user's exit-face function in WGSL, judged on the GPU as method `user`.
#[derive(clap::Args)]
pub(crate) struct WgslArg {
    /// A WGSL file defining `user_prepare` and `user_exit` (user guide, docs/your-own.md),
    /// spliced into the GPU's shader and judged as method `user` beside the methods listed (needs
    /// --backend gpu).
    #[arg(long, value_name = "FILE")]
    pub(crate) wgsl: Option<PathBuf>,
}

impl WgslArg {
    /// The backend `b` asks for and the methods of family `F` `list` names, the user's WGSL method
    /// first when `--wgsl` gives one (the GPU opened with it, after the compiler has checked it).
    pub(crate) fn open<F: Family>(
        &self,
        b: BackendArg,
        list: &str,
    ) -> Result<(Backend, Vec<&'static F::Method>), Error> {
        let mut methods = crate::family::parse_list::<F>(list)?;
        let Some(path) = &self.wgsl else {
            return Ok((b.open()?, methods));
        };
        let Some(user) = F::user_wgsl() else {
            return Err(format!(
                "--wgsl {} takes an exit-face function (exit faces and walks), not {} methods",
                path.display(),
                F::NAME
            )
            .into());
        };
        if b.fma || b.backend != BackendKind::Gpu {
            return Err(format!(
                "--wgsl {} runs a WGSL function on the GPU: add --backend gpu",
                path.display()
            )
            .into());
        }
        let size = std::fs::metadata(path)
            .map_err(|e| format!("--wgsl {}: {e}", path.display()))?
            .len();
        if size > MAX_WGSL {
            return Err(format!(
                "--wgsl {}: {size} bytes, more than the {MAX_WGSL} a shader function may hold",
                path.display()
            )
            .into());
        }
        let source =
            std::fs::read_to_string(path).map_err(|e| format!("--wgsl {}: {e}", path.display()))?;
        let backend = Backend::gpu_with_user(&path.display().to_string(), &source)?;
        eprintln!("tetwalk: {}", backend.describe());
        methods.insert(0, user);
        Ok((backend, methods))
    }
}

/// The files a command reads and writes, declared beside its arguments ([`Io`]) and checked in
/// [`main`] before any work: no output is one of the run's inputs or another of its outputs (the same
/// file by identity: links followed, hard links and other spellings alike; standard input and output,
/// devices and pipes aside), so that nothing the user gave is overwritten and no output is lost.
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
    fn inputs(self, what: &str, ps: &[PathBuf]) -> Files {
        ps.iter().fold(self, |f, p| f.input(what, Some(p)))
    }

    /// The files the scene `name` is read from (none for a built-in or generated one).
    fn scene(self, what: &str, name: &str) -> Files {
        self.inputs(what, &crate::scenes::files_of(name))
    }

    /// An output (`--json`, `--dump`, `--out`).
    pub(crate) fn output(mut self, what: &str, p: Option<&Path>) -> Files {
        if let Some(p) = p {
            self.outputs.push((what.to_string(), p.to_path_buf()));
        }
        self
    }

    /// An error naming the first output that is an input, or another output.
    fn check(&self) -> Result<(), Error> {
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
    fn named(&self, e: std::io::Error) -> std::io::Error {
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

/// Most memory a command may plan to hold at once; larger runs are refused with the figure they need.
const MEMORY_BUDGET: u64 = 8 << 30;

/// Refuse `what` when it would need more than [`MEMORY_BUDGET`] bytes.
pub(crate) fn fits(what: &str, bytes: u128) -> Result<(), Error> {
    if bytes > MEMORY_BUDGET as u128 {
        return Err(format!(
            "{what} would need about {:.1} GiB of memory; tetwalk plans at most {} GiB at once",
            bytes as f64 / (1u64 << 30) as f64,
            MEMORY_BUDGET >> 30
        )
        .into());
    }
    Ok(())
}

/// A comma-separated list of backends (`--backend cpu,gpu`), each once, in order.
pub(crate) fn backend_list(text: &str) -> Result<Vec<BackendKind>, Error> {
    let mut kinds = Vec::new();
    for name in text.split(',').map(str::trim) {
        let kind = BackendKind::from_name(name).ok_or_else(|| {
            let known: Vec<_> = BackendKind::ALL.iter().map(|k| k.name()).collect();
            format!("--backend: '{name}' is not one of {}", known.join(", "))
        })?;
        if !kinds.contains(&kind) {
            kinds.push(kind);
        }
    }
    Ok(kinds)
}

/// Whether a scene must have constrained faces (`--no-faces` says it need not).
pub(crate) fn faces(no_faces: bool) -> crate::mesh::Faces {
    if no_faces {
        crate::mesh::Faces::Optional
    } else {
        crate::mesh::Faces::Required
    }
}

/// Parse `WxH` (or `W` for a square when `square` is allowed), each side in 1..=`max`.
pub(crate) fn size(text: &str, square: bool, max: u32) -> Result<(u32, u32), Error> {
    let parse = |s: &str| s.trim().parse::<u32>().ok().filter(|&v| v >= 1 && v <= max);
    let wh = match text.split_once('x') {
        Some((w, h)) => parse(w).zip(parse(h)),
        None if square => parse(text).map(|w| (w, w)),
        None => None,
    };
    wh.ok_or_else(|| {
        format!(
            "--size {text} is not {}, each side 1..={max}",
            if square { "W or WxH" } else { "WxH" }
        )
        .into()
    })
}
