//! `tetwalk render`: shaded renders, failure maps, heat maps and predicate maps as PNG.

use crate::cases::Case;
use crate::methods::parse_list;
use crate::render::{self, Image};
use crate::scenes::tets::{self, Family, Target};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum What {
    /// Flat-shaded view of the scene.
    Shaded,
    /// Each method's wrong rays coloured by kind, and a sheet of all methods side by side.
    Failures,
    /// Tetrahedra traversed per pixel.
    Heat,
    /// Exit faces over a grid of ulp steps of the ray origin, per method beside the exact answer.
    Predicate,
}

#[derive(clap::Args)]
pub struct Args {
    #[arg(value_enum)]
    what: What,
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// Which of `--views` viewpoints (as `tetwalk count` places them).
    #[arg(long, default_value_t = 0)]
    view: usize,
    #[arg(long, default_value_t = 160)]
    views: usize,
    /// WxH for scenes; W for predicate maps (square).
    #[arg(long, default_value = "512x512")]
    size: String,
    #[arg(long, default_value = "all")]
    methods: String,
    #[arg(long)]
    fma: bool,
    /// Predicate maps: the tetrahedron family and what the ray goes exactly through.
    #[arg(long, value_enum, default_value = "well")]
    family: Family,
    #[arg(long, value_parser = ["edge", "vertex"], default_value = "edge")]
    through: String,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output PNG (per-method images are written beside it, suffixed with the method).
    #[arg(long, default_value = "tetwalk.png")]
    out: PathBuf,
}

fn write(path: &Path, im: &Image) -> Result<(), String> {
    std::fs::write(path, im.png()).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("{} ({}x{})", path.display(), im.width, im.height);
    Ok(())
}

fn beside(out: &Path, suffix: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("tetwalk");
    out.with_file_name(format!("{stem}-{suffix}.png"))
}

pub fn run(a: Args) -> Result<ExitCode, String> {
    let methods: Vec<_> = parse_list(&a.methods)?
        .into_iter()
        .filter(|m| m.name != "exact")
        .collect();
    let (w, h) = a
        .size
        .split_once('x')
        .map_or(a.size.parse().ok().map(|w| (w, w)), |(w, h)| {
            Some((w.parse().ok()?, h.parse().ok()?))
        })
        .filter(|&(w, h): &(u32, u32)| w > 0 && h > 0)
        .ok_or_else(|| format!("--size {} is not WxH", a.size))?;
    match a.what {
        What::Predicate => {
            let target = if a.through == "edge" {
                Target::Edge
            } else {
                Target::Vertex
            };
            let (tet, ray) = tets::through(a.family, 1.0, target, &mut crate::scenes::rng(a.seed))
                .ok_or("no case could be generated")?;
            let case = Case {
                tet,
                org: ray.org,
                dir: ray.dir,
                entry: None,
            };
            let exact =
                render::face_image(&render::predicate_grid(&case, w, &render::exact_faces)?, w);
            let gpu = crate::gpu::Gpu::new().ok();
            for m in &methods {
                let mut row = vec![exact.clone()];
                for fma in [false, true] {
                    let faces = render::predicate_grid(&case, w, &|cs| {
                        Ok(cs.iter().map(|c| crate::cases::answer(c, m, fma)).collect())
                    })?;
                    row.push(render::face_image(&faces, w));
                }
                if let Some(g) = &gpu {
                    let faces = render::predicate_grid(&case, w, &|cs| {
                        crate::cases::answers_gpu(g, cs, m)
                    })?;
                    row.push(render::face_image(&faces, w));
                }
                write(&beside(&a.out, m.name), &Image::sheet(&row, 4))?;
            }
            println!(
                "each sheet: exact | cpu | cpu-fma{}; origin moved ±{} ulps in x (right) and y (up)",
                gpu.as_ref()
                    .map_or(String::new(), |g| format!(" | gpu ({})", g.describe())),
                w / 2
            );
        }
        what => {
            let mesh = crate::scenes::load(&a.scene)?;
            let f = render::frame(&mesh, a.view, a.views.max(1), w, h, &methods, a.fma)?;
            match what {
                What::Shaded => write(&a.out, &f.shaded())?,
                What::Heat => write(&a.out, &f.heat())?,
                _ => {
                    let maps: Vec<Image> = (0..methods.len()).map(|i| f.failures(i)).collect();
                    for (m, im) in methods.iter().zip(&maps) {
                        let wrong = f
                            .wrong
                            .iter()
                            .find(|(n, _)| n == m.name)
                            .map_or(0, |(_, v)| v.iter().flatten().count());
                        write(&beside(&a.out, m.name), im)?;
                        println!("  {}: {wrong} wrong rays", m.name);
                    }
                    write(&a.out, &Image::sheet(&maps, 4))?;
                    println!(
                        "sheet order: {}",
                        methods
                            .iter()
                            .map(|m| m.name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                }
            }
        }
    }
    print!("{}", render::legend());
    Ok(ExitCode::SUCCESS)
}
