//! `tetwalk count`: wrong rays per image, per method, on a scene.

use crate::methods::parse_list;
use crate::report::count::{self, Settings};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// A built-in scene (bunny-quality, bunny-cdt, bunny-quality-far, bunny-far, kuhn, jitter, fan and their
    /// -far), or a
    /// TetGen stem.
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// Viewpoints on a sphere around the model.
    #[arg(long)]
    views: Option<usize>,
    /// Image size, WxH.
    #[arg(long)]
    size: Option<String>,
    /// Methods to judge (comma-separated, or all); `exact` is the reference and always runs.
    #[arg(long, default_value = "all")]
    methods: String,
    /// Where the methods run: `cpu`, `cpu-fma` (as a GPU compiles them), or `gpu` (WGSL through wgpu).
    #[arg(long, value_parser = ["cpu", "cpu-fma", "gpu"], default_value = "cpu")]
    backend: String,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// `paper`: seed 000's 1,282 views of 1024x1024.
    #[arg(long, value_parser = ["paper"])]
    preset: Option<String>,
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(a: Args) -> Result<ExitCode, String> {
    let methods: Vec<_> = parse_list(&a.methods)?
        .into_iter()
        .filter(|m| m.name != "exact")
        .collect();
    let paper = a.preset.is_some();
    let views = a.views.unwrap_or(if paper { 1282 } else { 160 });
    let size = a
        .size
        .unwrap_or_else(|| if paper { "1024x1024" } else { "256x256" }.into());
    let (w, h) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| w > 0 && h > 0)
        .ok_or_else(|| format!("--size {size} is not WxH"))?;
    let mesh = crate::scenes::load(&a.scene)?;
    let settings = Settings {
        scene: a.scene,
        views,
        width: w,
        height: h,
        seed: a.seed,
        fov_deg: 40.0,
    };
    let backend: Box<dyn count::Backend> = if a.backend == "gpu" {
        let gpu = crate::gpu::Gpu::new().map_err(|e| e.to_string())?;
        Box::new(count::Gpu::new(gpu, &mesh))
    } else {
        Box::new(count::Cpu {
            fma: a.backend == "cpu-fma",
        })
    };
    let bar = super::progress(views as u64, "views");
    let report = count::run(&mesh, &settings, &methods, backend.as_ref(), &|| bar.inc(1))?;
    bar.finish_and_clear();
    print!("{}", report.markdown());
    super::write_json(a.json.as_deref(), &report)?;
    Ok(ExitCode::SUCCESS)
}
