//! Stress runs, for every family: each stress row's cases with their exact truths, every method's
//! answers on a backend, judged and tallied; campaigns (rounds of new cases, the tallies summed), the
//! labellings (`--relabel all`), and the backends compared.

use crate::backend::{Backend, BackendError, BackendKind, CPUS, Ran};
use crate::engine::answerer::Answerer;
use crate::engine::found::Failure;
use crate::exact::SignCounts;
use crate::family::contract::{Contract, cases_within};
use crate::family::{Family, Scale, Summed, Verdict};
use crate::registry::Named;

/// Settings of a stress run: cases per row, the seed, where the methods run, and the family's rows.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct StressSettings<F: Family> {
    pub cases: usize,
    #[serde(flatten)]
    pub rows: F::Rows,
    pub seed: u64,
    pub backend: Ran,
    /// Every case at this power-of-two scale (`--scale`); 1 unless asked.
    #[serde(skip_serializing_if = "Scale::is_one")]
    pub scale: Scale,
    /// What the kernel judged assumes: every case holds it ([`crate::family::contract`]).
    #[serde(skip_serializing_if = "Contract::is_default")]
    pub contract: Contract,
}

/// One method's counts on one row.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct StressTally<F: Family> {
    pub method: String,
    #[serde(flatten)]
    pub counts: F::Tally,
}

/// One row: what it is, what it reports of its cases, and each method's counts.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct RowReport<F: Family> {
    #[serde(flatten)]
    pub row: F::Row,
    #[serde(flatten)]
    pub facts: F::RowFacts,
    /// Per method, in the order of [`StressReport::methods`].
    pub tallies: Vec<StressTally<F>>,
}

/// One row and method under every labelling ([`Family::LABELLINGS`], the cases' own first).
#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct Relabelled<F: Family> {
    #[serde(flatten)]
    pub(crate) row: F::Row,
    pub(crate) method: String,
    /// Wrong answers under each labelling.
    pub(crate) wrong: Vec<u64>,
}

#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct StressReport<F: Family> {
    pub(crate) settings: StressSettings<F>,
    /// Rounds of `settings.cases` cases per row, seeds `seed`, `seed + 1`, … (one unless a campaign).
    pub rounds: u64,
    pub(crate) methods: Vec<String>,
    pub rows: Vec<RowReport<F>>,
    /// Signs the oracle decided in its f64 filter and exactly, making the cases' truths (none where
    /// the family's oracle decides with rationals alone).
    #[serde(skip_serializing_if = "is_zero")]
    pub(crate) oracle: SignCounts,
    /// With `--relabel all`: per row and method, wrong answers under each labelling.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) relabelled: Option<Vec<Relabelled<F>>>,
}

/// Whether no sign was counted.
fn is_zero(c: &SignCounts) -> bool {
    *c == SignCounts::default()
}

/// Who answers a row's cases: a registered method on the run's backend, or a user's program outside
/// tetwalk ([`Answerer`]).
pub enum Who<'a, F: Family> {
    Method(&'a F::Method),
    Outside(&'a Answerer),
}

impl<F: Family> Clone for Who<'_, F> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<F: Family> Copy for Who<'_, F> {}

impl<'a, F: Family> Who<'a, F> {
    /// Every one of `methods`.
    pub fn methods(methods: &[&'a F::Method]) -> Vec<Who<'a, F>> {
        methods.iter().map(|&m| Who::Method(m)).collect()
    }

    /// Its name in reports and found cases.
    pub fn name(&self) -> &str {
        match self {
            Who::Method(m) => m.name(),
            Who::Outside(a) => &a.name,
        }
    }

    /// Its answers to `cases` (a method's on `backend`).
    pub(crate) fn answers(
        &self,
        backend: &Backend,
        cases: &[F::Case],
    ) -> Result<Vec<F::Answer>, BackendError> {
        match self {
            Who::Method(m) => F::answers(backend, m, cases),
            Who::Outside(a) => a
                .answers::<F>(cases)
                .map_err(|e| BackendError::Outside(e.to_string())),
        }
    }

    /// A wrong answer of its where it ran, as a found case records it.
    pub(crate) fn failure(&self, backend: &Backend, answer: F::Answer) -> Failure<F> {
        match self {
            Who::Method(m) => Failure::<F>::of(m, backend, answer),
            Who::Outside(a) => Failure {
                method: a.name.clone(),
                backend: crate::choice::BackendKind::Outside,
                adapter: None,
                answer,
            },
        }
    }
}

/// A wrong answer a run shows: its row, who answered and where, the case and the answer.
pub struct Wrong<'a, F: Family> {
    pub(crate) row: &'a F::Row,
    pub who: Who<'a, F>,
    pub(crate) on: &'a Backend,
    pub(crate) case: &'a F::Case,
    pub(crate) answer: &'a F::Answer,
}

/// What [`run`] shows of each wrong answer.
pub(crate) type OnWrong<'a, F> = dyn FnMut(Wrong<F>) + 'a;

/// `F::case` with the oracle's stage counts on this thread.
fn counted<T>(f: impl FnOnce() -> T) -> (T, SignCounts) {
    let before = crate::exact::counts();
    let out = f();
    (out, crate::exact::counts().since(before))
}

/// Cases of family `F` with their exact truths.
pub(crate) type Judged<F> = Vec<(<F as Family>::Case, <F as Family>::Truth)>;

/// A row's cases with their truths, and the oracle's counts making them ([`cases_of`] with the
/// settings' rows, seed, cases, scale and contract).
pub fn row_cases<F: Family>(s: &StressSettings<F>, row: F::Row) -> (Judged<F>, SignCounts) {
    cases_of::<F>(&s.rows, row, s.seed, s.cases, s.scale, &s.contract)
}

/// The first `count` cases of row `row` under `rows` that hold `contract`, each at `scale`, with
/// their truths, and the oracle's counts making them (the cases `stress` judges there, and
/// `gen-cases` writes); case `i` a pure function of the seed, the row and `i`, generated in
/// parallel.
pub(crate) fn cases_of<F: Family>(
    rows: &F::Rows,
    row: F::Row,
    seed: u64,
    count: usize,
    scale: Scale,
    contract: &Contract,
) -> (Judged<F>, SignCounts) {
    let made = std::sync::Mutex::new(SignCounts::default());
    let cases = cases_within::<F>(contract, count, |i| {
        let (c, k) = counted(|| {
            let made = F::case(rows, row, seed, i)?;
            if scale.is_one() {
                return Some(made);
            }
            // At another scale: the case scaled, judged again as it now is.
            crate::family::scaled_judged::<F>(&made.0, scale)
        });
        if let Ok(mut m) = made.lock() {
            *m += k;
        }
        c
    });
    let counts = made.into_inner().unwrap_or_default();
    (cases, counts)
}

/// [`cases_of`]'s cases, every one of the first `count` (what `gen-cases` writes); an error saying how
/// many can be made where some cannot.
pub(crate) fn every_case_of<F: Family>(
    rows: &F::Rows,
    row: F::Row,
    seed: u64,
    count: usize,
    scale: Scale,
    contract: &Contract,
) -> Result<Judged<F>, String> {
    let (made, _) = cases_of::<F>(rows, row, seed, count, scale, contract);
    if made.len() < count {
        return Err(format!(
            "only {} of the row's first {count} cases can be made at scale {scale}{} (the others round there, or the oracle refuses them; stress judges the same {}): nothing was written",
            made.len(),
            if contract.is_default() {
                String::new()
            } else {
                format!(" within the contract ({})", contract.describe())
            },
            made.len()
        ));
    }
    Ok(made)
}

/// Each method's answers to `cases` on `backend`, as the methods see them under the rows' labelling
/// and mapped back.
fn answered<F: Family>(
    s: &StressSettings<F>,
    m: Who<F>,
    backend: &Backend,
    cases: &[(F::Case, F::Truth)],
) -> Result<Vec<F::Answer>, BackendError> {
    let seen: Vec<F::Case> = cases.iter().map(|(c, _)| F::relabel(&s.rows, c)).collect();
    Ok(m.answers(backend, &seen)?
        .into_iter()
        .map(|a| F::unrelabel(&s.rows, a))
        .collect())
}

/// `m`'s answers to a row's cases on `backend`, judged and tallied; `each` sees every answer with its
/// verdict. The stress table and the conformance kit judge with this.
pub(crate) fn judge<F: Family>(
    s: &StressSettings<F>,
    m: Who<F>,
    backend: &Backend,
    cases: &[(F::Case, F::Truth)],
    mut each: impl FnMut(&F::Case, &F::Truth, &F::Answer, Verdict),
) -> Result<F::Tally, BackendError> {
    let mut t = F::Tally::default();
    for ((c, x), a) in cases.iter().zip(answered(s, m, backend, cases)?) {
        F::tally(&mut t, c, x, &a);
        each(c, x, &a, F::verdict(c, x, &a));
    }
    Ok(t)
}

/// Every method on `s.cases` cases of every row on `backend`, each answer judged exactly; `tick` is
/// told how many cases each row held, and `wrong` sees every wrong answer.
pub fn run<F: Family>(
    s: &StressSettings<F>,
    methods: &[Who<F>],
    backend: &Backend,
    tick: &(dyn Fn(u64) + Sync),
    wrong: &mut OnWrong<F>,
) -> Result<StressReport<F>, BackendError> {
    let mut rows = Vec::new();
    let mut oracle = SignCounts::default();
    for row in F::rows(&s.rows) {
        let (cases, counts) = row_cases(s, row);
        oracle += counts;
        let mut tallies = Vec::new();
        for &m in methods {
            let on = match m {
                Who::Method(m) => backend.for_method(m),
                Who::Outside(_) => backend,
            };
            let counts = judge(s, m, backend, &cases, |case, _, answer, v| {
                if let Verdict::Wrong(_) = v {
                    wrong(Wrong {
                        row: &row,
                        who: m,
                        on,
                        case,
                        answer,
                    });
                }
            })?;
            tallies.push(StressTally {
                method: m.name().to_string(),
                counts,
            });
        }
        tick(s.cases as u64);
        rows.push(RowReport {
            row,
            facts: F::row_facts(&cases),
            tallies,
        });
    }
    Ok(StressReport {
        settings: s.clone(),
        rounds: 1,
        methods: methods.iter().map(|m| m.name().to_string()).collect(),
        rows,
        oracle,
        relabelled: None,
    })
}

impl<F: Family> StressReport<F> {
    /// Another round's report of the same run added to this one.
    pub(crate) fn add(&mut self, more: &StressReport<F>) {
        for (a, b) in self.rows.iter_mut().zip(&more.rows) {
            a.facts.add(&b.facts);
            for (x, y) in a.tallies.iter_mut().zip(&b.tallies) {
                x.counts.add(&y.counts);
            }
        }
        self.oracle += more.oracle;
        self.rounds += more.rounds;
    }

    /// Run again under every other labelling ([`Family::LABELLINGS`]; the cases' own is this report)
    /// and keep each row's and method's wrong answers under all of them.
    pub(crate) fn relabel_all(
        &mut self,
        methods: &[Who<F>],
        backend: &Backend,
    ) -> Result<(), BackendError> {
        let wrong = |r: &StressReport<F>| -> Vec<u64> {
            r.rows
                .iter()
                .flat_map(|row| row.tallies.iter().map(|t| F::wrong(&t.counts)))
                .collect()
        };
        let all = super::under_labellings(wrong(self), F::LABELLINGS, |k| {
            let s = StressSettings {
                rows: F::relabelled(&self.settings.rows, k),
                ..self.settings.clone()
            };
            Ok::<_, BackendError>(wrong(&run(&s, methods, backend, &|_| {}, &mut |_| {})?))
        })?;
        let mut all = all.into_iter();
        self.relabelled = Some(
            self.rows
                .iter()
                .flat_map(|row| row.tallies.iter().map(move |t| (row.row, t.method.clone())))
                .map(|(row, method)| Relabelled {
                    row,
                    method,
                    wrong: all.next().unwrap_or_default(),
                })
                .collect(),
        );
        Ok(())
    }
}

/// A differential campaign: rounds of [`run`], round `k` with seed `seed + k`, until `seconds` have
/// passed (one round at least); the tallies summed over rounds.
pub fn campaign<F: Family>(
    s: &StressSettings<F>,
    methods: &[Who<F>],
    backend: &Backend,
    seconds: f64,
    tick: &(dyn Fn(u64) + Sync),
    wrong: &mut OnWrong<F>,
) -> Result<StressReport<F>, BackendError> {
    let t0 = std::time::Instant::now();
    let mut total = run(s, methods, backend, tick, wrong)?;
    while t0.elapsed().as_secs_f64() < seconds {
        let round = StressSettings {
            seed: s.seed.wrapping_add(total.rounds),
            ..s.clone()
        };
        total.add(&run(&round, methods, backend, tick, wrong)?);
    }
    Ok(total)
}

/// Cases one method answers differently on the GPU than on each CPU backend (one per arithmetic
/// model, in [`crate::methods::Model::ALL`]'s order): which model the GPU computes as.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Pairs {
    pub(crate) method: String,
    /// Per CPU backend, by name: the cases the GPU answers otherwise.
    #[serde(serialize_with = "by_name")]
    pub gpu_vs: Vec<(BackendKind, u64)>,
}

/// `[(kind, n)]` as `{"name": n}`, in order.
fn by_name<S: serde::Serializer>(pairs: &[(BackendKind, u64)], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut map = s.serialize_map(Some(pairs.len()))?;
    for (k, n) in pairs {
        map.serialize_entry(crate::choice::Choice::name(*k), n)?;
    }
    map.end()
}

/// One row of the comparison: per method, how many of the row's cases each pair of backends answers
/// differently.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct CompareRow<F: Family> {
    #[serde(flatten)]
    pub(crate) row: F::Row,
    pub cases: usize,
    pub methods: Vec<Pairs>,
}

/// How often two backends answer differently, per row and method: cpu vs cpu-fma, cpu vs gpu, cpu-fma
/// vs gpu (the comparison mode).
#[derive(Clone, Debug, serde::Serialize)]
#[serde(bound = "")]
pub struct Disagreements<F: Family> {
    pub methods: Vec<String>,
    pub rows: Vec<CompareRow<F>>,
    pub(crate) gpu: Ran,
}

/// The same generated cases on the GPU and on the CPU in every arithmetic model, every method but the
/// reference.
pub fn compare<F: Family>(
    s: &StressSettings<F>,
    methods: &[&F::Method],
    gpu: &Backend,
) -> Result<Disagreements<F>, BackendError> {
    let judged: Vec<&F::Method> = methods
        .iter()
        .copied()
        .filter(|m| !m.is_reference())
        .collect();
    let mut rows = Vec::new();
    for row in F::rows(&s.rows) {
        let cases: Vec<F::Case> = row_cases(s, row).0.into_iter().map(|(c, _)| c).collect();
        let mut per = Vec::new();
        for &m in &judged {
            let on_gpu = F::answers(gpu, m, &cases)?;
            let gpu_vs = CPUS
                .iter()
                .map(|cpu| {
                    let a = F::answers(cpu, m, &cases)?;
                    let differ = a.iter().zip(&on_gpu).filter(|(p, q)| p != q).count() as u64;
                    Ok((cpu.kind(), differ))
                })
                .collect::<Result<_, BackendError>>()?;
            per.push(Pairs {
                method: m.name().to_string(),
                gpu_vs,
            });
        }
        rows.push(CompareRow {
            row,
            cases: cases.len(),
            methods: per,
        });
    }
    Ok(Disagreements {
        methods: judged.iter().map(|m| m.name().to_string()).collect(),
        rows,
        gpu: gpu.ran(),
    })
}
