//! `tetwalk verify`: the register of claims checked, one PASS / FAIL line per claim on each backend
//! (`crate::engine::verify`); exit status 1 when a claim does not go as the register says.

use super::{JsonOut, Status};
use crate::backend::{Backend, BackendKind};
use crate::choice::Choice;
use crate::engine::verify::{CheckResult, pick, verify};
use crate::report::verify::{line, register_table};
use std::collections::HashMap;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Check only these claims (comma-separated): a check's name (`woop-watertight@cpu`) or a method's
    /// (every backend of it) [default: all].
    #[arg(long, value_delimiter = ',')]
    run: Vec<String>,
    /// Leave out these claims (names as for --run).
    #[arg(long, value_delimiter = ',')]
    skip: Vec<String>,
    /// Cases per stress row and scale (ray–triangle rows take a tenth).
    #[arg(long, allow_negative_numbers = true, default_value_t = 2000)]
    cases: usize,
    /// The found corpus: the counterexamples, and the cases every standing claim must survive.
    #[arg(long, default_value = "corpora/found")]
    found: PathBuf,
    /// Print the register as the markdown table of docs/results.md and stop.
    #[arg(long)]
    register: bool,
    /// Also write every check's findings as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default().output("--json", self.json.as_deref())
    }
}

pub(crate) fn run(a: Args) -> Status {
    if a.register {
        print!("{}", register_table());
        return Ok(ExitCode::SUCCESS);
    }
    if a.cases == 0 {
        return Err("--cases 0 would check nothing".into());
    }
    // A row's cases of the largest family, with their truths and answers, are held at once.
    let per_case = crate::family::Kind::ALL
        .iter()
        .map(|&k| crate::with_family!(k, F => <F as crate::family::Family>::BYTES_PER_CASE))
        .max()
        .unwrap_or(0);
    super::fits(&format!("--cases {}", a.cases), a.cases as u128 * per_case)?;
    let checks = pick(&a.run, &a.skip)?;
    if checks.is_empty() {
        return Err("--run and --skip leave no claim to check".into());
    }
    if !a.found.is_dir() {
        return Err(format!("--found {}: not a folder of found cases", a.found.display()).into());
    }
    let out = JsonOut::new(a.json.as_deref())?;
    let mut backends: HashMap<BackendKind, Result<Backend, String>> = HashMap::new();
    let mut done: Vec<CheckResult> = Vec::new();
    let mut skipped = Vec::new();
    for c in checks {
        let b = backends
            .entry(c.backend)
            .or_insert_with(|| Backend::open(c.backend).map_err(|e| e.to_string()));
        let b = match b {
            Ok(b) => b,
            Err(why) => {
                println!("SKIP  {:<26} {why}", c.name);
                skipped.push(c.name);
                continue;
            }
        };
        let adapter = b.ran().adapter;
        if c.elsewhere(adapter.as_deref()) {
            let here = adapter.unwrap_or_default();
            let word = c.adapter.unwrap_or_default();
            println!(
                "SKIP  {:<26} registered for {word}; {here} has its own check",
                c.name
            );
            skipped.push(c.name);
            continue;
        }
        let checked = verify(c, b, a.cases, &a.found)?;
        println!("{}", line(&checked));
        done.push(checked);
    }
    if done.is_empty() {
        return Err("no claim could be checked here (every one skipped)".into());
    }
    let against: Vec<&str> = done
        .iter()
        .filter(|c| c.as_registered == Some(false))
        .map(|c| c.name)
        .collect();
    eprintln!(
        "tetwalk verify: {} claims checked, {} stand, {} refuted, {} skipped; {}",
        done.len(),
        done.iter().filter(|c| c.holds).count(),
        done.iter().filter(|c| !c.holds).count(),
        skipped.len(),
        if against.is_empty() {
            "every one as the register says".to_string()
        } else {
            format!("against the register: {}", against.join(", "))
        }
    );
    out.finish(&serde_json::json!({ "checks": done, "skipped": skipped }))?;
    Ok(if against.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
