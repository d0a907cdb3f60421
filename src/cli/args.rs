//! The arguments commands share — `--backend`, `--fail-on`, `--t-ulps`, an answerer, a contract, a
//! WGSL function, views, sizes, lists — with their checks, and the memory budget every planned run is
//! held to.

use super::Error;
use crate::backend::{Backend, BackendKind};
use crate::choice::Choice;
use crate::engine::MEMORY_BUDGET;
use crate::exact::hit::T_ULPS;
use crate::family::Family;
use crate::family::contract::{Contract, EntryGiven, Orientation, Origin};
use crate::registry::{ByName, Registered};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use std::path::PathBuf;
use std::process::ExitCode;

/// A clap value parser for a [`Choice`]: its names are the possible values.
pub(crate) fn choice<T: Choice>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|v| v.name()))
        .map(|s| T::from_name(&s).expect("clap checked the name"))
}

/// A clap value parser for a registered method of kind `T`: the registry's names are the possible
/// values.
pub(crate) fn registered<T: Registered>() -> impl TypedValueParser<Value = ByName<T>> {
    PossibleValuesParser::new(T::registered().iter().map(|m| m.name()))
        .map(|s| ByName::named(&s).expect("clap checked the name"))
}

/// `--backend`, shared by every command that runs methods.
#[derive(clap::Args, Clone, Copy)]
pub(crate) struct BackendArg {
    /// Where the methods run: `cpu` (plain f32), `cpu-fma` (as a GPU compiles them: products
    /// contracted to fused multiply-adds), `cpu-ftz` (as a GPU that flushes subnormals computes them),
    /// `cpu-gpu` (both at once, as an NVIDIA GPU computes them) or `gpu` (WGSL through wgpu; the
    /// `exact` reference stays on the CPU).
    #[arg(long, value_parser = choice::<BackendKind>(), default_value = "cpu")]
    pub(crate) backend: BackendKind,
    /// Not an option: the FMA choice is spelled `--backend cpu-fma`.
    #[arg(long, hide = true)]
    pub(crate) fma: bool,
}

impl BackendArg {
    /// The backend asked for; the old `--fma` spelling is refused with the right one.
    pub(crate) fn open(self) -> Result<Backend, Error> {
        if self.fma {
            return Err(format!(
                "--fma is spelled --backend cpu-fma (asked for --backend {}; `gpu` runs whatever the GPU's compiler makes of the WGSL)",
                self.backend.name()
            )
            .into());
        }
        let b = Backend::open(self.backend)?;
        if let Backend::Gpu(_) = b {
            eprintln!("tetwalk: {}", b.describe());
        }
        Ok(b)
    }
}

/// What `--fail-on` fails on.
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum FailOn {
    /// Any method gave a wrong answer.
    Wrong,
    /// A method's claim was refuted (the register's claims: `exact` and `certified` never wrong, the
    /// octree's `exact` cell test never wrong, `woop-watertight` never leaks).
    Claims,
}

impl FailOn {
    pub(crate) fn name(self) -> &'static str {
        match self {
            FailOn::Wrong => "wrong",
            FailOn::Claims => "claims",
        }
    }
}

/// `--fail-on`, shared by every command that judges methods: an exit status for CI and nightly jobs.
#[derive(clap::Args, Clone, Copy, Debug)]
pub(crate) struct FailArg {
    /// Exit with status 1 when a method gave a wrong answer (`wrong`) or when a method's claim was
    /// refuted (`claims`: `exact` or `certified` wrong anywhere, the octree's `exact` too,
    /// `woop-watertight` leaking), after
    /// writing everything the run writes; one summary line per method on standard error. Without it
    /// the status says only whether the run could be made.
    #[arg(long, value_enum, value_name = "RULE")]
    pub(crate) fail_on: Option<FailOn>,
}

impl FailArg {
    /// The exit status `standings` earn under the rule, each method's summary line (and the verdict)
    /// on standard error.
    pub(crate) fn status(
        self,
        command: &str,
        standings: &[crate::engine::standing::Standing],
    ) -> ExitCode {
        let Some(rule) = self.fail_on else {
            return ExitCode::SUCCESS;
        };
        for s in standings {
            eprintln!("tetwalk {command}: {}", s.line());
        }
        let failed: Vec<&str> = standings
            .iter()
            .filter(|s| match rule {
                FailOn::Wrong => s.wrong > 0,
                FailOn::Claims => s.claim_fails(),
            })
            .map(|s| s.method.as_str())
            .collect();
        if rule == FailOn::Claims && standings.iter().all(|s| s.claim.is_none()) {
            eprintln!(
                "tetwalk {command}: --fail-on claims: no method judged here makes a claim (exact and certified claim robustness, as the octree's exact does, woop-watertight no leak)"
            );
        }
        if failed.is_empty() {
            return ExitCode::SUCCESS;
        }
        eprintln!(
            "tetwalk {command}: --fail-on {}: {}",
            rule.name(),
            failed.join(", ")
        );
        ExitCode::FAILURE
    }
}

/// `--t-ulps`: a number of ulps (0 or more, finite), or [`T_ULPS`].
pub(crate) fn t_ulps(given: Option<f64>) -> Result<f64, Error> {
    match given {
        None => Ok(T_ULPS),
        Some(u) if u.is_finite() && u >= 0.0 => Ok(u),
        Some(u) => Err(format!("--t-ulps {u} is not a number of ulps (0 or more)").into()),
    }
}

/// Most viewpoints a count or bench places.
const MAX_VIEWS: usize = crate::scenes::camera::Views::MOST;

/// `--views N` of a count or bench (`what`): 1 to [`MAX_VIEWS`].
pub(crate) fn view_count(views: usize, what: &str) -> Result<usize, Error> {
    match views {
        0 => Err(format!("--views 0: a {what} needs at least one view").into()),
        v if v > MAX_VIEWS => Err(format!(
            "--views {v}: more than the {MAX_VIEWS} viewpoints a {what} places (seed 000 has 1,282)"
        )
        .into()),
        v => Ok(v),
    }
}

/// Most ulps a near-edge or near-vertex ray is moved (2^20: beyond that it is no longer near, and
/// offsets cross binades until the coordinates leave f32's range).
const MAX_ULPS: i32 = 1 << 20;

/// `--flatness` and `--ulps` of the generated families: flatness in `[2^-126, 1]` (below the smallest
/// normal f32 the flattest families' jitter underflows to nothing), ulps in `1..=2^20`.
pub(crate) fn generator(flatness: f32, ulps: i32) -> Result<(), Error> {
    if !(flatness > 0.0 && flatness <= 1.0) {
        return Err(format!("--flatness {flatness} is not in (0, 1]").into());
    }
    if flatness < f32::MIN_POSITIVE {
        return Err(format!(
            "--flatness {flatness:e} is below 2^-126 ({:e}), the smallest normal f32: the flattest families' jitter would underflow to nothing",
            f32::MIN_POSITIVE
        )
        .into());
    }
    if !(1..=MAX_ULPS).contains(&ulps) {
        return Err(format!(
            "--ulps {ulps} is not a number of ulps in 1..={MAX_ULPS} (a near ray moved further is no longer near)"
        )
        .into());
    }
    Ok(())
}

/// Largest WGSL file `--wgsl` reads.
const MAX_WGSL: u64 = 1 << 20;

/// `--answerer CMD` and its settings: a user's program answering cases over its standard input and
/// output (docs/answerers.md), shared by `stress` and `shrink`.
#[derive(clap::Args, Clone)]
pub(crate) struct AnswererArg {
    /// A program outside tetwalk that answers cases (a shell command, started once): batches of cases
    /// on its standard input, one answer per case on its standard output (docs/answerers.md), judged
    /// in place of tetwalk's own methods.
    #[arg(long, value_name = "CMD")]
    pub(crate) answerer: Option<String>,
    /// The answerer's name in tables and found cases.
    #[arg(
        long,
        value_name = "NAME",
        default_value = "answerer",
        requires = "answerer"
    )]
    answerer_name: String,
    /// How cases and answers travel: `json` (JSON Lines, every family) or `binary` (fixed
    /// little-endian records: exit faces, triangles, octree cells).
    #[arg(long, value_parser = choice::<crate::engine::answerer::WireFormat>(), default_value = "json", requires = "answerer")]
    answerer_format: crate::engine::answerer::WireFormat,
    /// Seconds the answerer may take on one batch; past them it is stopped, with everything it
    /// started, and the run fails saying so.
    #[arg(long, value_name = "S", default_value_t = 60.0, requires = "answerer")]
    answerer_seconds: f64,
    /// Cases per batch.
    #[arg(
        long,
        value_name = "N",
        default_value_t = 10_000,
        requires = "answerer"
    )]
    answerer_batch: usize,
    /// The answerer claims what its family's methods claim when they claim: never a wrong answer
    /// (exit faces, octree cells), no leak (triangles): `stress --fail-on claims`, `count --fail-on
    /// claims` and the like hold it to that.
    #[arg(long, requires = "answerer")]
    answerer_claims: bool,
    /// Exit faces: how the answerer numbers a tetrahedron's faces, `a,b,c,d` (its face i is the
    /// case's face the i-th), or `auto` (found on well-shaped cases, reported, applied; an error when
    /// none fits) [default: 0,1,2,3].
    #[arg(long, value_name = "FACES", requires = "answerer")]
    faces: Option<String>,
}

/// An error unless `name` is a plain name (a found case's folder is named after it): letters, digits,
/// `.`, `_` and `-`, beginning with a letter or digit, at most 64 characters.
fn plain_name(name: &str) -> Result<(), Error> {
    let ok = !name.is_empty()
        && name.len() <= 64
        && name.starts_with(|c: char| c.is_ascii_alphanumeric())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'));
    match ok {
        true => Ok(()),
        false => Err(format!(
            "--answerer-name '{}' is not a plain name: letters, digits, '.', '_' and '-', beginning with a letter or digit, at most 64 characters (found cases are filed in a folder of that name)",
            name.chars().take(80).collect::<String>()
        )
        .into()),
    }
}

impl AnswererArg {
    /// The answerer started, if one is given, its face numbering set (found with `well` cases of
    /// the contract `k` under `auto`).
    pub(crate) fn start<F: Family>(
        &self,
        k: &Contract,
    ) -> Result<Option<crate::engine::answerer::Answerer>, Error> {
        use crate::engine::answerer::{Answerer, find_numbering};
        use crate::engine::numbering::parse_faces;
        let Some(cmd) = &self.answerer else {
            return Ok(None);
        };
        if !(self.answerer_seconds > 0.0 && self.answerer_seconds <= 1e6) {
            return Err(format!(
                "--answerer-seconds {} is not in (0, 1e6]",
                self.answerer_seconds
            )
            .into());
        }
        if self.answerer_batch == 0 || self.answerer_batch > 1_000_000 {
            return Err(format!(
                "--answerer-batch {} is not 1 to 1,000,000 cases",
                self.answerer_batch
            )
            .into());
        }
        plain_name(&self.answerer_name)?;
        if crate::family::by_name::<F>(&self.answerer_name).is_ok() || self.answerer_name == "all" {
            return Err(format!(
                "--answerer-name {}: that names tetwalk's own; name the answerer otherwise",
                self.answerer_name
            )
            .into());
        }
        if self.faces.is_some() && !F::FACES {
            return Err(format!(
                "--faces numbers a tetrahedron's faces; {} cases have none",
                F::NAME
            )
            .into());
        }
        let mut a = Answerer::start(
            &self.answerer_name,
            cmd,
            self.answerer_format,
            std::time::Duration::from_secs_f64(self.answerer_seconds),
            self.answerer_batch,
        )?;
        a.claims = self.answerer_claims;
        match self.faces.as_deref() {
            None => {}
            Some("auto") => {
                let (faces, cases) = find_numbering::<F>(&a, k)?;
                a.faces = faces;
                eprintln!(
                    "tetwalk: {}'s face i is the case's face {:?}[i] (found on {cases} well-shaped cases, each asked in every numbering; give --faces {} to skip the search)",
                    a.name,
                    a.faces,
                    a.faces.map(|f| f.to_string()).join(",")
                );
            }
            Some(f) => a.faces = parse_faces(f)?,
        }
        Ok(Some(a))
    }
}

/// What a kernel assumes of its cases (docs/answerers.md, "Contracts"), shared by `stress`,
/// `gen-cases` and `shrink`: every case made or tried holds it.
#[derive(clap::Args, Clone)]
pub(crate) struct ContractArg {
    /// Exit faces: where each ray's origin may lie — `anywhere` (the rows' own: inside or before),
    /// `before` the entry face, on the `entry` face (or as near it inside as f32 allows), or `inside`
    /// the tetrahedron; several comma-separated (`inside,entry`), each case made for one in turn.
    #[arg(long, value_parser = choice::<Origin>(), value_delimiter = ',', default_value = "anywhere")]
    origin: Vec<Origin>,
    /// Directions of length 1 (rounded to f32; each case judged as it then is).
    #[arg(long)]
    unit_direction: bool,
    /// Exit faces: whether cases carry their entry face — `any` (every other case), `given` (all)
    /// or `none`.
    #[arg(long, value_parser = choice::<EntryGiven>(), default_value = "any")]
    entry: EntryGiven,
    /// Exit faces: `positive` tetrahedra only, `negative` ones only (TetGen's order: every case
    /// mirrored), or `any` orientation (half the cases mirrored).
    #[arg(long, value_parser = choice::<Orientation>(), default_value = "positive")]
    orientation: Orientation,
    /// Exit faces: lines within this distance of an edge, relative to the longest edge, are outside
    /// the contract (a kernel's epsilon); 0 for none.
    #[arg(long, value_name = "REL", default_value_t = 0.0)]
    tolerance: f64,
}

impl ContractArg {
    /// An error where `--scale` scales what the contract then undoes: a direction scaled by 2^D
    /// and made a unit one again.
    pub(crate) fn at_scale(&self, scale: crate::family::Scale) -> Result<(), Error> {
        // `--scale E` scales the direction too.
        if self.unit_direction && scale.direction != 0 {
            return Err(format!(
                "--scale {}/{} scales the directions by 2^{}, which --unit-direction undoes (every direction has length 1): give --scale {}/0",
                scale.points, scale.direction, scale.direction, scale.points
            )
            .into());
        }
        Ok(())
    }

    /// Whether it states nothing beyond what the rows make (every flag at its default).
    pub(crate) fn is_default(&self) -> bool {
        self.origin.iter().all(|&o| o == Origin::Anywhere)
            && !self.unit_direction
            && self.entry == EntryGiven::Any
            && self.orientation == Orientation::Positive
            && self.tolerance == 0.0
    }

    /// The contract, checked for family `F` (only exit faces hold more than a unit direction).
    pub(crate) fn contract<F: Family>(&self) -> Result<Contract, Error> {
        if self.origin.len() > 1 && self.origin.contains(&Origin::Anywhere) {
            return Err(format!(
                "--origin {}: anywhere already allows every placement; give it alone, or the placements (before, entry, inside) without it",
                self.origin.iter().map(|o| o.name()).collect::<Vec<_>>().join(",")
            )
            .into());
        }
        let k = Contract {
            origin: crate::family::contract::Origins::of(&self.origin),
            unit_direction: self.unit_direction,
            entry: self.entry,
            orientation: self.orientation,
            tolerance: self.tolerance,
        };
        k.check_for::<F>()?;
        Ok(k)
    }
}

/// `--wgsl FILE`: a user's exit-face function in WGSL, judged on the GPU as method `user`.
#[derive(clap::Args)]
pub(crate) struct WgslArg {
    /// A WGSL file defining `user_prepare` and `user_exit` (user guide, docs/your-own.md),
    /// spliced into the GPU's shader and judged as method `user` beside the methods listed (needs
    /// --backend gpu).
    #[arg(long, value_name = "FILE")]
    pub(crate) wgsl: Option<PathBuf>,
}

impl WgslArg {
    /// The backend `b` asks for and the methods of family `F` `list` names, the user's WGSL method
    /// first when `--wgsl` gives one (the GPU opened with it, after the compiler has checked it).
    pub(crate) fn open<F: Family>(
        &self,
        b: BackendArg,
        list: &str,
    ) -> Result<(Backend, Vec<&'static F::Method>), Error> {
        let mut methods = crate::family::parse_list::<F>(list)?;
        let Some(path) = &self.wgsl else {
            return Ok((b.open()?, methods));
        };
        let Some(user) = F::user_wgsl() else {
            return Err(format!(
                "--wgsl {} takes an exit-face function (exit faces and walks), not {} methods",
                path.display(),
                F::NAME
            )
            .into());
        };
        if b.fma || b.backend != BackendKind::Gpu {
            return Err(format!(
                "--wgsl {} runs a WGSL function on the GPU: add --backend gpu",
                path.display()
            )
            .into());
        }
        let size = std::fs::metadata(path)
            .map_err(|e| format!("--wgsl {}: {e}", path.display()))?
            .len();
        if size > MAX_WGSL {
            return Err(format!(
                "--wgsl {}: {size} bytes, more than the {MAX_WGSL} a shader function may hold",
                path.display()
            )
            .into());
        }
        let source =
            std::fs::read_to_string(path).map_err(|e| format!("--wgsl {}: {e}", path.display()))?;
        let backend = Backend::gpu_with_user(&path.display().to_string(), &source)?;
        eprintln!("tetwalk: {}", backend.describe());
        methods.insert(0, user);
        Ok((backend, methods))
    }
}

/// Refuse `what` when it would need more than [`MEMORY_BUDGET`] bytes.
pub(crate) fn fits(what: &str, bytes: u128) -> Result<(), Error> {
    if bytes > MEMORY_BUDGET as u128 {
        return Err(format!(
            "{what} would need about {:.1} GiB of memory; tetwalk plans at most {} GiB at once",
            bytes as f64 / (1u64 << 30) as f64,
            MEMORY_BUDGET >> 30
        )
        .into());
    }
    Ok(())
}

/// The backends of a list (`--backend cpu,gpu`) opened, each once, in order.
pub(crate) fn open_each(kinds: &[BackendKind]) -> Result<Vec<Backend>, Error> {
    let mut backends = Vec::new();
    for (i, &k) in kinds.iter().enumerate() {
        if !kinds[..i].contains(&k) {
            backends.push(Backend::open(k)?);
        }
    }
    Ok(backends)
}

/// The scene a command loads and walks.
#[derive(clap::Args)]
pub(crate) struct SceneArg {
    /// A built-in scene (bunny-quality, bunny-cdt, bunny-quality-far, bunny-far, bunny-paper once built
    /// by corpora/scenes/bunny-paper.sh, kuhn, jitter, fan and their -far), a TetGen stem, or a Gmsh `.msh` (4.1 or 2.2), VTK `.vtk` / `.vtu` or MEDIT `.mesh`
    /// file (its triangles the constrained faces).
    #[arg(long, default_value = "bunny-quality")]
    pub(crate) scene: String,
    /// Accept a scene without constrained faces (no TetGen `.face` or an empty one, no triangles in
    /// another format): every ray then leaves the mesh.
    #[arg(long)]
    pub(crate) no_faces: bool,
}

impl SceneArg {
    /// The scene loaded, with its name.
    pub(crate) fn load(&self) -> Result<crate::scenes::Loaded, crate::mesh::MeshError> {
        crate::scenes::load(&self.scene, faces(self.no_faces))
    }

    /// The files the scene is read from, which no output may be.
    pub(crate) fn files(&self, files: super::Files) -> super::Files {
        files.scene("--scene", &self.scene)
    }
}

/// Whether a scene must have constrained faces (`--no-faces` says it need not).
pub(crate) fn faces(no_faces: bool) -> crate::mesh::Faces {
    if no_faces {
        crate::mesh::Faces::Optional
    } else {
        crate::mesh::Faces::Required
    }
}

/// Parse `WxH` (or `W` for a square when `square` is allowed), each side in 1..=`max`.
pub(crate) fn size(text: &str, square: bool, max: u32) -> Result<(u32, u32), Error> {
    let parse = |s: &str| s.trim().parse::<u32>().ok().filter(|&v| v >= 1 && v <= max);
    let wh = match text.split_once('x') {
        Some((w, h)) => parse(w).zip(parse(h)),
        None if square => parse(text).map(|w| (w, w)),
        None => None,
    };
    wh.ok_or_else(|| {
        format!(
            "--size {text} is not {}, each side 1..={max}",
            if square { "W or WxH" } else { "WxH" }
        )
        .into()
    })
}
