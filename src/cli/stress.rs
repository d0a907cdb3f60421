//! `tetwalk stress`: the failure table over tetrahedron families and ray kinds.

use super::{BackendArg, FailArg, JsonOut, Outcome, WgslArg, choice};
use crate::backend::{Backend, BackendKind};
use crate::cases::{Case, Subject};
use crate::choice::Choice;
use crate::found::{Answer, Failure, Record};
use crate::registry::Method;
use crate::registry::{TriangleMethod, parse_triangle_list};
use crate::registry::{parse_list, parse_octree_list};
use crate::report::octree as cell_report;
use crate::report::standing::{Standings, summed};
use crate::report::stress::{self, Row, Settings};
use crate::report::triangle::{self as tri, StressSettings};
use crate::scenes::cells;
use crate::scenes::closed::{Aim, Place, Shape};
use std::collections::HashMap;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Which family of methods: `exit-face` (tetrahedra, seeds 000 and 003), `triangle` (closed
    /// triangle meshes, seed 004: leaks, double hits, wrong first hits) or `octree` (octree cells,
    /// seed 001: wrong exit faces and quarters).
    #[arg(long, value_parser = ["exit-face", "triangle", "octree"], default_value = "exit-face")]
    family: String,
    /// Cases per row [default: 100000 for exit-face, 2000 for triangle].
    #[arg(long, allow_negative_numbers = true)]
    cases: Option<i64>,
    /// Rows (comma-separated) [default: all of them]; exit-face only.
    #[arg(long, value_parser = choice::<Row>(), value_delimiter = ',')]
    families: Vec<Row>,
    /// Triangle rows: closed mesh shapes (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<Shape>(), value_delimiter = ',')]
    shapes: Vec<Shape>,
    /// Triangle rows: where rays are aimed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<Aim>(), value_delimiter = ',')]
    aims: Vec<Aim>,
    /// Octree rows: where rays leave the cell (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<cells::Aim>(), value_delimiter = ',')]
    cell_aims: Vec<cells::Aim>,
    /// Octree rows: where cells are placed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<cells::Place>(), value_delimiter = ',')]
    cell_places: Vec<cells::Place>,
    /// Triangle rows: where meshes are placed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<Place>(), value_delimiter = ',')]
    places: Vec<Place>,
    /// Methods (comma-separated, or all).
    #[arg(long, default_value = "all")]
    methods: String,
    /// Seed of the generated cases.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    wgsl: WgslArg,
    #[command(flatten)]
    fail: FailArg,
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
    super::generator(a.flatness, a.ulps)?;
    if let Some(seconds) = a.seconds
        && !(seconds.is_finite() && seconds >= 0.0)
    {
        return Err(format!("--seconds {seconds} is not a number of seconds").into());
    }
    let triangle = a.family == "triangle";
    if a.wgsl.wgsl.is_some() && (triangle || a.seconds.is_some()) {
        return Err("--wgsl judges an exit-face function in a stress table (a campaign files found cases for tetwalk's own methods: fuzz a --wgsl function with TETWALK_FUZZ_WGSL)".into());
    }
    let cases = a.cases.unwrap_or(if triangle { 2_000 } else { 100_000 });
    if cases <= 0 {
        return Err(
            format!("--cases {cases}: a stress run needs at least one case per row").into(),
        );
    }
    let cases = cases as usize;
    if triangle {
        return run_triangle(a, cases);
    }
    if a.family == "octree" {
        return run_octree(a, cases);
    }
    if !(a.cell_aims.is_empty() && a.cell_places.is_empty()) {
        return Err("--cell-aims and --cell-places choose octree rows; add --family octree".into());
    }
    if !(a.shapes.is_empty() && a.aims.is_empty() && a.places.is_empty()) {
        return Err(
            "--shapes, --aims and --places choose triangle rows; add --family triangle".into(),
        );
    }
    if a.compare && a.fail.fail_on.is_some() {
        return Err("--compare counts disagreements between backends and judges nothing: leave out --fail-on".into());
    }
    if a.compare && a.wgsl.wgsl.is_some() {
        return Err("--compare runs every method on cpu and cpu-fma too; a --wgsl function runs on the GPU only".into());
    }
    // A row's cases, their classifications and one method's answers are held at once.
    super::fits(&format!("--cases {cases}"), cases as u128 * 112)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let (backend, methods) = if a.compare {
        if a.backend.backend != BackendKind::Cpu {
            return Err("--compare runs cpu, cpu-fma and gpu itself; leave out --backend".into());
        }
        let gpu = BackendArg {
            backend: BackendKind::Gpu,
            ..a.backend
        };
        (gpu.open()?, parse_list(&a.methods)?)
    } else {
        a.wgsl.open(a.backend, &a.methods)?
    };
    let settings = Settings {
        cases,
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
        return shown(out, a.fail, report.markdown(), &report);
    };
    let mut filing = Filing::new(a.found, a.keep);
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
    filing.print(report.rounds, "");
    out.finish(&report)?;
    Ok(a.fail.status("stress", &report.standings()))
}

/// A campaign's filing of failures as found cases: new ones only, at most `keep` per method, row and
/// kind (each with the same case for the robust methods that fail on it too); the first error stops
/// filing and is reported.
struct Filing {
    dir: PathBuf,
    keep: usize,
    kept: HashMap<(String, String, &'static str), usize>,
    seen: u64,
    filed: Vec<PathBuf>,
    error: Option<String>,
}

impl Filing {
    fn new(dir: PathBuf, keep: usize) -> Filing {
        Filing {
            dir,
            keep,
            kept: HashMap::new(),
            seen: 0,
            filed: Vec::new(),
            error: None,
        }
    }

    /// What the campaign filed, after its table.
    fn print(&self, rounds: u64, note: &str) {
        println!(
            "\n{} wrong answers in {rounds} rounds{note}; {} new found cases filed under {} (at most {} per method, row and kind):",
            self.seen,
            self.filed.len(),
            self.dir.display(),
            self.keep
        );
        for f in &self.filed {
            println!("  {}", f.display());
        }
    }

    /// A wrong exit face of `m` on `case`.
    fn file(&mut self, row: Row, m: &Method, backend: &Backend, case: &Case, face: Option<usize>) {
        let on = backend.for_method(m);
        self.file_record(
            row.name(),
            Record {
                subject: Subject::Exit(*case),
                failure: Some(Failure {
                    method: m.name.to_string(),
                    backend: on.kind(),
                    adapter: on.adapter(),
                    answer: Answer::Face(face.map(|f| f as u8)),
                }),
            },
        );
    }

    /// A found case of a row (named `row`).
    fn file_record(&mut self, row: &str, record: Record) {
        self.seen += 1;
        let kind = record.failure.as_ref().map_or("", |f| f.kind().wrong_key());
        let method = record
            .failure
            .as_ref()
            .map_or(String::new(), |f| f.method.clone());
        let key = (method, row.to_string(), kind);
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
                .and_then(|_| crate::staged::write(&file, (r.to_json() + "\n").as_bytes()));
            if let Err(e) = written {
                self.error = Some(format!("{}: {e}", file.display()));
                return;
            }
            self.filed.push(file);
        }
    }

    /// Where a found case is filed: by method, row, kind and an FNV-1a hash of its line, so that the
    /// same failure always files under the same name, once.
    fn path(&self, row: &str, r: &Record) -> PathBuf {
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
            .join(format!("stress-{row}-{kind}-{hash:016x}.json"))
    }
}

/// `stress --family triangle`: the closed-mesh rows, or a campaign over them with `--seconds`.
fn run_triangle(a: Args, cases: usize) -> Outcome {
    if a.compare || a.relabel.is_some() || !a.families.is_empty() {
        return Err("--compare, --relabel and --families are for --family exit-face".into());
    }
    let methods: Vec<&TriangleMethod> = parse_triangle_list(&a.methods)?;
    // A row's cases (about 1 KiB each with their exact answers) and one method's hits are held at once.
    super::fits(&format!("--cases {cases}"), cases as u128 * 2048)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let backend = a.backend.open()?;
    let mut settings = StressSettings {
        cases,
        shapes: or_all(a.shapes),
        aims: or_all(a.aims),
        places: or_all(a.places),
        seed: a.seed,
        backend: backend.describe(),
        flatness: a.flatness,
        ulps: a.ulps,
    };
    let rows = settings.shapes.len() * settings.aims.len() * settings.places.len();
    let Some(seconds) = a.seconds else {
        let bar = super::progress((cases * rows) as u64, "rays");
        let report = tri::stress(
            &settings,
            &methods,
            &backend,
            &|n| bar.inc(n),
            &mut |_, _| {},
        )?;
        bar.finish_and_clear();
        return shown(out, a.fail, report.markdown(), &report);
    };
    rounds(
        Filing::new(a.found, a.keep),
        seconds,
        out,
        a.fail,
        |round, filing| {
            settings.seed = a.seed + round;
            let r = tri::stress(
                &settings,
                &methods,
                &backend,
                &|_| {},
                &mut |row, record| filing.file_record(row, record),
            )?;
            Ok((r.markdown(), r))
        },
    )
}

/// A campaign over tables that are not summed: rounds of `round` (given its number, from 0) until
/// `seconds` have passed (one at least), filing failures; the last round's table is printed and
/// written with `--json`, the exit status from every round's standings.
fn rounds<R: serde::Serialize + Standings>(
    mut filing: Filing,
    seconds: f64,
    out: JsonOut,
    fail: FailArg,
    mut round: impl FnMut(u64, &mut Filing) -> Result<(String, R), super::Error>,
) -> Outcome {
    let t0 = std::time::Instant::now();
    let mut done = 0;
    let mut last = None;
    let mut standings = Vec::new();
    while done == 0 || t0.elapsed().as_secs_f64() < seconds {
        let (text, report) = round(done, &mut filing)?;
        standings = summed(standings.into_iter().chain(report.standings()));
        last = Some((text, report));
        done += 1;
    }
    if let Some(e) = filing.error {
        return Err(e.into());
    }
    let (text, report) = last.expect("one round at least");
    print!("{text}");
    filing.print(done, " (the table is the last round's)");
    out.finish(&report)?;
    Ok(fail.status("stress", &standings))
}

/// `stress --family octree`.
fn run_octree(a: Args, cases: usize) -> Outcome {
    if a.compare || a.relabel.is_some() || !a.families.is_empty() {
        return Err("--compare, --relabel and --families are for --family exit-face".into());
    }
    let methods = parse_octree_list(&a.methods)?;
    // A row's cases with their exact answers (about 200 bytes each) are held at once.
    super::fits(&format!("--cases {cases}"), cases as u128 * 256)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let backend = a.backend.open()?;
    let mut settings = cell_report::StressSettings {
        cases,
        aims: or_all(a.cell_aims),
        places: or_all(a.cell_places),
        seed: a.seed,
        backend: backend.describe(),
        ulps: a.ulps,
    };
    let Some(seconds) = a.seconds else {
        let report = cell_report::stress(&settings, &methods, &backend, &mut |_, _| {})?;
        return shown(out, a.fail, report.markdown(), &report);
    };
    rounds(
        Filing::new(a.found, a.keep),
        seconds,
        out,
        a.fail,
        |round, filing| {
            settings.seed = a.seed + round;
            let r = cell_report::stress(&settings, &methods, &backend, &mut |row, record| {
                filing.file_record(row, record)
            })?;
            Ok((r.markdown(), r))
        },
    )
}

/// The values given, or every value when none is.
fn or_all<T: Choice>(given: Vec<T>) -> Vec<T> {
    if given.is_empty() {
        T::ALL.to_vec()
    } else {
        given
    }
}

/// Print a report and write it with `--json`; the exit status `--fail-on` gives it.
fn shown(
    out: JsonOut,
    fail: FailArg,
    text: String,
    report: &(impl serde::Serialize + Standings),
) -> Outcome {
    print!("{text}");
    out.finish(report)?;
    Ok(fail.status("stress", &report.standings()))
}
