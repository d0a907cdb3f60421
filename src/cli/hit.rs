//! `tetwalk hit`: ray–triangle cases (seed 004's question), one JSON line per case and method, each
//! method's answer beside the exact one. Read as `exit` reads its cases: line by line as they come.

use super::Status;
use super::answer::{Answered, Answering, Part, Takes, answer, standing};
use crate::choice::{BackendKind, Choice};
use crate::family::{self, Kind, Triangle};
use crate::registry::{Named, TRIANGLE_METHODS};

/// The arguments of `hit`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    common: super::answer::Common,
    /// A hit's `t` is right within this many ulps of the exact `t` (of the f32 nearest it), and
    /// always needs `0 < t < ∞` [default: 4096].
    #[arg(long, value_name = "ULPS", allow_negative_numbers = true)]
    t_ulps: Option<f64>,
    /// Also answer every case with each method's 4-wide version (seed 004's SIMD packets, where a
    /// method has one), the ray in every lane, and compare: each line of such a method says
    /// `"wide_same"`, and any case answered otherwise than by the scalar version, bit for bit, gives
    /// exit status 1. Plain f32 only (`--backend cpu`).
    #[arg(long)]
    wide: bool,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        self.common.io()
    }
}

pub fn run(
    Args {
        common: a,
        t_ulps,
        wide,
    }: Args,
) -> Status {
    let methods = family::parse_list::<Triangle>(&a.method)?;
    let t_ulps = super::t_ulps(t_ulps)?;
    if wide {
        if a.backend.backend != BackendKind::Cpu {
            return Err(format!(
                "--wide compares the 4-wide versions with the scalar ones in plain f32, where they answer alike: give --backend cpu, not {}",
                a.backend.backend.name()
            )
            .into());
        }
        if methods.iter().all(|m| m.wide.is_none()) {
            let have: Vec<&str> = TRIANGLE_METHODS
                .iter()
                .filter(|m| m.wide.is_some())
                .map(|m| m.name())
                .collect();
            return Err(format!(
                "--wide: none of the methods asked for has a 4-wide version ({} have)",
                have.join(", ")
            )
            .into());
        }
    }
    let outside = a.answerer.start::<Triangle>(&Default::default())?;
    if let Some(x) = &outside {
        if wide {
            return Err("--wide compares tetwalk's 4-wide versions; an --answerer has none".into());
        }
        return super::answer::outside::<Triangle>("hit", x, &a, refuse, t_ulps);
    }
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
        standing: &standing::<Triangle>,
    }
    .run(
        |batch, summary| {
            let answered = Answered::Methods(&methods, &backend);
            let mut part = Part::<Triangle>::new(answered, t_ulps);
            part.wide = wide;
            let mut parts: [Box<dyn Takes>; 1] = [Box::new(part)];
            answer(batch, &mut parts, refuse, None, summary)
        },
        || Ok(()),
    )
}

/// `hit` answers ray–triangle cases only.
fn refuse(_: Kind) -> String {
    "not a ray-triangle case (tri or tris); tetwalk exit answers it".into()
}
