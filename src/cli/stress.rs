//! `tetwalk stress`: the failure table over tetrahedron families and ray kinds.

use super::{BackendArg, JsonOut, Outcome, choice};
use crate::backend::{Backend, BackendKind};
use crate::cases::{Case, Subject};
use crate::choice::Choice;
use crate::found::{Answer, Failure, Record};
use crate::registry::Method;
use crate::registry::parse_list;
use crate::report::stress::{self, Row, Settings};
use std::collections::HashMap;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Cases per row.
    #[arg(long, allow_negative_numbers = true, default_value_t = 100_000)]
    cases: usize,
    /// Rows (comma-separated) [default: all of them].
    #[arg(long, value_parser = choice::<Row>(), value_delimiter = ',')]
    families: Vec<Row>,
    /// Methods (comma-separated, or all).
    #[arg(long, default_value = "all")]
    methods: String,
    /// Seed of the generated cases.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    backend: BackendArg,
    /// Instead of judging, count how often cpu, cpu-fma and gpu answer differently (needs a GPU).
    #[arg(long)]
    compare: bool,
    /// Flatness of the degenerate families, in (0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1e-3)]
    flatness: f32,
    /// Largest ulp offset of the near-edge and near-vertex rows.
    #[arg(long, allow_negative_numbers = true, default_value_t = 4)]
    ulps: i32,
    /// `all`: run again under each of the 12 orientation-preserving relabellings of every case's
    /// tetrahedron and give each row's and method's wrong answers with the cases' own labelling beside
    /// their min / median / max.
    #[arg(long, value_parser = ["all"])]
    relabel: Option<String>,
    /// A differential campaign: rounds of new cases (seed, seed + 1, …) until this many seconds have
    /// passed, every new failure filed under `--found`.
    #[arg(long, allow_negative_numbers = true)]
    seconds: Option<f64>,
    /// Where a campaign files its failures as found cases (one folder per method), replayed by
    /// `cargo test`.
    #[arg(long, default_value = "corpora/found")]
    found: PathBuf,
    /// A campaign files at most this many new failures per method, row and kind of wrong answer.
    #[arg(long, default_value_t = 3)]
    keep: usize,
    /// Also write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(a: Args) -> Outcome {
    if !(a.flatness > 0.0 && a.flatness <= 1.0) {
        return Err(format!("--flatness {} is not in (0, 1]", a.flatness).into());
    }
    if a.ulps < 1 {
        return Err(format!("--ulps {} is not a number of ulps (1 or more)", a.ulps).into());
    }
    let methods = parse_list(&a.methods)?;
    if a.cases == 0 {
        return Err("--cases 0: a stress run needs at least one case per row".into());
    }
    // A row's cases, their classifications and one method's answers are held at once.
    super::fits(&format!("--cases {}", a.cases), a.cases as u128 * 112)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let backend = if a.compare {
        if a.backend.backend != BackendKind::Cpu {
            return Err("--compare runs cpu, cpu-fma and gpu itself; leave out --backend".into());
        }
        BackendArg {
            backend: BackendKind::Gpu,
            ..a.backend
        }
        .open()?
    } else {
        a.backend.open()?
    };
    let settings = Settings {
        cases: a.cases,
        rows: if a.families.is_empty() {
            Row::ALL.to_vec()
        } else {
            a.families
        },
        seed: a.seed,
        backend: backend.describe(),
        flatness: a.flatness,
        ulps: a.ulps,
        relabel: crate::tet::EVEN_PERMUTATIONS[0],
    };
    if a.relabel.is_some() && (a.compare || a.seconds.is_some()) {
        return Err("--relabel reruns one stress table; leave out --compare and --seconds".into());
    }
    if a.compare {
        let d = stress::compare(&settings, &methods, &backend)?;
        print!("{}", d.markdown());
        out.finish(&d)?;
        return Ok(ExitCode::SUCCESS);
    }
    let Some(seconds) = a.seconds else {
        let bar = super::progress((settings.cases * settings.rows.len()) as u64, "cases");
        let mut report = stress::run(
            &settings,
            &methods,
            &backend,
            &|n| bar.inc(n),
            &mut |_, _, _, _| {},
        )?;
        if a.relabel.is_some() {
            report.relabel_all(&methods, &backend)?;
        }
        bar.finish_and_clear();
        print!("{}", report.markdown());
        out.finish(&report)?;
        return Ok(ExitCode::SUCCESS);
    };
    if !(seconds.is_finite() && seconds >= 0.0) {
        return Err(format!("--seconds {seconds} is not a number of seconds").into());
    }
    let mut filing = Filing {
        dir: a.found,
        keep: a.keep,
        kept: HashMap::new(),
        seen: 0,
        filed: Vec::new(),
        error: None,
    };
    let report = stress::campaign(
        &settings,
        &methods,
        &backend,
        seconds,
        &|_| {},
        &mut |row, m, case, face| filing.file(row, m, &backend, case, face),
    )?;
    if let Some(e) = filing.error {
        return Err(e.into());
    }
    print!("{}", report.markdown());
    println!(
        "\n{} wrong answers in {} rounds; {} new found cases filed under {} (at most {} per method, row and kind):",
        filing.seen,
        report.rounds,
        filing.filed.len(),
        filing.dir.display(),
        filing.keep
    );
    for f in &filing.filed {
        println!("  {}", f.display());
    }
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}

/// A campaign's filing of failures as found cases: new ones only, at most `keep` per method, row and
/// kind (each with the same case for the robust methods that fail on it too); the first error stops
/// filing and is reported.
struct Filing {
    dir: PathBuf,
    keep: usize,
    kept: HashMap<(String, Row, &'static str), usize>,
    seen: u64,
    filed: Vec<PathBuf>,
    error: Option<String>,
}

impl Filing {
    fn file(&mut self, row: Row, m: &Method, backend: &Backend, case: &Case, face: Option<usize>) {
        self.seen += 1;
        let on = backend.for_method(m);
        let record = Record {
            subject: Subject::Exit(*case),
            failure: Some(Failure {
                method: m.name.to_string(),
                backend: on.kind(),
                adapter: on.adapter(),
                answer: Answer::Face(face.map(|f| f as u8)),
            }),
        };
        let kind = record.failure.as_ref().map_or("", |f| f.kind().wrong_key());
        let key = (m.name.to_string(), row, kind);
        let n = self.kept.get(&key).copied().unwrap_or(0);
        if n >= self.keep || self.error.is_some() || self.path(row, &record).exists() {
            return;
        }
        self.kept.insert(key, n + 1);
        // The same case for every method that claims robustness and fails on it too (on the CPU):
        // a failure of a claim is a finding of its own, as `fuzz-import` files it.
        let records = match record.with_robust_failures() {
            Ok(r) => r,
            Err(e) => {
                self.error = Some(e.to_string());
                return;
            }
        };
        for r in records {
            let file = self.path(row, &r);
            if file.exists() {
                continue;
            }
            let written = file
                .parent()
                .map_or(Ok(()), std::fs::create_dir_all)
                .and_then(|_| std::fs::write(&file, r.to_json() + "\n"));
            if let Err(e) = written {
                self.error = Some(format!("{}: {e}", file.display()));
                return;
            }
            self.filed.push(file);
        }
    }

    /// Where a found case is filed: by method, row, kind and an FNV-1a hash of its line, so that the
    /// same failure always files under the same name, once.
    fn path(&self, row: Row, r: &Record) -> PathBuf {
        let line = r.to_json();
        let hash = line.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
        });
        let (method, kind) = r
            .failure
            .as_ref()
            .map_or(("", ""), |f| (f.method.as_str(), f.kind().wrong_key()));
        self.dir
            .join(method)
            .join(format!("stress-{}-{kind}-{hash:016x}.json", row.name()))
    }
}
