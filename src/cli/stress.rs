//! `tetwalk stress`: the failure table over tetrahedron families and ray kinds.

use super::{BackendArg, JsonOut, Outcome, choice};
use crate::backend::BackendKind;
use crate::choice::Choice;
use crate::registry::parse_list;
use crate::report::stress::{self, Row, Settings};
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
    };
    if a.compare {
        let d = stress::compare(&settings, &methods, &backend)?;
        print!("{}", d.markdown());
        out.finish(&d)?;
        return Ok(ExitCode::SUCCESS);
    }
    let bar = super::progress((settings.cases * settings.rows.len()) as u64, "cases");
    let report = stress::run(&settings, &methods, &backend, &|n| bar.inc(n))?;
    bar.finish_and_clear();
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}
