//! `tetwalk exit`: one JSON line per case and method — one tetrahedron's exit face, or a walk through
//! a generated mesh — with the exact answer beside it. Read as the lines come.

use super::Status;
pub use super::answer::Args;
use super::answer::{Answered, Answering, Part, Takes, answer, standing};
use crate::family::{ExitFace, Kind, Walks};
use crate::registry::Named;

pub fn run(a: Args) -> Status {
    if a.t_ulps.is_some() {
        return Err("--t-ulps judges a hit's t: it is for tetwalk hit (and judge)".into());
    }
    let (backend, methods) = a.wgsl.open::<ExitFace>(a.backend, &a.method)?;
    Answering {
        command: "exit",
        names: methods.iter().map(|m| m.name().to_string()).collect(),
        missed: true,
        leaks: false,
        backend: backend.describe(),
        file: a.file.as_deref(),
        json: a.json.as_deref(),
        fail: a.fail,
        standing: standing::<ExitFace>,
    }
    .run(
        |batch, summary| {
            let mut parts: [Box<dyn Takes>; 2] = [
                Box::new(Part::<ExitFace>::new(
                    Answered::Methods(&methods, &backend),
                    0.0,
                )),
                Box::new(Part::<Walks>::new(
                    Answered::Methods(&methods, &backend),
                    0.0,
                )),
            ];
            answer(batch, &mut parts, refuse, None, summary)
        },
        || Ok(()),
    )
}

/// Why `exit` answers no case of family `k`.
fn refuse(k: Kind) -> String {
    match k {
        Kind::Triangle => "a ray-triangle case: tetwalk hit answers it",
        _ => "an octree cell case: tetwalk box-exit answers it",
    }
    .into()
}
