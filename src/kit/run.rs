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
        note: None,
        also: Vec::new(),
    }
}

/// The CPU backend computing in the settings' model.
fn backend(s: &Settings) -> &'static Backend {
    CPUS.iter()
        .find(|b| matches!(b, Backend::Cpu { model } if *model == s.model))
        .expect("a CPU backend for every model")
}

/// Judge method `m` of family `F` exactly, group by group: the convention check (a family whose
/// answers name faces), every stress row of the family (the engine's rows and judging, as `tetwalk
/// stress` runs them), then a property campaign of random inputs through the family's fuzz target's
/// generator; every group scaled by [`crate::kit::SCALE_VARIABLE`]. The first failing group stops
/// the run, or, with [`Settings::every_group`], every failing one is reported.
pub fn check<F: Family>(m: &F::Method, s: &Settings) -> Result<Passed, Box<Failed>> {
    check_with::<F>(m, s, |_| None)
}

/// [`check`], with `explain` asked what the method's answers fit where the convention check finds
/// that tetwalk's own numbering does not ([`convention`]).
pub(crate) fn check_with<F: Family>(
    m: &F::Method,
    s: &Settings,
    explain: impl FnOnce(&crate::engine::numbering::Numbering) -> Option<String>,
) -> Result<Passed, Box<Failed>> {
    let s = &s
        .scaled_by_environment()
        .map_err(|why| Box::new(Failed::not_run(m.name(), F::NAME, "settings", why)))?;
    let on = backend(s);
    convention::<F>(m, s, explain)?;
    let st = StressSettings::<F> {
        contract: s.contract,
        cases: F::kit_row_cases(s.cases),
        rows: F::Rows::default(),
        seed: s.seed,
        backend: on.ran(),
        scale: Default::default(),
    };
    let mut passed = Passed::default();
    let mut failed: Vec<Failed> = Vec::new();
    let mut close = |t: KitTally<F>, passed: &mut Passed| -> Result<(), Box<Failed>> {
        match t.close(s, m, passed) {
            Err(f) if s.every_group => {
                failed.push(*f);
                Ok(())
            }
            other => other,
        }
    };
    for row in F::rows(&st.rows) {
        let mut t = KitTally::<F>::new(format!("stress row {}", F::row_name(&row)));
        let cases = row_cases(&st, row).0;
        judge(&st, Who::Method(m), on, &cases, |c, x, a, v| {
            t.add(s, (m, on), (c, x, a), v)
        })
        .expect("the CPU answers every case");
        close(t, &mut passed)?;
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
    close(t, &mut passed)?;
    match failed.len() {
        0 => Ok(passed),
        _ => {
            let mut first = failed.remove(0);
            first.also = failed;
            Err(Box::new(first))
        }
    }
}

/// `first`'s groups then `then`'s, as one run: `then` is not run where `first` failed, unless
/// [`Settings::every_group`] asks for every group (each failure then reported).
pub(crate) fn and_then(
    s: &Settings,
    first: Result<Passed, Box<Failed>>,
    then: impl FnOnce() -> Result<Passed, Box<Failed>>,
) -> Result<Passed, Box<Failed>> {
    match (first, s.every_group) {
        (Err(f), false) => Err(f),
        (Ok(mut p), _) => {
            p.groups.extend(then()?.groups);
            Ok(p)
        }
        (Err(mut f), true) => {
            if let Err(g) = then() {
                let mut g = *g;
                let rest = std::mem::take(&mut g.also);
                f.also.push(g);
                f.also.extend(rest);
            }
            Err(f)
        }
    }
}

/// The convention check, for a family whose answers name a tetrahedron's faces: on the `well` row's
/// cases under the contract, every face numbering is tried as `tetwalk exit --faces auto` tries an
/// answerer's. Where the method's answers fit another numbering than tetwalk's own (face `i` opposite
/// vertex `i`), the run stops saying which; where none fits, `explain` may say what does (the family's
/// own probe, such as another orientation), and otherwise the groups judge the method as it is.
fn convention<F: Family>(
    m: &F::Method,
    s: &Settings,
    explain: impl FnOnce(&crate::engine::numbering::Numbering) -> Option<String>,
) -> Result<(), Box<Failed>> {
    use crate::engine::numbering::{IDENTITY, Numbering, find};
    if !F::FACES {
        return Ok(());
    }
    let on = backend(s);
    let ask = |cases: &[F::Case], p: &[u8; 4]| {
        let sent: Vec<F::Case> = cases.iter().map(|c| F::for_program(c, p)).collect();
        F::answers(on, m, &sent)
    };
    let not_run =
        |why: String| Box::new(Failed::not_run(m.name(), F::NAME, "convention check", why));
    // The kit hands a method its tetrahedra as the family's methods take them (positively oriented,
    // the case's faces renumbered where it was mirrored): the numbering is searched on cases that are
    // so already, and another orientation is `explain`'s to probe.
    let k = crate::family::contract::Contract {
        orientation: crate::family::contract::Orientation::Positive,
        ..s.contract
    };
    let (found, asked) = find::<F, _>(&k, ask).map_err(|e| not_run(e.to_string()))?;
    match found {
        Numbering::Fits(IDENTITY) => Ok(()),
        Numbering::Fits(p) => Err(not_run(format!(
            "its answers to {asked} well-shaped cases ({}) fit when its face i is tetwalk's face {}[i]: it numbers a tetrahedron's faces otherwise than tetwalk, whose face i is opposite vertex i (`FACE_VERTICES`); renumber its answers (and the entry face it is given) into tetwalk's",
            s.contract.describe(),
            faces_list(p)
        ))),
        miss => match explain(&miss) {
            Some(why) => Err(not_run(why)),
            None => Ok(()),
        },
    }
}

/// A face numbering written `[a, b, c, d]`.
pub(crate) fn faces_list(p: [u8; 4]) -> String {
    format!("[{}]", p.map(|f| f.to_string()).join(", "))
}

/// Judge method `m` of family `F` on one case (a property test's, a regression test's): `Ok` where
/// its answer is right (or the line misses the cell, or the settings accept the failure), else the
/// failure reported as a run's first is, shrunk.
pub(crate) fn check_case<F: Family>(
    m: &F::Method,
    case: &F::Case,
    s: &Settings,
) -> Result<(), Box<Failed>> {
    let truth = F::truth(case).map_err(|e| {
        Box::new(Failed::not_run(
            m.name(),
            F::NAME,
            "case",
            format!("the oracle cannot judge the case: {e}"),
        ))
    })?;
    let on = backend(s);
    let answer =
        F::answers(on, m, std::slice::from_ref(case)).expect("the CPU answers every case")[0];
    let mut t = KitTally::<F>::new("case".into());
    t.add(
        s,
        (m, on),
        (case, &truth, &answer),
        F::verdict(case, &truth, &answer),
    );
    t.close(s, m, &mut Passed::default())
}

/// A case line of family `F` read back (a report's `case:` line, or its `found:` line, whose failure
/// fields are left aside).
pub(crate) fn from_line<F: Family>(line: &str) -> Result<F::Case, crate::cases::CaseError> {
    let mut obj = crate::cases::object(line)?;
    let case = F::take_case(&mut obj)?;
    match obj
        .keys()
        .find(|k| !crate::engine::found::FAILURE_FIELDS.contains(&k.as_str()))
    {
        Some(k) => Err(crate::cases::CaseError::UnknownField(k.clone())),
        None => Ok(case),
    }
}

/// Case `i` of `F`'s stress row `row` drawn with `seed` (as `tetwalk stress` draws it); an error
/// naming the rows where `row` is none of them, `None` where the oracle cannot judge that case.
pub(crate) fn row_case<F: Family>(
    row: &str,
    seed: u64,
    i: usize,
) -> Result<Option<F::Case>, crate::cases::CaseError> {
    let rows = F::Rows::default();
    let all = F::rows(&rows);
    let r = all.iter().find(|r| F::row_name(r) == row).ok_or_else(|| {
        let names: Vec<String> = all.iter().map(F::row_name).collect();
        crate::cases::field_error(
            "row",
            format!(
                "'{row}' is not a stress row of the {} family: {}",
                F::NAME,
                names.join(", ")
            ),
        )
    })?;
    Ok(F::case(&rows, *r, seed, i).map(|(c, _)| c))
}

/// The kit's trait for a family's case type ([`crate::kit::KitCase`]) and `arbitrary::Arbitrary` (the
/// family's fuzz target's decoder), implemented from the family's [`Family`]: written once here, named
/// in each family's `kit.rs`.
macro_rules! kit_case {
    ($case:ty, $family:ty) => {
        impl $crate::kit::sealed::Sealed for $case {}

        impl $crate::kit::KitCase for $case {
            const FAMILY: &'static str = <$family as $crate::family::Family>::NAME;
            fn from_line(line: &str) -> Result<Self, $crate::cases::CaseError> {
                $crate::kit::run::from_line::<$family>(line)
            }
            fn to_line(&self) -> String {
                serde_json::Value::Object(<$family as $crate::family::Family>::case_json(self))
                    .to_string()
            }
            fn from_bytes(bytes: &[u8]) -> Option<Self> {
                <$family as $crate::family::Family>::arbitrary(&mut arbitrary::Unstructured::new(
                    bytes,
                ))
            }
            fn within(
                &self,
                contract: &$crate::family::contract::Contract,
                key: u64,
            ) -> Option<Self> {
                $crate::family::contract::within::<$family>(contract, self, key).map(|(c, _)| c)
            }
            fn rows() -> Vec<String> {
                use $crate::family::Family;
                <$family>::rows(&Default::default())
                    .iter()
                    .map(<$family>::row_name)
                    .collect()
            }
            fn row_case(
                row: &str,
                seed: u64,
                i: usize,
            ) -> Result<Option<Self>, $crate::cases::CaseError> {
                $crate::kit::run::row_case::<$family>(row, seed, i)
            }
        }

        impl<'a> arbitrary::Arbitrary<'a> for $case {
            fn arbitrary(u: &mut arbitrary::Unstructured<'a>) -> arbitrary::Result<Self> {
                <$family as $crate::family::Family>::arbitrary(u)
                    .ok_or(arbitrary::Error::IncorrectFormat)
            }
        }
    };
}
pub(crate) use kit_case;

/// A registered method of family `F` run through the kit, by name (tetwalk's own tests check that
/// the kit fails a method exactly where `tetwalk stress` counts it).
pub fn registered<F: Family>(
    name: &str,
    s: &Settings,
) -> Result<Result<Passed, Box<Failed>>, crate::registry::UnknownMethod> {
    Ok(check::<F>(family::by_name::<F>(name)?, s))
}
