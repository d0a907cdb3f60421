//! `tetwalk check-filters`' table and JSON: every filter's signs per exponent regime
//! ([`crate::engine::filters::Rounds`]).

use crate::choice::Choice;
use crate::engine::filters::{Filter, FilterTally, Regime, Rounds};

/// One regime's tally of one filter.
#[derive(serde::Serialize)]
pub(crate) struct Row {
    regime: Regime,
    filter: Filter,
    #[serde(flatten)]
    tally: FilterTally,
}

/// The rounds as `--json` writes them.
#[derive(serde::Serialize)]
pub struct Report {
    rounds: u64,
    first_seed: u64,
    cases_per_regime: u64,
    rows: Vec<Row>,
    refuted: Vec<String>,
}

/// The refutations found, one line each.
pub(crate) fn refuted(r: &Rounds) -> Vec<String> {
    r.campaign
        .refuted
        .iter()
        .map(|x| format!("{x:?}"))
        .collect()
}

/// The rounds' JSON report.
pub fn report(r: &Rounds) -> Report {
    let rows = r
        .campaign
        .tallies
        .iter()
        .flat_map(|(regime, tallies)| {
            tallies.iter().map(|(filter, t)| Row {
                regime: *regime,
                filter: *filter,
                tally: *t,
            })
        })
        .collect();
    Report {
        rounds: r.rounds,
        first_seed: r.first_seed,
        cases_per_regime: r.cases as u64 * r.rounds,
        rows,
        refuted: refuted(r),
    }
}

/// The rounds' heading and their table: per regime and filter, signs asked, how often the exact
/// stage decided, decided signs wrong.
pub fn table(r: &Rounds) -> String {
    let mut out = format!(
        "{} from seed {}, {} cases per regime and round, {:.0} s\n\n",
        super::counted(r.rounds, "round", "rounds"),
        r.first_seed,
        r.cases,
        r.seconds
    );
    out += "| regime | filter | signs | exact stage | wrong |\n|---|---|---|---|---|\n";
    for (regime, tallies) in &r.campaign.tallies {
        for (filter, t) in tallies {
            out += &format!(
                "| {} | {} | {} | {:.2}% | {} |\n",
                regime.name(),
                filter.name(),
                t.asked,
                100.0 * t.exact_stage as f64 / t.asked.max(1) as f64,
                t.wrong
            );
        }
    }
    out
}
