//! `tetwalk exit`: one JSON line per case and method — one tetrahedron's exit face, or a walk through
//! a generated mesh — with the exact answer beside it. Read as the lines come.

use super::answer::{Answered, Answering, Part, Takes, answer, standing};
use super::{Status, WgslArg};
use crate::family::{ExitFace, Kind, Walks};
use crate::registry::Named;

/// The arguments of `exit`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    common: super::answer::Common,
    #[command(flatten)]
    wgsl: WgslArg,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        self.common.io().input("--wgsl", self.wgsl.wgsl.as_deref())
    }
}

pub fn run(Args { common: a, wgsl }: Args) -> Status {
    let (backend, methods) = wgsl.open::<ExitFace>(a.backend, &a.method)?;
    let outside = a.answerer.start::<ExitFace>(&Default::default())?;
    if let Some(x) = &outside {
        return super::answer::outside::<ExitFace>("exit", x, &a, refuse_walks, 0.0);
    }
    Answering {
        command: "exit",
        names: methods.iter().map(|m| m.name().to_string()).collect(),
        missed: true,
        leaks: false,
        backend: backend.describe(),
        file: a.file.as_deref(),
        input: None,
        json: a.json.as_deref(),
        fail: a.fail,
        standing: &standing::<ExitFace>,
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

/// Why `exit --answerer` answers no case of family `k`.
fn refuse_walks(k: Kind) -> String {
    match k {
        Kind::Walk => "a walk case: an answerer answers one tetrahedron's cases (count --answerer walks a scene through it)".into(),
        k => refuse(k),
    }
}

/// Why `exit` answers no case of family `k`.
fn refuse(k: Kind) -> String {
    match k {
        Kind::Triangle => "a ray-triangle case: tetwalk hit answers it",
        _ => "an octree cell case: tetwalk box-exit answers it",
    }
    .into()
}
