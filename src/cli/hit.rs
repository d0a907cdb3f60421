//! `tetwalk hit`: ray–triangle cases (seed 004's question), one JSON line per case and method, each
//! method's answer beside the exact one. Read as `exit` reads its cases: line by line as they come.

use super::Outcome;
pub use super::exit::Args;
use super::exit::{Answering, Line, Summary, Tally};
use crate::backend::Backend;
use crate::cases::{HitCase, HitTruth, Subject, judge_hit};
use crate::choice::Choice;
use crate::found::Record;
use crate::methods::triangle::nearest_of;
use crate::registry::{TriangleMethod, parse_triangle_list};
use crate::report::standing::Standing;
use serde_json::{Value, json};

pub fn run(a: Args) -> Outcome {
    if a.wgsl.wgsl.is_some() {
        return Err("--wgsl takes an exit-face function (exit, stress, walk, count); hit judges ray-triangle methods".into());
    }
    let methods = parse_triangle_list(&a.method)?;
    let t_ulps = super::t_ulps(a.t_ulps)?;
    let backend = a.backend.open()?;
    Answering {
        command: "hit",
        names: methods.iter().map(|m| m.name.to_string()).collect(),
        missed: false,
        leaks: true,
        backend: backend.describe(),
        file: a.file.as_deref(),
        json: a.json.as_deref(),
        fail: a.fail,
        standing: |t| Standing::triangle(&t.method, t.right + t.wrong, t.wrong, t.leaks),
    }
    .run(
        |batch, summary| answer(batch, &methods, &backend, t_ulps, summary),
        || Ok(()),
    )
}

/// A ray–triangle verdict line: the nearest hit `g` (a triangle of the case and its `t`, or none)
/// beside the exact answer, counted in `tally`. Right when the triangle is ([`HitTruth::right`]) and,
/// for a hit, its `t` is ([`HitTruth::judge_t`], within `t_ulps`); on a closed mesh, `hits` (every
/// triangle the method reports) say whether the ray leaks.
pub(super) fn hit_verdict(
    (n, method, backend): (usize, &str, &str),
    (case, truth): (&HitCase, &HitTruth),
    g: Option<(u32, f32)>,
    hits: &[u32],
    t_ulps: f64,
    tally: &mut Tally,
) -> Value {
    let t = g.map(|(i, t)| truth.judge_t(i, t, t_ulps));
    let correct = truth.right(g.map(|(i, _)| i)) && t.is_none_or(|t| t.right);
    tally.right += correct as u64;
    tally.wrong += !correct as u64;
    let first = truth.first();
    let mut line = json!({
        "line": n, "method": method, "backend": backend,
        "hit": g.is_some(), "t": g.map(|(_, t)| t), "t_ulps": t.and_then(|t| t.ulps),
        "exact_hit": first.is_some(), "exact_t": first.map(|p| ratio(&p.t)),
    });
    let o = line.as_object_mut().expect("an object");
    if case.closed {
        let leak = truth.leaks(hits);
        if let Some(l) = tally.leaks.as_mut() {
            *l += leak as u64;
        }
        o.insert("tri".into(), json!(g.map(|(i, _)| i)));
        let holding = first.map_or(vec![], |p| p.holding.clone());
        let boundary = holding.iter().any(|&i| truth.each[i as usize].on_boundary);
        o.insert("exact_tris".into(), json!(holding));
        o.insert("on_boundary".into(), Value::Bool(boundary));
        o.insert("crosses".into(), json!(first.map(|p| p.crosses)));
        o.insert("leak".into(), Value::Bool(leak));
    } else {
        o.insert("on_boundary".into(), Value::Bool(truth.each[0].on_boundary));
    }
    o.insert("correct".into(), Value::Bool(correct));
    line
}

/// A rational as `p/q`.
fn ratio(q: &rug::Rational) -> String {
    format!("{}/{}", q.numer(), q.denom())
}

fn answer(
    batch: &[Line],
    methods: &[&'static TriangleMethod],
    backend: &Backend,
    t_ulps: f64,
    summary: &mut Summary,
) -> Result<String, super::Error> {
    let parsed: Vec<(usize, Result<_, String>)> = batch
        .iter()
        .filter(|(_, l)| l.as_ref().map_or(true, |l| !l.trim().is_empty()))
        .map(|(n, l)| {
            let p = l.clone().and_then(|l| {
                match Record::parse(&l).map_err(|e| e.to_string())?.subject {
                    Subject::Hit(h) => judge_hit(&h).map(|t| (h, t)).map_err(|e| e.to_string()),
                    _ => {
                        Err("not a ray-triangle case (tri or tris); tetwalk exit answers it".into())
                    }
                }
            });
            (*n, p)
        })
        .collect();
    let cases: Vec<_> = parsed
        .iter()
        .filter_map(|(_, p)| p.as_ref().ok().map(|(h, _)| *h))
        .collect();
    let mut got = Vec::new();
    for m in methods {
        got.push(backend.triangle_hits(m, &cases)?);
    }
    let mut s = String::new();
    let mut k = 0;
    for (n, p) in &parsed {
        summary.lines += 1;
        let (case, truth) = match p {
            Err(e) => {
                summary.errors += 1;
                s += &json!({"line": n, "error": e}).to_string();
                s.push('\n');
                continue;
            }
            Ok(x) => x,
        };
        for ((m, g), tally) in methods.iter().zip(&got).zip(&mut summary.methods) {
            let ids: Vec<u32> = g[k].iter().map(|&(i, _)| i).collect();
            let line = hit_verdict(
                (*n, m.name, backend.kind().name()),
                (case, truth),
                nearest_of(&g[k]),
                &ids,
                t_ulps,
                tally,
            );
            s += &line.to_string();
            s.push('\n');
        }
        k += 1;
    }
    Ok(s)
}
