//! Each method's standing after a run, from its report: answers judged, wrong, and whether the claim
//! its paper makes (the register's claims) was refuted. `--fail-on` turns standings into an exit
//! status.

use crate::registry::{METHODS, OCTREE_METHODS, TRIANGLE_METHODS};

/// What a method's paper claims, and how often this run refuted it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Claim {
    /// The claim: `robust` (never a wrong exit: `exact`, `certified`) or `no leak` (a ray through a
    /// closed surface never passes through it: `woop-watertight`).
    pub claim: &'static str,
    /// Answers that refute it; `None` when this run does not judge it (a count of first hits does
    /// not tell leaks from misses beside the object).
    pub refuted: Option<u64>,
}

/// One method's standing.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Standing {
    pub method: String,
    /// Answers judged (cases or rays whose exact answer is defined).
    pub judged: u64,
    pub wrong: u64,
    pub claim: Option<Claim>,
}

impl Standing {
    /// A method that claims nothing (answers given from outside).
    pub fn unclaimed(method: &str, judged: u64, wrong: u64) -> Standing {
        Standing {
            method: method.to_string(),
            judged,
            wrong,
            claim: None,
        }
    }

    /// A method's standing with `claim` when it makes it.
    fn claiming(method: &str, judged: u64, wrong: u64, makes: bool, claim: Claim) -> Standing {
        Standing {
            claim: makes.then_some(claim),
            ..Standing::unclaimed(method, judged, wrong)
        }
    }

    /// The claim `robust`, refuted by every wrong answer.
    fn robust(wrong: u64) -> Claim {
        Claim {
            claim: "robust",
            refuted: Some(wrong),
        }
    }

    /// An exit-face method's standing: its claim (`robust`) refuted by every wrong answer.
    pub fn exit_face(method: &str, judged: u64, wrong: u64) -> Standing {
        let robust = METHODS.iter().any(|m| m.name == method && m.claims_robust);
        Standing::claiming(method, judged, wrong, robust, Standing::robust(wrong))
    }

    /// A ray–triangle method's standing: its claim (`no leak`) refuted by its leaks, when the run
    /// counts them.
    pub fn triangle(method: &str, judged: u64, wrong: u64, leaks: Option<u64>) -> Standing {
        let watertight = TRIANGLE_METHODS
            .iter()
            .any(|m| m.name == method && m.claims_watertight);
        let claim = Claim {
            claim: "no leak",
            refuted: leaks,
        };
        Standing::claiming(method, judged, wrong, watertight, claim)
    }

    /// An octree cell method's standing: the exact reference claims `robust`, the seed's methods
    /// nothing.
    pub fn cell(method: &str, judged: u64, wrong: u64) -> Standing {
        let exact = OCTREE_METHODS
            .iter()
            .any(|m| m.name == method && m.reference);
        Standing::claiming(method, judged, wrong, exact, Standing::robust(wrong))
    }

    /// Its summary line: `method: W wrong of J judged`, then its claim's fate.
    pub fn line(&self) -> String {
        let mut s = format!(
            "{}: {} wrong of {} judged",
            self.method, self.wrong, self.judged
        );
        match &self.claim {
            None => {}
            Some(Claim {
                claim,
                refuted: Some(0),
            }) => s += &format!("; claims {claim}: holds here"),
            Some(Claim {
                claim,
                refuted: Some(n),
            }) => s += &format!("; claims {claim}: REFUTED by {n}"),
            Some(Claim {
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
}

/// The standings of several runs of the same methods (rows of a table, labellings) added up by method,
/// in first-seen order.
pub fn summed(all: impl IntoIterator<Item = Standing>) -> Vec<Standing> {
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
    fn standings(&self) -> Vec<Standing>;
}

impl Standings for super::count::CountReport {
    fn standings(&self) -> Vec<Standing> {
        let judged = self.methods.iter().skip(1);
        judged
            .map(|m| Standing::exit_face(&m.method, self.rays, m.wrong_total))
            .collect()
    }
}

impl Standings for super::octree::OctreeCountReport {
    fn standings(&self) -> Vec<Standing> {
        let each = self.methods.iter();
        each.map(|m| Standing::cell(&m.method, self.rays, m.wrong_total))
            .collect()
    }
}

impl Standings for super::triangle::TriangleCountReport {
    fn standings(&self) -> Vec<Standing> {
        let each = self.methods.iter();
        each.map(|m| {
            let wrong = m.wrong_triangle + m.false_miss;
            Standing::triangle(&m.method, self.rays, wrong, None)
        })
        .collect()
    }
}

impl Standings for super::stress::StressReport {
    fn standings(&self) -> Vec<Standing> {
        summed(self.rows.iter().flat_map(|r| {
            r.tallies
                .iter()
                .map(|t| Standing::exit_face(&t.method, t.judged, t.wrong_face + t.no_exit_face))
        }))
    }
}

impl Standings for super::triangle::HitStressReport {
    fn standings(&self) -> Vec<Standing> {
        summed(self.rows.iter().flat_map(|r| {
            r.tallies
                .iter()
                .map(|t| Standing::triangle(&t.method, r.rays, t.wrong_first_hits, Some(t.leaks)))
        }))
    }
}

impl Standings for super::octree::CellStressReport {
    fn standings(&self) -> Vec<Standing> {
        summed(self.rows.iter().flat_map(|r| {
            r.tallies
                .iter()
                .map(|t| Standing::cell(&t.method, t.judged, t.wrong))
        }))
    }
}
