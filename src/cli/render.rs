//! `tetwalk render`: shaded renders, failure maps, heat maps, predicate and leak maps as PNG — the
//! arguments, the checks every picture shares and the files written; each picture is drawn by its
//! family's folder (`cli::render`), as the families' list says.

use super::{BackendArg, JsonOut, Status, choice};
use crate::backend::{Backend, BackendError, BackendKind};
use crate::choice::Choice;
use crate::choice::Model;
use crate::family::{self, Family};
use crate::registry::Named;
use crate::render::{self, Image};
use crate::scenes::closed::{MeshShape, TriPlace};
use crate::scenes::tets::TetShape;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum What {
    /// Flat-shaded view of the scene.
    Shaded,
    /// Each method's wrong rays coloured by kind, and a sheet of all methods side by side.
    Failures,
    /// Tetrahedra traversed per pixel.
    Heat,
    /// Seed 001's octree cells traversed per pixel by the first octree method of `--methods` (each
    /// leaf's triangles tested with `mt`), the octree of depth 8 and leaf capacity 6.
    OctreeHeat,
    /// Exit faces over a grid of ulp steps of the ray origin, per method beside the exact answer.
    Predicate,
    /// Ray–triangle methods around a shared edge of a closed mesh (a case of the stress rows' `edge`
    /// row): which of its two triangles each reports (one, the other, both, or none of the mesh: a
    /// leak) for rays exactly through the edge at points along it (the middle row) and a few ulps
    /// beside it, per method beside the exact answer.
    Leak,
}

#[derive(clap::Args)]
pub(crate) struct Args {
    /// What to draw.
    #[arg(value_enum)]
    pub(crate) what: What,
    /// The scene of `shaded`, `failures`, `heat` and `octree-heat`.
    #[command(flatten)]
    pub(crate) scene: super::SceneArg,
    /// Which of `--views` viewpoints, 0-based (placed as `tetwalk count` places them).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0)]
    pub(crate) view: usize,
    /// Viewpoints on the sphere around the model, as in `tetwalk count`.
    #[arg(long, allow_negative_numbers = true, default_value_t = 160)]
    pub(crate) views: usize,
    /// WxH for scenes; W for predicate maps (square).
    #[arg(long, default_value = "512x512")]
    pub(crate) size: String,
    /// Methods (comma-separated, or all).
    #[arg(long, default_value = "all")]
    pub(crate) methods: String,
    /// Where the methods run, for scenes (predicate and leak maps show every backend side by side,
    /// and take no other).
    #[command(flatten)]
    pub(crate) backend: BackendArg,
    /// Predicate maps: the tetrahedron's shape (`--family` is an older name for it).
    #[arg(long, alias = "family", value_parser = choice::<TetShape>(), default_value = "well")]
    pub(crate) tet_shape: TetShape,
    /// Predicate maps: what the ray goes exactly through.
    #[arg(long, value_parser = ["edge", "vertex"], default_value = "edge")]
    pub(crate) through: String,
    /// Leak maps: the closed mesh.
    #[arg(long, value_parser = choice::<MeshShape>(), default_value = "tetrahedron")]
    pub(crate) shape: MeshShape,
    /// Leak maps: where the mesh is placed.
    #[arg(long, value_parser = choice::<TriPlace>(), default_value = "embree")]
    pub(crate) place: TriPlace,
    /// Seed: of the viewpoints (as `tetwalk count --seed`), or of the predicate or leak map's case.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Output PNG (per-method images are written beside it, suffixed with the method).
    #[arg(long, default_value = "tetwalk.png")]
    pub(crate) out: PathBuf,
    /// Also write what was drawn (files, wrong rays per method) as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        self.scene
            .files(super::Files::default())
            .output("--out", Some(&self.out))
            .output("--json", self.json.as_deref())
    }
}

/// What a render drew, as `--json` writes it.
#[derive(Default, serde::Serialize)]
pub(crate) struct Drawn {
    pub(crate) files: Vec<String>,
    /// Failure maps: wrong rays per method.
    pub(crate) wrong: Vec<(String, usize)>,
    pub(crate) legend: String,
}

/// `im` written to `path` as PNG (staged), said on standard output and recorded in `drawn`.
pub(crate) fn write(path: &Path, im: &Image, drawn: &mut Drawn) -> Result<(), super::Error> {
    let png = im.png()?;
    let mut staged = super::Staged::new("--out", path)?;
    staged.write_all(&png)?;
    staged.finish()?;
    println!("{} ({}x{})", path.display(), im.width, im.height);
    drawn.files.push(path.display().to_string());
    Ok(())
}

/// The path of a per-method image beside `out`, suffixed with `suffix`.
pub(crate) fn beside(out: &Path, suffix: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("tetwalk");
    out.with_file_name(format!("{stem}-{suffix}.png"))
}

pub(crate) fn run(a: Args) -> Status {
    // The place checked writable before any work (a probe staged there and removed).
    drop(super::Staged::new("--out", &a.out)?);
    if matches!(
        a.what,
        What::Shaded | What::Failures | What::Heat | What::OctreeHeat
    ) {
        super::view_count(a.views, "render")?;
    }
    if matches!(a.what, What::Leak | What::Predicate) && a.backend.backend != BackendKind::Cpu {
        return Err(format!(
            "--backend {}: a {} map shows every backend side by side (exact | cpu | cpu-fma | gpu when there is one); leave out --backend",
            a.backend.backend.name(),
            if a.what == What::Leak { "leak" } else { "predicate" }
        )
        .into());
    }
    draw(a)
}

crate::families!(__render_families);

/// `render`'s pictures, each drawn by its family's folder (`cli::render`), from the families' list:
/// `families!(__render_families)`.
#[doc(hidden)]
#[macro_export]
macro_rules! __render_families {
    ([] { $($line:tt)* } counted { $($c:tt)* } kit { $($k:tt)* } commands { $($cm:tt)* } fuzz { $($f:tt)* } bench { $($b:tt)* } pictures { $($m:ident: [$($w:ident),*]),* } $($rest:tt)*) => {
        /// Draw what `a` asks for with the family that draws it.
        fn draw(a: Args) -> Status {
            match a.what {
                $($(What::$w)|* => $crate::family::$m::cli::render(a),)*
            }
        }
    };
}

/// The methods a picture draws (the reference left out: the others are drawn against it), the
/// `--json` output, and the picture's size; refused when it would not fit in memory, or when a
/// failure or predicate map would draw nothing.
pub(crate) fn drawn_methods<F: Family>(a: &Args) -> Result<Drawing<F>, super::Error> {
    let methods: Vec<_> = family::parse_list::<F>(&a.methods)?
        .into_iter()
        .filter(|m| !m.is_reference())
        .collect();
    let json = JsonOut::new(a.json.as_deref())?;
    let (w, h) = super::size(&a.size, true, 65536)?;
    super::fits(
        &format!("--size {w}x{h}"),
        w as u128 * h as u128 * crate::engine::count::bytes_per_ray(methods.len()) as u128,
    )?;
    if methods.is_empty() && matches!(a.what, What::Failures | What::Predicate) {
        return Err(format!(
            "--methods {}: nothing to draw, the reference is what the methods are drawn against",
            a.methods
        )
        .into());
    }
    Ok(Drawing {
        methods,
        json,
        width: w,
        height: h,
    })
}

/// What a picture draws: [`drawn_methods`].
pub(crate) struct Drawing<F: Family> {
    pub(crate) methods: Vec<&'static F::Method>,
    pub(crate) json: JsonOut,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

/// The legend printed and, with `--json`, what was drawn written.
pub(crate) fn finish(drawn: Drawn, json: JsonOut) -> Status {
    json.done(&drawn.legend, &drawn)
}

/// Predicate or leak maps: the exact panel, the key, the legend, and what a sheet shows beside the
/// backends it is drawn on (the CPU plain and fused, and the GPU where there is one).
pub(crate) struct Maps<'a> {
    pub(crate) exact: Image,
    pub(crate) key: &'a [(&'a str, [u8; 3])],
    pub(crate) legend: String,
    /// What the panels show, said after the backends.
    pub(crate) shows: String,
}

impl Maps<'_> {
    /// Each method's sheet (its heading, the exact panel and one per backend, each titled, and the
    /// key) written beside `out`, all of them into `out`, and what a sheet shows said.
    pub(crate) fn draw<M: Named>(
        self,
        out: &Path,
        json: JsonOut,
        methods: &[&M],
        heading: impl Fn(&M) -> String,
        panel: impl Fn(&M, &Backend) -> Result<Image, BackendError>,
    ) -> Status {
        let mut backends = vec![
            Backend::Cpu {
                model: Model::Plain,
            },
            Backend::Cpu {
                model: Model::Fused,
            },
        ];
        let gpu = Backend::open(BackendKind::Gpu).ok();
        let gpu_name = gpu.as_ref().map(|g| format!(" | {}", g.describe()));
        backends.extend(gpu);
        let mut drawn = Drawn::default();
        let mut sheets = Vec::new();
        for m in methods {
            let mut row = vec![("exact".to_string(), self.exact.clone())];
            for b in &backends {
                row.push((render::backend_title(b), panel(m, b)?));
            }
            let sheet = render::sheet(&heading(m), &row, self.key);
            write(&beside(out, m.name()), &sheet, &mut drawn)?;
            sheets.push(sheet);
        }
        write(out, &render::stacked(&sheets, 8), &mut drawn)?;
        println!(
            "each sheet: exact | cpu | cpu-fma{}; {}",
            gpu_name.unwrap_or_default(),
            self.shows
        );
        drawn.legend = self.legend;
        finish(drawn, json)
    }
}

/// A map that is square (predicate and leak maps) refuses `--size WxH` with `W ≠ H`.
pub(crate) fn square(text: &str, w: u32, h: u32) -> Result<(), super::Error> {
    if w != h {
        return Err(
            format!("--size {text}: this map is square, W by W pixels: give --size {w}").into(),
        );
    }
    Ok(())
}
