//! `tetwalk count`: wrong rays per image, per method, on a scene, for every family that counts one.

use super::{BackendArg, Error, FailArg, JsonOut, Status, WgslArg};
use crate::choice::Choice;
use crate::engine::count::{self, AnswerSource, CountSettings, ReferenceWalk, Shard};
use crate::engine::standing::Standings;
use crate::family::CountKind;
use crate::family::contract::Contract;
use crate::family::count::Counted;
use crate::family::wrong::WrongRay;
use crate::report::count::CountFormats;
use crate::scenes::camera::Views;
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub(crate) struct Args {
    #[command(subcommand)]
    merge: Option<Merge>,
    /// Which family: `walk` (the exit-face methods' walks through the tetrahedra, seed 000 Table 4;
    /// `exit-face` says the same), `triangle` (each primary ray's nearest hit among the scene's
    /// constrained faces, every triangle tested, seed 004's methods) or `octree` (each primary ray
    /// walked through seed 001's octree over those faces); each judged against the reference walk's
    /// exact first hit.
    #[arg(long, value_parser = count_family(), default_value = "walk")]
    family: CountKind,
    #[command(flatten)]
    own: FamilyFlags,
    #[command(flatten)]
    pub(crate) scene: super::SceneArg,
    /// Viewpoints on a sphere around the model [default: 160, 16 with --family triangle or octree, or
    /// 1282 with --preset paper].
    #[arg(long, allow_negative_numbers = true)]
    views: Option<usize>,
    /// Image size, WxH [default: 256x256 (128x128 with --family triangle), or 1024x1024 with
    /// --preset paper].
    #[arg(long)]
    size: Option<String>,
    /// Methods to judge (comma-separated, or all); the reference always runs [default: all; none
    /// beside an --answerer].
    #[arg(long)]
    methods: Option<String>,
    #[command(flatten)]
    answerer: super::AnswererArg,
    /// What the answerer assumes of each step it is asked (docs/answerers.md, "Contracts"): each
    /// step's case is made under it from the line the previous step's case followed.
    #[command(flatten)]
    contract: super::ContractArg,
    /// The walk every method is judged against: `exact`, or `certified` (proven to end where `exact`
    /// ends, step for step, and several times faster).
    #[arg(long, value_parser = reference_walk(), default_value_t)]
    reference: ReferenceWalk,
    /// Re-judge about this many rays, chosen by the seed, with the full `exact` walk; a disagreement
    /// with the reference is an error that stops the count.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1000)]
    audit: u64,
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    wgsl: WgslArg,
    #[command(flatten)]
    fail: FailArg,
    /// Seed of the viewpoints' rotation (`render` places views the same way for the same seed).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// `paper`: seed 000's 1,282 views of 1024x1024.
    #[arg(long, value_parser = ["paper"])]
    preset: Option<String>,
    /// Count only views `v` with `v % N == I` (`I/N`, 0-based): one of N disjoint slices, whose reports
    /// `tetwalk count merge` adds up to the whole count's exactly.
    #[arg(long, default_value = "0/1")]
    shard: String,
    /// `all`: count again under each of the 12 orientation-preserving relabellings of the tetrahedra
    /// (the same for the whole mesh), 12 times the work, and give each method's wrong rays with the
    /// mesh's own labelling beside their min / median / max.
    #[arg(long, value_parser = ["all"])]
    relabel: Option<String>,
    /// Also write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Instead of counting, write the exact inputs of every ray the count would walk, for another
    /// program's kernel: a header line (scene, views, shard), then per ray `{"view", "pixel": [x, y],
    /// "org", "dir", "start"}` (`start`: the tetrahedron holding the camera). `tetwalk scene export`
    /// writes the mesh; `tetwalk judge FILE ANSWERS` judges the walks.
    #[arg(long, value_name = "FILE")]
    rays_out: Option<PathBuf>,
    /// Write every wrong ray here, one JSON line each (view, pixel, the ray, where the method and the
    /// `exact` walk stopped, the first wrong step, the distance from the edge, the count's family, views
    /// and settings); `tetwalk replay` reads it.
    #[arg(long)]
    dump: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        match &self.merge {
            Some(Merge::Merge { reports, json }) => super::Files::default()
                .inputs("REPORTS", reports)
                .output("--json", json.as_deref()),
            None => self
                .scene
                .files(super::Files::default())
                .input("--wgsl", self.wgsl.wgsl.as_deref())
                .output("--json", self.json.as_deref())
                .output("--dump", self.dump.as_deref())
                .output("--rays-out", self.rays_out.as_deref()),
        }
    }
}

#[derive(clap::Subcommand)]
enum Merge {
    /// Add up the JSON reports of a sharded count (`--shard I/N`, every I once) into one, of one
    /// family.
    Merge {
        /// The shards' reports (`count --shard I/N --json FILE`).
        #[arg(required = true)]
        reports: Vec<PathBuf>,
        /// Also write the merged report as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

/// `count --family`: a counted family's name, or one of its [`Counted::COUNT_ALIASES`] (`exit-face`
/// for `walk`).
/// `--reference`'s values: the walks tetwalk vouches for as robust.
fn reference_walk() -> impl clap::builder::TypedValueParser<Value = ReferenceWalk> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(ReferenceWalk::vouched().map(|r| r.name()))
        .map(|n| ReferenceWalk::named(&n).expect("clap checked the name"))
}

fn count_family() -> impl clap::builder::TypedValueParser<Value = CountKind> {
    use clap::builder::TypedValueParser;
    let named: Vec<(&str, CountKind)> = CountKind::ALL
        .iter()
        .flat_map(|&k| {
            let aliases = crate::with_counted!(k, F => F::COUNT_ALIASES);
            std::iter::once(k.name())
                .chain(aliases.iter().copied())
                .map(move |n| (n, k))
        })
        .collect();
    let names: Vec<&'static str> = named.iter().map(|(n, _)| *n).collect();
    clap::builder::PossibleValuesParser::new(names).map(move |s| {
        named
            .iter()
            .find(|(n, _)| *n == s)
            .map(|(_, k)| *k)
            .expect("one of the possible values")
    })
}

fn merge(reports: &[PathBuf], json: Option<&std::path::Path>) -> Status {
    let out = JsonOut::new(json)?;
    let read: Vec<(String, serde_json::Value)> = super::read_reports(reports)?;
    crate::with_counted!(count::shards_family(&read)?, F => {
        let m = count::merge(&count::read_shards::<F>(read)?)?;
        out.done(&m.table(), &m)
    })
}

/// `I/N` with `I < N`.
pub(super) fn shard(text: &str) -> Result<Shard, Error> {
    text.split_once('/')
        .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)))
        .filter(|&(i, n)| n >= 1 && i < n)
        .map(|(index, count)| Shard { index, count })
        .ok_or_else(|| format!("--shard {text} is not I/N with 0 <= I < N").into())
}

/// What a counted family's own flags set, and what its count adds (its folder's `cli.rs`).
pub(crate) trait Flags: CountFormats {
    /// Its own flags, from among every counted family's.
    type Flags;
    fn own(all: &FamilyFlags) -> &Self::Flags;
    fn settings(own: &Self::Flags) -> Self::CountSettings;
    /// Whether its count can ask an `--answerer` every step of every walk.
    const ASKS: bool = false;
    /// The `--answerer` started under the contract `k` states, asked as [`Flags::asking`] says
    /// (only where [`Flags::ASKS`]), with that contract.
    fn start(
        _a: &super::AnswererArg,
        _k: &super::ContractArg,
    ) -> Result<Option<(crate::engine::answerer::Answerer, Contract)>, Error> {
        Ok(None)
    }
    /// The walks an answerer gives, asked step by step through `mesh` under contract `k` (`None`
    /// unless [`Flags::ASKS`]).
    fn asking<'a>(
        _x: &'a crate::engine::answerer::Answerer,
        _mesh: &'a crate::mesh::Mesh,
        _k: Contract,
    ) -> Option<Box<count::GivenWalks<'a>>> {
        None
    }
    /// `--rays-out`: the exact inputs of every ray the count would walk, for another program's kernel;
    /// refused where the family has none to write.
    fn rays_out(_a: &Args, _shard: Shard, _path: &std::path::Path) -> Status {
        Err(RAYS_OUT_ALONE.into())
    }
    /// Whether it writes `--rays-out` files ([`Flags::rays_out`]), which `judge` judges with
    /// [`Flags::judge_rays`].
    const RAYS_OUT: bool = false;
    /// `judge` on a `--rays-out` file of its count: `header` (the file's first line), then the rays in
    /// `input`, the walks given for them in `a`'s answers judged as the count judges them.
    fn judge_rays(
        _a: &crate::cli::judge::Args,
        _header: serde_json::Value,
        _input: Box<dyn std::io::BufRead + Send>,
    ) -> Status {
        Err(RAYS_OUT_ALONE.into())
    }
}

/// Why `--rays-out` is refused with other flags or families.
pub(crate) const RAYS_OUT_ALONE: &str = "--rays-out writes the inputs of a walk count and judges nothing: leave out --family triangle or octree, --wgsl, --relabel, --dump and --fail-on";

/// Every counted family's own flags, each from its folder (`src/family/NAME/cli.rs`), from the
/// families' list.
#[doc(hidden)]
#[macro_export]
macro_rules! __count_flags {
    ([] { $($(#[$doc:meta])* $v:ident => $n:literal, $ty:path, $m:ident;)* } counted { $($c:ident: $cm:ident),* } $($rest:tt)*) => {
        /// Every counted family's own flags.
        #[derive(clap::Args)]
        pub(crate) struct FamilyFlags {
            $(
                #[command(flatten)]
                pub $cm: $crate::family::$cm::cli::CountFlags,
            )*
        }
    };
}
crate::families!(__count_flags);

pub(crate) fn run(a: Args) -> Status {
    if let Some(Merge::Merge { reports, json }) = &a.merge {
        return merge(reports, json.as_deref());
    }
    let shard = shard(&a.shard)?;
    if let Some(path) = &a.rays_out {
        if a.wgsl.wgsl.is_some()
            || a.relabel.is_some()
            || a.dump.is_some()
            || a.fail.fail_on.is_some()
        {
            return Err(RAYS_OUT_ALONE.into());
        }
        return crate::with_counted!(a.family, F => F::rays_out(&a, shard, path));
    }
    crate::with_counted!(a.family, F => counted::<F>(a, shard))
}

/// The count of family `F`.
fn counted<F: Flags>(a: Args, shard: Shard) -> Status {
    let family = F::settings(F::own(&a.own));
    F::check(&family)?;
    let fail = a.fail;
    let asked = a.answerer.answerer.is_some();
    if asked && !F::ASKS {
        return Err(format!(
            "--answerer walks the tetrahedra step by step (--family walk); {} counts have no exit faces to ask",
            F::NAME
        )
        .into());
    }
    if !asked && !a.contract.is_default() {
        return Err("--origin, --entry, --orientation, --unit-direction and --tolerance state what an --answerer assumes of each step; tetwalk's methods walk as published: give --answerer, or leave them out".into());
    }
    if asked && a.relabel.is_some() {
        return Err("--relabel walks relabelled meshes; an --answerer is asked about the scene's own: leave out --relabel".into());
    }
    let list = match (&a.methods, asked) {
        (Some(m), _) => m.clone(),
        (None, false) => "all".into(),
        (None, true) => "none".into(),
    };
    let (backend, methods) = a
        .wgsl
        .open::<F>(a.backend, if list == "none" { "all" } else { &list })?;
    let methods = if list == "none" { Vec::new() } else { methods };
    let out = JsonOut::new(a.json.as_deref())?;
    let mut dump = Dump::new(a.dump.as_deref())?;
    let views = views::<F>(
        &a,
        methods.len() + usize::from(a.answerer.answerer.is_some()),
    )?;
    held(shard, views.views)?;
    let scene = a.scene.load()?;
    let outside = F::start(&a.answerer, &a.contract)?;
    let settings = CountSettings::<F> {
        views,
        reference: a.reference,
        family,
        audit: a.audit,
        shard,
        answerer: outside.as_ref().map(|(x, k)| x.asked(k)),
    };
    let labellings = if a.relabel.is_some() {
        count::RELABELLINGS
    } else {
        1
    };
    let bar = super::progress(
        "count",
        (shard.held(views.views) * labellings) as u64,
        "views",
    );
    let asking = outside
        .as_ref()
        .and_then(|(x, k)| F::asking(x, &scene.mesh, *k));
    let given = outside.as_ref().map(|(x, _)| x).zip(asking.as_deref());
    let answerers = AnswerSource::<F>::judged(
        given.map(|(x, asking)| (x.name.as_str(), asking)),
        methods.iter().copied(),
        settings.reference,
    );
    let mut write = |w: &WrongRay| dump.write(w);
    // The mesh's own labelling gives the report and the dump.
    let mut report = count::run(
        &scene,
        &settings,
        &answerers,
        &backend,
        &|| bar.inc(1),
        Some(&mut write),
    )?;
    if labellings > 1 {
        count::relabel_all(&mut report, &scene, &answerers, &backend, &|| bar.inc(1))?;
    }
    bar.finish_and_clear();
    if let Some((x, _)) = &outside {
        x.finish()?;
    }
    dump.finish()?;
    print!("{}", report.table());
    out.finish(&report)?;
    Ok(fail.status(
        "count",
        &report.standings_with(outside.as_ref().map(|(x, _)| x)),
    ))
}

/// `--dump FILE`: every wrong ray, one JSON line each, the file complete or absent.
pub(crate) struct Dump(Option<super::Staged>);

impl Dump {
    pub(crate) fn new(path: Option<&std::path::Path>) -> Result<Dump, super::Error> {
        Ok(Dump(
            path.map(|p| super::Staged::new("--dump", p)).transpose()?,
        ))
    }

    pub(crate) fn write(&mut self, w: &WrongRay) -> std::io::Result<()> {
        let Some(d) = self.0.as_mut() else {
            return Ok(());
        };
        serde_json::to_writer(&mut *d, w)?;
        d.write_all(b"\n")
    }

    pub(crate) fn finish(self) -> Result<(), super::Error> {
        self.0.map_or(Ok(()), |d| d.finish())
    }
}

/// A shard that holds at least one of the `views` (`--shard 5/10` of 3 views holds none).
pub(crate) fn held(shard: Shard, views: usize) -> Result<(), super::Error> {
    if shard.held(views) == 0 {
        return Err(format!(
            "--shard {}/{} holds no view of the {views} (views v with v % {} == {})",
            shard.index, shard.count, shard.count, shard.index
        )
        .into());
    }
    Ok(())
}

/// The views a count of `methods` methods asks for: `--views` and `--size`, else seed 000's with
/// `--preset paper`, else the family's; a view larger than the memory it needs allows is refused.
pub(crate) fn views<F: Counted>(a: &Args, methods: usize) -> Result<Views, super::Error> {
    let (views, size) = F::DEFAULT_VIEWS;
    let paper = a.preset.is_some();
    let views = super::view_count(a.views.unwrap_or(if paper { 1282 } else { views }), "count")?;
    let size = a
        .size
        .clone()
        .unwrap_or_else(|| if paper { "1024x1024" } else { size }.into());
    let (width, height) = super::size(&size, false, 65536)?;
    super::fits(
        &format!("--size {width}x{height}"),
        width as u128 * height as u128 * crate::engine::count::bytes_per_ray(methods) as u128,
    )?;
    Ok(Views::new(views, width, height, a.seed))
}
