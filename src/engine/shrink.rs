//! Shrinking, as proptest shrinks a failing input: a failure's case made as simple as it can be while
//! the same method on the same backend still fails it the same way (the same answer, the same kind of
//! wrong ending, the same exact right answers, a refuted claim still refuted, a line that crosses the
//! cell not turned into one that only touches it, and at least half the original's clearance, so
//! that a clear failure stays as clear: [`Family::clearance`]). Smaller cases first ([`Family::smaller`]: fewer triangles, a
//! smaller mesh), then each number of the case ([`Family::numbers`]) replaced by the simplest value
//! that keeps the failure: zero, an integer, or the number rounded to fewer significant bits, fewest
//! first and then smallest in magnitude, pass after pass until none changes.

use crate::backend::Backend;
use crate::choice::{BackendKind, Choice};
use crate::engine::Backends;
use crate::engine::answerer::Answerer as Program;
use crate::engine::found::{Failure, Found, FoundError, Hold, check, cpu_backends};
use crate::family::contract::Contract;
use crate::family::wrong::WrongRay;
use crate::family::{self, Family, Verdict, owner};
use crate::registry::Named;
use crate::walk::OutcomeKind;

/// Checks one shrink may make at most (each judges one candidate exactly and answers it once).
pub(crate) const CHECKS: usize = 20_000;

/// Passes over the numbers at most (each after the first only where the one before changed some).
const PASSES: usize = 8;

/// Significant bits of an f32: from the leading to the last set bit of its significand, 0 for zero
/// (a subnormal counts its own bits; infinities and NaN the full 24).
pub(crate) fn significant_bits(x: f32) -> u32 {
    if x == 0.0 {
        return 0;
    }
    if !x.is_finite() {
        return 24;
    }
    let bits = x.to_bits() & 0x7f_ffff;
    let significand = if x.is_normal() {
        bits | 0x80_0000
    } else {
        bits
    };
    32 - significand.leading_zeros() - significand.trailing_zeros()
}

/// `x` rounded to `k` significant bits (to nearest, ties away from zero), exactly representable.
fn round_to_bits(x: f32, k: u32) -> f32 {
    let x = x as f64;
    let quantum = 2f64.powi(x.abs().log2().floor() as i32 + 1 - k as i32);
    ((x / quantum).round() * quantum) as f32
}

/// The values simpler than `x` to try in its place, simplest first: fewer significant bits, then a
/// smaller magnitude (zero, integers, `x` rounded to 1, 2, … bits).
fn simpler(x: f32) -> Vec<f32> {
    let key = |v: f32| (significant_bits(v), v.abs().to_bits());
    let mut out: Vec<f32> = [0.0, x.trunc(), x.round()]
        .into_iter()
        .chain((1..significant_bits(x)).map(|k| round_to_bits(x, k)))
        .filter(|v| v.is_finite() && key(*v) < key(x))
        .collect();
    out.sort_by_key(|&v| key(v));
    out.dedup();
    out
}

/// Whether two numbers agree but for their last 12 of 24 bits (and are not zero).
fn nearly_equal(a: f32, b: f32) -> bool {
    a != 0.0 && (a - b).abs() <= a.abs().max(b.abs()) * 2f32.powi(-12)
}

/// What a shrink gives: the simplest case found and how much work it took.
#[derive(Clone, Debug)]
pub struct Shrunk<F: Family> {
    pub(crate) case: F::Case,
    /// What the method answers on it (wrong the same way as on the original).
    pub(crate) answer: F::Answer,
    pub checks: usize,
    /// Whether the check budget ran out before no simpler case was left.
    pub exhausted: bool,
}

/// Whoever answers the cases a shrink tries: a method on a backend, or a program outside tetwalk.
pub(crate) type AnswerFn<'a, F> =
    dyn Fn(&<F as Family>::Case) -> Result<<F as Family>::Answer, FoundError> + 'a;

/// Shrink `case`, on which `m` (running on `backend`) answers wrongly: the simplest case on which it
/// still does, the same way, and on which each of `keep` still holds its claim (on the CPU plain,
/// fused and flushed). An error when `m` does not fail `case` to begin with.
pub fn shrink<F: Family>(
    m: &F::Method,
    backend: &Backend,
    case: &F::Case,
    keep: &[&F::Method],
    budget: usize,
) -> Result<Shrunk<F>, FoundError> {
    let answer = |c: &F::Case| Ok(F::answers(backend, m, std::slice::from_ref(c))?[0]);
    shrink_with::<F>(&answer, m.name(), case, keep, budget, &Contract::default())
}

/// [`shrink_with`] for a program outside tetwalk, each case tried asked of it alone, inside `contract`.
pub(crate) fn shrink_outside<F: Family>(
    x: &crate::engine::answerer::Answerer,
    case: &F::Case,
    budget: usize,
    contract: &Contract,
) -> Result<Shrunk<F>, FoundError> {
    let ask = |c: &F::Case| {
        Ok(x.answers::<F>(std::slice::from_ref(c))
            .map_err(|e| FoundError::Field {
                field: "answerer",
                why: e.to_string(),
            })?[0])
    };
    shrink_with::<F>(&ask, &x.name, case, &[], budget, contract)
}

/// [`shrink`] for any answerer, `name` naming it; every case tried holds `contract` (what the
/// answerer assumes), and a failure that is no tie does not shrink into one.
pub(crate) fn shrink_with<F: Family>(
    answerer: &AnswerFn<F>,
    name: &str,
    case: &F::Case,
    keep: &[&F::Method],
    budget: usize,
    contract: &Contract,
) -> Result<Shrunk<F>, FoundError> {
    let kept: Vec<(&F::Method, Hold)> = keep.iter().map(|&k| (k, Hold::Claim)).collect();
    let mut checks = 0;
    let Some((kind, claim, answer, tie, truth)) = failure::<F>(answerer, case, contract)? else {
        return Err(FoundError::Field {
            field: "case",
            why: format!("{name} answers it rightly: there is no failure to shrink"),
        });
    };
    // A line that crosses the cell stays one that crosses it: it does not shrink into a graze.
    let touching = F::touch_only(case);
    let (said, clear) = (F::answer_json(&answer), F::clearance(case, &truth));
    let mut best = Shrunk {
        case: *case,
        answer,
        checks: 0,
        exhausted: false,
    };
    // Whether `c` fails as the original does; counts the check, and refuses once the budget is spent.
    let same = |c: &F::Case, checks: &mut usize| -> Result<Option<F::Answer>, FoundError> {
        if *checks >= budget {
            return Ok(None);
        }
        *checks += 1;
        let Some(a) = failure::<F>(answerer, c, contract)?
            .filter(|(k, refuted, _, t, _)| *k == kind && (*refuted || !claim) && (tie || !t))
            .filter(|(_, _, a, _, x)| {
                F::answer_json(a) == said
                    && F::same_truth(x, &truth)
                    && F::clearance(c, x) >= clear / 2.0
            })
            .filter(|_| touching || !F::touch_only(c))
            .map(|(_, _, a, _, _)| a)
        else {
            return Ok(None);
        };
        let held = kept.is_empty()
            || check::<F>(std::slice::from_ref(c), &kept, &cpu_backends())?.is_none();
        Ok(held.then_some(a))
    };
    'smaller: loop {
        for c in F::smaller(&best.case) {
            if let Some(a) = same(&c, &mut checks)? {
                best.case = c;
                best.answer = a;
                continue 'smaller;
            }
        }
        break;
    }
    let mut numbers = F::numbers(&best.case);
    for _ in 0..PASSES {
        let mut changed = false;
        // A shrink may make two of a case's points one (a closed mesh's corners are its distinct
        // points), so the numbers can grow fewer as they are walked.
        let mut i = 0;
        while i < numbers.len() {
            'value: for v in simpler(numbers[i]) {
                // The numbers nearly equal to this one (a vertex and the point a ray is aimed at
                // near it) moved with it first, then it alone.
                let mut together = numbers.clone();
                for (j, x) in together.iter_mut().enumerate() {
                    if j == i || nearly_equal(*x, numbers[i]) {
                        *x = v;
                    }
                }
                let mut alone = numbers.clone();
                alone[i] = v;
                let mut tried: Vec<F::Case> = Vec::new();
                if let Some(c) = F::with_numbers(&best.case, &together) {
                    // The point the ray is aimed at (origin plus direction) moved with them too.
                    let r = F::ray(&best.case);
                    let aim = (r.org + r.dir).to_array();
                    if aim.iter().any(|&t| nearly_equal(t, numbers[i])) {
                        let mut moved = F::ray(&c);
                        for (k, &t) in aim.iter().enumerate() {
                            if nearly_equal(t, numbers[i]) {
                                moved.dir[k] = v - moved.org[k];
                            }
                        }
                        tried.push(F::with_ray(&c, moved));
                    }
                    tried.push(c);
                }
                tried.extend(F::with_numbers(&best.case, &alone));
                for c in tried {
                    if let Some(a) = same(&c, &mut checks)? {
                        numbers = F::numbers(&c);
                        best.case = c;
                        best.answer = a;
                        changed = true;
                        break 'value;
                    }
                }
            }
            i += 1;
        }
        if !changed {
            break;
        }
    }
    best.checks = checks;
    best.exhausted = checks >= budget;
    Ok(best)
}

/// How a case fails: the kind of wrong ending, whether the claim is refuted, the answer, whether the
/// case is a tie, and its exact truth.
type Failing<F> = (
    OutcomeKind,
    bool,
    <F as Family>::Answer,
    bool,
    <F as Family>::Truth,
);

/// How `answerer` fails `case`, if it does: the kind of wrong ending, whether the answer refutes the
/// family's claim (a leak, for triangles), the answer, and whether the case is a tie. A case the
/// oracle refuses (a flat tetrahedron, an origin outside the mesh), or outside `contract`, fails
/// nothing.
fn failure<F: Family>(
    answerer: &AnswerFn<F>,
    case: &F::Case,
    contract: &Contract,
) -> Result<Option<Failing<F>>, FoundError> {
    // A case its own line does not read back as (a zero direction, a number the reader refuses) is
    // not a case.
    if !family::readable::<F>(case) {
        return Ok(None);
    }
    let Ok(truth) = F::truth(case) else {
        return Ok(None);
    };
    if !contract.is_default() && !F::holds(contract, case, &truth) {
        return Ok(None);
    }
    let answer = answerer(case)?;
    Ok(match F::verdict(case, &truth, &answer) {
        Verdict::Wrong(kind) => Some((
            kind,
            F::refutes_claim(case, &truth, &answer),
            answer,
            F::tie(&truth),
            truth,
        )),
        _ => None,
    })
}

/// A found case shrunk (with what the shrink took), or why it was left as it is.
pub(crate) type ShrunkOrLeft<F> = Result<(Found<F>, Shrunk<F>), String>;

/// A found case shrunk on the backend it was found on, the original kept ([`Found::original`]); a
/// GPU finding made on another adapter, or on a backend that cannot be opened here, is left as it is
/// (with why).
pub fn shrink_found<F: Family>(
    found: &Found<F>,
    budget: usize,
) -> Result<ShrunkOrLeft<F>, FoundError> {
    shrink_found_with(found, &mut Backends::default(), budget)
}

/// [`shrink_found`] with the backends opened once each in `backends`.
fn shrink_found_with<F: Family>(
    found: &Found<F>,
    backends: &mut Backends,
    budget: usize,
) -> Result<ShrunkOrLeft<F>, FoundError> {
    let f = found.failed("shrink")?;
    let backend = match found_on(backends, f) {
        Ok(b) => b,
        Err(why) => return Ok(Err(why)),
    };
    let m = family::by_name::<F>(&f.method)?;
    Ok(Ok(shrink_on(found, m, backend, budget)?))
}

/// `found` shrunk with its method `m` on `backend` (where it was found), the original kept; every
/// other method of the registry that claims and holds its claim on the case as found still holds it
/// on the shrunk one (so that a finding stays one method's).
pub(crate) fn shrink_on<F: Family>(
    found: &Found<F>,
    m: &F::Method,
    backend: &Backend,
    budget: usize,
) -> Result<(Found<F>, Shrunk<F>), FoundError> {
    let mut keep = Vec::new();
    for k in F::methods()
        .iter()
        .filter(|k| k.info().claim.is_some() && k.name() != m.name())
    {
        let held = [(k, Hold::Claim)];
        if check::<F>(std::slice::from_ref(&found.case), &held, &cpu_backends())?.is_none() {
            keep.push(k);
        }
    }
    let s = shrink::<F>(m, backend, &found.case, &keep, budget)?;
    Ok((shrunk(found, &s), s))
}

/// `found` with its case replaced by the shrunk one `s` and its answer there, the case as found kept.
pub(crate) fn shrunk<F: Family>(found: &Found<F>, s: &Shrunk<F>) -> Found<F> {
    Found {
        case: s.case,
        failure: found.failure.clone().map(|f| Failure {
            answer: s.answer,
            ..f
        }),
        original: Some(found.original.unwrap_or(found.case)),
    }
}

/// The significant bits of a case's numbers, summed and at most ([`significant_bits`]).
pub fn bits<F: Family>(case: &F::Case) -> (u32, u32) {
    let n = F::numbers(case);
    (
        n.iter().map(|&x| significant_bits(x)).sum(),
        n.iter().map(|&x| significant_bits(x)).max().unwrap_or(0),
    )
}

/// One shell line that reproduces a found case: its case piped into the command that answers its
/// family's cases, with its method and backend (`tetwalk replay --found FILE` where no command reads
/// them).
pub(crate) fn reproduce<F: Family>(found: &Found<F>) -> Option<String> {
    let f = found.failure.as_ref()?;
    let cmd = F::COMMAND?;
    Some(format!(
        "echo '{}' | tetwalk {cmd} --method {} --backend {}",
        found.case_line(),
        f.method,
        crate::choice::Choice::name(f.backend)
    ))
}

/// Where a case is: its file and 1-based line.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct Place {
    /// The file, as given.
    pub(crate) file: String,
    /// Its line, from 1.
    pub(crate) line: usize,
}

/// One case shrunk, as `tetwalk shrink` reports it.
#[derive(Debug, serde::Serialize)]
pub(crate) struct CaseShrunk {
    /// Where the case was.
    pub(crate) file: String,
    /// Its line, from 1.
    pub(crate) line: usize,
    /// The method that fails it (an answerer's name).
    pub(crate) method: String,
    /// Where it ran: a backend, or `outside` (`--answerer`).
    pub(crate) backend: String,
    /// How many numbers the case has.
    pub(crate) numbers: usize,
    /// Their significant bits summed, before and after ([`bits`]).
    pub(crate) bits_before: u32,
    pub(crate) bits_after: u32,
    /// The most significant bits of any one number, before and after.
    pub(crate) largest_before: u32,
    pub(crate) largest_after: u32,
    /// How far each case is from another right answer ([`Family::clearance`]), before and after.
    pub(crate) clearance_before: f64,
    pub(crate) clearance_after: f64,
    /// Candidates checked.
    pub(crate) checks: usize,
    /// Whether the check budget ran out first (a simpler case may exist).
    pub(crate) exhausted: bool,
    /// The shrunk found case, its original in `original`.
    pub(crate) shrunk: serde_json::Value,
    /// One shell line that reproduces it.
    pub(crate) reproduce: Option<String>,
}

impl CaseShrunk {
    /// What a shrink of `before` to `s` at `at` did, by `method` on `backend`.
    fn measured<F: Family>(
        at: &Place,
        before: &F::Case,
        s: &Shrunk<F>,
        method: String,
        backend: String,
        shrunk: serde_json::Value,
        reproduce: Option<String>,
    ) -> CaseShrunk {
        let (bits_before, largest_before) = bits::<F>(before);
        let (bits_after, largest_after) = bits::<F>(&s.case);
        let clearance = |c: &F::Case| F::truth(c).map_or(0.0, |x| F::clearance(c, &x));
        CaseShrunk {
            file: at.file.clone(),
            line: at.line,
            method,
            backend,
            numbers: F::numbers(before).len(),
            bits_before,
            bits_after,
            largest_before,
            largest_after,
            clearance_before: clearance(before),
            clearance_after: clearance(&s.case),
            checks: s.checks,
            exhausted: s.exhausted,
            shrunk,
            reproduce,
        }
    }

    /// Whether the search found a simpler case (fewer significant bits in all, or in the largest).
    pub(crate) fn simpler(&self) -> bool {
        self.bits_after < self.bits_before || self.largest_after < self.largest_before
    }
}

/// What `tetwalk shrink` did: the cases shrunk, and those left as they were, with why (found on a GPU
/// not here, a dump line without a diverging step).
#[derive(Debug, Default, serde::Serialize)]
pub(crate) struct ShrinkReport {
    /// The cases shrunk (or found as simple as the search finds).
    pub(crate) cases: Vec<CaseShrunk>,
    /// The cases left as they were, and why.
    pub(crate) left: Vec<(Place, String)>,
}

impl ShrinkReport {
    /// Significant bits per number before and after, over every case shrunk; `None` where none was.
    pub(crate) fn mean_bits(&self) -> Option<(f64, f64)> {
        let numbers: usize = self.cases.iter().map(|d| d.numbers).sum();
        let mean = |f: fn(&CaseShrunk) -> u32| {
            self.cases.iter().map(|d| f(d) as f64).sum::<f64>() / numbers as f64
        };
        (numbers > 0).then(|| (mean(|d| d.bits_before), mean(|d| d.bits_after)))
    }
}

/// Where `f` was found, opened here (a GPU finding only on its own adapter), or why not.
fn found_on<'b, F: Family>(
    backends: &'b mut Backends,
    f: &Failure<F>,
) -> Result<&'b Backend, String> {
    let b = backends.open(f.backend)?;
    f.runs_on(b)?;
    Ok(b)
}

/// A found case at `at` shrunk on the backend it was found on, or why it is left as it is.
pub(crate) fn shrink_case<F: Family>(
    found: &Found<F>,
    at: &Place,
    backends: &mut Backends,
    checks: usize,
) -> Result<Result<CaseShrunk, String>, FoundError> {
    let (shrunk, s) = match shrink_found_with(found, backends, checks)? {
        Ok(done) => done,
        Err(why) => return Ok(Err(why)),
    };
    let f = found.failed("shrink")?;
    Ok(Ok(CaseShrunk::measured(
        at,
        &found.case,
        &s,
        f.method.clone(),
        f.backend.name().to_string(),
        serde_json::from_str(&shrunk.to_json()).expect("a found case's line is JSON"),
        reproduce(&shrunk),
    )))
}

/// A case at `at` shrunk for a program outside tetwalk, inside its contract, or why it is left as it
/// is (the case breaks the contract).
pub(crate) fn shrink_case_outside<F: Family>(
    found: &Found<F>,
    a: &Program,
    contract: &Contract,
    at: &Place,
    checks: usize,
) -> Result<Result<CaseShrunk, String>, FoundError> {
    let s = match shrink_outside::<F>(a, &found.case, checks, contract) {
        Ok(s) => s,
        Err(FoundError::Field { field: "case", why }) => return Ok(Err(why)),
        Err(e) => return Err(e),
    };
    let line = serde_json::Value::Object(F::case_json(&s.case)).to_string();
    let quoted = |t: &str| format!("'{}'", t.replace('\'', "'\\''"));
    let reproduce = F::COMMAND.map(|command| {
        format!(
            "echo {} | tetwalk {command} --answerer {} --answerer-format {}{}",
            quoted(&line),
            quoted(&a.cmd),
            a.format.name(),
            match a.faces {
                [0, 1, 2, 3] => String::new(),
                f => format!(" --faces {}", f.map(|x| x.to_string()).join(",")),
            }
        )
    });
    Ok(Ok(CaseShrunk::measured(
        at,
        &found.case,
        &s,
        a.name.clone(),
        "outside".into(),
        serde_json::Value::Object(F::case_json(&s.case)),
        reproduce,
    )))
}

/// A dump line's diverging step as a found case (of the family whose case the dump holds: a walk's
/// step, one tetrahedron), its answer the divergence's in that family's form, or why it has none.
fn from_dump<F: Family>(
    method: &str,
    case: serde_json::Map<String, serde_json::Value>,
    answer: &serde_json::Value,
    backend: BackendKind,
) -> Result<Found<F>, String> {
    let case = Found::<F>::from_object(case).map_err(|e| e.to_string())?;
    let method = family::by_name::<F>(method).map_err(|e| e.to_string())?;
    let answer = F::parse_answer(answer, &case.case)?;
    Ok(Found::of(
        case.case,
        Failure {
            method: method.name().to_string(),
            backend,
            adapter: None,
            answer,
        },
    ))
}

/// A `count --dump` line at `at` shrunk: the found case of its diverging step (`from_dump`), or
/// why it has none.
pub(crate) fn shrink_dump_line(
    obj: serde_json::Map<String, serde_json::Value>,
    at: &Place,
    backends: &mut Backends,
    checks: usize,
) -> Result<Result<CaseShrunk, String>, FoundError> {
    let w: WrongRay =
        serde_json::from_value(serde_json::Value::Object(obj)).map_err(|e| FoundError::Field {
            field: "wrong ray",
            why: e.to_string(),
        })?;
    let WrongRay {
        case: Some(case),
        divergence: Some(d),
        backend: Some(backend),
        method,
        ..
    } = w
    else {
        return Ok(Err(
            "no diverging step was observed (a GPU walk, walks given from outside, or a method that walks no tetrahedra: a triangle or octree count's)".into(),
        ));
    };
    let answer = serde_json::json!(d.face);
    crate::with_family!(owner(&case), F => match from_dump::<F>(&method, case, &answer, backend) {
        Ok(found) => shrink_case::<F>(&found, at, backends, checks),
        Err(why) => Ok(Err(why)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_bits_count_from_the_leading_to_the_last_set_bit() {
        assert_eq!(significant_bits(0.0), 0);
        assert_eq!(significant_bits(1.0), 1);
        assert_eq!(significant_bits(-3.0), 2);
        assert_eq!(significant_bits(0.75), 2);
        assert_eq!(significant_bits(10000.0), 10);
        assert_eq!(significant_bits(f32::from_bits(1)), 1);
        assert_eq!(significant_bits(1.0f32.next_up()), 24);
    }

    #[test]
    fn simpler_values_have_fewer_bits_or_a_smaller_magnitude_and_come_simplest_first() {
        let x = 10000.584f32;
        let s = simpler(x);
        assert_eq!(s[0], 0.0);
        assert!(s.contains(&10001.0) && s.contains(&8192.0));
        for w in s.windows(2) {
            assert!(significant_bits(w[0]) <= significant_bits(w[1]));
        }
        assert!(s.iter().all(|&v| significant_bits(v) < significant_bits(x)));
        assert!(simpler(0.0).is_empty());
        assert_eq!(simpler(1.0), vec![0.0]);
    }
}

/// How `tetwalk shrink` shrinks a file's lines: the checks each shrink may make, the program outside
/// tetwalk the cases are shrunk for (with the contract it assumes, checked for each case's family), and
/// whether the file is to be rewritten with its lines shrunk.
pub(crate) struct ShrinkLines<'a> {
    /// Candidates one shrink may check.
    pub(crate) checks: usize,
    /// The program the cases are shrunk for, and its contract; `None`: each case's own method.
    pub(crate) outside: Option<(&'a Program, Contract)>,
    /// Whether the file is rewritten (a dump's lines are refused then).
    pub(crate) in_place: bool,
}

/// Every line of `text` (the file named `file`) shrunk as `how` says, blank lines kept: a found case
/// on the backend it was found on (or for the program outside), a `count --dump` line as its diverging
/// step. Each case's place and what became of it (shrunk, or left as it is and why) is given to `each`
/// and kept in `report`. The text with every shrunk case's line in place of its own; an error names
/// the line.
pub(crate) fn shrink_lines(
    file: &str,
    text: &str,
    how: &ShrinkLines,
    backends: &mut Backends,
    report: &mut ShrinkReport,
    mut each: impl FnMut(&str, Result<&CaseShrunk, &str>) -> std::io::Result<()>,
) -> Result<String, ShrinkLinesError> {
    let mut rewritten = String::new();
    for (n, line) in text.lines().enumerate() {
        let at = Place {
            file: file.to_string(),
            line: n + 1,
        };
        let place = |e: &dyn std::fmt::Display| format!("{} line {}: {e}", at.file, at.line);
        let fail = |e: &dyn std::fmt::Display| ShrinkLinesError::Line(place(e));
        if line.trim().is_empty() {
            rewritten += line;
            rewritten += "\n";
            continue;
        }
        let obj = crate::cases::object(line).map_err(|e| fail(&e))?;
        let dump = obj.contains_key("pixel") && obj.contains_key("scene");
        if dump && how.in_place {
            return Err(fail(
                &"a count's dump is not rewritten: leave out --in-place (its shrunk cases are printed)",
            ));
        }
        let result = if let Some((x, contract)) = &how.outside {
            if dump {
                return Err(fail(
                    &"--answerer shrinks cases (one per line), not a count's dump",
                ));
            }
            crate::with_family!(owner(&obj), F => Found::<F>::from_object(obj)
            .and_then(|found| {
                contract.check_for::<F>().map_err(|why| FoundError::Field {
                    field: "contract",
                    why,
                })?;
                shrink_case_outside::<F>(&found, x, contract, &at, how.checks)
            }))
        } else if dump {
            shrink_dump_line(obj, &at, backends, how.checks)
        } else {
            crate::with_family!(owner(&obj), F => Found::<F>::from_object(obj)
                .and_then(|found| shrink_case::<F>(&found, &at, backends, how.checks)))
        }
        .map_err(|e| fail(&e))?;
        match result {
            Ok(done) => {
                each(&place(&"case"), Ok(&done))?;
                rewritten += &done.shrunk.to_string();
                report.cases.push(done);
            }
            Err(why) => {
                each(&place(&"case"), Err(&why))?;
                rewritten += line;
                report.left.push((at.clone(), why));
            }
        }
        rewritten += "\n";
    }
    Ok(rewritten)
}

/// Why [`shrink_lines`] stopped: a line (named) that could not be read or shrunk, or what `each`
/// returned.
#[derive(Debug, thiserror::Error)]
pub(crate) enum ShrinkLinesError {
    /// A line that could not be read or shrunk, named with its file and number.
    #[error("{0}")]
    Line(String),
    /// What `each` returned (its source, so that a closed standard output is told apart).
    #[error("{0}")]
    Write(#[from] std::io::Error),
}
