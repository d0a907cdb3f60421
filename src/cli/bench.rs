//! `tetwalk bench`: walk speed per method and backend on a scene's primary rays.

use super::Status;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Which family: `exit-face` (walks) or `triangle` (seed 004 Figure 5's measure: every primary
    /// ray of one view against every triangle, one thread, packets of 1x1 to 8x8, speedups over
    /// mt-precomputed on single rays).
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(FAMILIES), default_value = "exit-face")]
    pub(crate) family: String,
    #[command(flatten)]
    pub(crate) scene: super::SceneArg,
    /// Viewpoints on a sphere around the model (`--family triangle` times the first inside the mesh).
    #[arg(long, allow_negative_numbers = true, default_value_t = 16)]
    pub(crate) views: usize,
    /// Image size, WxH [default: 1024x1024, or 256x256 (seed 004's) with --family triangle].
    #[arg(long)]
    pub(crate) size: Option<String>,
    /// Methods to time (comma-separated, or all); on a GPU, those with a GPU version.
    #[arg(long, default_value = "all")]
    pub(crate) methods: String,
    /// Backends, comma-separated (`cpu`, `cpu-fma`, `gpu`), timed on the same rays in one run.
    #[arg(long, value_parser = super::choice::<crate::choice::BackendKind>(), value_delimiter = ',', default_value = "cpu")]
    pub(crate) backend: Vec<crate::choice::BackendKind>,
    /// Rays handed to a backend at once (whole views; one 1024² view by default: larger batches were
    /// slower end to end on an H200, their host buffers being fresh memory each time).
    #[arg(long, default_value_t = 1 << 20)]
    pub(crate) batch: usize,
    /// Also time the walks over seed 003's layouts (Tet32, Tet20, Tet16) of the methods that have them.
    #[arg(long)]
    pub(crate) layouts: bool,
    /// Put the mesh in Hilbert order first (seed 003 §3).
    #[arg(long)]
    pub(crate) hilbert: bool,
    /// Seed of the viewpoints' rotation.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Time each batch this many times: each timing is a sample, and rows give the median and range.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    pub(crate) repeat: usize,
    /// A report of an earlier run (its `--json`): each row's median is compared with the same row's
    /// there, as criterion compares (faster or slower where it leaves that row's range).
    #[arg(long)]
    pub(crate) baseline: Option<PathBuf>,
    /// Also write the report as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        self.scene
            .files(super::Files::default())
            .input("--baseline", self.baseline.as_deref())
            .output("--json", self.json.as_deref())
    }
}

crate::families!(__bench_families);

/// `bench --family`'s values and what each runs (its family folder's `cli::bench`), from the
/// families' list.
#[doc(hidden)]
#[macro_export]
macro_rules! __bench_families {
    ([] { $($line:tt)* } counted { $($c:tt)* } kit { $($k:tt)* } commands { $($cm:tt)* } fuzz { $($f:tt)* } bench { $($m:ident: $n:literal),* } $($rest:tt)*) => {
        /// `bench --family`'s values.
        const FAMILIES: &[&str] = &[$($n),*];

        pub(crate) fn run(a: Args) -> Status {
            $(
                if a.family == $n {
                    return $crate::family::$m::cli::bench(a);
                }
            )*
            Err(format!("--family {}: no family is timed so", a.family).into())
        }
    };
}
