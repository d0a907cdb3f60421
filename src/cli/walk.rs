//! `tetwalk walk`: rays through a generated mesh, each method's walk judged step by step.

use super::{BackendArg, JsonOut, Status, WgslArg, choice};
use crate::backend::Backend;
use crate::mesh::layout::Layout;
use crate::mesh::reorder::hilbert_sorted;
use crate::methods::Model;
use crate::registry::{Named, reference};
use crate::report::relabel_spread;
use crate::scenes::{self, Generated};
use crate::tet::EVEN_PERMUTATIONS;
use crate::walk::layouts::{Kind, Source};
use crate::walk::{OutcomeKind, Walk, default_max_steps, locate, same_result};
use glam::Vec3;
use rayon::prelude::*;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The generated mesh.
    #[arg(long, value_parser = choice::<Generated>(), default_value = "fan")]
    mesh: Generated,
    /// Grid cells per side, or 16·size tetrahedra in the fan.
    #[arg(long, allow_negative_numbers = true, default_value_t = 8)]
    size: u32,
    /// Move the mesh and rays this far from the origin along (1, 1, 1); exact up to 2^20.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    offset: f32,
    /// Rays walked (half aimed exactly through vertices and edges).
    #[arg(long, allow_negative_numbers = true, default_value_t = 10000)]
    rays: usize,
    /// Methods (comma-separated, or all).
    #[arg(long, default_value = "all")]
    methods: String,
    /// Where the walks run: a CPU backend, `cpu`, `cpu-fma`, `cpu-ftz` or `cpu-gpu` (every step is judged by the oracle on the CPU, so the
    /// GPU has no place here; `count --backend gpu` walks on it).
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    wgsl: WgslArg,
    /// Seed of the rays (and of the jittered grid).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Walk the methods that can (aman20, aman20-scaled) over this compact layout instead of the plain
    /// mesh (their "diverged" column is then not measured).
    #[arg(long, value_parser = choice::<Kind>())]
    layout: Option<Kind>,
    /// Reorder points and tetrahedra along a Hilbert curve, by region, first (seed 003 §5).
    #[arg(long)]
    hilbert: bool,
    /// `all`: also walk under each of the 12 orientation-preserving relabellings of the tetrahedra
    /// (the same for the whole mesh) and report, per method, wrong results and cycles with the mesh's
    /// own labelling beside their min / median / max over the 12.
    #[arg(long, value_parser = ["all"])]
    relabel: Option<String>,
    /// Also write the table as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .input("--wgsl", self.wgsl.wgsl.as_deref())
            .output("--json", self.json.as_deref())
    }
}

/// One method's walks: how they ended ([`OutcomeKind::ALL`] order), how many ended elsewhere than the
/// `exact` walk, how many took a step outside the exact exit set, and the steps.
#[derive(Default, Clone, Copy, serde::Serialize)]
struct Tally {
    rays: u64,
    kinds: [u64; 5],
    wrong: u64,
    diverged: u64,
    steps: u64,
}

#[derive(serde::Serialize)]
struct Row {
    method: String,
    layout: Option<Kind>,
    #[serde(flatten)]
    tally: Tally,
}

/// One method under the 12 relabellings: wrong results and cycles for each, the identity first.
#[derive(serde::Serialize)]
struct Relabelled {
    method: String,
    wrong: Vec<u64>,
    cycles: Vec<u64>,
}

#[derive(serde::Serialize)]
struct WalkReport {
    mesh: Generated,
    size: u32,
    offset: f32,
    tetrahedra: usize,
    rays: usize,
    outside: usize,
    seed: u64,
    backend: crate::backend::BackendKind,
    methods: Vec<Row>,
    /// With `--relabel all`.
    relabellings: Option<Vec<Relabelled>>,
}

pub fn run(a: Args) -> Status {
    let (backend, methods) = a.wgsl.open::<crate::family::Walks>(a.backend, &a.methods)?;
    // Every ray keeps one tally per method until the table is made.
    super::fits(
        &format!("--rays {}", a.rays),
        a.rays as u128 * (32 + 64 * methods.len() as u128),
    )?;
    let out = JsonOut::new(a.json.as_deref())?;
    // `None`: a --wgsl function's walks, on the GPU, judged by their endings.
    let model = match &backend {
        Backend::Cpu { model } => Some(*model),
        Backend::Gpu(_) if a.wgsl.wgsl.is_some() => {
            if a.relabel.is_some() || a.layout.is_some() {
                return Err(
                    "--wgsl walks the plain mesh on the GPU; leave out --relabel and --layout"
                        .into(),
                );
            }
            None
        }
        Backend::Gpu(_) => {
            let cpus: Vec<&str> = crate::choice::Model::ALL
                .iter()
                .map(|m| crate::choice::Choice::name(m.backend()))
                .collect();
            return Err(format!("walk judges every step with the oracle on the CPU: use --backend {} (count --backend gpu walks on the GPU; a --wgsl function walks there too)", cpus.join(", ")).into());
        }
    };
    let offset = Vec3::splat(a.offset);
    let mesh = scenes::generated_mesh(a.mesh, a.size, offset, a.seed)?;
    let mesh = if a.hilbert {
        hilbert_sorted(&mesh)
    } else {
        mesh
    };
    if a.relabel.is_some() && a.layout.is_some() {
        return Err("--relabel walks the plain mesh; leave out --layout".into());
    }
    let layout = a.layout.map(|_| Layout::build(&mesh));
    let rays = scenes::rays(a.mesh, &mesh, offset, a.rays, a.seed);
    let per_ray = match model {
        Some(model) => walk_tallies(
            &mesh,
            &rays,
            &methods,
            model,
            a.layout.zip(layout.as_ref()),
            true,
        ),
        None => gpu_tallies(&backend, &mesh, &rays, &methods)?,
    };
    let checked = model.is_some();
    let outside = per_ray.iter().filter(|r| r.is_none()).count();
    println!(
        "mesh {:?} size {} offset {} ({} tetrahedra), {} rays, seed {}, {}{}\n",
        a.mesh,
        a.size,
        a.offset,
        mesh.tets.len(),
        rays.len() - outside,
        a.seed,
        model.map_or_else(|| backend.describe(), |m| m.words().into()),
        if outside > 0 {
            format!(
                ", {} starting outside skipped",
                crate::report::counted(outside as u64, "ray", "rays")
            )
        } else {
            String::new()
        },
    );
    println!(
        "| method | hit | left mesh | no exit face | cycle | step limit | wrong result | diverged | mean steps |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut report = WalkReport {
        mesh: a.mesh,
        size: a.size,
        offset: a.offset,
        tetrahedra: mesh.tets.len(),
        rays: rays.len() - outside,
        outside,
        seed: a.seed,
        backend: a.backend.backend,
        methods: Vec::new(),
        relabellings: None,
    };
    for (i, m) in methods.iter().enumerate() {
        let mut s = Tally::default();
        for t in per_ray.iter().flatten() {
            let t = t[i];
            s.rays += t.rays;
            s.wrong += t.wrong;
            s.diverged += t.diverged;
            s.steps += t.steps;
            (0..5).for_each(|k| s.kinds[k] += t.kinds[k]);
        }
        let k = s.kinds;
        let on_layout = a
            .layout
            .filter(|_| m.layout_walk(model.unwrap_or(Model::Plain)).is_some());
        let name = on_layout.map_or(m.name().to_string(), |k| format!("{} ({k:?})", m.name()));
        let diverged = if on_layout.is_some() || !checked {
            "-".to_string()
        } else {
            s.diverged.to_string()
        };
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            name,
            k[0],
            k[1],
            k[2],
            k[3],
            k[4],
            s.wrong,
            diverged,
            s.steps as f64 / s.rays.max(1) as f64
        );
        report.methods.push(Row {
            method: m.name().into(),
            layout: on_layout,
            tally: s,
        });
    }
    if a.relabel.is_some() {
        report.relabellings = Some(relabellings(
            &mesh,
            &rays,
            &methods,
            model.unwrap_or(Model::Plain),
        )?);
    }
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}

/// Per ray (none when its origin is outside the mesh), each method's tally: checked walks (every step
/// judged, so that "diverged" is measured) or plain ones.
fn walk_tallies(
    mesh: &crate::mesh::Mesh,
    rays: &[crate::tet::Ray],
    methods: &[&'static crate::registry::Method],
    model: Model,
    layout: Option<(Kind, &Layout)>,
    checked: bool,
) -> Vec<Option<Vec<Tally>>> {
    let max = default_max_steps(mesh);
    let exact = reference();
    rays.par_iter()
        .map(|ray| {
            let start = locate(mesh, ray.org, 0).ok()?;
            let reference = exact.walk(Model::Plain)(mesh, ray, start, max);
            let tallies = methods
                .iter()
                .map(|m| {
                    let (w, div) = match layout.zip(m.layout_walk(model)) {
                        Some(((kind, layout), walk)) => {
                            let (end, steps) = walk(
                                kind,
                                layout,
                                &mesh.points,
                                ray,
                                &Source::new(layout, start),
                                max,
                            );
                            (
                                Walk {
                                    outcome: end.to_outcome(mesh),
                                    steps,
                                },
                                None,
                            )
                        }
                        None if checked => m.walk_checked(model)(mesh, ray, start, max),
                        None => (m.walk(model)(mesh, ray, start, max), None),
                    };
                    tally(mesh, ray, &w, &reference, div.is_some())
                })
                .collect();
            Some(tallies)
        })
        .collect()
}

/// One ray's tally: how walk `w` ended, whether wrongly (against the `exact` walk), whether it
/// diverged.
fn tally(
    mesh: &crate::mesh::Mesh,
    ray: &crate::tet::Ray,
    w: &Walk,
    exact: &Walk,
    diverged: bool,
) -> Tally {
    let mut t = Tally {
        rays: 1,
        steps: w.steps as u64,
        wrong: !same_result(mesh, ray, w, exact) as u64,
        diverged: diverged as u64,
        ..Tally::default()
    };
    t.kinds[w.outcome.kind().code() as usize] = 1;
    t
}

/// Per ray (none when its origin is outside the mesh), each method's tally from walks on the GPU
/// (`--wgsl`), judged by their endings against the `exact` walk on the CPU ("diverged" unmeasured).
fn gpu_tallies(
    backend: &Backend,
    mesh: &crate::mesh::Mesh,
    rays: &[crate::tet::Ray],
    methods: &[&'static crate::registry::Method],
) -> Result<Vec<Option<Vec<Tally>>>, super::Error> {
    let max = default_max_steps(mesh);
    let starts: Vec<Option<u32>> = rays
        .par_iter()
        .map(|r| locate(mesh, r.org, 0).ok())
        .collect();
    let asked: Vec<(crate::tet::Ray, u32)> = rays
        .iter()
        .zip(&starts)
        .filter_map(|(r, s)| Some((*r, (*s)?)))
        .collect();
    let on = backend.mesh(mesh);
    let mut walks = Vec::new();
    for m in std::iter::once(&reference()).chain(methods) {
        walks.push(backend.walks_from(m, &on, &asked, max)?.walks);
    }
    let mut k = 0;
    Ok(starts
        .iter()
        .map(|s| {
            s.map(|_| {
                let (ray, _) = asked[k];
                let exact = &walks[0][k];
                let t = walks[1..]
                    .iter()
                    .map(|w| tally(mesh, &ray, &w[k], exact, false))
                    .collect();
                k += 1;
                t
            })
        })
        .collect())
}

/// Every method's wrong results and cycles under each of the 12 orientation-preserving relabellings
/// ([`EVEN_PERMUTATIONS`], the identity first), printed with min / median / max.
fn relabellings(
    mesh: &crate::mesh::Mesh,
    rays: &[crate::tet::Ray],
    methods: &[&'static crate::registry::Method],
    model: Model,
) -> Result<Vec<Relabelled>, super::Error> {
    // Per method its wrong results, then its cycles.
    let measure = |k: usize| -> Result<Vec<u64>, super::Error> {
        let relabelled = mesh.relabelled(EVEN_PERMUTATIONS[k])?;
        let mut n = vec![0; 2 * methods.len()];
        for t in walk_tallies(&relabelled, rays, methods, model, None, false)
            .iter()
            .flatten()
        {
            for (i, t) in t.iter().enumerate() {
                n[2 * i] += t.wrong;
                n[2 * i + 1] += t.kinds[OutcomeKind::Cycle.code() as usize];
            }
        }
        Ok(n)
    };
    let all = crate::engine::under_labellings(measure(0)?, EVEN_PERMUTATIONS.len(), measure)?;
    let out: Vec<Relabelled> = methods
        .iter()
        .zip(all.chunks(2))
        .map(|(m, n)| Relabelled {
            method: m.name().into(),
            wrong: n[0].clone(),
            cycles: n[1].clone(),
        })
        .collect();
    println!("\nunder the 12 orientation-preserving relabellings of the tetrahedra\n");
    println!(
        "| method | wrong, own | min | median | max | cycles, own | min | median | max |\n|---|---|---|---|---|---|---|---|---|"
    );
    for r in &out {
        println!(
            "| {} | {} | {} |",
            r.method,
            relabel_spread(&r.wrong),
            relabel_spread(&r.cycles)
        );
    }
    Ok(out)
}
