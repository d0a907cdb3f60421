//! The `tetwalk` command line: every command-line type lives here; each subcommand builds a report
//! value, prints it, and can write it as JSON (`--json FILE`, checked writable before the run starts).

pub(crate) mod answer;
mod args;
pub(crate) mod bench;
mod check_filters;
pub(crate) mod count;
mod fuzz_import;
pub(crate) mod gen_cases;
pub(crate) mod judge;
mod output;
mod paper;
pub(crate) mod render;
mod replay;
mod scene;
mod shrink;
pub(crate) mod stress;
mod verify;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

pub(crate) use args::*;
pub(crate) use output::*;

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
    Scene(scene::SceneCommand),
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

fn methods(json: Option<PathBuf>) -> Status {
    let out = JsonOut::new(json.as_deref())?;
    let rows = crate::family::listed();
    print!("{}", crate::report::methods::table(&rows));
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
