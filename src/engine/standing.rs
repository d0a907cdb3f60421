//! Each method's standing after a run, from its report: answers judged, wrong, and whether the claim
//! its paper makes (the register's claims) was refuted. `--fail-on` turns standings into an exit
//! status.

use crate::engine::stress::StressReport;
use crate::family::Family;
use crate::registry::{Claim, Named};

/// What a method's claim is, and how often this run refuted it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Held {
    /// The claim: `robust` (never a wrong answer: `exact`, `certified`, the octree's `exact`) or `no
    /// leak` (a ray through a closed surface never passes through it: `woop-watertight`).
    pub(crate) claim: &'static str,
    /// Answers that refute it; `None` when this run does not judge it (a count of first hits does
    /// not tell leaks from misses beside the object).
    pub(crate) refuted: Option<u64>,
}

/// One method's standing.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Standing {
    pub(crate) method: String,
    /// Answers judged (cases or rays whose exact answer is defined).
    pub(crate) judged: u64,
    pub wrong: u64,
    pub(crate) claim: Option<Held>,
}

impl Standing {
    /// A method that claims nothing (answers given from outside).
    pub(crate) fn unclaimed(method: &str, judged: u64, wrong: u64) -> Standing {
        Standing {
            method: method.to_string(),
            judged,
            wrong,
            claim: None,
        }
    }

    /// A method's standing, its claim (if it makes one) refuted as `refuted` says of that claim: a
    /// robust method by every wrong answer, a watertight one by its leaks where the run counts them.
    pub(crate) fn of(
        method: &impl Named,
        judged: u64,
        wrong: u64,
        refuted: impl FnOnce(Claim) -> Option<u64>,
    ) -> Standing {
        Standing {
            claim: method.info().claim.map(|c| Held {
                claim: c.name(),
                refuted: refuted(c),
            }),
            ..Standing::unclaimed(method.name(), judged, wrong)
        }
    }

    /// The standing of the method of family `F` called `name` (a method outside the registry claims
    /// nothing).
    pub(crate) fn named<F: Family>(
        name: &str,
        judged: u64,
        wrong: u64,
        refuted: impl FnOnce(Claim) -> Option<u64>,
    ) -> Standing {
        match crate::family::by_name::<F>(name) {
            Ok(m) => Standing::of(m, judged, wrong, refuted),
            Err(_) => Standing::unclaimed(name, judged, wrong),
        }
    }

    /// Its summary line: `method: W wrong of J judged`, then its claim's fate.
    pub fn line(&self) -> String {
        let mut s = format!(
            "{}: {} wrong of {} judged",
            self.method, self.wrong, self.judged
        );
        match &self.claim {
            None => {}
            Some(Held { claim, .. }) if self.judged == 0 => {
                s += &format!("; claims {claim}: not shown (no case judged)")
            }
            Some(Held {
                claim,
                refuted: Some(0),
            }) => s += &format!("; claims {claim}: holds here"),
            Some(Held {
                claim,
                refuted: Some(n),
            }) => s += &format!("; claims {claim}: REFUTED by {n}"),
            Some(Held {
                claim,
                refuted: None,
            }) => s += &format!("; claims {claim}: not judged by this run"),
        }
        s
    }

    /// Whether a claim of this method was refuted.
    pub fn refuted(&self) -> bool {
        self.claim
            .as_ref()
            .is_some_and(|c| c.refuted.is_some_and(|n| n > 0))
    }

    /// Whether its claim is not upheld here: refuted, or judged on no case at all (a claim holds only
    /// where something was judged).
    pub(crate) fn claim_fails(&self) -> bool {
        self.refuted() || (self.claim.is_some() && self.judged == 0)
    }
}

/// The standings of several runs of the same methods (rows of a table, labellings) added up by method,
/// in first-seen order.
pub(crate) fn summed(all: impl IntoIterator<Item = Standing>) -> Vec<Standing> {
    let mut out: Vec<Standing> = Vec::new();
    for s in all {
        match out.iter_mut().find(|o| o.method == s.method) {
            None => out.push(s),
            Some(o) => {
                o.judged += s.judged;
                o.wrong += s.wrong;
                if let (Some(a), Some(b)) = (o.claim.as_mut(), s.claim) {
                    a.refuted = a.refuted.zip(b.refuted).map(|(x, y)| x + y);
                }
            }
        }
    }
    out
}

/// A report's standings, one per method judged (a count's reference row is what the others are
/// judged against, audited: not among them).
pub trait Standings {
    /// The family judged.
    type Of: Family;
    fn standings(&self) -> Vec<Standing>;
    /// The answers of the method or program named that refute its family's claim.
    fn refuted(&self, name: &str) -> u64;
    /// The standings, with the claim a program outside tetwalk makes (`--answerer-claims`) held to
    /// its answers here.
    fn standings_with(&self, outside: Option<&crate::engine::answerer::Answerer>) -> Vec<Standing> {
        let mut s = self.standings();
        if let Some(x) = outside {
            x.claim::<Self::Of>(&mut s, self.refuted(&x.name));
        }
        s
    }
}

impl<F: Family> Standings for StressReport<F> {
    type Of = F;

    fn refuted(&self, name: &str) -> u64 {
        self.rows
            .iter()
            .flat_map(|row| &row.tallies)
            .filter(|t| t.method == name)
            .map(|t| F::refuted(&t.counts))
            .sum()
    }

    fn standings(&self) -> Vec<Standing> {
        summed(self.rows.iter().flat_map(|r| {
            r.tallies.iter().map(|t| {
                let wrong = F::wrong(&t.counts);
                let judged = F::judged(&r.facts, &t.counts);
                Standing::named::<F>(&t.method, judged, wrong, |_| Some(F::refuted(&t.counts)))
            })
        }))
    }
}

impl<F: crate::family::count::Counted> Standings for crate::engine::count::CountReport<F> {
    type Of = F;

    /// Its wrong rays (the rays a count judges refute a robust claim; first hits cannot tell leaks
    /// from misses beside the object).
    fn refuted(&self, name: &str) -> u64 {
        use crate::family::count::Counts;
        let own = F::reference_row() as usize;
        self.methods
            .iter()
            .skip(own)
            .filter(|m| m.method == name)
            .map(|m| m.counts.wrong_total())
            .sum()
    }

    fn standings(&self) -> Vec<Standing> {
        use crate::family::count::Counts;
        let own = F::reference_row() as usize;
        self.methods
            .iter()
            .skip(own)
            .map(|m| {
                let wrong = m.counts.wrong_total();
                Standing::named::<F>(&m.method, self.rays, wrong, |c| match c {
                    Claim::Robust => Some(wrong),
                    // A count of first hits cannot tell leaks from misses beside the object.
                    Claim::NoLeak => None,
                })
            })
            .collect()
    }
}
