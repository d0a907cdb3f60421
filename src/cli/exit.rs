//! `tetwalk exit`: one JSON line per case and method, with the exact answer beside it.

use crate::cases::{self, Case};
use crate::exact::Classification;
use crate::methods::parse_list;
use rayon::prelude::*;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// A method name, a comma-separated list, or `all`.
    #[arg(long, default_value = "all")]
    method: String,
    /// Run each method as a GPU compiler may compile it (products contracted to fused multiply-add).
    #[arg(long)]
    fma: bool,
    /// Where the methods run: `cpu`, or `gpu` (WGSL through wgpu; `exact` stays on the CPU).
    #[arg(long, value_parser = ["cpu", "gpu"], default_value = "cpu")]
    backend: String,
    /// JSON Lines file of cases; standard input when absent.
    file: Option<PathBuf>,
}

/// A line's case and its exact answer, or what is wrong with it.
type Parsed = Result<(Case, Classification), String>;

pub fn run(args: Args) -> Result<ExitCode, String> {
    let methods = parse_list(&args.method)?;
    let lines: Vec<String> = match &args.file {
        Some(p) => {
            let f = std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?;
            std::io::BufReader::new(f).lines().collect::<Result<_, _>>()
        }
        None => std::io::stdin().lock().lines().collect::<Result<_, _>>(),
    }
    .map_err(|e| format!("reading cases: {e}"))?;
    let parsed: Vec<(usize, Parsed)> = lines
        .par_iter()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            (
                i + 1,
                Case::parse(l).and_then(|c| cases::classify(&c).map(|x| (c, x))),
            )
        })
        .collect();
    let valid: Vec<Case> = parsed
        .iter()
        .filter_map(|(_, r)| r.as_ref().ok().map(|(c, _)| *c))
        .collect();
    let gpu = if args.backend == "gpu" {
        let g = crate::gpu::Gpu::new().map_err(|e| e.to_string())?;
        eprintln!("tetwalk exit: GPU {}", g.describe());
        Some(g)
    } else {
        None
    };
    // Per method, every valid case's face: one batch on the GPU, or case by case on the CPU.
    let mut faces: Vec<Vec<Option<usize>>> = Vec::new();
    for m in &methods {
        faces.push(match &gpu {
            Some(g) if m.name != "exact" => cases::answers_gpu(g, &valid, m)?,
            _ => valid
                .par_iter()
                .map(|c| cases::answer(c, m, args.fma))
                .collect(),
        });
    }
    let mut k = 0;
    let out: Vec<(String, bool)> = parsed
        .iter()
        .map(|(n, r)| match r {
            Err(e) => (serde_json::json!({"line": n, "error": e}).to_string() + "\n", false),
            Ok((_, c)) => {
                let mut s = String::new();
                for (m, f) in methods.iter().zip(&faces) {
                    let j = cases::judged(c, f[k]);
                    let v = serde_json::json!({
                        "line": n, "method": m.name, "face": j.face,
                        "exact_exit": j.exact_exit, "exact_entry": j.exact_entry, "correct": j.correct,
                    });
                    s += &(v.to_string() + "\n");
                }
                k += 1;
                (s, true)
            }
        })
        .collect();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    for (s, _) in &out {
        w.write_all(s.as_bytes()).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;
    let errors = out.iter().filter(|(_, ok)| !ok).count();
    if errors > 0 {
        eprintln!("tetwalk exit: {errors} line(s) could not be answered");
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}
