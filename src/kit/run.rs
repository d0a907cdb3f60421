//! The kit's run, over any family: every stress row, then a property campaign through the family's
//! fuzz generator, judged group by group (`kit::exit_faces`, `triangles` and `cells` call it with a
//! user's method). Public with the `internals` feature, for tetwalk's own tests.

use super::{Failed, Group, Passed, Settings, per_million};
use crate::backend::{Backend, CPUS};
use crate::engine::found::Found;
use crate::engine::shrink;
use crate::engine::stress::{StressSettings, Who, judge, row_cases};
use crate::family::{self, Family, Verdict};
use crate::registry::Named;
use rand::RngExt;

/// One group's count and its first failure.
struct KitTally<F: Family> {
    name: String,
    judged: u64,
    failures: u64,
    first: Option<Found<F>>,
}

impl<F: Family> KitTally<F> {
    fn new(name: String) -> Self {
        KitTally {
            name,
            judged: 0,
            failures: 0,
            first: None,
        }
    }

    /// Count one answer; a failure unless the settings accept it.
    fn add(
        &mut self,
        s: &Settings,
        (m, on): (&F::Method, &Backend),
        (case, truth, answer): (&F::Case, &F::Truth, &F::Answer),
        verdict: Verdict,
    ) {
        if verdict == Verdict::NotJudged {
            return;
        }
        self.judged += 1;
        let failed = match s.accept.claim_only {
            true => F::refutes_claim(case, truth, answer),
            false => matches!(verdict, Verdict::Wrong(_)),
        };
        if !failed || (s.accept.touch_only && F::touch_only(case)) {
            return;
        }
        self.failures += 1;
        if self.first.is_none() {
            let failure = crate::engine::found::Failure::of(m, on, *answer);
            self.first = Some(Found::of(*case, failure));
        }
    }

    /// Passed, or failed beyond the budget.
    fn close(self, s: &Settings, m: &F::Method, passed: &mut Passed) -> Result<(), Box<Failed>> {
        let over =
            self.failures > 0 && per_million(self.failures, self.judged) > s.accept.per_million;
        match self.first {
            Some(found) if over => Err(Box::new(failed(
                s,
                m,
                self.name,
                self.judged,
                self.failures,
                found,
            ))),
            _ => {
                passed.groups.push(Group {
                    name: self.name,
                    judged: self.judged,
                    failed: self.failures,
                });
                Ok(())
            }
        }
    }
}

/// The report of a group's first failure, the case read back from its line and judged again.
fn failed<F: Family>(
    s: &Settings,
    m: &F::Method,
    group: String,
    judged: u64,
    failures: u64,
    found: Found<F>,
) -> Failed {
    let original = found.case_line();
    let on = backend(s);
    let answer = |c: &F::Case| Ok(F::answers(on, m, std::slice::from_ref(c))?[0]);
    let found = shrink::shrink_with::<F>(
        &answer,
        m.name(),
        &found.case,
        &[],
        shrink::CHECKS,
        &s.contract,
    )
    .map_or(found.clone(), |x| shrink::shrunk(&found, &x));
    let f = found
        .failure
        .as_ref()
        .expect("a failure records what failed");
    let again = Found::<F>::parse(&found.case_line()).ok().and_then(|back| {
        let truth = F::truth(&back.case).ok()?;
        let now = F::answers(backend(s), m, &[back.case]).ok()?.pop()?;
        let wrong = match s.accept.claim_only {
            true => F::refutes_claim(&back.case, &truth, &now),
            false => matches!(F::verdict(&back.case, &truth, &now), Verdict::Wrong(_)),
        };
        Some(wrong && F::answer_json(&now) == F::answer_json(&f.answer))
    });
    Failed {
        method: m.name().to_string(),
        family: F::NAME,
        group,
        judged,
        failures,
        case: found.case_line(),
        original,
        found: found.to_json(),
        answered: format!(
            "{} (backend {})",
            F::describe(&f.answer),
            crate::choice::Choice::name(f.backend)
        ),
        right: F::truth(&found.case)
            .map_or_else(|e| e.to_string(), |t| F::right_answers(&found.case, &t)),
        reproduced: again == Some(true),
    }
}

/// The CPU backend computing in the settings' model.
fn backend(s: &Settings) -> &'static Backend {
    CPUS.iter()
        .find(|b| matches!(b, Backend::Cpu { model } if *model == s.model))
        .expect("a CPU backend for every model")
}

/// Judge method `m` of family `F` exactly, group by group: every stress row of the family (the
/// engine's rows and judging, as `tetwalk stress` runs them), then a property campaign of random
/// inputs through the family's fuzz target's generator.
pub fn check<F: Family>(m: &F::Method, s: &Settings) -> Result<Passed, Box<Failed>> {
    let on = backend(s);
    let st = StressSettings::<F> {
        contract: s.contract,
        cases: F::kit_row_cases(s.cases),
        rows: F::Rows::default(),
        seed: s.seed,
        backend: on.ran(),
        scale: Default::default(),
    };
    let mut passed = Passed::default();
    for row in F::rows(&st.rows) {
        let mut t = KitTally::<F>::new(format!("stress row {}", F::row_name(&row)));
        let cases = row_cases(&st, row).0;
        judge(&st, Who::Method(m), on, &cases, |c, x, a, v| {
            t.add(s, (m, on), (c, x, a), v)
        })
        .expect("the CPU answers every case");
        t.close(s, m, &mut passed)?;
    }
    let mut t = KitTally::<F>::new(format!("property campaign ({} generator)", F::FUZZ_TARGET));
    let salt = F::NAME
        .bytes()
        .fold(0xc0f0_4a11u64, |h, b| h.rotate_left(5) ^ b as u64);
    let mut rng = crate::scenes::rng(s.seed ^ salt);
    let mut cases = Vec::new();
    for i in 0..F::kit_properties(s.properties) {
        let bytes: Vec<u8> = (0..rng.random_range(16..160))
            .map(|_| rng.random())
            .collect();
        // Each input made to hold the contract, and kept where it then does.
        let made = F::arbitrary(&mut arbitrary::Unstructured::new(&bytes)).and_then(|c| {
            match s.contract.is_default() {
                true => Some((c, F::truth(&c).ok()?)),
                false => crate::family::contract::within::<F>(&s.contract, &c, i as u64),
            }
        });
        cases.extend(made);
    }
    let asked: Vec<F::Case> = cases.iter().map(|(c, _)| *c).collect();
    let answers = F::answers(on, m, &asked).expect("the CPU answers every case");
    for ((c, x), a) in cases.iter().zip(&answers) {
        t.add(s, (m, on), (c, x, a), F::verdict(c, x, a));
    }
    t.close(s, m, &mut passed)?;
    Ok(passed)
}

/// A registered method of family `F` run through the kit, by name (tetwalk's own tests check that
/// the kit fails a method exactly where `tetwalk stress` counts it).
pub fn registered<F: Family>(
    name: &str,
    s: &Settings,
) -> Result<Result<Passed, Box<Failed>>, crate::registry::UnknownMethod> {
    Ok(check::<F>(family::by_name::<F>(name)?, s))
}
