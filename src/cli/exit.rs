//! `tetwalk exit`: one JSON line per case and method, with the exact answer beside it.

use crate::cases::{self, Case};
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
    /// JSON Lines file of cases; standard input when absent.
    file: Option<PathBuf>,
}

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
    let out: Vec<(String, bool)> = lines
        .par_iter()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let n = i + 1;
            match Case::parse(l).and_then(|c| cases::classify(&c).map(|x| (c, x))) {
                Err(e) => (serde_json::json!({"line": n, "error": e}).to_string() + "\n", false),
                Ok((case, c)) => {
                    let mut s = String::new();
                    for m in &methods {
                        let j = cases::judge(&case, &c, m, args.fma);
                        let v = serde_json::json!({
                            "line": n, "method": m.name, "face": j.face,
                            "exact_exit": j.exact_exit, "exact_entry": j.exact_entry, "correct": j.correct,
                        });
                        s += &(v.to_string() + "\n");
                    }
                    (s, true)
                }
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
