//! `tetwalk check-filters`: the filter checker ([`crate::engine::filters`]) as a campaign — every
//! filtered sign beside the exact sign, per exponent regime, with how often the exact stage was needed.

use super::{JsonOut, Status};
use crate::choice::Choice;
use crate::engine::filters::{Campaign, Filter, FilterTally, Regime, check};
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Cases per regime and round (each case asks every filter once).
    #[arg(long, default_value_t = 20_000)]
    cases: usize,
    /// Keep running rounds (seeds S, S+1, ...) for this many seconds; 0: one round.
    #[arg(long, default_value_t = 0)]
    seconds: u64,
    /// Seed of the first round.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Also write the tallies (per regime and filter) and the refutations found as JSON here.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default().output("--json", self.json.as_deref())
    }
}

#[derive(serde::Serialize)]
struct Row {
    regime: Regime,
    filter: Filter,
    #[serde(flatten)]
    tally: FilterTally,
}

#[derive(serde::Serialize)]
struct Report {
    rounds: u64,
    first_seed: u64,
    cases_per_regime: u64,
    rows: Vec<Row>,
    refuted: Vec<String>,
}

pub(crate) fn run(a: Args) -> Status {
    if a.cases == 0 {
        return Err("--cases 0 checks nothing: give at least 1".into());
    }
    let json = JsonOut::new(a.json.as_deref())?;
    let start = std::time::Instant::now();
    let mut total: Option<Campaign> = None;
    let mut rounds = 0u64;
    loop {
        let c = check(a.cases, a.seed.wrapping_add(rounds));
        rounds += 1;
        match &mut total {
            None => total = Some(c),
            Some(t) => t.add(c),
        }
        if start.elapsed().as_secs() >= a.seconds {
            break;
        }
    }
    let total = total.expect("one round ran");
    println!(
        "{} from seed {}, {} cases per regime and round, {:.0} s\n",
        crate::report::counted(rounds, "round", "rounds"),
        a.seed,
        a.cases,
        start.elapsed().as_secs_f64()
    );
    println!("| regime | filter | signs | exact stage | wrong |\n|---|---|---|---|---|");
    let mut rows = Vec::new();
    for (regime, tallies) in &total.tallies {
        for (filter, t) in tallies {
            println!(
                "| {} | {} | {} | {:.2}% | {} |",
                regime.name(),
                filter.name(),
                t.asked,
                100.0 * t.exact_stage as f64 / t.asked.max(1) as f64,
                t.wrong
            );
            rows.push(Row {
                regime: *regime,
                filter: *filter,
                tally: *t,
            });
        }
    }
    let refuted: Vec<String> = total.refuted.iter().map(|r| format!("{r:?}")).collect();
    for r in &refuted {
        eprintln!("refuted: {r}");
    }
    json.finish(&Report {
        rounds,
        first_seed: a.seed,
        cases_per_regime: a.cases as u64 * rounds,
        rows,
        refuted,
    })?;
    let wrong = total.wrong();
    if wrong > 0 {
        eprintln!(
            "tetwalk check-filters: {} from the exact sign",
            crate::report::counted(wrong, "decided sign differs", "decided signs differ")
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}
