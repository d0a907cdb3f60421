//! The `tetwalk` command line.

mod count;
mod exit;
mod fuzz_import;
mod gen_cases;
mod render;
mod scene;
mod stress;
mod walk;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

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
    /// List the exit-face methods.
    Methods,
    /// Answer (tetrahedron, ray) cases from JSON Lines with each method, judged exactly.
    Exit(exit::Args),
    /// Write generated (tetrahedron, ray) cases as JSON Lines.
    GenCases(gen_cases::Args),
    /// Walk rays through a generated mesh with each method, every step judged exactly.
    Walk(walk::Args),
    /// Wrong exit faces and "no exit face" per million cases, per method and tetrahedron family.
    Stress(stress::Args),
    /// Wrong rays per image, per method, on a scene (seed 000 Table 4), judged exactly.
    Count(count::Args),
    /// Shaded renders, failure maps, heat maps, predicate maps (PNG).
    Render(render::Args),
    /// The GPU adapters wgpu finds.
    GpuInfo,
    /// Turn fuzzer crash files into readable found cases (corpora/found/METHOD/).
    FuzzImport(fuzz_import::Args),
    /// Build or describe scenes.
    #[command(subcommand)]
    Scene(scene::Scene),
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Methods => {
            println!("| method | claims robust | implements |\n|---|---|---|");
            for m in crate::methods::METHODS {
                println!(
                    "| {} | {} | {} |",
                    m.name,
                    if m.claims_robust { "yes" } else { "no" },
                    m.source
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Exit(a) => exit::run(a),
        Command::GenCases(a) => gen_cases::run(a),
        Command::Walk(a) => walk::run(a),
        Command::Stress(a) => stress::run(a),
        Command::Scene(s) => scene::run(s),
        Command::Count(a) => count::run(a),
        Command::FuzzImport(a) => fuzz_import::run(a),
        Command::Render(a) => render::run(a),
        Command::GpuInfo => {
            let found = crate::gpu::adapters();
            if found.is_empty() {
                println!(
                    "no GPU adapter found (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe)"
                );
            }
            for a in found {
                println!("{a}");
            }
            Ok(ExitCode::SUCCESS)
        }
    };
    result.unwrap_or_else(|e| {
        eprintln!("tetwalk: {e}");
        ExitCode::from(2)
    })
}

/// A progress bar on standard error (drawn only when it is a terminal and the work lasts).
fn progress(len: u64, unit: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(len),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let style = format!("{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {unit} ({{eta}} left)");
    if let Ok(st) = indicatif::ProgressStyle::with_template(&style) {
        bar.set_style(st);
    }
    bar
}

/// Write `value` as pretty JSON to `path`, when one is given.
fn write_json(path: Option<&std::path::Path>, value: &impl serde::Serialize) -> Result<(), String> {
    let Some(p) = path else { return Ok(()) };
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    std::fs::write(p, text).map_err(|e| format!("{}: {e}", p.display()))
}
