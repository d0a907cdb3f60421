//! `tetwalk stress`: the failure table over tetrahedron families and ray kinds.

use crate::methods::parse_list;
use crate::report::stress::{self, Row, Settings};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Cases per row.
    #[arg(long, default_value_t = 100_000)]
    cases: usize,
    /// Rows (comma-separated); all by default.
    #[arg(long, value_enum, value_delimiter = ',')]
    families: Vec<Row>,
    #[arg(long, default_value = "all")]
    methods: String,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[arg(long)]
    fma: bool,
    /// Where the methods run: `cpu` (with `--fma`, as a GPU compiles them) or `gpu`.
    #[arg(long, value_parser = ["cpu", "gpu"], default_value = "cpu")]
    backend: String,
    /// Instead of judging, count how often cpu, cpu-fma and gpu answer differently (needs a GPU).
    #[arg(long)]
    compare: bool,
    /// Flatness of the degenerate families, in (0, 1].
    #[arg(long, default_value_t = 1e-3)]
    flatness: f32,
    /// Largest ulp offset of the near-edge and near-vertex rows.
    #[arg(long, default_value_t = 4)]
    ulps: i32,
    /// Also write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(a: Args) -> Result<ExitCode, String> {
    if !(a.flatness > 0.0 && a.flatness <= 1.0) {
        return Err(format!("--flatness {} is not in (0, 1]", a.flatness));
    }
    let methods = parse_list(&a.methods)?;
    let settings = Settings {
        cases: a.cases,
        rows: if a.families.is_empty() {
            Row::ALL.to_vec()
        } else {
            a.families
        },
        seed: a.seed,
        backend: String::new(),
        flatness: a.flatness,
        ulps: a.ulps.max(1),
    };
    let gpu = if a.backend == "gpu" || a.compare {
        Some(crate::gpu::Gpu::new().map_err(|e| e.to_string())?)
    } else {
        None
    };
    if let (true, Some(g)) = (a.compare, &gpu) {
        let d = stress::compare(&settings, &methods, g)?;
        print!("{}", d.markdown());
        super::write_json(a.json.as_deref(), &d)?;
        return Ok(ExitCode::SUCCESS);
    }
    let (answers, backend) = match &gpu {
        Some(g) => (stress::Answers::Gpu(g), format!("gpu: {}", g.describe())),
        None => (
            stress::Answers::Cpu { fma: a.fma },
            if a.fma {
                "cpu-fma (as a GPU compiles it)".into()
            } else {
                "cpu".into()
            },
        ),
    };
    let settings = Settings {
        backend,
        ..settings
    };
    let bar = super::progress((settings.cases * settings.rows.len()) as u64, "cases");
    let report = stress::run(&settings, &methods, &answers, &bar)?;
    bar.finish_and_clear();
    print!("{}", report.markdown());
    super::write_json(a.json.as_deref(), &report)?;
    Ok(ExitCode::SUCCESS)
}
