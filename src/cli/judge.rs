//! `tetwalk judge`: answers computed anywhere (a C++ or CUDA kernel's, dumped as JSON Lines) judged
//! exactly against their cases, in the verdict lines `exit` and `hit` write for tetwalk's own methods.

use super::Status;
use super::answer::{Answering, Input};
use super::count::Flags;
use crate::choice::Choice;
use crate::engine::answering::{AnswerTally, answer, open_cases, read_answers};
use crate::engine::standing::Standing;
use crate::family::{CountKind, Kind};
use serde_json::Value;
use std::io::BufRead;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// JSON Lines of cases, as `exit` and `hit` read them (exit-face and ray–triangle cases), or the
    /// rays of a scene as `count --rays-out` writes them (its header line first); `-` is standard
    /// input.
    pub(crate) cases: PathBuf,
    /// JSON Lines of answers, one per case, by the case's line number (1-based): `{"line": n,
    /// "face": 0..3|null}` for a tetrahedron (in the case's own numbering), `{"line": n, "hit":
    /// true|false, "t": number|null}` for one triangle, `{"line": n, "tri": i|null, "t": number|null}`
    /// for a closed mesh (the nearest hit), `{"line": n, "face": "-x"|"+x"|…|null, "quarter": [su, sv]}`
    /// for an octree cell (`box-exit`'s cases); `-` is standard input. For a scene's rays, one walk
    /// per ray: `{"view": v,
    /// "pixel": [x, y], "kind": "hit"|"left_mesh"|"no_exit_face"|"cycle"|"step_limit", "tet": t,
    /// "face": f (hit, left_mesh), "period": p (cycle), "steps": n (optional)}`, judged as `count`
    /// judges (the same table; `--json` the same report).
    pub(crate) answers: PathBuf,
    /// For a scene's rays: write every wrong ray here, as `count --dump` does.
    #[arg(long)]
    pub(crate) dump: Option<PathBuf>,
    /// The name the verdict lines give the method that answered.
    #[arg(long, default_value = "yours")]
    pub(crate) name: String,
    /// Also write a summary (lines, errors, right / wrong / lines missing the tetrahedron) as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
    /// A hit's `t` is right within this many ulps of the exact `t` (of the f32 nearest it), and always
    /// needs `0 < t < ∞` [default: 4096].
    #[arg(long, value_name = "ULPS", allow_negative_numbers = true)]
    pub(crate) t_ulps: Option<f64>,
    #[command(flatten)]
    pub(crate) fail: super::FailArg,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .input("CASES", Some(&self.cases))
            .input("ANSWERS", Some(&self.answers))
            .output("--json", self.json.as_deref())
            .output("--dump", self.dump.as_deref())
    }
}

pub(crate) fn run(a: Args) -> Status {
    if a.fail.fail_on == Some(super::FailOn::Claims) {
        return Err("--fail-on claims: judge's answers are yours, and tetwalk knows no claim of theirs; --fail-on wrong fails on any wrong answer".into());
    }
    let t_ulps = super::t_ulps(a.t_ulps)?;
    let stdin = std::path::Path::new("-");
    if a.cases == stdin && a.answers == stdin {
        return Err(
            "CASES and ANSWERS are both `-`: standard input can be one of them, not both".into(),
        );
    }
    let (header, input) = open_cases(&a.cases)?;
    if let Some(header) = header {
        if a.t_ulps.is_some() {
            return Err("--t-ulps judges a hit's t in triangle cases; a scene's walks end in a tetrahedron's face".into());
        }
        return judge_rays(&a, header, input);
    }
    if a.dump.is_some() {
        return Err(
            "--dump writes the wrong rays of a scene's walks (cases from count --rays-out)".into(),
        );
    }
    // Taken out line by line; what is left has no case.
    let answers = std::cell::RefCell::new(read_answers(&a.answers)?);
    let standing = |t: &AnswerTally| Standing::unclaimed(&t.method, t.right + t.wrong, t.wrong);
    // The tallies count neither misses nor leaks: each family's fields come with its first line (no
    // triangle fields on tetrahedron lines).
    Answering {
        input: Some(input),
        ..Answering::new(
            "judge",
            vec![a.name.clone()],
            "given".to_string(),
            Input {
                file: Some(&a.cases),
                json: a.json.as_deref(),
                fail: a.fail,
            },
            &standing,
        )
    }
    .run(
        |batch, summary| {
            let mut parts = crate::families!(__given_parts, &a.name, t_ulps);
            let mut given = answers.borrow_mut();
            Ok(answer(
                batch,
                &mut parts,
                refuse,
                Some(&mut given),
                summary,
            )?)
        },
        || {
            let mut extra: Vec<usize> = answers.borrow().keys().copied().collect();
            extra.sort_unstable();
            if extra.is_empty() {
                return Ok(());
            }
            Err(format!(
                "{}: answers for {}, with no case in {}",
                a.answers.display(),
                crate::engine::line_runs(&extra),
                a.cases.display()
            )
            .into())
        },
    )
}

/// `judge` judges no walk case: answers to walks come as a scene's rays.
fn refuse(_: Kind) -> String {
    "judge answers tetrahedron, triangle and octree cell cases, not walk cases".into()
}

/// Walks given for the rays of a `count --rays-out` file (`header`, its first line, then `input`),
/// judged by the counted family that writes such files ([`Flags::RAYS_OUT`]), as its count judges them.
fn judge_rays(a: &Args, header: Value, input: Box<dyn BufRead + Send>) -> Status {
    let kind = CountKind::ALL
        .iter()
        .copied()
        .find(|&k| crate::with_counted!(k, F => <F as Flags>::RAYS_OUT))
        .ok_or("no counted family writes rays to judge")?;
    crate::with_counted!(kind, F => <F as Flags>::judge_rays(a, header, input))
}
