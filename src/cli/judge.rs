//! `tetwalk judge`: answers computed anywhere (a C++ or CUDA kernel's, dumped as JSON Lines) judged
//! exactly against their cases, in the verdict lines `exit` and `hit` write for tetwalk's own methods.

use super::count::{Dump, RaysHeader};
use super::exit::{Line, MAX_LINE, Summary, answer_all, exit_verdict, reader};
use super::hit::hit_verdict;
use super::{JsonOut, Outcome};
use crate::cases::{Subject, classify, judge_hit, number};
use crate::found::Record;
use crate::report::count;
use crate::report::wrong::WrongRay;
use crate::walk::{Outcome as Ending, OutcomeKind, Walk};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::io::BufRead;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// JSON Lines of cases, as `exit` and `hit` read them (exit-face and ray–triangle cases), or the
    /// rays of a scene as `count --rays-out` writes them (its header line first).
    cases: PathBuf,
    /// JSON Lines of answers, one per case, by the case's line number (1-based): `{"line": n,
    /// "face": 0..3|null}` for a tetrahedron (in the case's own numbering), `{"line": n, "hit":
    /// true|false, "t": number|null}` for one triangle, `{"line": n, "tri": i|null, "t": number|null}`
    /// for a closed mesh (the nearest hit), `{"line": n, "face": "-x"|"+x"|…|null, "quarter": [su, sv]}`
    /// for an octree cell (`box-exit`'s cases). For a scene's rays, one walk per ray: `{"view": v,
    /// "pixel": [x, y], "kind": "hit"|"left_mesh"|"no_exit_face"|"cycle"|"step_limit", "tet": t,
    /// "face": f (hit, left_mesh), "period": p (cycle), "steps": n (optional)}`, judged as `count`
    /// judges (the same table; `--json` the same report).
    answers: PathBuf,
    /// For a scene's rays: write every wrong ray here, as `count --dump` does.
    #[arg(long)]
    dump: Option<PathBuf>,
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

/// Each non-blank line of an answers file as a JSON value, with its line number, handed to `take`,
/// read through `exit`'s reader (each line at most its length bound); an error names file and line.
fn each_answer(
    path: &Path,
    mut take: impl FnMut(usize, Value) -> Result<(), String>,
) -> Result<(), JudgeError> {
    let file = path.display().to_string();
    let f = std::fs::File::open(path).map_err(|e| JudgeError::File {
        file: file.clone(),
        why: e.to_string(),
    })?;
    for (i, l) in reader(Box::new(std::io::BufReader::new(f))) {
        let at = |why: String| JudgeError::Answer {
            file: file.clone(),
            line: i,
            why,
        };
        let l = l.map_err(at)?;
        if l.trim().is_empty() {
            continue;
        }
        let v: Value = serde_json::from_str(&l).map_err(|e| at(e.to_string()))?;
        take(i, v).map_err(at)?;
    }
    Ok(())
}

/// The answers by case line, read whole (each a JSON object with a `line`).
fn read_answers(path: &Path) -> Result<HashMap<usize, Value>, JudgeError> {
    let mut out = HashMap::new();
    each_answer(path, |_, v| {
        let n = v
            .get("line")
            .and_then(Value::as_u64)
            .filter(|&n| n >= 1)
            .ok_or("needs \"line\", the case's line number (1-based)")? as usize;
        match out.insert(n, v) {
            Some(_) => Err(format!("a second answer for case line {n}")),
            None => Ok(()),
        }
    })?;
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
    if let Some(header) = scene_header(&a.cases)? {
        return judge_scene(&a, header);
    }
    if a.dump.is_some() {
        return Err(
            "--dump writes the wrong rays of a scene's walks (cases from count --rays-out)".into(),
        );
    }
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
        Subject::Box(c) => {
            let x =
                crate::exact::boxes::box_exit(c.lo, c.hi, &c.ray()).map_err(|e| e.to_string())?;
            let given = match answer.get("face") {
                None | Some(Value::Null) => None,
                Some(f) => {
                    crate::found::box_answer(&json!({"face": f, "quarter": answer.get("quarter")}))?
                }
            };
            let given = given.map(|(f, q)| (f as usize, q));
            Ok(super::box_exit::box_verdict(
                n, name, "given", &x, given, tally,
            ))
        }
        Subject::Walk(_) => {
            Err("judge answers tetrahedron, triangle and octree cell cases, not walk cases".into())
        }
    }
}

/// The header of a `count --rays-out` file, when `path` is one (its first line holds a scene).
fn scene_header(path: &Path) -> Result<Option<RaysHeader>, JudgeError> {
    let file = path.display().to_string();
    let f = std::fs::File::open(path).map_err(|e| JudgeError::File {
        file: file.clone(),
        why: e.to_string(),
    })?;
    // The first line only, at most a line's length bound (a longer one is no header).
    let mut first = Vec::new();
    std::io::BufReader::new(std::io::Read::take(f, MAX_LINE))
        .read_until(b'\n', &mut first)
        .map_err(|e| JudgeError::File {
            file: file.clone(),
            why: e.to_string(),
        })?;
    match serde_json::from_slice::<Value>(&first) {
        Ok(v) if v.get("scene").is_some() => {
            serde_json::from_value(v)
                .map(Some)
                .map_err(|e| JudgeError::Answer {
                    file,
                    line: 1,
                    why: format!("not a count --rays-out header: {e}"),
                })
        }
        _ => Ok(None),
    }
}

/// Walks given per (view, pixel), read whole from the answers file.
type GivenMap = HashMap<(usize, u32, u32), Walk>;

/// One walk answer: `view`, `pixel` and steps taken out, the rest an [`Outcome`] in its serde form.
fn walk_answer(mut v: Value) -> Result<((usize, u32, u32), Walk), String> {
    let o = v.as_object_mut().ok_or("an answer is a JSON object")?;
    let view = o
        .remove("view")
        .and_then(|x| x.as_u64())
        .ok_or("needs \"view\", the ray's view")? as usize;
    let pixel = o
        .remove("pixel")
        .and_then(|p| serde_json::from_value::<[u32; 2]>(p).ok())
        .ok_or("needs \"pixel\": [x, y]")?;
    let steps = match o.remove("steps") {
        None => 0,
        Some(s) => s
            .as_u64()
            .and_then(|s| u32::try_from(s).ok())
            .ok_or("\"steps\" is a count of tetrahedra")?,
    };
    let outcome: Ending = serde_json::from_value(v).map_err(|e| e.to_string())?;
    Ok(((view, pixel[0], pixel[1]), Walk { outcome, steps }))
}

/// A scene's walks computed elsewhere, judged as `count` judges its methods.
fn judge_scene(a: &Args, header: RaysHeader) -> Outcome {
    let out = JsonOut::new(a.json.as_deref())?;
    let mut dump = Dump::new(a.dump.as_deref())?;
    let mesh = crate::scenes::load(&header.scene, super::faces(header.no_faces))?;
    if mesh.tets.len() != header.tetrahedra {
        return Err(format!(
            "{}: scene {} has {} tetrahedra here, {} where the rays were written",
            a.cases.display(),
            header.scene,
            mesh.tets.len(),
            header.tetrahedra
        )
        .into());
    }
    let file = a.answers.display().to_string();
    let mut given = GivenMap::new();
    each_answer(&a.answers, |_, v| {
        let (key, w) = walk_answer(v)?;
        let (kind, tet, face) = w.outcome.parts();
        if tet as usize >= mesh.tets.len() {
            return Err(format!(
                "tet {tet} is not a tetrahedron of the scene (0..{})",
                mesh.tets.len()
            ));
        }
        if matches!(kind, OutcomeKind::Hit | OutcomeKind::LeftMesh) && face >= 4 {
            return Err("face must be 0..3".into());
        }
        match given.insert(key, w) {
            Some(_) => Err(format!(
                "a second answer for view {} pixel [{}, {}]",
                key.0, key.1, key.2
            )),
            None => Ok(()),
        }
    })?;
    let width = header.views.width;
    let lookup = |v: usize, rays: &[crate::tet::Ray]| -> Result<Vec<Walk>, count::CountError> {
        (0..rays.len() as u32)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                given.get(&(v, x, y)).copied().ok_or_else(|| {
                    count::CountError::Given(format!(
                        "{file}: no answer for view {v} pixel [{x}, {y}]"
                    ))
                })
            })
            .collect()
    };
    let settings = count::Settings {
        scene: header.scene.clone(),
        views: header.views,
        reference: "certified".into(),
        audit: 1000,
        shard: header.shard,
    };
    let mut write = |w: &WrongRay| dump.write(w);
    let report = count::run_walkers(
        &mesh,
        &settings,
        &[count::Walker::Given(&a.name, &lookup)],
        &crate::backend::CPU,
        &|| (),
        Some(&mut write),
    )?;
    if report.rays != given.len() as u64 {
        return Err(format!(
            "{file}: {} answers for the {} rays of {}",
            given.len(),
            report.rays,
            a.cases.display()
        )
        .into());
    }
    dump.finish()?;
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(std::process::ExitCode::SUCCESS)
}
