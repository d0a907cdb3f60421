//! `tetwalk hit`: ray–triangle cases (seed 004's question), one JSON line per case and method, each
//! method's answer beside the exact one. Read as `exit` reads its cases: line by line as they come.

use super::Status;
pub use super::answer::Args;
use super::answer::{Answered, Answering, Part, Takes, answer, standing};
use crate::family::{self, Kind, Triangle};
use crate::registry::Named;

pub fn run(a: Args) -> Status {
    if a.wgsl.wgsl.is_some() {
        return Err("--wgsl takes an exit-face function (exit, stress, walk, count); hit judges ray-triangle methods".into());
    }
    let methods = family::parse_list::<Triangle>(&a.method)?;
    let t_ulps = super::t_ulps(a.t_ulps)?;
    let backend = a.backend.open()?;
    Answering {
        command: "hit",
        names: methods.iter().map(|m| m.name().to_string()).collect(),
        missed: false,
        leaks: true,
        backend: backend.describe(),
        file: a.file.as_deref(),
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
