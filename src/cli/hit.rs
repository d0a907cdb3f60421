//! `tetwalk hit`: ray–triangle cases (seed 004's question), one JSON line per case and method, each
//! method's answer beside the exact one. Read as `exit` reads its cases: line by line as they come.

use super::Status;
use super::answer::{Answered, Answering, Part, Takes, answer, standing};
use crate::family::{self, Kind, Triangle};
use crate::registry::Named;

/// The arguments of `hit`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    common: super::answer::Common,
    /// A hit's `t` is right within this many ulps of the exact `t` (of the f32 nearest it), and
    /// always needs `0 < t < ∞` [default: 4096].
    #[arg(long, value_name = "ULPS", allow_negative_numbers = true)]
    t_ulps: Option<f64>,
}

pub fn run(Args { common: a, t_ulps }: Args) -> Status {
    let methods = family::parse_list::<Triangle>(&a.method)?;
    let t_ulps = super::t_ulps(t_ulps)?;
    let backend = a.backend.open()?;
    Answering {
        command: "hit",
        names: methods.iter().map(|m| m.name().to_string()).collect(),
        missed: false,
        leaks: true,
        backend: backend.describe(),
        file: a.file.as_deref(),
        input: None,
        json: a.json.as_deref(),
        fail: a.fail,
        standing: standing::<Triangle>,
    }
    .run(
        |batch, summary| {
            let answered = Answered::Methods(&methods, &backend);
            let mut parts: [Box<dyn Takes>; 1] =
                [Box::new(Part::<Triangle>::new(answered, t_ulps))];
            answer(batch, &mut parts, refuse, None, summary)
        },
        || Ok(()),
    )
}

/// `hit` answers ray–triangle cases only.
fn refuse(_: Kind) -> String {
    "not a ray-triangle case (tri or tris); tetwalk exit answers it".into()
}
