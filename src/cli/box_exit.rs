//! `tetwalk box-exit`: octree cell cases (seed 001), one JSON line per case and method: the exit face
//! and quarter each method answers, beside every exact exit face and quarter. Read as `exit` reads its
//! cases: line by line as they come.

use super::Status;
use super::answer::{Answered, Answering, Part, Takes, answer, standing};
use crate::family::{self, Kind, OctreeCells};
use crate::registry::Named;

#[derive(clap::Args)]
pub struct Args {
    /// A method name, a comma-separated list, or `all`.
    #[arg(long, default_value = "all")]
    method: String,
    #[command(flatten)]
    backend: super::BackendArg,
    #[command(flatten)]
    fail: super::FailArg,
    /// Also write a summary (lines, errors, per method right / wrong / lines not crossing the open
    /// box) as JSON here.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// JSON Lines file of cases `{"box": [[lx, ly, lz], [hx, hy, hz]], "org", "dir"}` (found cases
    /// too); standard input when absent.
    file: Option<std::path::PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .input("FILE", self.file.as_deref())
            .output("--json", self.json.as_deref())
    }
}

pub fn run(a: Args) -> Status {
    let methods = family::parse_list::<OctreeCells>(&a.method)?;
    let backend = a.backend.open()?;
    Answering {
        command: "box-exit",
        names: methods.iter().map(|m| m.name().to_string()).collect(),
        missed: true,
        leaks: false,
        backend: backend.describe(),
        file: a.file.as_deref(),
        input: None,
        json: a.json.as_deref(),
        fail: a.fail,
        standing: &standing::<OctreeCells>,
    }
    .run(
        |batch, summary| {
            let answered = Answered::Methods(&methods, &backend);
            let mut parts: [Box<dyn Takes>; 1] =
                [Box::new(Part::<OctreeCells>::new(answered, 0.0))];
            answer(batch, &mut parts, refuse, None, summary)
        },
        || Ok(()),
    )
}

/// `box-exit` answers octree cell cases only.
fn refuse(_: Kind) -> String {
    "not an octree cell case: box-exit answers {\"box\", \"org\", \"dir\"}".into()
}
