//! `tetwalk check-filters`: the filter checker ([`crate::engine::filters`]) as a campaign — every
//! filtered sign beside the exact sign, per exponent regime, with how often the exact stage was needed.

use super::{JsonOut, Status};
use crate::engine::filters::Rounds;
use crate::report::filters;
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

pub(crate) fn run(a: Args) -> Status {
    if a.cases == 0 {
        return Err("--cases 0 checks nothing: give at least 1".into());
    }
    let json = JsonOut::new(a.json.as_deref())?;
    let r = Rounds::run(a.cases, a.seed, a.seconds);
    print!("{}", filters::table(&r));
    for line in filters::refuted(&r) {
        eprintln!("refuted: {line}");
    }
    json.finish(&filters::report(&r))?;
    let wrong = r.campaign.wrong();
    if wrong > 0 {
        eprintln!(
            "tetwalk check-filters: {} from the exact sign",
            crate::report::counted(wrong, "decided sign differs", "decided signs differ")
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}
