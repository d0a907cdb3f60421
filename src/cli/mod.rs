//! The `tetwalk` command line: every command-line type lives here; each subcommand builds a report
//! value, prints it, and can write it as JSON (`--json FILE`, checked writable before the run starts).

pub(crate) mod answer;
mod args;
pub(crate) mod bench;
mod check_filters;
pub(crate) mod count;
mod export_kernel;
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
    Methods(Listed),
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
    /// The seeds' tables that tetwalk reproduces, ours beside theirs (printed; `paper --out` writes
    /// them, as in corpora/results/paper.md).
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
    GpuInfo(Listed),
    /// Every filtered sign (oracle filters, certified's f32 stage per model) beside the exact sign, on
    /// inputs from every exponent regime; exit status 1 when a decided sign is wrong.
    CheckFilters(check_filters::Args),
    /// Turn fuzzer crash files into readable found cases (corpora/found/METHOD/).
    FuzzImport(fuzz_import::Args),
    /// Write `certified` as a shader function (WGSL, GLSL, HLSL, MSL) for your own GPU code.
    ExportKernel(export_kernel::Args),
    /// Build or describe scenes.
    #[command(subcommand)]
    Scene(scene::SceneCommand),
}

/// What `methods` and `gpu-info` take.
#[derive(clap::Args)]
struct Listed {
    /// Also write the list as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl Io for Listed {
    fn io(&self) -> Files {
        Files::default().output("--json", self.json.as_deref())
    }
}

/// Each command's files (checked before it runs) and its run, from one list of a command enum's
/// variants and their runs.
macro_rules! commands {
    ($e:ident { $($v:ident => $run:expr),* $(,)? }) => {
        impl Io for $e {
            fn io(&self) -> Files {
                match self {
                    $($e::$v(a) => a.io(),)*
                }
            }
        }

        impl $e {
            fn run(self) -> Status {
                match self {
                    $($e::$v(a) => $run(a),)*
                }
            }
        }
    };
}

commands!(Command {
    Methods => methods,
    Answer => FamilyCommand::run,
    Judge => judge::run,
    GenCases => gen_cases::run,
    Stress => stress::run,
    Count => count::run,
    Paper => paper::run,
    Bench => bench::run,
    Render => render::run,
    Replay => replay::run,
    Shrink => shrink::run,
    Verify => verify::run,
    GpuInfo => gpu_info,
    CheckFilters => check_filters::run,
    FuzzImport => fuzz_import::run,
    ExportKernel => export_kernel::run,
    Scene => scene::run,
});

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

        commands!(FamilyCommand { $($v => $crate::family::$m::cli::run),* });
    };
}

pub fn main() -> ExitCode {
    crate::process::quiet_mesa();
    crate::process::clean_on_interrupt();
    crate::process::quiet_on_closed_output();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.kind() == clap::error::ErrorKind::InvalidUtf8 => {
            eprintln!("tetwalk: {}", not_utf8(std::env::args_os()));
            return ExitCode::from(2);
        }
        Err(e) => e.exit(),
    };
    let result = cli.command.io().check().and_then(|()| cli.command.run());
    result.unwrap_or_else(|e| {
        if crate::process::closed_output(&*e) {
            crate::staged::remove_all();
            return ExitCode::from(crate::process::CLOSED_OUTPUT);
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

/// Which argument is not UTF-8 (clap says only that one is), with the flag before it: file paths are
/// taken as they are, but scene names and other values are text.
fn not_utf8(args: impl Iterator<Item = std::ffi::OsString>) -> String {
    let args: Vec<std::ffi::OsString> = args.collect();
    let Some(k) = args.iter().position(|a| a.to_str().is_none()) else {
        return "an argument is not UTF-8".into();
    };
    let after = args[..k]
        .last()
        .and_then(|a| a.to_str())
        .filter(|a| a.starts_with('-'))
        .map_or(String::new(), |f| format!(", the value of {f}"));
    format!(
        "argument {k} ('{}'{after}) is not UTF-8: scene names and other values are text (give a file whose name is not UTF-8 through a link that is)",
        args[k].to_string_lossy()
    )
}

fn methods(Listed { json }: Listed) -> Status {
    let out = JsonOut::new(json.as_deref())?;
    let rows = crate::family::listed();
    out.done(&crate::report::methods::table(&rows), &rows)
}

fn gpu_info(Listed { json }: Listed) -> Status {
    let out = JsonOut::new(json.as_deref())?;
    let found = crate::backend::Backend::adapters();
    if found.is_empty() {
        println!(
            "no GPU adapter found (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe)"
        );
    }
    for a in &found {
        println!("{a}");
    }
    out.done("", &serde_json::json!({ "adapters": found }))
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// clap checks a command's definition only in debug builds (plain `cargo test`), where a clash
    /// panics on first use; the clash it found (two families' flattened flag structs named alike,
    /// one group id) is looked for here in every build: within each command, every argument and
    /// group id is unique.
    #[test]
    fn every_command_passes_claps_checks() {
        fn unique_ids(c: &clap::Command, path: &str) {
            let mut ids = std::collections::HashSet::new();
            let args = c.get_arguments().map(|a| a.get_id());
            for id in args.chain(c.get_groups().map(|g| g.get_id())) {
                assert!(ids.insert(id.clone()), "{path}: the id '{id}' twice");
            }
            for s in c.get_subcommands() {
                unique_ids(s, &format!("{path} {}", s.get_name()));
            }
        }
        let cli = super::Cli::command();
        unique_ids(&cli, "tetwalk");
        cli.debug_assert();
    }

    /// Every flag a command's help names is one the command takes (or an alias of one), unless the
    /// help names it as another command's (`count --dump`, `stress --rows`): a help that sends the
    /// user to a flag the command refuses is found here.
    #[test]
    fn every_flag_a_commands_help_names_is_its_own() {
        fn walk(c: &mut clap::Command, path: &str, commands: &[String], wrong: &mut Vec<String>) {
            let own: Vec<String> = c
                .get_arguments()
                .flat_map(|a| {
                    let mut names: Vec<String> =
                        a.get_long().into_iter().map(String::from).collect();
                    names.extend(
                        a.get_all_aliases()
                            .unwrap_or_default()
                            .into_iter()
                            .map(String::from),
                    );
                    names
                })
                .collect();
            let help = c.render_long_help().to_string();
            let words: Vec<&str> = help
                .split(|ch: char| ch.is_whitespace() || "`(),;:[]'\"".contains(ch))
                .filter(|w| !w.is_empty())
                .collect();
            for (k, w) in words.iter().enumerate() {
                let Some(flag) = w.strip_prefix("--") else {
                    continue;
                };
                let flag: String = flag
                    .chars()
                    .take_while(|ch| ch.is_ascii_alphanumeric() || *ch == '-')
                    .collect();
                let another = k > 0 && commands.iter().any(|n| n == words[k - 1]);
                let clap_own = ["help", "version"].contains(&flag.as_str());
                if !flag.is_empty() && !another && !own.contains(&flag) && !clap_own {
                    wrong.push(format!("{path}: --{flag}"));
                }
            }
            let names: Vec<String> = c
                .get_subcommands()
                .map(|s| s.get_name().to_string())
                .collect();
            for s in c.get_subcommands_mut() {
                let p = format!("{path} {}", s.get_name());
                let mut all = commands.to_vec();
                all.extend(names.iter().cloned());
                walk(s, &p, &all, wrong);
            }
        }
        let mut cli = super::Cli::command();
        let names: Vec<String> = cli
            .get_subcommands()
            .map(|s| s.get_name().to_string())
            .collect();
        let mut wrong = Vec::new();
        walk(&mut cli, "tetwalk", &names, &mut wrong);
        assert!(wrong.is_empty(), "{wrong:#?}");
    }
}
