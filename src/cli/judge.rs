//! `tetwalk judge`: answers computed anywhere (a C++ or CUDA kernel's, dumped as JSON Lines) judged
//! exactly against their cases, in the verdict lines `exit` and `hit` write for tetwalk's own methods.

use super::Outcome;
use super::exit::{Line, Summary, answer_all, exit_verdict, reader};
use super::hit::hit_verdict;
use crate::cases::{Subject, classify, judge_hit, number};
use crate::found::Record;
use serde_json::{Value, json};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// JSON Lines of cases, as `exit` and `hit` read them (exit-face and ray–triangle cases).
    cases: PathBuf,
    /// JSON Lines of answers, one per case, by the case's line number (1-based): `{"line": n,
    /// "face": 0..3|null}` for a tetrahedron (in the case's own numbering), `{"line": n, "hit":
    /// true|false, "t": number|null}` for one triangle, `{"line": n, "tri": i|null, "t": number|null}`
    /// for a closed mesh (the nearest hit).
    answers: PathBuf,
    /// The name the verdict lines give the method that answered.
    #[arg(long, default_value = "yours")]
    name: String,
    /// Also write a summary (lines, errors, right / wrong / lines missing the tetrahedron) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

/// Why an answers file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum JudgeError {
    #[error("{file}:{line}: {why}")]
    Answer {
        file: String,
        line: usize,
        why: String,
    },
    #[error("{file}: {why}")]
    File { file: String, why: String },
}

/// The answers by case line, read whole (each a JSON object with a `line`), line by line through
/// `exit`'s reader (each line at most its length bound).
fn read_answers(path: &Path) -> Result<HashMap<usize, Value>, JudgeError> {
    let file = path.display().to_string();
    let f = std::fs::File::open(path).map_err(|e| JudgeError::File {
        file: file.clone(),
        why: e.to_string(),
    })?;
    let mut out = HashMap::new();
    for (i, l) in reader(Box::new(std::io::BufReader::new(f))) {
        let bad = |why: String| JudgeError::Answer {
            file: file.clone(),
            line: i,
            why,
        };
        let l = l.map_err(bad)?;
        if l.trim().is_empty() {
            continue;
        }
        let v: Value = serde_json::from_str(&l).map_err(|e| bad(e.to_string()))?;
        let n = v
            .get("line")
            .and_then(Value::as_u64)
            .filter(|&n| n >= 1)
            .ok_or_else(|| bad("needs \"line\", the case's line number (1-based)".into()))?
            as usize;
        if out.insert(n, v).is_some() {
            return Err(bad(format!("a second answer for case line {n}")));
        }
    }
    Ok(out)
}

/// A number field as the nearest f32 to its decimal text ([`number`]), or null.
fn f32_field(v: &Value, k: &str) -> Result<Option<f32>, String> {
    match v.get(k) {
        None | Some(Value::Null) => Ok(None),
        Some(x) => number(x).map(Some).map_err(|e| format!("{k}: {e}")),
    }
}

pub fn run(a: Args) -> Outcome {
    let mut answers = read_answers(&a.answers)?;
    let outcome = answer_all(
        "judge",
        vec![a.name.clone()],
        true,
        "given".to_string(),
        Some(&a.cases),
        a.json.as_deref(),
        |batch, summary| Ok(verdicts(batch, &a.name, &mut answers, summary)),
    )?;
    if !answers.is_empty() {
        let mut extra: Vec<usize> = answers.keys().copied().collect();
        extra.sort_unstable();
        return Err(format!(
            "{}: answers for line(s) {extra:?}, which hold no case in {}",
            a.answers.display(),
            a.cases.display()
        )
        .into());
    }
    Ok(outcome)
}

/// The verdict lines of a batch of case lines, each judged against its answer (taken out of `answers`).
fn verdicts(
    batch: &[Line],
    name: &str,
    answers: &mut HashMap<usize, Value>,
    summary: &mut Summary,
) -> String {
    let mut s = String::new();
    for (n, l) in batch {
        if l.as_ref().is_ok_and(|t| t.trim().is_empty()) {
            continue;
        }
        summary.lines += 1;
        let answer = answers.remove(n);
        let line = l
            .clone()
            .and_then(|text| verdict(*n, &text, name, answer, &mut summary.methods[0]));
        let line = line.unwrap_or_else(|e| {
            summary.errors += 1;
            json!({"line": n, "error": e})
        });
        s += &line.to_string();
        s.push('\n');
    }
    s
}

fn verdict(
    n: usize,
    text: &str,
    name: &str,
    answer: Option<Value>,
    tally: &mut super::exit::Tally,
) -> Result<Value, String> {
    let subject = Record::parse(text).map_err(|e| e.to_string())?.subject;
    let answer = answer.ok_or_else(|| "no answer for this line in the answers".to_string())?;
    match subject {
        Subject::Exit(c) => {
            let x = classify(&c).map_err(|e| e.to_string())?;
            let face = match answer.get("face") {
                None | Some(Value::Null) => None,
                Some(f) => Some(
                    f.as_u64()
                        .filter(|&f| f < 4)
                        .ok_or_else(|| format!("the answer's face {f} is not 0..3 or null"))?
                        as usize,
                ),
            };
            Ok(exit_verdict(n, name, "given", &x, face, tally))
        }
        Subject::Hit(h) => {
            let truth = judge_hit(&h).map_err(|e| e.to_string())?;
            let t = f32_field(&answer, "t")?;
            let g = if h.closed {
                match answer.get("tri") {
                    None | Some(Value::Null) => None,
                    Some(i) => {
                        let i = i
                            .as_u64()
                            .filter(|&i| (i as usize) < h.tris().len())
                            .ok_or_else(|| {
                                format!("the answer's tri {i} is not a triangle of the case")
                            })?;
                        Some((i as u32, t.ok_or("a hit's answer needs its \"t\"")?))
                    }
                }
            } else {
                match answer.get("hit").and_then(Value::as_bool) {
                    Some(true) => Some((0, t.ok_or("a hit's answer needs its \"t\"")?)),
                    Some(false) => None,
                    None => return Err("the answer needs \"hit\": true or false".into()),
                }
            };
            Ok(hit_verdict(n, name, "given", &h, &truth, g, tally))
        }
        Subject::Walk(_) => {
            Err("judge answers tetrahedron and triangle cases, not walk cases".into())
        }
    }
}
