//! `tetwalk gen-cases`: generated cases as JSON Lines — the arguments every family shares, the
//! checks and the writing; each family's flags and cases are in its folder (`cli::gen_cases`), and
//! the families that write are those of the families' list's `gen_cases` section. A stress row's
//! cases are exactly those `tetwalk stress` judges for the same arguments and seed.

use super::{JsonOut, Status};
use crate::family::contract::Contract;
use crate::family::{Family, Scale};
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// In (0, 1]; smaller is flatter [default: 1 for tetrahedra, the stress rows' 0.001 with
    /// --shape].
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) flatness: Option<f32>,
    /// Largest offset of the near-* rays, in ulps of the case's largest coordinate (so a zero
    /// coordinate moves as far as the others).
    #[arg(long, allow_negative_numbers = true, default_value_t = 4)]
    pub(crate) ulps: i32,
    /// Cases to write (at most 100,000,000).
    #[arg(long, allow_negative_numbers = true, default_value_t = 100)]
    pub(crate) count: usize,
    /// Seed of the generator.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Every case at a power-of-two scale, as `stress --scale` takes it (`E`, or `E/D` for the
    /// direction at its own).
    #[arg(long, allow_hyphen_values = true, value_parser = Scale::parse, default_value = "0")]
    pub(crate) scale: Scale,
    #[command(flatten)]
    families: GenFlags,
    #[command(flatten)]
    contract: super::ContractArg,
    /// Also write what was generated (settings and count) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default().output("--json", self.json.as_deref())
    }
}

/// The stress row `row` of family `F` under `rows`: its first `count` cases (the cases `stress` judges
/// there), each at `scale`, written as `line` makes them (`None`: a case it leaves out, such as a ray
/// that misses every triangle under `--single`); an error, with nothing written, when some of them
/// cannot be made (the oracle refuses one, or it rounds at `scale`), each made to hold `contract`.
/// The number of lines written.
pub(crate) fn row<F: Family>(
    rows: &F::Rows,
    row: F::Row,
    a: &Args,
    contract: &Contract,
    line: impl Fn(&F::Case, &F::Truth) -> Option<serde_json::Map<String, serde_json::Value>> + Sync,
) -> Result<usize, super::Error> {
    // Every case made before a line is written: a short run writes nothing; they are held at once.
    super::fits(
        &format!("--count {}", a.count),
        a.count as u128 * F::BYTES_PER_CASE,
    )?;
    let made =
        crate::engine::stress::every_case_of::<F>(rows, row, a.seed, a.count, a.scale, contract)?;
    Ok(write_lines(made.iter().filter_map(|(c, x)| line(c, x)))?)
}

/// Each object on a line of standard output, as JSON Lines; how many were written.
pub(crate) fn write_lines(
    lines: impl Iterator<Item = serde_json::Map<String, serde_json::Value>>,
) -> std::io::Result<usize> {
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let mut written = 0;
    for obj in lines {
        writeln!(w, "{}", serde_json::Value::Object(obj))?;
        written += 1;
    }
    w.flush()?;
    Ok(written)
}

/// A run of `gen-cases` once its arguments are checked: the flatness (its default the family's),
/// the `--json` output and the contract, checked for the family written.
pub(crate) struct Start {
    pub(crate) flatness: f32,
    pub(crate) out: JsonOut,
    pub(crate) contract: Contract,
}

/// The shared arguments checked, with `flatness` the family's default, then the family's own
/// (`checks`); the `--json` output opened and the contract checked for family `F`.
pub(crate) fn start<F: Family>(
    a: &Args,
    flatness: f32,
    checks: impl FnOnce() -> Result<(), super::Error>,
) -> Result<Start, super::Error> {
    let flatness = a.flatness.unwrap_or(flatness);
    super::generator(flatness, a.ulps)?;
    if a.count > 100_000_000 {
        return Err(format!("--count {} is more than 100,000,000 cases", a.count).into());
    }
    checks()?;
    let out = JsonOut::new(a.json.as_deref())?;
    let contract = a.contract.contract::<F>()?;
    a.contract.at_scale(a.scale)?;
    Ok(Start {
        flatness,
        out,
        contract,
    })
}

/// Done: what was generated written as JSON (with `--json`).
pub(crate) fn generated(out: JsonOut, generated: &impl serde::Serialize) -> Status {
    out.done("", generated)
}

crate::families!(__gen_case_families);

/// `gen-cases`' families, from the families' list: each family's flags (its folder's
/// `cli::GenFlags`, a group apart from every other family's: flags of two families together are
/// refused), and the family that writes — the first whose flags ask for its cases
/// (`cli::gen_cases`), the last writing when none does.
#[doc(hidden)]
#[macro_export]
macro_rules! __gen_case_families {
    ([] { $($line:tt)* } counted { $($c:tt)* } kit { $($k:tt)* } commands { $($cm:tt)* } fuzz { $($f:tt)* } bench { $($b:tt)* } pictures { $($p:tt)* } gen_cases { $($m:ident),* } $($rest:tt)*) => {
        /// Every family's `gen-cases` flags.
        struct GenFlags {
            $($m: $crate::family::$m::cli::GenFlags,)*
        }

        impl clap::FromArgMatches for GenFlags {
            fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
                Ok(GenFlags {
                    $($m: clap::FromArgMatches::from_arg_matches(m)?,)*
                })
            }

            fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
                $(self.$m.update_from_arg_matches(m)?;)*
                Ok(())
            }
        }

        impl clap::Args for GenFlags {
            fn augment_args(cmd: clap::Command) -> clap::Command {
                $(let cmd = <$crate::family::$m::cli::GenFlags as clap::Args>::augment_args(cmd);)*
                apart(cmd, &[$(<$crate::family::$m::cli::GenFlags as clap::Args>::group_id()),*])
            }

            fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
                $(let cmd = <$crate::family::$m::cli::GenFlags as clap::Args>::augment_args_for_update(cmd);)*
                apart(cmd, &[$(<$crate::family::$m::cli::GenFlags as clap::Args>::group_id()),*])
            }
        }

        pub(crate) fn run(a: Args) -> Status {
            $(
                if let Some(done) = $crate::family::$m::cli::gen_cases(&a, &a.families.$m) {
                    return done;
                }
            )*
            unreachable!("the last family of the list's gen_cases writes when no other does")
        }
    };
}

/// Each family's flags (its group of `groups`) set apart: a flag of one given with a flag of another
/// is refused, the error naming both.
fn apart(mut cmd: clap::Command, groups: &[Option<clap::Id>]) -> clap::Command {
    let members: Vec<Vec<clap::Id>> = groups
        .iter()
        .flatten()
        .map(|g| {
            cmd.get_groups()
                .find(|grp| grp.get_id() == g)
                .map(|grp| grp.get_args().cloned().collect())
                .unwrap_or_default()
        })
        .collect();
    for (k, own) in members.iter().enumerate() {
        let others: Vec<clap::Id> = members
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != k)
            .flat_map(|(_, m)| m.iter().cloned())
            .collect();
        for arg in own {
            cmd = cmd.mut_arg(arg.as_str(), |a| a.conflicts_with_all(others.clone()));
        }
    }
    cmd
}
