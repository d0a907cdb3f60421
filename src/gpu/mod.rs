//! The methods and the walk as WGSL compute shaders, run through `wgpu` on whatever adapter there is
//! (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME` respected), headless. The shader and its buffer layouts are
//! generated from the Rust definitions ([`shader`]).

use crate::choice::{Choice, Traffic};
use crate::mesh::Mesh;
use crate::mesh::layout::Layout;
use crate::methods::Model;
use crate::methods::triangle::Nearest;
use crate::registry::{GpuVersion as GpuSupport, Method, Named, OctreeMethod, TriangleMethod};
use crate::tet::{Ray, Tet};
use crate::walk::layouts::{LayoutKind, LayoutOutcome, Source};
use crate::walk::{Outcome, OutcomeKind, Walk};
use rayon::prelude::*;
use shader::binding::{
    CASES, CELLS, COUNTERS, ENDINGS, FACEINFO, FACES, HIT_FACES, LAYOUT_RAYS, LAYOUT_WORDS, OCTREE,
    OCTREE_BOXES, OCTREE_TRIS, PARAMS, POINTS, RAYS, REFERENCE, SENT,
};
use shader::{Ending, GROUP, Params};
use std::collections::HashMap;
use std::sync::Mutex;
use wgpu::util::DeviceExt;

pub mod export;
pub mod shader;

/// What the shader writes for "no exit face".
pub(crate) const NONE: i32 = -1;

/// Why the GPU cannot be used, or what went wrong on it.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found{0} (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe)"
    )]
    NoAdapter(String),
    #[error("the GPU device could not be opened: {0}")]
    Device(String),
    #[error("the shader did not compile on this adapter: {0}")]
    Shader(String),
    /// A user's WGSL (`--wgsl`) that does not compile, with the compiler's message.
    #[error("{0}")]
    UserWgsl(String),
    #[error("method '{method}' has no GPU version: {why}")]
    NoGpuMethod {
        method: &'static str,
        why: &'static str,
    },
    #[error(
        "method '{0}' has no layout walk (seed 003's layouts are walked by the 2-D frame methods)"
    )]
    NoLayoutWalk(&'static str),
    #[error("reading results back from the GPU failed: {0}")]
    Readback(String),
    #[error("the GPU wrote outcome code {0}, which no outcome kind has")]
    BadOutcome(u32),
    #[error("walks compared on the GPU with no reference walk of the same rays kept there")]
    NoReference,
    #[error(
        "{0} rays are too many to keep on the GPU as a reference walk (one binding holds them)"
    )]
    TooManyToKeep(usize),
}

/// The module with a user's WGSL spliced in, parsed and validated: an error in their lines is shown
/// with their file's name and line numbers; one in tetwalk's part (their functions missing or of
/// another type than the call expects) says what the call expects.
fn user_module(path: &str, source: &str) -> Result<String, GpuError> {
    use wgpu::naga;
    let module = shader::with_user(source);
    let theirs = source.lines().count() as u32;
    let explain = |at: Option<naga::SourceLocation>, snippet: String, message: String| {
        if at.is_some_and(|l| l.line_number <= theirs) {
            GpuError::UserWgsl(snippet)
        } else {
            GpuError::UserWgsl(format!(
                "{path}: tetwalk's call of your functions does not compile: {message}\n{path} must define\n{}",
                shader::USER_SIGNATURE
            ))
        }
    };
    let parsed = naga::front::wgsl::parse_str(&module).map_err(|e| {
        explain(
            e.location(&module),
            e.emit_to_string_with_path(&module, path),
            e.to_string(),
        )
    })?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&parsed)
    .map_err(|e| {
        explain(
            e.location(&module),
            e.emit_to_string_with_path(&module, path),
            {
                // The validator's reason is at the end of its error's chain.
                let mut m = e.as_inner().to_string();
                let mut at: Option<&dyn std::error::Error> =
                    std::error::Error::source(e.as_inner());
                while let Some(x) = at {
                    m += &format!(": {x}");
                    at = x.source();
                }
                m
            },
        )
    })?;
    Ok(module)
}

impl shader::Case {
    /// A case as the shader reads it.
    pub(crate) fn new(tet: &Tet, ray: &Ray, entry: Option<usize>) -> shader::Case {
        let [v0, v1, v2, v3] = tet.map(|p| p.extend(0.0).to_array());
        shader::Case {
            v0,
            v1,
            v2,
            v3,
            org: ray.org.extend(0.0).to_array(),
            dir: ray.dir.extend(0.0).to_array(),
            entry: entry.map_or(-1, |e| e as i32),
            pad0: 0,
            pad1: 0,
            pad2: 0,
        }
    }
}

/// Adapters found, one line each: name, backend, device type, driver.
pub(crate) fn adapters() -> Vec<String> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
        .iter()
        .map(|a| describe(&a.get_info()))
        .collect()
}

fn describe(i: &wgpu::AdapterInfo) -> String {
    format!(
        "{} ({:?}, {:?}, driver {} {})",
        i.name, i.backend, i.device_type, i.driver, i.driver_info
    )
}

/// A GPU with the shader module; each method's pipelines are compiled when first used, and the
/// buffers a dispatch needs are kept and grown, never made anew per call.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    module: wgpu::ShaderModule,
    pipelines: Mutex<HashMap<String, wgpu::ComputePipeline>>,
    /// What the module's names are prefixed with: [`shader::USER_PREFIX`] around a user's WGSL.
    prefix: &'static str,
    info: wgpu::AdapterInfo,
    max_groups: u32,
    /// The largest buffer one binding may see.
    max_binding: u64,
    /// Timestamp queries, where the adapter has them: kernel time apart from transfers.
    timestamps: Option<wgpu::QuerySet>,
    scratch: Mutex<HashMap<&'static str, wgpu::Buffer>>,
    /// Every byte written to the GPU and read back, and the kernel time measured, since it was opened.
    traffic: Mutex<Traffic>,
    /// The rays whose reference walk is kept on the GPU ([`After::Keep`]): how many, and a
    /// fingerprint of them, which the walks compared with it must match.
    kept_rays: Mutex<Option<(usize, u64)>>,
    /// Readback buffers of dispatches whose output stays on the GPU, returned when read.
    readbacks: Mutex<Vec<wgpu::Buffer>>,
    /// How many dispatches have sent records back into the kept `sent` buffer (the last one's are
    /// there).
    last_sent: Mutex<u64>,
}

/// An entry point of the module and the override constants its pipeline is compiled with.
#[derive(Clone, Copy, Debug)]
struct Entry<'a> {
    name: &'a str,
    constants: &'a [(&'static str, f64)],
}

impl<'a> Entry<'a> {
    /// An entry point with no override constants.
    fn plain(name: &'a str) -> Entry<'a> {
        Entry {
            name,
            constants: &[],
        }
    }
}

/// One dispatch's work: the entry point; its items, item `i` made by `input.1(i)` and uploaded to
/// binding `input.0`; `limit` ([`Params::limit`]); the (binding, buffer) pairs made beforehand; and
/// the binding read back.
struct Job<'a, I> {
    entry: Entry<'a>,
    count: usize,
    limit: u32,
    input: (u32, &'a (dyn Fn(usize) -> I + Sync)),
    bound: &'a [(u32, &'a wgpu::Buffer)],
    out_at: u32,
    /// What becomes of the output.
    after: After,
    /// Where the items bound at `input.0` are.
    items: Items<'a>,
    /// With [`After::Compare`], where each triangle a hit names came from (`compare_hits`); `None`
    /// where the endings are the mesh's (`compare_endings`).
    hits: Option<&'a wgpu::Buffer>,
    /// With [`After::Keep`], the items (in the batch, ascending) whose outputs are read back.
    picked: &'a [usize],
    /// The index of the dispatch's first item in the batch ([`Gpu::dispatch`] sets it).
    first: usize,
}

/// What becomes of a dispatch's output (walk endings, for the last two).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum After {
    /// Read back.
    Read,
    /// Kept on the GPU as the reference walk's endings (`compare_endings` and `compare_hits` read
    /// them) and not read back, but for the picked items': the steps summed there and the walks it
    /// flagged sent back (`hold_endings`), for the CPU to walk ([`Gpu::amend_reference`]).
    Keep,
    /// Compared there with the kept reference endings: only the walks not settled equal come back,
    /// with the steps summed (`compare_endings`, or `compare_hits` for nearest hits on triangles).
    Compare,
}

/// Where a dispatch's items are: made and uploaded (`Job::input`'s function), or already on the GPU
/// for the whole batch (that function is then not called).
#[derive(Clone, Copy)]
enum Items<'a> {
    Upload,
    /// The reference walk's rays, kept with its endings ([`After::Keep`]).
    Reference,
    /// Items uploaded once for every method of a view (an octree walk's rays with their entry
    /// cells).
    Bound(&'a wgpu::Buffer),
}

impl<I> Clone for Job<'_, I> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<I> Copy for Job<'_, I> {}

impl<'a, I> Job<'a, I> {
    /// `count` items made by `input.1` uploaded to binding `input.0`, run at `entry` with `limit`
    /// and the buffers `bound`, binding `out_at` read back ([`After::Read`], [`Items::Upload`]).
    fn read(
        entry: Entry<'a>,
        count: usize,
        limit: u32,
        input: (u32, &'a (dyn Fn(usize) -> I + Sync)),
        bound: &'a [(u32, &'a wgpu::Buffer)],
        out_at: u32,
    ) -> Self {
        Job {
            entry,
            count,
            limit,
            input,
            bound,
            out_at,
            after: After::Read,
            items: Items::Upload,
            hits: None,
            picked: &[],
            first: 0,
        }
    }
}

/// The override constant choosing `m` ([`shader::place`]), or why `m` has no GPU version.
fn chooser<T: Named>(
    constant: &'static str,
    m: &T,
    all: &[T],
) -> Result<(&'static str, f64), GpuError> {
    if let GpuSupport::CpuOnly(why) = m.info().gpu {
        return Err(GpuError::NoGpuMethod {
            method: m.name(),
            why,
        });
    }
    shader::place(m, all)
        .map(|at| (constant, at))
        .ok_or(GpuError::NoGpuMethod {
            method: m.name(),
            why: "it is not in tetwalk's registry, which the shader is generated from",
        })
}

/// [`chooser`] for an octree method.
fn octree_constant(m: &OctreeMethod) -> Result<(&'static str, f64), GpuError> {
    chooser(shader::OCTREE_METHOD, m, crate::registry::OCTREE_METHODS)
}

/// [`chooser`] for the ray–triangle test of the octree walk.
fn triangle_constant(m: &TriangleMethod) -> Result<(&'static str, f64), GpuError> {
    chooser(
        shader::TRIANGLE_METHOD,
        m,
        crate::registry::TRIANGLE_METHODS,
    )
}

/// The ending codes a walk may end with: an outcome, or flagged for the CPU.
fn walk_known(kind: u32) -> bool {
    kind == shader::FLAGGED || OutcomeKind::from_code(kind).is_some()
}

/// The ending codes an octree walk may end with.
fn octree_known(kind: u32) -> bool {
    OutcomeKind::from_code(kind).is_some()
}

/// The ending codes of a nearest hit: a hit, or none.
fn nearest_known(kind: u32) -> bool {
    matches!(
        OutcomeKind::from_code(kind),
        Some(OutcomeKind::Hit | OutcomeKind::LeftMesh)
    )
}

/// Items of one dispatch at most (a test sends batches larger than this).
pub const DISPATCH_RUN: usize = 1 << 22;

/// Items made and staged at once by one task of an upload.
const UPLOAD_RUN: usize = 1 << 16;

/// Bytes of the two timestamps of a pass.
const TIMESTAMP_BYTES: u64 = 2 * 8;

/// The comparison's counters read back: walks sent back, steps summed (low and high words), padding.
const COUNTER_BYTES: u64 = 4 * 4;

/// Where a dispatch's output stays on the GPU, the records sent back that are read with its
/// counters, in the same wait: one for every `AHEAD_PER` items and `AHEAD_LEAST` more (32 bytes
/// each: half a byte a ray and 512 bytes more a dispatch, where a second wait for the rest, when
/// more were sent back, costs far more on a real GPU).
const AHEAD_PER: usize = 64;
const AHEAD_LEAST: usize = 16;

/// Bytes of a record sent back.
const SENT_SIZE: usize = std::mem::size_of::<shader::Sent>();

/// A dispatch submitted and not yet read back ([`Gpu::collect`]).
struct Submitted {
    /// Its readback: its own where the output stays on the GPU (it may be read in one wait with
    /// others'), the kept one otherwise.
    read: wgpu::Buffer,
    /// Bytes read before the timestamps: the output, or the counters, the picked items' outputs
    /// and the records read ahead.
    read_bytes: u64,
    /// How many items were picked, and where the output stays on the GPU, how many records are
    /// read ahead.
    picked: usize,
    ahead: Option<usize>,
    /// Bytes written for it, and the waits its upload took.
    written: u64,
    waited: u64,
    /// The number of the last dispatch whose records are in the kept `sent` buffer when this one
    /// was submitted ([`Gpu::last_sent`]).
    sent_by: u64,
}

/// One dispatch read back ([`Gpu::collect`]): whether all the records it sent back were read, and
/// what crossed for it.
struct Collected<T> {
    done: Dispatched<T>,
    complete: bool,
    traffic: Traffic,
}

/// Walks compared on the GPU, submitted and not yet read back: [`Gpu::gather`] reads several at
/// once, in one wait.
pub(crate) struct Queued {
    parts: Vec<Submitted>,
    /// Bytes uploaded for them beyond their dispatches' (an octree walk's rays with their entry
    /// cells, once for every method of a view).
    uploaded: u64,
    /// Which ending codes they may send back.
    known: fn(u32) -> bool,
}

/// Queued walks read back ([`Gpu::gather`]): the steps summed and the walks sent back, or `None`
/// where a later dispatch sent its records over theirs before they were read; what crossed for
/// them.
pub(crate) struct Gathered {
    pub(crate) done: Option<Dispatched<Ending>>,
    pub(crate) traffic: Traffic,
}

/// What a dispatch returns: its output and, where the adapter measures it, its kernel time; for a
/// walk compared on the GPU, the walks sent back and the steps summed instead of the output.
#[derive(Debug)]
pub struct Dispatched<T> {
    pub(crate) items: Vec<T>,
    pub(crate) kernel_seconds: Option<f64>,
    pub(crate) sent: Vec<shader::Sent>,
    pub(crate) steps: u64,
}

impl<T> Dispatched<T> {
    /// Nothing yet: no items, records or steps, the kernel time 0 where it is `measured`.
    fn none(measured: bool) -> Self {
        Dispatched {
            items: Vec::new(),
            kernel_seconds: measured.then_some(0.0),
            sent: Vec::new(),
            steps: 0,
        }
    }

    /// `d` after these: its items and records after theirs, its steps and kernel time added.
    fn add(&mut self, d: Dispatched<T>) {
        self.kernel_seconds = self
            .kernel_seconds
            .zip(d.kernel_seconds)
            .map(|(a, b)| a + b);
        self.sent.extend(d.sent);
        self.steps += d.steps;
        if self.items.is_empty() {
            self.items = d.items;
        } else {
            self.items.extend(d.items);
        }
    }
}

impl Dispatched<Ending> {
    /// The same, refused where an ending or a record sent back has a code `known` refuses.
    fn checked(self, known: impl Fn(u32) -> bool + Sync) -> Result<Self, GpuError> {
        let bad = self.items.par_iter().find_any(|e| !known(e.kind)).copied();
        let bad = bad.or_else(|| {
            self.sent
                .iter()
                .map(|s| s.ending())
                .find(|e| !known(e.kind))
        });
        match bad {
            Some(e) => Err(GpuError::BadOutcome(e.kind)),
            None => Ok(self),
        }
    }
}

impl Gpu {
    /// Open the adapter named by `WGPU_ADAPTER_NAME` (substring, any case), or the default one.
    pub(crate) fn new() -> Result<Gpu, GpuError> {
        Self::with_module(shader::COMMITTED.into(), "")
    }

    /// The same with a user's exit-face functions spliced in as method `user`
    /// ([`shader::with_user`]), checked first by the WGSL compiler: its message names `path` and the
    /// user's own line numbers.
    pub(crate) fn with_user(path: &str, source: &str) -> Result<Gpu, GpuError> {
        Self::with_module(user_module(path, source)?, shader::USER_PREFIX)
    }

    fn with_module(source: String, prefix: &'static str) -> Result<Gpu, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
            Ok(name) => pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
                .into_iter()
                .find(|a| {
                    a.get_info()
                        .name
                        .to_lowercase()
                        .contains(&name.to_lowercase())
                })
                .ok_or_else(|| GpuError::NoAdapter(format!(" named '{name}'")))?,
            Err(_) => pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            }))
            .map_err(|e| GpuError::NoAdapter(format!(": {e}")))?,
        };
        let info = adapter.get_info();
        let has = adapter.limits();
        let limits = wgpu::Limits {
            max_storage_buffers_per_shader_stage: 8,
            max_storage_buffer_binding_size: has.max_storage_buffer_binding_size,
            max_buffer_size: has.max_buffer_size,
            ..wgpu::Limits::downlevel_defaults().using_resolution(has)
        };
        let features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tetwalk"),
            required_limits: limits.clone(),
            required_features: features,
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        // Shader errors become a GpuError, not a panic.
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tetwalk.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
        }
        let timestamps = features.contains(wgpu::Features::TIMESTAMP_QUERY).then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("kernel time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            })
        });
        Ok(Gpu {
            max_groups: limits.max_compute_workgroups_per_dimension,
            max_binding: limits
                .max_storage_buffer_binding_size
                .min(limits.max_buffer_size),
            device,
            queue,
            module,
            pipelines: Mutex::new(HashMap::new()),
            prefix,
            info,
            traffic: Mutex::new(Traffic {
                kernel_seconds: timestamps.is_some().then_some(0.0),
                ..Traffic::default()
            }),
            timestamps,
            scratch: Mutex::new(HashMap::new()),
            kept_rays: Mutex::new(None),
            readbacks: Mutex::new(Vec::new()),
            last_sent: Mutex::new(0),
        })
    }

    /// The pipeline of `entry`, compiled once for each set of its constants.
    fn pipeline(&self, entry: Entry) -> Result<wgpu::ComputePipeline, GpuError> {
        let key = format!("{}{:?}", entry.name, entry.constants);
        let mut cache = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = cache.get(&key) {
            return Ok(p.clone());
        }
        let names: Vec<String> = entry
            .constants
            .iter()
            .map(|(k, _)| format!("{}{k}", self.prefix))
            .collect();
        let constants: Vec<(&str, f64)> = names
            .iter()
            .zip(entry.constants)
            .map(|(k, (_, v))| (k.as_str(), *v))
            .collect();
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let p = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry.name),
                layout: None,
                module: &self.module,
                entry_point: Some(entry.name),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                cache: None,
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(format!("{key}: {e}")));
        }
        cache.insert(key, p.clone());
        Ok(p)
    }

    /// The entry points of `method`, or why it has none.
    fn entry_points(method: &Method) -> Result<[String; 2], GpuError> {
        match method.info().gpu {
            GpuSupport::Wgsl(_) => Ok(shader::entry_points(method)),
            GpuSupport::CpuOnly(why) => Err(GpuError::NoGpuMethod {
                method: method.name(),
                why,
            }),
        }
    }

    /// Adapter, backend and driver, for reports.
    pub(crate) fn describe(&self) -> String {
        describe(&self.info)
    }

    /// Whether kernel times are measured (the adapter has timestamp queries).
    pub fn measures_kernels(&self) -> bool {
        self.timestamps.is_some()
    }

    /// The most items of `item_bytes` each one binding can hold.
    fn max_items(&self, item_bytes: usize) -> usize {
        (self.max_binding / item_bytes as u64).max(1) as usize
    }

    /// What crossed between the CPU and this GPU since it was opened.
    pub(crate) fn traffic(&self) -> Traffic {
        *self.traffic.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A buffer made once with `data` (a mesh).
    fn storage(&self, data: &[u8]) -> wgpu::Buffer {
        self.traffic
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .written += data.len() as u64;
        // Zero-length bindings are not allowed: pad empty inputs.
        let data = if data.is_empty() {
            &[0u8; 16][..]
        } else {
            data
        };
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: data,
                usage: wgpu::BufferUsages::STORAGE,
            })
    }

    /// The kept buffer `name`, grown (to a power of two) when smaller than `size`.
    fn scratch(
        &self,
        kept: &mut HashMap<&'static str, wgpu::Buffer>,
        name: &'static str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let size = size.max(16).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        if let Some(b) = kept.get(name)
            && b.size() >= size
        {
            return b.clone();
        }
        let b = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(name),
            size: size.next_power_of_two().min(self.max_binding.max(size)),
            usage,
            mapped_at_creation: false,
        });
        kept.insert(name, b.clone());
        b
    }

    /// Submit `job` (at least one item) in one dispatch, its items made in parallel and uploaded;
    /// [`Gpu::collect`] reads it back.
    fn submit_once<I: bytemuck::Pod + Send, T: bytemuck::Pod + Send>(
        &self,
        kept: &mut HashMap<&'static str, wgpu::Buffer>,
        job: Job<I>,
    ) -> Result<Submitted, GpuError> {
        let Job {
            entry,
            count,
            limit,
            input: (input_at, input),
            bound,
            out_at,
            after,
            items,
            hits,
            picked,
            first,
        } = job;
        let pipeline = self.pipeline(entry)?;
        // The second pass over the output, where it stays on the GPU.
        let compare = match (after, hits) {
            (After::Compare, None) => Some(self.pipeline(Entry::plain("compare_endings"))?),
            (After::Compare, Some(_)) => Some(self.pipeline(Entry::plain("compare_hits"))?),
            (After::Keep, _) => Some(self.pipeline(Entry::plain("hold_endings"))?),
            (After::Read, _) => None,
        };
        let (in_size, out_size) = (std::mem::size_of::<I>(), std::mem::size_of::<T>());
        let in_bytes = (count * in_size) as u64;
        let out_bytes = (count * out_size) as u64;
        let uniform = self.scratch(
            kept,
            "params",
            16,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let upload_items = matches!(items, Items::Upload);
        let input_buf = match items {
            Items::Upload => self.scratch(
                kept,
                "input",
                in_bytes,
                wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
            ),
            Items::Reference => kept
                .get("reference_items")
                .ok_or(GpuError::NoReference)?
                .clone(),
            Items::Bound(b) => b.clone(),
        };
        let out = self.scratch(
            kept,
            "output",
            out_bytes,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let sent_bytes = (count * SENT_SIZE) as u64;
        // The picked items (in this dispatch), and the records sent back that are read with the
        // counters where the output stays on the GPU.
        let picked: Vec<u64> = picked
            .iter()
            .filter(|&&p| (first..first + count).contains(&p))
            .map(|&p| (p - first) as u64)
            .collect();
        let ahead = compare
            .as_ref()
            .map(|_| (count / AHEAD_PER + AHEAD_LEAST).min(count));
        let read_bytes = match ahead {
            Some(ahead) => COUNTER_BYTES + (picked.len() * out_size + ahead * SENT_SIZE) as u64,
            None => out_bytes,
        };
        // Where the output stays on the GPU, a readback of its own, which may wait for other
        // dispatches' to be read in the same wait; the kept one otherwise.
        let read = match ahead {
            Some(_) => self.pooled(read_bytes + TIMESTAMP_BYTES),
            None => self.scratch(
                kept,
                "readback",
                out_bytes + TIMESTAMP_BYTES,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
        };
        let params = Params {
            count: count as u32,
            limit,
            first: first as u32,
            item_first: if upload_items { 0 } else { first as u32 },
        };
        self.queue
            .write_buffer(&uniform, 0, bytemuck::bytes_of(&params));
        // Made in parallel straight into a kept upload buffer mapped for writing, in runs of
        // [`UPLOAD_RUN`] items (each run a mapped range of its own), then copied on the GPU.
        let in_span = 0..in_bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let mut waited = 0;
        let upload = if upload_items {
            let upload = self.scratch(
                kept,
                "upload",
                in_bytes,
                wgpu::BufferUsages::MAP_WRITE | wgpu::BufferUsages::COPY_SRC,
            );
            self.map(&upload, wgpu::MapMode::Write, in_span.clone())?;
            waited = 1;
            (0..count.div_ceil(UPLOAD_RUN))
                .into_par_iter()
                .try_for_each(|run| {
                    let first = run * UPLOAD_RUN;
                    let last = count.min(first + UPLOAD_RUN);
                    let items: Vec<I> = (first..last).map(input).collect();
                    let span = (first * in_size) as u64..(last * in_size) as u64;
                    let mut view = upload
                        .slice(span)
                        .get_mapped_range_mut()
                        .map_err(|e| GpuError::Readback(e.to_string()))?;
                    view.copy_from_slice(bytemuck::cast_slice(&items));
                    Ok::<(), GpuError>(())
                })?;
            upload.unmap();
            Some(upload)
        } else {
            None
        };
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: PARAMS,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: input_at,
                resource: input_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: out_at,
                resource: out.as_entire_binding(),
            },
        ];
        entries.extend(bound.iter().map(|(b, buf)| wgpu::BindGroupEntry {
            binding: *b,
            resource: buf.as_entire_binding(),
        }));
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        // Items fill rows of at most `max_groups` workgroups; the shader numbers them across rows.
        let groups = (count as u32).div_ceil(GROUP);
        let x = groups.min(self.max_groups);
        let mut enc = self.device.create_command_encoder(&Default::default());
        if let Some(upload) = &upload {
            enc.copy_buffer_to_buffer(upload, 0, &input_buf, 0, in_span.end);
        }
        if after == After::Keep {
            // The rays, kept with the endings.
            let items = kept.get("reference_items").ok_or(GpuError::NoReference)?;
            enc.copy_buffer_to_buffer(&input_buf, 0, items, (first * in_size) as u64, in_bytes);
        }
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(entry.name),
                timestamp_writes: self.timestamps.as_ref().map(|query_set| {
                    wgpu::ComputePassTimestampWrites {
                        query_set,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    }
                }),
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
        }
        // What is read back: the output, or where it stays on the GPU, the counters (and the
        // picked items' outputs, and the first records sent back).
        match &compare {
            None => enc.copy_buffer_to_buffer(&out, 0, &read, 0, out_bytes),
            Some(compare) => {
                let sent = self.scratch(
                    kept,
                    "sent",
                    sent_bytes,
                    wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                );
                let counters = self.scratch(
                    kept,
                    "counters",
                    COUNTER_BYTES,
                    wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_SRC
                        | wgpu::BufferUsages::COPY_DST,
                );
                let reference = kept.get("reference").ok_or(GpuError::NoReference)?.clone();
                if after == After::Keep {
                    let at = (first * out_size) as u64;
                    enc.copy_buffer_to_buffer(&out, 0, &reference, at, out_bytes);
                }
                fn bind(binding: u32, buf: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
                    wgpu::BindGroupEntry {
                        binding,
                        resource: buf.as_entire_binding(),
                    }
                }
                let mut entries = vec![
                    bind(PARAMS, &uniform),
                    bind(ENDINGS, &out),
                    bind(SENT, &sent),
                    bind(COUNTERS, &counters),
                ];
                if after == After::Compare {
                    entries.push(bind(REFERENCE, &reference));
                }
                entries.extend(hits.map(|h| bind(HIT_FACES, h)));
                let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: None,
                    layout: &compare.get_bind_group_layout(0),
                    entries: &entries,
                });
                enc.clear_buffer(&counters, 0, None);
                {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("compare"),
                        timestamp_writes: None,
                    });
                    pass.set_pipeline(compare);
                    pass.set_bind_group(0, &group, &[]);
                    pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
                }
                // Each run of consecutive picked items in one copy (every item: one copy).
                enc.copy_buffer_to_buffer(&counters, 0, &read, 0, COUNTER_BYTES);
                let size = out_size as u64;
                let mut to = COUNTER_BYTES;
                for run in picked.chunk_by(|a, b| *b == a + 1) {
                    let bytes = run.len() as u64 * size;
                    enc.copy_buffer_to_buffer(&out, run[0] * size, &read, to, bytes);
                    to += bytes;
                }
                let ahead = ahead.unwrap_or(0);
                enc.copy_buffer_to_buffer(&sent, 0, &read, to, (ahead * SENT_SIZE) as u64);
            }
        }
        if let Some(q) = &self.timestamps {
            let resolved = self.scratch(
                kept,
                "timestamps",
                TIMESTAMP_BYTES,
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            );
            enc.resolve_query_set(q, 0..2, &resolved, 0);
            enc.copy_buffer_to_buffer(&resolved, 0, &read, read_bytes, TIMESTAMP_BYTES);
        }
        self.queue.submit([enc.finish()]);
        // This dispatch's records are now the ones in the kept `sent` buffer.
        let mut last = self.last_sent.lock().unwrap_or_else(|e| e.into_inner());
        if ahead.is_some() {
            *last += 1;
        }
        Ok(Submitted {
            read,
            read_bytes,
            picked: picked.len(),
            ahead,
            written: (if upload_items { in_bytes } else { 0 })
                + std::mem::size_of::<Params>() as u64,
            waited,
            sent_by: *last,
        })
    }

    /// A readback buffer of at least `size` bytes for one dispatch, from those returned
    /// ([`Gpu::collect`] returns them).
    fn pooled(&self, size: u64) -> wgpu::Buffer {
        let size = size.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let mut pool = self.readbacks.lock().unwrap_or_else(|e| e.into_inner());
        match pool.iter().position(|b| b.size() >= size) {
            Some(at) => pool.swap_remove(at),
            None => self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: size.next_power_of_two(),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    /// Read back dispatches submitted ([`Gpu::submit_once`]), all in one wait: each one's output's
    /// items read in parallel straight from the mapped buffer, or where it stays on the GPU, its
    /// counters, picked items and records sent back, with the kernel time where the adapter
    /// measures it and what crossed for it (the wait counted on the first). Records beyond those
    /// read ahead are read in a second wait where they are still on the GPU (no later dispatch
    /// sent any); a dispatch whose records are not all read back is not complete.
    fn collect<T: bytemuck::Pod + Send>(
        &self,
        kept: &mut HashMap<&'static str, wgpu::Buffer>,
        submitted: Vec<Submitted>,
    ) -> Result<Vec<Collected<T>>, GpuError> {
        let out_size = std::mem::size_of::<T>();
        let spans: Vec<_> = submitted
            .iter()
            .map(|s| (&s.read, 0..s.read_bytes + TIMESTAMP_BYTES))
            .collect();
        self.map_all(&spans, wgpu::MapMode::Read)?;
        let last_sent = *self.last_sent.lock().unwrap_or_else(|e| e.into_inner());
        let mut collected = Vec::with_capacity(submitted.len());
        for (k, s) in submitted.into_iter().enumerate() {
            let span = 0..s.read_bytes + TIMESTAMP_BYTES;
            // The output's items, or where it stays on the GPU, the counters, the picked items and
            // the first records.
            let (items, counters, mut records, kernel_seconds) = {
                let bytes = s
                    .read
                    .get_mapped_range(span.clone())
                    .map_err(|e| GpuError::Readback(e.to_string()))?;
                let (front, stamps) = bytes.split_at(s.read_bytes as usize);
                let stamps: [u64; 2] = bytemuck::pod_read_unaligned(stamps);
                let period = f64::from(self.queue.get_timestamp_period());
                let (counters, front, records) = match s.ahead {
                    Some(_) => {
                        let (counters, rest) = front.split_at(COUNTER_BYTES as usize);
                        let (picked, records) = rest.split_at(s.picked * out_size);
                        (bytemuck::pod_read_unaligned(counters), picked, records)
                    }
                    None => ([0u32; 4], front, &[][..]),
                };
                let items: Vec<T> = front
                    .par_chunks(out_size)
                    .map(bytemuck::pod_read_unaligned)
                    .collect();
                let records: Vec<shader::Sent> = bytemuck::pod_collect_to_vec(records);
                (
                    items,
                    counters,
                    records,
                    self.timestamps
                        .as_ref()
                        .map(|_| stamps[1].saturating_sub(stamps[0]) as f64 * period * 1e-9),
                )
            };
            s.read.unmap();
            let mut traffic = Traffic {
                written: s.written,
                read: span.end,
                dispatches: 1,
                waits: u64::from(k == 0) + s.waited,
                sent_back: 0,
                kernel_seconds,
            };
            let [n, low, high, _] = counters;
            let (n, mut complete) = (n as usize, true);
            if let Some(ahead) = s.ahead {
                self.readbacks
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push(s.read);
                if n <= ahead {
                    records.truncate(n);
                } else if s.sent_by == last_sent {
                    // The rest, in a second wait.
                    let bytes = ((n - ahead) * SENT_SIZE) as u64;
                    let (sent, read) = (
                        kept.get("sent").ok_or(GpuError::NoReference)?.clone(),
                        self.scratch(
                            kept,
                            "readback",
                            bytes,
                            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                        ),
                    );
                    let mut enc = self.device.create_command_encoder(&Default::default());
                    enc.copy_buffer_to_buffer(&sent, (ahead * SENT_SIZE) as u64, &read, 0, bytes);
                    self.queue.submit([enc.finish()]);
                    self.map(&read, wgpu::MapMode::Read, 0..bytes)?;
                    {
                        let view = read
                            .get_mapped_range(0..bytes)
                            .map_err(|e| GpuError::Readback(e.to_string()))?;
                        records.extend(bytemuck::pod_collect_to_vec::<u8, shader::Sent>(&view));
                    }
                    read.unmap();
                    traffic.read += bytes;
                    traffic.waits += 1;
                } else {
                    // A later dispatch sent its records over the rest.
                    complete = false;
                }
                if complete {
                    traffic.sent_back = records.len() as u64;
                }
            }
            {
                let mut total = self.traffic.lock().unwrap_or_else(|e| e.into_inner());
                // The waits were counted where they were made.
                *total = total.plus(&Traffic {
                    waits: 0,
                    ..traffic
                });
            }
            collected.push(Collected {
                done: Dispatched {
                    items,
                    kernel_seconds,
                    sent: records,
                    steps: u64::from(low) | u64::from(high) << 32,
                },
                complete,
                traffic,
            });
        }
        Ok(collected)
    }

    /// Map `span` of `buffer` and wait until it is mapped.
    fn map(
        &self,
        buffer: &wgpu::Buffer,
        mode: wgpu::MapMode,
        span: std::ops::Range<u64>,
    ) -> Result<(), GpuError> {
        self.map_all(&[(buffer, span)], mode)
    }

    /// Map each span of its buffer, and wait once until all are mapped.
    fn map_all(
        &self,
        spans: &[(&wgpu::Buffer, std::ops::Range<u64>)],
        mode: wgpu::MapMode,
    ) -> Result<(), GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        for (buffer, span) in spans {
            let tx = tx.clone();
            buffer.map_async(mode, span.clone(), move |r| {
                let _ = tx.send(r);
            });
        }
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        self.traffic.lock().unwrap_or_else(|e| e.into_inner()).waits += 1;
        for _ in spans {
            rx.recv()
                .map_err(|e| GpuError::Readback(e.to_string()))?
                .map_err(|e| GpuError::Readback(e.to_string()))?;
        }
        Ok(())
    }

    /// `job` over any count, in dispatches of at most [`DISPATCH_RUN`] items (and what the
    /// adapter's largest binding holds), each made by `each` from the run's job.
    fn runs<I: bytemuck::Pod + Send, T: bytemuck::Pod + Send>(
        &self,
        kept: &mut HashMap<&'static str, wgpu::Buffer>,
        job: Job<I>,
        mut each: impl FnMut(&mut HashMap<&'static str, wgpu::Buffer>, Job<I>) -> Result<(), GpuError>,
    ) -> Result<(), GpuError> {
        self.pipeline(job.entry)?;
        if job.after == After::Keep {
            // The whole batch's items and endings, kept for the walks compared with them.
            // Read back whole where asked ([`Gpu::kept_endings`]).
            let usage = wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC;
            for (name, size) in [
                ("reference", std::mem::size_of::<T>()),
                ("reference_items", std::mem::size_of::<I>()),
            ] {
                self.scratch(kept, name, (job.count * size) as u64, usage);
            }
        }
        let per = self
            .max_items(std::mem::size_of::<I>())
            .min(self.max_items(std::mem::size_of::<T>()))
            .min(DISPATCH_RUN);
        let (input_at, input) = job.input;
        for first in (0..job.count).step_by(per) {
            let shifted = |i: usize| input(first + i);
            each(
                kept,
                Job {
                    count: per.min(job.count - first),
                    input: (input_at, &shifted),
                    first,
                    ..job
                },
            )?;
        }
        Ok(())
    }

    /// `job` run now over any count ([`Gpu::runs`]): each dispatch submitted and read back before
    /// the next, their outputs in order, their kernel times summed.
    fn dispatch<I: bytemuck::Pod + Send, T: bytemuck::Pod + Send>(
        &self,
        job: Job<I>,
    ) -> Result<Dispatched<T>, GpuError> {
        let mut out = Dispatched::none(self.measures_kernels());
        let mut kept = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        self.runs::<I, T>(&mut kept, job, |kept, run| {
            let submitted = self.submit_once::<I, T>(kept, run)?;
            // Read at once, with the scratch held: its records are the last sent.
            out.add(self.collect::<T>(kept, vec![submitted])?.remove(0).done);
            Ok(())
        })?;
        Ok(out)
    }

    /// `job`, its output compared on the GPU ([`After::Compare`]) or kept there ([`After::Keep`]),
    /// submitted and not read back: [`Gpu::gather`] reads it with others in one wait. `known` says which ending codes it may
    /// send back.
    fn queue<I: bytemuck::Pod + Send>(
        &self,
        job: Job<I>,
        known: fn(u32) -> bool,
    ) -> Result<Queued, GpuError> {
        let mut parts = Vec::new();
        let mut kept = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        self.runs::<I, Ending>(&mut kept, job, |kept, run| {
            parts.push(self.submit_once::<I, Ending>(kept, run)?);
            Ok(())
        })?;
        Ok(Queued {
            parts,
            known,
            uploaded: 0,
        })
    }

    /// The walks kept or compared on the GPU that were queued ([`Gpu::walks_keeping`],
    /// [`Gpu::walks_against`], [`Gpu::nearest_against`], [`Gpu::octree_walks_against`]), each with
    /// the steps summed, the picked endings and the walks sent back, all read back in one wait; `done` is `None` for one whose records
    /// a later one sent over before they were read (queue it again alone). Traffic is each one's,
    /// the wait counted on the first.
    pub(crate) fn gather(&self, queued: Vec<Queued>) -> Result<Vec<Gathered>, GpuError> {
        let mut kept = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let sizes: Vec<usize> = queued.iter().map(|q| q.parts.len()).collect();
        let known: Vec<_> = queued.iter().map(|q| (q.known, q.uploaded)).collect();
        let all = queued.into_iter().flat_map(|q| q.parts).collect();
        let mut collected = self.collect::<Ending>(&mut kept, all)?.into_iter();
        let mut gathered = Vec::with_capacity(sizes.len());
        for (n, (known, uploaded)) in sizes.into_iter().zip(known) {
            let mut done = Dispatched::none(self.measures_kernels());
            let (mut complete, mut traffic) = (
                true,
                Traffic {
                    written: uploaded,
                    kernel_seconds: done.kernel_seconds,
                    ..Traffic::default()
                },
            );
            for c in collected.by_ref().take(n) {
                complete &= c.complete;
                traffic = traffic.plus(&c.traffic);
                done.add(c.done);
            }
            let done = match complete {
                true => Some(done.checked(known)?),
                false => None,
            };
            gathered.push(Gathered { done, traffic });
        }
        Ok(gathered)
    }

    /// Each case's answer by `method`, as the shader writes it: a face, [`NONE`] for no exit face, or
    /// [`shader::UNSETTLED`] for a case the CPU must answer; with the kernel time where measured.
    pub fn exit_faces(
        &self,
        method: &Method,
        cases: &[shader::Case],
    ) -> Result<Dispatched<i32>, GpuError> {
        let [exit, _] = Self::entry_points(method)?;
        let input = |i| cases[i];
        self.dispatch(Job::read(
            Entry::plain(&exit),
            cases.len(),
            0,
            (CASES, &input),
            &[],
            FACES,
        ))
    }

    /// The exit face and quarter of each octree cell case (`v0`, `v1` the corners) with `method`:
    /// `4 f + q`, or negative for none.
    pub(crate) fn box_exits(
        &self,
        method: &OctreeMethod,
        cases: &[shader::Case],
    ) -> Result<Vec<i32>, GpuError> {
        let constants = [octree_constant(method)?];
        let entry = Entry {
            name: shader::CELL_EXIT,
            constants: &constants,
        };
        let input = |i| cases[i];
        let job = Job::read(entry, cases.len(), 0, (CASES, &input), &[], FACES);
        Ok(self.dispatch(job)?.items)
    }

    /// Upload a scene's triangles and the constrained face each came from (tetrahedron and face,
    /// from both sides: [`crate::mesh::surface::both_sides`]; a count compares hits on them,
    /// [`Gpu::nearest_against`], [`Gpu::octree_walks_against`]; empty where nothing is compared).
    pub(crate) fn upload_triangles(
        &self,
        tris: &[crate::tet::Tri],
        from: &[[(u32, u8); 2]],
    ) -> GpuTriangles {
        let faces: Vec<[u32; 4]> = from
            .iter()
            .map(|&[(t, f), (u, g)]| [t, u32::from(f), u, u32::from(g)])
            .collect();
        GpuTriangles {
            points: self.triangle_points(tris),
            faces: self.storage(bytemuck::cast_slice(&faces)),
            count: tris.len(),
            faced: from.len() == tris.len(),
        }
    }

    /// Upload an octree over triangles uploaded for it, for [`Gpu::octree_walks`].
    pub(crate) fn upload_octree(&self, o: &crate::octree::Octree, tris: GpuTriangles) -> GpuOctree {
        let boxes: Vec<[f32; 4]> = o
            .boxes
            .iter()
            .flat_map(|[lo, hi]| [lo.extend(0.0).to_array(), hi.extend(0.0).to_array()])
            .collect();
        GpuOctree {
            words: self.storage(bytemuck::cast_slice(&o.words)),
            boxes: self.storage(bytemuck::cast_slice(&boxes)),
            triangles: self.storage(bytemuck::cast_slice(&o.triangles)),
            tris,
            entered: Mutex::new(None),
        }
    }

    /// Walk every ray from its entry cell's address (`HULL`: a miss) through the uploaded octree with
    /// `method`, each leaf's triangles tested with `tri`.
    pub(crate) fn octree_walks(
        &self,
        method: &OctreeMethod,
        tri: &TriangleMethod,
        o: &GpuOctree,
        rays: &[(Ray, u32)],
        max_steps: u32,
    ) -> Result<Vec<Ending>, GpuError> {
        let ray = |i: usize| shader::WalkRay::new(&rays[i].0, rays[i].1);
        let batch = (rays.len(), &ray as _, Items::Upload);
        let out = self.octree_dispatch(method, tri, o, batch, max_steps, None, |job| {
            self.dispatch(job)
        })?;
        Ok(out.checked(octree_known)?.items)
    }

    /// [`Gpu::octree_walks`] of the rays of the reference walk kept on the GPU (`kept`, with the
    /// tetrahedron it started from; refused for other rays), each walk compared there with it
    /// (`compare_hits`, a hit taken as the face its triangle came from): the cells summed, and only
    /// the walks not settled there come back ([`Dispatched::sent`]), queued ([`Gpu::gather`]). The
    /// rays with their entry cells (`entered`, called once for the kept rays) are uploaded once for
    /// every method compared.
    pub(crate) fn octree_walks_against(
        &self,
        method: &OctreeMethod,
        tri: &TriangleMethod,
        o: &GpuOctree,
        entered: &dyn Fn() -> Vec<(Ray, u32)>,
        max_steps: u32,
        kept: &[(Ray, u32)],
    ) -> Result<Queued, GpuError> {
        let (hits, these) = self.faces_for(&o.tris, kept)?;
        let mut upload_bytes = 0;
        let items = {
            let mut uploaded = o.entered.lock().unwrap_or_else(|e| e.into_inner());
            match &*uploaded {
                Some((of, items)) if *of == these => items.clone(),
                _ => {
                    let asked: Vec<shader::WalkRay> = entered()
                        .par_iter()
                        .map(|(r, cell)| shader::WalkRay::new(r, *cell))
                        .collect();
                    let bytes: &[u8] = bytemuck::cast_slice(&asked);
                    upload_bytes = bytes.len() as u64;
                    let items = self.storage(bytes);
                    *uploaded = Some((these, items.clone()));
                    items
                }
            }
        };
        let ray = |i: usize| shader::WalkRay::new(&kept[i].0, kept[i].1);
        let batch = (kept.len(), &ray as _, Items::Bound(&items));
        let queued = self.octree_dispatch(method, tri, o, batch, max_steps, Some(hits), |job| {
            self.queue(job, octree_known)
        })?;
        Ok(Queued {
            uploaded: upload_bytes,
            ..queued
        })
    }

    /// The job of [`Gpu::octree_walks`] of a batch (how many rays, each with its entry cell, and
    /// where they are), compared with the kept reference walk through `hits` where given, given to
    /// `run`.
    #[allow(clippy::too_many_arguments)]
    fn octree_dispatch<R>(
        &self,
        method: &OctreeMethod,
        tri: &TriangleMethod,
        o: &GpuOctree,
        (count, ray, items): (usize, &(dyn Fn(usize) -> shader::WalkRay + Sync), Items),
        max_steps: u32,
        hits: Option<&wgpu::Buffer>,
        run: impl FnOnce(Job<shader::WalkRay>) -> Result<R, GpuError>,
    ) -> Result<R, GpuError> {
        let constants = [octree_constant(method)?, triangle_constant(tri)?];
        let entry = Entry {
            name: shader::OCTREE_WALK,
            constants: &constants,
        };
        let bound = [
            (OCTREE, &o.words),
            (OCTREE_BOXES, &o.boxes),
            (OCTREE_TRIS, &o.triangles),
            (POINTS, &o.tris.points),
        ];
        run(Job {
            after: if hits.is_some() {
                After::Compare
            } else {
                After::Read
            },
            items,
            hits,
            ..Job::read(entry, count, max_steps, (RAYS, ray), &bound, ENDINGS)
        })
    }

    /// The faces `tris` came from, to compare hits on them with the reference walk kept for `kept`
    /// (refused for other rays, or triangles uploaded without their faces), and the kept rays'
    /// count and fingerprint.
    fn faces_for<'a>(
        &self,
        tris: &'a GpuTriangles,
        kept: &[(Ray, u32)],
    ) -> Result<(&'a wgpu::Buffer, (usize, u64)), GpuError> {
        let these = self.check_kept(kept)?;
        if !tris.faced {
            return Err(GpuError::NoReference);
        }
        Ok((&tris.faces, these))
    }

    /// Refuse to compare walks of `rays` unless they are the rays (with their starting
    /// tetrahedra) whose reference walk is kept on the GPU: their count and fingerprint.
    fn check_kept(&self, rays: &[(Ray, u32)]) -> Result<(usize, u64), GpuError> {
        let these = (rays.len(), fingerprint(rays));
        let kept = *self.kept_rays.lock().unwrap_or_else(|e| e.into_inner());
        if kept != Some(these) {
            return Err(GpuError::NoReference);
        }
        Ok(these)
    }

    /// Upload a mesh for [`Gpu::walks`].
    pub(crate) fn upload(&self, mesh: &Mesh) -> GpuMesh {
        let cells: Vec<shader::Cell> = mesh
            .cells
            .iter()
            .zip(&mesh.neighbors)
            .map(|(c, n)| {
                let [v0, v1, v2, v3] = c.v.map(|p| p.to_array());
                let [n0, n1, n2, n3] = *n;
                shader::Cell {
                    v0,
                    n0,
                    v1,
                    n1,
                    v2,
                    n2,
                    v3,
                    n3,
                }
            })
            .collect();
        let info: Vec<u32> = mesh
            .mirror
            .iter()
            .zip(&mesh.constrained)
            .map(|(m, &c)| {
                let mirror = (0..4).fold(0u32, |acc, f| acc | ((m[f] as u32 & 3) << (2 * f)));
                mirror | (c as u32) << 8
            })
            .collect();
        GpuMesh {
            cells: self.storage(bytemuck::cast_slice(&cells)),
            info: self.storage(bytemuck::cast_slice(&info)),
            tetrahedra: mesh.tets.len(),
        }
    }

    /// Walk every ray from its starting tetrahedron with `method` on the GPU: each ray's ending, its
    /// code checked ([`Ending::walk`] reads it).
    pub(crate) fn walks(
        &self,
        method: &Method,
        mesh: &GpuMesh,
        rays: &[(Ray, u32)],
        max_steps: u32,
    ) -> Result<Dispatched<Ending>, GpuError> {
        let out = self.walk_job(method, mesh, rays, max_steps, After::Read, &[], |job| {
            self.dispatch(job)
        })?;
        out.checked(walk_known)
    }

    /// Whether a batch of `rays` rays can be kept on the GPU as a reference walk (its rays fit one
    /// binding, which the compared walks read whole).
    pub(crate) fn keeps(&self, rays: usize) -> bool {
        (rays * std::mem::size_of::<shader::WalkRay>()) as u64 <= self.max_binding
    }

    /// [`Gpu::walks`] kept on the GPU as the reference walk's rays and endings, queued
    /// ([`Gpu::gather`]): only the endings of `picked` are read back ([`Dispatched::items`]), with
    /// the steps summed and the walks flagged ([`Dispatched::sent`]). A batch kept must fit one
    /// binding ([`Gpu::keeps`]): refused otherwise.
    pub(crate) fn walks_keeping(
        &self,
        method: &Method,
        mesh: &GpuMesh,
        rays: &[(Ray, u32)],
        max_steps: u32,
        picked: &[usize],
    ) -> Result<Queued, GpuError> {
        self.walk_job(method, mesh, rays, max_steps, After::Keep, picked, |job| {
            self.queue(job, walk_known)
        })
    }

    /// `method`'s walks of the kept rays (`rays`, which must be the kept ones: refused otherwise),
    /// each ending compared there with the kept one (`compare_endings`), queued ([`Gpu::gather`]):
    /// the steps summed, and only the walks not settled as ending where the reference ends come
    /// back ([`Dispatched::sent`]).
    pub(crate) fn walks_against(
        &self,
        method: &Method,
        mesh: &GpuMesh,
        rays: &[(Ray, u32)],
        max_steps: u32,
    ) -> Result<Queued, GpuError> {
        self.walk_job(method, mesh, rays, max_steps, After::Compare, &[], |job| {
            self.queue(job, walk_known)
        })
    }

    /// The job of `method`'s walks of `rays` and what becomes of them, given to `run`: with
    /// [`After::Keep`] the rays are the kept ones from now on, with [`After::Compare`] they must be
    /// (refused otherwise).
    #[allow(clippy::too_many_arguments)]
    fn walk_job<R>(
        &self,
        method: &Method,
        mesh: &GpuMesh,
        rays: &[(Ray, u32)],
        max_steps: u32,
        after: After,
        picked: &[usize],
        run: impl FnOnce(Job<shader::WalkRay>) -> Result<R, GpuError>,
    ) -> Result<R, GpuError> {
        match after {
            After::Read => {}
            After::Keep => {
                let mut kept = self.kept_rays.lock().unwrap_or_else(|e| e.into_inner());
                *kept = None;
                if !self.keeps(rays.len()) {
                    return Err(GpuError::TooManyToKeep(rays.len()));
                }
                *kept = Some((rays.len(), fingerprint(rays)));
            }
            After::Compare => {
                self.check_kept(rays)?;
            }
        }
        let [_, walk] = Self::entry_points(method)?;
        let ray = |i: usize| shader::WalkRay::new(&rays[i].0, rays[i].1);
        let mesh = [(CELLS, &mesh.cells), (FACEINFO, &mesh.info)];
        let walk = Entry::plain(&walk);
        run(Job {
            after,
            items: if after == After::Compare {
                Items::Reference
            } else {
                Items::Upload
            },
            picked,
            ..Job::read(walk, rays.len(), max_steps, (RAYS, &ray), &mesh, ENDINGS)
        })
    }

    /// Write the CPU's walks of rays the reference walk flagged (by index in its batch) over its
    /// endings kept on the GPU, so that walks compared with it from then on, and its endings read
    /// back, meet the endings the CPU judges with; the bytes written.
    pub(crate) fn amend_reference(&self, walks: &[(usize, Walk)]) -> Result<u64, GpuError> {
        let kept = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let reference = kept.get("reference").ok_or(GpuError::NoReference)?;
        let size = std::mem::size_of::<Ending>();
        for (i, w) in walks {
            let e = Ending::of(w);
            self.queue
                .write_buffer(reference, (i * size) as u64, bytemuck::bytes_of(&e));
        }
        let bytes = (walks.len() * size) as u64;
        self.traffic
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .written += bytes;
        Ok(bytes)
    }

    /// Every ending of the reference walk kept on the GPU for `rays` (refused for other rays), read
    /// back.
    pub(crate) fn kept_endings(&self, rays: &[(Ray, u32)]) -> Result<Vec<Ending>, GpuError> {
        self.check_kept(rays)?;
        let mut kept = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let reference = kept.get("reference").ok_or(GpuError::NoReference)?.clone();
        let bytes = (rays.len() * std::mem::size_of::<Ending>()) as u64;
        let read = self.scratch(
            &mut kept,
            "readback",
            bytes,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(&reference, 0, &read, 0, bytes);
        self.queue.submit([enc.finish()]);
        self.map(&read, wgpu::MapMode::Read, 0..bytes)?;
        let endings = {
            let view = read
                .get_mapped_range(0..bytes)
                .map_err(|e| GpuError::Readback(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view)
        };
        read.unmap();
        self.traffic.lock().unwrap_or_else(|e| e.into_inner()).read += bytes;
        Ok(endings)
    }
}

impl Gpu {
    /// The entry points of a ray–triangle method, or why it has none.
    fn triangle_entry_points(method: &TriangleMethod) -> Result<[String; 2], GpuError> {
        match method.info().gpu {
            GpuSupport::Wgsl(_) => Ok(shader::triangle_entry_points(method)),
            GpuSupport::CpuOnly(why) => Err(GpuError::NoGpuMethod {
                method: method.name(),
                why,
            }),
        }
    }

    /// Triangles as the shader reads them: three `points` each.
    fn triangle_points(&self, tris: &[crate::tet::Tri]) -> wgpu::Buffer {
        let points: Vec<[f32; 4]> = tris
            .iter()
            .flatten()
            .map(|p| [p.x, p.y, p.z, 0.0])
            .collect();
        self.storage(bytemuck::cast_slice(&points))
    }

    /// `method`'s answer for each (ray, triangle) pair, the triangle an index into `tris`: the `t` of a
    /// hit that counts, or `None`.
    pub(crate) fn triangle_pairs(
        &self,
        method: &TriangleMethod,
        tris: &[crate::tet::Tri],
        pairs: &[(Ray, u32)],
    ) -> Result<Vec<Option<f32>>, GpuError> {
        let [hit, _] = Self::triangle_entry_points(method)?;
        let points = self.triangle_points(tris);
        let ray = |i: usize| shader::WalkRay::new(&pairs[i].0, pairs[i].1);
        let bound = [(POINTS, &points)];
        let job = Job::read(
            Entry::plain(&hit),
            pairs.len(),
            0,
            (RAYS, &ray),
            &bound,
            ENDINGS,
        );
        let out: Dispatched<Ending> = self.dispatch(job)?;
        out.items
            .iter()
            .map(|e| Ok(e.triangle_hit()?.map(|(_, t)| t)))
            .collect()
    }

    /// `method`'s nearest hit among `tris` (every one tried) for each ray: the triangle and its `t`.
    pub(crate) fn nearest_triangles(
        &self,
        method: &TriangleMethod,
        tris: &[crate::tet::Tri],
        rays: &[Ray],
    ) -> Result<Dispatched<Nearest>, GpuError> {
        let points = self.triangle_points(tris);
        let ray = |i: usize| shader::WalkRay::new(&rays[i], 0);
        let out = self.nearest(
            method,
            (&points, tris.len()),
            rays.len(),
            &ray,
            None,
            |job| self.dispatch(job),
        )?;
        let out = out.checked(nearest_known)?;
        Ok(Dispatched {
            items: out
                .items
                .iter()
                .map(Ending::triangle_hit)
                .collect::<Result<_, _>>()?,
            kernel_seconds: out.kernel_seconds,
            sent: Vec::new(),
            steps: 0,
        })
    }

    /// [`Gpu::nearest_triangles`] among uploaded triangles for the rays of the reference walk kept
    /// on the GPU (`kept`, with the tetrahedron it started from; refused for other rays), read
    /// there, each nearest hit compared there with the reference walk's ending (`compare_hits`, a
    /// hit taken as the face its triangle came from): only the rays not settled there come back
    /// ([`Dispatched::sent`]: HIT with the triangle and the bits of `t`, or LEFT_MESH), queued
    /// ([`Gpu::gather`]).
    pub(crate) fn nearest_against(
        &self,
        method: &TriangleMethod,
        tris: &GpuTriangles,
        kept: &[(Ray, u32)],
    ) -> Result<Queued, GpuError> {
        let (faces, _) = self.faces_for(tris, kept)?;
        let ray = |i: usize| shader::WalkRay::new(&kept[i].0, kept[i].1);
        self.nearest(
            method,
            (&tris.points, tris.count),
            kept.len(),
            &ray,
            Some(faces),
            |job| self.queue(job, nearest_known),
        )
    }

    /// The nearest-hit kernel of `method` over `tris` (the points and how many triangles) for `count`
    /// rays: uploaded (`ray`), or where `hits` is given, the kept reference walk's rays, compared
    /// with it there; the job given to `run`.
    fn nearest<R>(
        &self,
        method: &TriangleMethod,
        (points, triangles): (&wgpu::Buffer, usize),
        count: usize,
        ray: &(dyn Fn(usize) -> shader::WalkRay + Sync),
        hits: Option<&wgpu::Buffer>,
        run: impl FnOnce(Job<shader::WalkRay>) -> Result<R, GpuError>,
    ) -> Result<R, GpuError> {
        let [_, nearest] = Self::triangle_entry_points(method)?;
        let (nearest, bound) = (Entry::plain(&nearest), [(POINTS, points)]);
        run(Job {
            after: if hits.is_some() {
                After::Compare
            } else {
                After::Read
            },
            items: if hits.is_some() {
                Items::Reference
            } else {
                Items::Upload
            },
            hits,
            ..Job::read(
                nearest,
                count,
                triangles as u32,
                (RAYS, ray),
                &bound,
                ENDINGS,
            )
        })
    }

    /// Upload seed 003's three layouts of a mesh and its points for [`Gpu::layout_walks`].
    pub(crate) fn upload_layout(&self, layout: &Layout, points: &[glam::Vec3]) -> GpuLayout {
        let tet32: Vec<u32> = layout
            .tet32
            .iter()
            .flat_map(|t| [t.v[0], t.v[1], t.v[2], t.vx, t.n[0], t.n[1], t.n[2], t.n[3]])
            .collect();
        let tet20: Vec<u32> = layout
            .tet20
            .iter()
            .flat_map(|t| [t.vx, t.n[0], t.n[1], t.n[2], t.n[3]])
            .collect();
        let tet16: Vec<u32> = layout
            .tet16
            .iter()
            .flat_map(|t| [t.vx, t.nx[0], t.nx[1], t.nx[2]])
            .collect();
        let points: Vec<[f32; 4]> = points.iter().map(|p| p.extend(0.0).to_array()).collect();
        GpuLayout {
            words: [&tet32, &tet20, &tet16].map(|w| self.storage(bytemuck::cast_slice(w))),
            points: self.storage(bytemuck::cast_slice(&points)),
            tetrahedra: layout.tet32.len(),
        }
    }

    /// Walk every ray from its source tetrahedron over layout `kind` with `method` (seed 003
    /// Algorithms 2-7); each ray's ending ([`Ending::layout_walk`] reads it), a face named by the
    /// vertex across it.
    pub(crate) fn layout_walks(
        &self,
        method: &Method,
        kind: LayoutKind,
        layout: &GpuLayout,
        rays: &[(Ray, Source)],
        max_steps: u32,
    ) -> Result<Dispatched<Ending>, GpuError> {
        Self::entry_points(method)?;
        if method.layout_walk(Model::Plain).is_none() {
            return Err(GpuError::NoLayoutWalk(method.name()));
        }
        let entry = shader::layout_entry_point(method, kind);
        let words = &layout.words[LayoutKind::ALL.iter().position(|&k| k == kind).unwrap_or(0)];
        let ray = |i: usize| {
            let (r, s) = &rays[i];
            shader::LayoutRay {
                org: r.org.to_array(),
                start: s.tet,
                dir: r.dir.to_array(),
                pad: 0,
                vertices: s.vertices,
                neighbors: s.neighbors,
            }
        };
        let mesh = [(LAYOUT_WORDS, words), (POINTS, &layout.points)];
        let entry = Entry::plain(&entry);
        let input = (LAYOUT_RAYS, &ray as &(dyn Fn(usize) -> _ + Sync));
        self.dispatch(Job::read(
            entry,
            rays.len(),
            max_steps,
            input,
            &mesh,
            ENDINGS,
        ))
    }
}

/// Seed 003's layouts of a mesh and its points, uploaded to the GPU.
pub(crate) struct GpuLayout {
    /// Tet32, Tet20, Tet16, in [`LayoutKind::ALL`] order.
    words: [wgpu::Buffer; 3],
    points: wgpu::Buffer,
    pub(crate) tetrahedra: usize,
}

impl Ending {
    /// The layout walk this ending says (a face named by the vertex across it), and its steps.
    pub(crate) fn layout_walk(&self) -> Option<(LayoutOutcome, u32)> {
        Some((
            LayoutOutcome {
                kind: OutcomeKind::from_code(self.kind)?,
                tet: self.tet,
                x: self.x,
            },
            self.steps,
        ))
    }
}

impl Ending {
    /// A ray–triangle answer: `HIT` with the triangle and the bits of its `t`, or `LEFT_MESH` for none.
    pub(crate) fn triangle_hit(&self) -> Result<Nearest, GpuError> {
        match OutcomeKind::from_code(self.kind) {
            Some(OutcomeKind::Hit) => Ok(Some((self.tet, f32::from_bits(self.x)))),
            Some(OutcomeKind::LeftMesh) => Ok(None),
            _ => Err(GpuError::BadOutcome(self.kind)),
        }
    }

    /// The octree walk this ending says (its code checked by [`Gpu::octree_walks`]).
    pub(crate) fn octree_walk(&self) -> crate::walk::octree::OctreeWalk {
        use crate::walk::octree::End;
        let end = match OutcomeKind::from_code(self.kind) {
            Some(OutcomeKind::Hit) => End::Hit {
                tri: self.tet,
                t: f32::from_bits(self.x),
            },
            Some(OutcomeKind::LeftMesh) => End::Miss,
            Some(OutcomeKind::NoExitFace) => End::NoExitFace { cell: self.tet },
            Some(OutcomeKind::Cycle) => End::Cycle {
                cell: self.tet,
                period: self.x,
            },
            _ => End::StepLimit { cell: self.tet },
        };
        crate::walk::octree::OctreeWalk {
            end,
            cells: self.steps,
        }
    }

    /// The walk this ending says, or `None` for a ray the method flagged (a step its f32 stage could
    /// not settle), which the CPU must walk. Codes are checked by [`Gpu::walks`].
    pub(crate) fn walk(&self) -> Option<Walk> {
        let kind = OutcomeKind::from_code(self.kind)?;
        Some(Walk {
            outcome: Outcome::from_parts(kind, self.tet, self.x),
            steps: self.steps,
        })
    }
}

/// A fingerprint of a batch of rays and their starts, in order (to match walks with the reference
/// walk kept for the same rays).
fn fingerprint(rays: &[(Ray, u32)]) -> u64 {
    rays.par_iter()
        .enumerate()
        .map(|(i, (r, start))| {
            let words = [r.org.to_array(), r.dir.to_array()].concat();
            let h = words.iter().fold(u64::from(*start), |h, x| {
                (h ^ u64::from(x.to_bits())).wrapping_mul(0x100_0000_01b3)
            });
            h.wrapping_mul(i as u64 * 2 + 1)
        })
        .reduce(|| 0, |a, b| a ^ b)
}

impl shader::Sent {
    /// The walk's ending as the walk kernel wrote it.
    pub(crate) fn ending(&self) -> Ending {
        Ending {
            kind: self.kind,
            tet: self.tet,
            x: self.x,
            steps: self.steps,
        }
    }

    /// The reference walk's ending beside it (without its steps), or `None` where it is not one
    /// the CPU can read.
    pub(crate) fn reference(&self) -> Option<Walk> {
        Ending {
            kind: self.r_kind,
            tet: self.r_tet,
            x: self.r_x,
            steps: 0,
        }
        .walk()
    }
}

impl Ending {
    /// A walk as the shader writes its ending.
    pub(crate) fn of(w: &Walk) -> Ending {
        let (kind, tet, x) = w.outcome.parts();
        Ending {
            kind: kind.code(),
            tet,
            x,
            steps: w.steps,
        }
    }
}

impl shader::WalkRay {
    /// A ray to walk from tetrahedron `start`.
    pub(crate) fn new(ray: &Ray, start: u32) -> shader::WalkRay {
        shader::WalkRay {
            org: ray.org.to_array(),
            start,
            dir: ray.dir.to_array(),
            pad: 0,
        }
    }
}

/// A mesh uploaded to the GPU.
pub(crate) struct GpuMesh {
    cells: wgpu::Buffer,
    info: wgpu::Buffer,
    pub(crate) tetrahedra: usize,
}

/// An octree uploaded for [`Gpu::octree_walks`], over its triangles.
pub(crate) struct GpuOctree {
    words: wgpu::Buffer,
    boxes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    tris: GpuTriangles,
    /// The rays last compared ([`Gpu::octree_walks_against`]: how many and their fingerprint) with
    /// their entry cells, uploaded once for every method.
    entered: Mutex<Option<((usize, u64), wgpu::Buffer)>>,
}

/// A scene's triangles uploaded ([`Gpu::upload_triangles`]): three `points` each, and the face each
/// came from (tetrahedron and face, from both sides), which `compare_hits` settles a hit on.
pub(crate) struct GpuTriangles {
    points: wgpu::Buffer,
    faces: wgpu::Buffer,
    count: usize,
    /// Whether `faces` names each triangle's face (none were given where nothing is compared).
    faced: bool,
}

/// Whether tests must have an adapter (`TETWALK_REQUIRE_GPU=1`, as CI sets).
pub fn required() -> bool {
    std::env::var("TETWALK_REQUIRE_GPU").is_ok_and(|v| v == "1")
}
