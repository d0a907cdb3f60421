//! `tetwalk verify`: the register of claims checked, one PASS / FAIL line per claim on each backend
//! (`crate::engine::verify`); exit status 1 when a claim does not go as the register says.

use super::{JsonOut, Status};
use crate::choice::Choice;
use crate::engine::verify::{Verified, pick, verify_all};
use crate::report::verify::{against, register_table, summary, verified_line};
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
        super::Files::default()
            .folder("--found", &self.found)
            .output("--json", self.json.as_deref())
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
        return Err(format!(
            "--found {}: not a folder of found cases (the register's counterexamples are a checkout's corpora/found: run verify in the repository, or give --found DIR)",
            a.found.display()
        )
        .into());
    }
    let out = JsonOut::new(a.json.as_deref())?;
    let all = verify_all(&checks, a.cases, &a.found, |v| {
        println!("{}", verified_line(v))
    })?;
    let done: Vec<_> = all.iter().filter_map(Verified::checked).collect();
    let skipped: Vec<_> = all.iter().filter_map(Verified::skipped).collect();
    if done.is_empty() {
        return Err("no claim could be checked here (every one skipped)".into());
    }
    eprintln!("tetwalk verify: {}", summary(&all));
    out.finish(&serde_json::json!({ "checks": done, "skipped": skipped }))?;
    Ok(if against(&all).is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
