//! How the exit-face family reads: its stress table and verdict lines (the report layer: formatting
//! only, as `crate::report` calls it).

use super::{ExitFace, Face};
use crate::engine::stress::StressReport;
use crate::exact::Classification;
use crate::family::{Family, Verdict};
use crate::report::Formats;
use crate::report::lines::{Lines, Said, TetSaid, correct, fields};
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
        c: &crate::tet::Case,
        x: &Classification,
        face: &Face,
        _: f64,
    ) -> (Map<String, Value>, Said) {
        let v = Self::verdict(c, x, face);
        let ok = correct(v);
        let said = TetSaid {
            wrong: match v {
                Verdict::Wrong(_) if face.is_some() => Some("wrong_face"),
                Verdict::Wrong(_) => Some("no_exit_face"),
                _ => None,
            },
            tie: Self::tie(x),
            touch_only: x.meets() && Self::touch_only(c),
        };
        let verdict = match v {
            Verdict::Right => "right",
            Verdict::NotJudged => "not_judged",
            Verdict::Wrong(_) => said.wrong.unwrap_or_default(),
        };
        let line = json!({
            "face": face, "exact_exit": x.exit.to_vec(), "exact_entry": x.entry.to_vec(),
            "correct": ok, "verdict": verdict, "tie": said.tie, "touch_only": said.touch_only,
        });
        (
            fields(line),
            Said {
                correct: ok,
                cell: true,
                tet: Some(said),
                ..Said::default()
            },
        )
    }
}
