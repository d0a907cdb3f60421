//! How the exit-face family reads: its stress table and verdict lines (the report layer: formatting
//! only, as `crate::report` calls it).

use super::{ExitFace, Face};
use crate::engine::stress::StressReport;
use crate::exact::Classification;
use crate::family::Said;
use crate::report::Formats;
use crate::report::lines::{Lines, fields};
use crate::report::stress::{per_million, relabellings, rounds, seeds, table};
use serde_json::{Map, Value, json};

impl Formats for ExitFace {
    /// Per row and method, wrong exit faces / "no exit face", per million judged cases.
    fn stress_table(r: &StressReport<Self>) -> String {
        let s = &r.settings;
        let offset = match s.rows.offset {
            0.0 => String::new(),
            d => format!(", every case moved {d} along (1, 1, 1)"),
        };
        let contract = match s.contract.is_default() {
            true => String::new(),
            false => format!(", within the contract: {}", s.contract.describe()),
        };
        let mut out = format!(
            "{} cases per row{}, {}, {}, flatness {}, near-* within {} ulps of each case's largest coordinate{offset}{contract}; cells: wrong face / no exit face per million judged cases\n\n",
            s.cases,
            rounds(r),
            seeds(r),
            s.backend,
            s.rows.flatness,
            s.rows.ulps
        );
        out += &table(r, |t| {
            format!(
                "{} / {}",
                per_million(t.wrong_face, t.judged),
                per_million(t.no_exit_face, t.judged)
            )
        });
        out += &format!(
            "\noracle: {} signs decided by the f64 filter, {} exactly\n",
            r.oracle.filter, r.oracle.exact
        );
        out + &relabellings(r, "wrong answers (wrong face or no exit face)")
    }
}

impl Lines for ExitFace {
    fn verdict_line(
        _: &crate::tet::Case,
        x: &Classification,
        face: &Face,
        said: &Said,
    ) -> Map<String, Value> {
        let tet = said.tet.unwrap_or_default();
        let verdict = match said.correct {
            Some(true) => "right",
            None => "not_judged",
            Some(false) => tet.wrong.unwrap_or_default(),
        };
        fields(json!({
            "face": face, "exact_exit": x.exit.to_vec(), "exact_entry": x.entry.to_vec(),
            "correct": said.correct, "verdict": verdict, "tie": tet.tie, "touch_only": tet.touch_only,
        }))
    }
}
