//! The backend seam: where a method's exit faces and walks are computed — the CPU in plain f32, the CPU
//! as a GPU compiles it (fused multiply-adds, see [`crate::methods`]), the CPU as a GPU may compute
//! (subnormals flushed to zero, [`crate::fpenv`]), or a GPU through wgpu (with the `gpu` feature;
//! without it, asking for the GPU is an error). Every
//! command, the fuzz targets and the tests ask for answers here. The reference method runs on the CPU
//! whatever the backend (it has no GPU version), and reports say so.

use crate::cases::{BoxCase, Case, HitCase, normalized};
pub use crate::choice::{BackendKind, Ran, Traffic};
/// `certified` written for a user's own shaders (`tetwalk export-kernel`): the device layer's, reached
/// through this seam as every GPU answer is.
#[cfg(feature = "gpu")]
pub use crate::gpu::export::{Lang as ShaderLang, export as export_kernel};
#[cfg(feature = "gpu")]
use crate::gpu::{self, GpuError, GpuMesh};
use crate::mesh::Mesh;
use crate::mesh::layout::Layout;
use crate::methods::Model;
use crate::methods::triangle::{Among, Nearest};
use crate::octree::Octree;
use crate::registry::{Method, Named, OctreeMethod, TriangleMethod};
use crate::tet::Ray;
use crate::walk::Walk;
use crate::walk::layouts::{LayoutKind, LayoutOutcome, Source};
use crate::walk::octree::OctreeWalk;
use rayon::prelude::*;

/// Why a backend cannot give an answer.
#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[cfg(not(feature = "gpu"))]
    #[error("this tetwalk was built without its GPU backend (the `gpu` feature)")]
    NoGpu,
    #[error("the GPU holds another mesh than the one walked")]
    OtherMesh,
    #[error("no reference walk is kept where the methods run")]
    NotKept,
    #[error(
        "method '{0}' has no layout walk (seed 003's layouts are walked by the 2-D frame methods)"
    )]
    NoLayoutWalk(&'static str),
    #[error("{0} needs a processor whose flush-to-zero mode tetwalk sets (x86-64 or AArch64)")]
    NoFlush(&'static str),
    #[error("{0} run on the CPU so far: use --backend cpu or cpu-fma")]
    CpuOnly(&'static str),
    #[error("method '{0}' runs only on the GPU (a user's WGSL): use --backend gpu")]
    GpuOnly(&'static str),
    #[error(
        "method '{0}' answered UNSETTLED (-2), which asks the CPU to finish, and it has no CPU version"
    )]
    Unsettled(&'static str),
    /// A program outside tetwalk gave no answers (`crate::engine::answerer`), or none can be opened.
    #[error("{0}")]
    Outside(String),
    /// A case the backend cannot place (a walk case's origin outside its mesh).
    #[error("{0}")]
    Case(String),
}

/// Fewer items than this are answered on the calling thread: handing a few to the thread pool costs
/// more than answering them (fuzz targets ask one at a time).
const PARALLEL_FROM: usize = 256;

/// `f` over `items`, in parallel when there are many.
fn map_all<T: Sync, U: Send>(items: &[T], f: impl Fn(&T) -> U + Sync + Send) -> Vec<U> {
    if items.len() < PARALLEL_FROM {
        items.iter().map(f).collect()
    } else {
        items.par_iter().map(f).collect()
    }
}

/// One CPU backend per arithmetic model ([`crate::arithmetic_models!`]), in [`Model::ALL`]'s order.
macro_rules! cpu_backends {
    ([] $($(#[$doc:meta])* $model:ident, $backend:ident => $name:literal,
        ($($arith:ident),*), {$($info:tt)*};)*) => {
        /// Every CPU backend, one per arithmetic model, in [`Model::ALL`]'s order.
        pub static CPUS: [Backend; Model::COUNT] = [$(Backend::Cpu { model: Model::$model }),*];
    };
}
crate::arithmetic_models!(cpu_backends);

/// The CPU in plain f32, where the reference runs.
pub static CPU: Backend = Backend::Cpu {
    model: Model::Plain,
};
/// The CPU as a GPU compiles the methods (fused multiply-adds).
pub static CPU_FMA: Backend = Backend::Cpu {
    model: Model::Fused,
};

/// A backend, opened.
pub enum Backend {
    Cpu {
        model: Model,
    },
    #[cfg(feature = "gpu")]
    Gpu(Box<gpu::Gpu>),
}

/// Seed 003's layouts of a mesh where a backend walks them (uploaded once to a GPU).
pub struct LayoutOn<'a> {
    pub(crate) layout: &'a Layout,
    pub(crate) points: &'a [glam::Vec3],
    #[cfg(feature = "gpu")]
    gpu: Option<gpu::GpuLayout>,
}

/// Layout walks from a backend (each outcome and its steps), with the GPU's kernel time.
pub struct LayoutWalked {
    pub walks: Vec<(LayoutOutcome, u32)>,
    pub(crate) kernel_seconds: Option<f64>,
}

/// A scene's triangles as a backend compares nearest hits on them: uploaded once to a GPU with the
/// face each came from, nothing on the CPU.
pub struct TrianglesOn {
    #[cfg(feature = "gpu")]
    gpu: Option<gpu::GpuTriangles>,
}

/// An octree and its triangles as a backend walks them: uploaded once to a GPU, nothing on the CPU.
pub struct OctreeOn {
    #[cfg(feature = "gpu")]
    gpu: Option<crate::gpu::GpuOctree>,
}

/// A mesh where a backend walks it (uploaded once to a GPU).
pub struct MeshOn<'a> {
    pub mesh: &'a Mesh,
    #[cfg(feature = "gpu")]
    gpu: Option<GpuMesh>,
}

impl Backend {
    /// Open a backend (a GPU backend opens the adapter).
    pub fn open(kind: BackendKind) -> Result<Backend, BackendError> {
        Ok(match kind {
            #[cfg(feature = "gpu")]
            BackendKind::Gpu => Backend::Gpu(Box::new(gpu::Gpu::new()?)),
            #[cfg(not(feature = "gpu"))]
            BackendKind::Gpu => return Err(BackendError::NoGpu),
            BackendKind::Outside => {
                return Err(BackendError::Outside(
                    "a program outside tetwalk answers there: it is asked with --answerer CMD"
                        .into(),
                ));
            }
            cpu => {
                let model = cpu.model().expect("a CPU backend has a model");
                if crate::registry::flushes(model) && !crate::fpenv::FLUSH_AVAILABLE {
                    return Err(BackendError::NoFlush(crate::choice::Choice::name(cpu)));
                }
                Backend::Cpu { model }
            }
        })
    }

    /// The GPU with a user's WGSL exit-face functions spliced in as method
    /// [`crate::registry::USER_WGSL`] (`--wgsl`; `path` names the file in compiler messages).
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub(crate) fn gpu_with_user(path: &str, source: &str) -> Result<Backend, BackendError> {
        #[cfg(feature = "gpu")]
        return Ok(Backend::Gpu(Box::new(gpu::Gpu::with_user(path, source)?)));
        #[cfg(not(feature = "gpu"))]
        Err(BackendError::NoGpu)
    }

    /// The GPU adapters wgpu finds, one line each (`tetwalk gpu-info`); none without the GPU feature.
    pub(crate) fn adapters() -> Vec<String> {
        #[cfg(feature = "gpu")]
        return gpu::adapters();
        #[cfg(not(feature = "gpu"))]
        Vec::new()
    }

    pub fn kind(&self) -> BackendKind {
        match self {
            Backend::Cpu { model } => model.backend(),
            #[cfg(feature = "gpu")]
            Backend::Gpu(_) => BackendKind::Gpu,
        }
    }

    /// What crossed between the CPU and the GPU since it was opened (none on the CPU, or without
    /// the `gpu` feature).
    pub fn traffic(&self) -> Option<Traffic> {
        match self {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => Some(g.traffic()),
            Backend::Cpu { .. } => None,
        }
    }

    /// The backend's kind, with the adapter and driver for a GPU.
    pub fn ran(&self) -> Ran {
        Ran {
            kind: self.kind(),
            adapter: match self {
                #[cfg(feature = "gpu")]
                Backend::Gpu(g) => Some(g.describe()),
                Backend::Cpu { .. } => None,
            },
        }
    }

    /// The backend's name, with the adapter and driver for a GPU ([`Ran`]'s text).
    pub fn describe(&self) -> String {
        self.ran().to_string()
    }

    /// Whether walks here report a kernel time (a GPU with timestamp queries).
    pub fn measures_kernels(&self) -> bool {
        match self {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => g.measures_kernels(),
            Backend::Cpu { .. } => false,
        }
    }

    /// Where `method` runs on this backend: here, or on the plain CPU for its family's reference.
    pub(crate) fn for_method(&self, method: &impl Named) -> &Backend {
        if method.is_reference() { &CPU } else { self }
    }

    /// Every hit `method` reports (a triangle of the case and its f32 `t`, in triangle order) for each
    /// triangle case.
    pub fn triangle_hits(
        &self,
        method: &TriangleMethod,
        cases: &[HitCase],
    ) -> Result<Vec<Vec<(u32, f32)>>, BackendError> {
        match self {
            Backend::Cpu { model } => {
                let hits = method.hits(*model);
                Ok(map_all(cases, |c| hits(c.tris(), &c.ray())))
            }
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                // Every case's triangles in one list, one (ray, triangle) pair each.
                let tris: Vec<crate::tet::Tri> = cases
                    .iter()
                    .flat_map(|c| c.tris().iter().copied())
                    .collect();
                let mut pairs = Vec::with_capacity(tris.len());
                for c in cases {
                    let first = pairs.len() as u32;
                    pairs.extend((0..c.tris().len() as u32).map(|k| (c.ray(), first + k)));
                }
                let ts = g.triangle_pairs(method, &tris, &pairs)?;
                let mut out = Vec::with_capacity(cases.len());
                let mut at = 0;
                for c in cases {
                    let n = c.tris().len();
                    out.push(
                        ts[at..at + n]
                            .iter()
                            .enumerate()
                            .filter_map(|(k, t)| t.map(|t| (k as u32, t)))
                            .collect(),
                    );
                    at += n;
                }
                Ok(out)
            }
        }
    }

    /// `method`'s nearest hit among `tris` for each ray, the rays taken `packet` at a time (each packet
    /// sharing an origin), many packets in parallel.
    pub fn trace_triangles(
        &self,
        method: &TriangleMethod,
        tris: &[crate::tet::Tri],
        rays: &[Ray],
        packet: usize,
        among: &Among,
    ) -> Result<Vec<Nearest>, BackendError> {
        match self {
            Backend::Cpu { model } => {
                let trace = method.fastest(*model);
                // Tasks of about 16,384 ray-triangle tests (a ray counted as one more), so that a few
                // large groups still make a task each (a lone task would run on the calling thread);
                // each group's triangles prepared once for its packets.
                let cost = (among.tests() + rays.len() as u64) / among.groups.len().max(1) as u64;
                let per_task = (16_384 / cost.max(1)).max(1) as usize;
                Ok(among
                    .groups
                    .par_chunks(per_task)
                    .flat_map_iter(|g| trace(tris, &among.ids, g, rays, packet))
                    .collect())
            }
            // A GPU thread answers one ray against every triangle (each packet's terms computed in
            // every thread): `among` is not used.
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => Ok(g.nearest_triangles(method, tris, rays)?.items),
        }
    }

    /// `method`'s exit face for each case, in the case's own numbering.
    pub fn exit_faces(
        &self,
        method: &Method,
        cases: &[Case],
    ) -> Result<Vec<Option<usize>>, BackendError> {
        Ok(self.exit_faces_timed(method, cases)?.0)
    }

    /// [`Backend::exit_faces`], with the GPU's kernel time where it measures one.
    pub(crate) fn exit_faces_timed(
        &self,
        method: &Method,
        cases: &[Case],
    ) -> Result<(Vec<Option<usize>>, Option<f64>), BackendError> {
        match self.for_method(method) {
            Backend::Cpu { .. } if !method.info.runs_on_cpu => {
                Err(BackendError::GpuOnly(method.info.name))
            }
            Backend::Cpu { model } => {
                let exit = method.exit(*model);
                let faces = map_all(cases, |c| {
                    let (tet, entry, map) = normalized(c);
                    exit(&tet, &c.ray(), entry).map(|f| map[f])
                });
                Ok((faces, None))
            }
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let prepared: Vec<_> = cases.iter().map(normalized).collect();
                let input: Vec<_> = cases
                    .iter()
                    .zip(&prepared)
                    .map(|(c, (tet, entry, _))| gpu::shader::Case::new(tet, &c.ray(), *entry))
                    .collect();
                let done = g.exit_faces(method, &input)?;
                if !method.info.runs_on_cpu && done.items.contains(&gpu::shader::UNSETTLED) {
                    return Err(BackendError::Unsettled(method.info.name));
                }
                // What the GPU could not settle, the CPU answers.
                let exit = method.exit(Model::Plain);
                let faces = done
                    .items
                    .into_iter()
                    .zip(&prepared)
                    .zip(cases)
                    .map(|((f, (tet, entry, map)), c)| match f {
                        gpu::shader::UNSETTLED => exit(tet, &c.ray(), *entry).map(|f| map[f]),
                        f => usize::try_from(f).ok().map(|f| map[f]),
                    })
                    .collect();
                Ok((faces, done.kernel_seconds))
            }
        }
    }

    /// `method`'s exit face and quarter (neighbour index) for each octree cell case; the reference runs
    /// on the CPU whatever the backend.
    pub fn box_exits(
        &self,
        method: &OctreeMethod,
        cases: &[BoxCase],
    ) -> Result<Vec<Option<(usize, usize)>>, BackendError> {
        let cpu = |model: Model| {
            let exit = method.exit(model);
            map_all(cases, |c| exit(c.lo, c.hi, &c.ray()))
        };
        match self.for_method(method) {
            Backend::Cpu { model } => Ok(cpu(*model)),
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let input: Vec<gpu::shader::Case> = cases
                    .iter()
                    .map(|c| gpu::shader::Case::new(&[c.lo, c.hi, c.lo, c.hi], &c.ray(), None))
                    .collect();
                Ok(g.box_exits(method, &input)?
                    .into_iter()
                    .map(|x| usize::try_from(x).ok().map(|x| (x / 4, x % 4)))
                    .collect())
            }
        }
    }

    /// Make an octree and its triangles ready to walk here (a GPU gets them uploaded, once, with
    /// the constrained face each came from, `from`, from both sides, on which a count compares
    /// hits there; empty where none is compared).
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub fn octree(
        &self,
        octree: &Octree,
        tris: &[crate::tet::Tri],
        from: &[[(u32, u8); 2]],
    ) -> OctreeOn {
        OctreeOn {
            #[cfg(feature = "gpu")]
            gpu: match self {
                #[cfg(feature = "gpu")]
                Backend::Gpu(g) => Some(g.upload_octree(octree, g.upload_triangles(tris, from))),
                Backend::Cpu { .. } => None,
            },
        }
    }

    /// Make a scene's triangles ready for the nearest hits a count compares where they are made
    /// ([`Backend::triangles_against`]): a GPU gets them uploaded, once, with the constrained face
    /// each came from (`from`, from both sides: [`crate::mesh::surface::both_sides`]).
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub fn triangles(&self, tris: &[crate::tet::Tri], from: &[[(u32, u8); 2]]) -> TrianglesOn {
        TrianglesOn {
            #[cfg(feature = "gpu")]
            gpu: match self {
                #[cfg(feature = "gpu")]
                Backend::Gpu(g) => Some(g.upload_triangles(tris, from)),
                Backend::Cpu { .. } => None,
            },
        }
    }

    /// `method`'s nearest hit among the triangles made ready as `on` for each ray of the last
    /// [`Backend::walks_keeping`] that kept its endings (from `start`), compared with them where
    /// they are made: on a GPU, queued ([`Backend::gather`]), only the rays not settled there as
    /// ending where the reference ends (the triangle and `t` of each, or `None`, in pixel order;
    /// no steps); `None` elsewhere.
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub fn triangles_against<'a>(
        &'a self,
        method: &'a TriangleMethod,
        on: &'a TrianglesOn,
        rays: &'a [Ray],
        start: u32,
    ) -> Result<Option<Pending<'a, Against<Nearest>>>, BackendError> {
        match self {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let up = on.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                let kept = map_all(rays, |r| (*r, start));
                let queued = g.nearest_against(method, up, &kept)?;
                Ok(Some(Pending::new(
                    queued,
                    move || g.nearest_against(method, up, &kept),
                    |done| {
                        let sent = in_pixel_order(done.sent, |_, e| e.triangle_hit())?;
                        Ok(Against { steps: 0, sent })
                    },
                )))
            }
            _ => Ok(None),
        }
    }

    /// `method`'s walks of `rays` through the octree `o` over `tris` (seed 001 §4.2.3), made ready
    /// here as `on` ([`Backend::octree`]), each leaf's triangles tested with `tri`; the reference runs
    /// on the CPU whatever the backend. On a GPU the entry cell comes from the cube map on the CPU, the
    /// loop runs in WGSL.
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    #[allow(clippy::too_many_arguments)]
    pub fn octree_walks(
        &self,
        method: &OctreeMethod,
        tri: &TriangleMethod,
        o: &Octree,
        tris: &[crate::tet::Tri],
        on: &OctreeOn,
        rays: &[Ray],
        max_steps: u32,
    ) -> Result<Vec<OctreeWalk>, BackendError> {
        let cpu = |model: Model| {
            let (walk, hit) = (method.walk(model), tri.hit(model));
            map_all(rays, |r| walk(o, tris, hit, r, max_steps))
        };
        match self.for_method(method) {
            Backend::Cpu { model } => Ok(cpu(*model)),
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let up = on.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                let ends = g.octree_walks(method, tri, up, &entry_cells(o, rays), max_steps)?;
                Ok(ends.iter().map(|e| e.octree_walk()).collect())
            }
        }
    }

    /// [`Backend::octree_walks`] of the rays of the last [`Backend::walks_keeping`] that kept its
    /// endings (from `start`), compared with them where they are made: on a GPU, queued
    /// ([`Backend::gather`]), the cells summed and only the walks not settled there as ending where
    /// the reference ends, in pixel order; `None` elsewhere.
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    #[allow(clippy::too_many_arguments)]
    pub fn octree_walks_against<'a>(
        &'a self,
        method: &'a OctreeMethod,
        tri: &'a TriangleMethod,
        o: &'a Octree,
        on: &'a OctreeOn,
        rays: &'a [Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Option<Pending<'a, Against<OctreeWalk>>>, BackendError> {
        match self.for_method(method) {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let up = on.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                let kept = map_all(rays, |r| (*r, start));
                let entered = move || entry_cells(o, rays);
                let queued = g.octree_walks_against(method, tri, up, &entered, max_steps, &kept)?;
                Ok(Some(Pending::new(
                    queued,
                    move || g.octree_walks_against(method, tri, up, &entered, max_steps, &kept),
                    |done| {
                        Ok(Against {
                            steps: done.steps,
                            sent: in_pixel_order(done.sent, |_, e| Ok(e.octree_walk()))?,
                        })
                    },
                )))
            }
            _ => Ok(None),
        }
    }

    /// `method`'s exit face for one case.
    pub fn exit_face(&self, method: &Method, case: &Case) -> Result<Option<usize>, BackendError> {
        Ok(self.exit_faces(method, std::slice::from_ref(case))?[0])
    }

    /// Make `mesh` ready to walk here (a GPU gets it uploaded).
    pub fn mesh<'a>(&self, mesh: &'a Mesh) -> MeshOn<'a> {
        MeshOn {
            mesh,
            #[cfg(feature = "gpu")]
            gpu: match self {
                #[cfg(feature = "gpu")]
                Backend::Gpu(g) => Some(g.upload(mesh)),
                Backend::Cpu { .. } => None,
            },
        }
    }

    /// Make seed 003's layouts of a mesh ready to walk here.
    pub fn layout<'a>(&self, layout: &'a Layout, points: &'a [glam::Vec3]) -> LayoutOn<'a> {
        LayoutOn {
            layout,
            points,
            #[cfg(feature = "gpu")]
            gpu: match self {
                #[cfg(feature = "gpu")]
                Backend::Gpu(g) => Some(g.upload_layout(layout, points)),
                Backend::Cpu { .. } => None,
            },
        }
    }

    /// `method`'s walk over layout `kind` of every ray from its source tetrahedron (seed 003
    /// Algorithms 2-7; the 2-D frame methods only).
    pub fn layout_walks(
        &self,
        method: &Method,
        kind: LayoutKind,
        on: &LayoutOn,
        rays: &[(Ray, Source)],
        max_steps: u32,
    ) -> Result<LayoutWalked, BackendError> {
        match self {
            Backend::Cpu { model } => {
                let walk = method
                    .layout_walk(*model)
                    .ok_or(BackendError::NoLayoutWalk(method.info.name))?;
                Ok(LayoutWalked {
                    walks: map_all(rays, |(r, s)| {
                        walk(kind, on.layout, on.points, r, s, max_steps)
                    }),
                    kernel_seconds: None,
                })
            }
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let uploaded = on.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                if uploaded.tetrahedra != on.layout.tet32.len() {
                    return Err(BackendError::OtherMesh);
                }
                let done = g.layout_walks(method, kind, uploaded, rays, max_steps)?;
                Ok(LayoutWalked {
                    walks: done
                        .items
                        .par_iter()
                        .map(|e| e.layout_walk().ok_or(GpuError::BadOutcome(e.kind)))
                        .collect::<Result<_, _>>()?,
                    kernel_seconds: done.kernel_seconds,
                })
            }
        }
    }

    /// `method`'s walk of every ray from tetrahedron `start` (which holds every origin).
    pub fn walks(
        &self,
        method: &Method,
        mesh: &MeshOn,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Vec<Walk>, BackendError> {
        let rays = map_all(rays, |r| (*r, start));
        Ok(self.walks_from(method, mesh, &rays, max_steps)?.walks)
    }

    /// [`Backend::walks`] as the reference walk a count compares its methods' answers with
    /// ([`Backend::walks_against`]): on a GPU that can keep the batch, kept there and read back
    /// with them ([`Backend::keep_walks`]); elsewhere every ending.
    pub fn walks_keeping(
        &self,
        method: &Method,
        mesh: &MeshOn,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
        picked: &[usize],
    ) -> Result<Kept, BackendError> {
        let keeping = self.keep_walks(method, mesh, rays, start, max_steps, picked)?;
        Ok(self.gather_view::<Walk>(keeping, Vec::new())?.kept)
    }

    /// [`Backend::walks_keeping`] queued: on a GPU that can keep the batch, kept there, only the
    /// steps summed and the endings of `picked` (indices into `rays`, ascending) to be read back
    /// ([`Backend::gather_view`], with the methods' answers queued after it), the rays it flagged
    /// then walked on the CPU and written over their endings there; elsewhere every ending, now.
    pub(crate) fn keep_walks<'a>(
        &'a self,
        method: &'a Method,
        mesh: &'a MeshOn,
        rays: &'a [Ray],
        start: u32,
        max_steps: u32,
        picked: &'a [usize],
    ) -> Result<Keeping<'a>, BackendError> {
        let from = map_all(rays, |r| (*r, start));
        match self.for_method(method) {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) if g.keeps(rays.len()) => {
                let uploaded = mesh.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                if uploaded.tetrahedra != mesh.mesh.tets.len() {
                    return Err(BackendError::OtherMesh);
                }
                let queued = g.walks_keeping(method, uploaded, &from, max_steps, picked)?;
                let finish = move |done: gpu::Dispatched<gpu::shader::Ending>| {
                    if !done.sent.is_empty() && !method.info.runs_on_cpu {
                        return Err(BackendError::Unsettled(method.info.name));
                    }
                    let walk = method.walk(Model::Plain);
                    let mut steps = done.steps;
                    let flagged: Vec<(usize, Walk)> = done
                        .sent
                        .iter()
                        .map(|s| {
                            let i = s.index as usize;
                            let w = walk(mesh.mesh, &rays[i], start, max_steps);
                            steps = steps - u64::from(s.steps) + u64::from(w.steps);
                            (i, w)
                        })
                        .collect();
                    let picked = picked
                        .iter()
                        .zip(&done.items)
                        .map(|(i, e)| {
                            e.walk()
                                .or_else(|| flagged.iter().find(|f| f.0 == *i).map(|f| f.1))
                                .ok_or(GpuError::BadOutcome(e.kind))
                        })
                        .collect::<Result<_, _>>()?;
                    let kept = Kept {
                        steps,
                        picked,
                        all: None,
                    };
                    Ok((kept, flagged))
                };
                Ok(Keeping::Queued(Pending::new(
                    queued,
                    move || g.walks_keeping(method, uploaded, &from, max_steps, picked),
                    finish,
                )))
            }
            _ => {
                let walks = self.walks_from(method, mesh, &from, max_steps)?.walks;
                Ok(Keeping::Read(Kept {
                    steps: walks.iter().map(|w| u64::from(w.steps)).sum(),
                    picked: picked.iter().map(|&i| walks[i]).collect(),
                    all: Some(walks),
                }))
            }
        }
    }

    /// Every ending of the reference walk kept where it was made ([`Backend::walks_keeping`]) for
    /// `rays` from `start`, read back.
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub fn kept_walks(&self, rays: &[Ray], start: u32) -> Result<Vec<Walk>, BackendError> {
        match self {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let from = map_all(rays, |r| (*r, start));
                let endings = g.kept_endings(&from)?;
                Ok(endings
                    .par_iter()
                    .map(|e| e.walk().ok_or(GpuError::BadOutcome(e.kind)))
                    .collect::<Result<_, _>>()?)
            }
            Backend::Cpu { .. } => Err(BackendError::NotKept),
        }
    }

    /// `method`'s walks of the rays of the last [`Backend::walks_keeping`] that kept its endings,
    /// compared with them where they are made: on a GPU, queued ([`Backend::gather`]), the steps
    /// summed and only the walks not settled there as ending where the reference ends (each to be
    /// judged exactly, with the rays the GPU flagged walked on the CPU); `None` elsewhere.
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub fn walks_against<'a>(
        &'a self,
        method: &'a Method,
        mesh: &'a MeshOn,
        rays: &'a [Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Option<Pending<'a>>, BackendError> {
        match self.for_method(method) {
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let uploaded = mesh.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                let from = map_all(rays, |r| (*r, start));
                let queued = g.walks_against(method, uploaded, &from, max_steps)?;
                let finish = move |done: gpu::Dispatched<gpu::shader::Ending>| {
                    let walk = method.walk(Model::Plain);
                    let (mut steps, mut flagged) = (done.steps, 0);
                    let sent = in_pixel_order(done.sent, |i, e| {
                        Ok(e.walk().unwrap_or_else(|| {
                            flagged += 1;
                            let w = walk(mesh.mesh, &rays[i], start, max_steps);
                            steps = steps - u64::from(e.steps) + u64::from(w.steps);
                            w
                        }))
                    })?;
                    if flagged > 0 && !method.info.runs_on_cpu {
                        return Err(BackendError::Unsettled(method.info.name));
                    }
                    Ok(Against { steps, sent })
                };
                Ok(Some(Pending::new(
                    queued,
                    move || g.walks_against(method, uploaded, &from, max_steps),
                    finish,
                )))
            }
            _ => Ok(None),
        }
    }

    /// `method`'s walk of every ray from its own starting tetrahedron, with the GPU's kernel time
    /// where it measures one.
    pub fn walks_from(
        &self,
        method: &Method,
        mesh: &MeshOn,
        rays: &[(Ray, u32)],
        max_steps: u32,
    ) -> Result<Walked, BackendError> {
        match self.for_method(method) {
            Backend::Cpu { .. } if !method.info.runs_on_cpu => {
                Err(BackendError::GpuOnly(method.info.name))
            }
            Backend::Cpu { model } => {
                let walks = method.walks(*model);
                if rays.len() < PARALLEL_FROM {
                    return Ok(Walked {
                        walks: walks(mesh.mesh, rays, max_steps),
                        kernel_seconds: None,
                        flagged: 0,
                    });
                }
                // Each chunk's walks written in place by the thread that walked them.
                let mut out = vec![Walk::NONE; rays.len()];
                out.par_chunks_mut(PARALLEL_FROM)
                    .zip(rays.par_chunks(PARALLEL_FROM))
                    .for_each(|(o, chunk)| o.copy_from_slice(&walks(mesh.mesh, chunk, max_steps)));
                Ok(Walked {
                    walks: out,
                    kernel_seconds: None,
                    flagged: 0,
                })
            }
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => {
                let uploaded = mesh.gpu.as_ref().ok_or(BackendError::OtherMesh)?;
                if uploaded.tetrahedra != mesh.mesh.tets.len() {
                    return Err(BackendError::OtherMesh);
                }
                let done = g.walks(method, uploaded, rays, max_steps)?;
                let flagged = done.items.par_iter().filter(|e| e.walk().is_none()).count();
                if flagged > 0 && !method.info.runs_on_cpu {
                    return Err(BackendError::Unsettled(method.info.name));
                }
                // Flagged rays (a step the GPU could not settle) are walked on the CPU.
                let walk = method.walk(Model::Plain);
                Ok(Walked {
                    walks: done
                        .items
                        .par_iter()
                        .zip(rays)
                        .map(|(e, (r, start))| {
                            e.walk()
                                .unwrap_or_else(|| walk(mesh.mesh, r, *start, max_steps))
                        })
                        .collect(),
                    kernel_seconds: done.kernel_seconds,
                    flagged,
                })
            }
        }
    }
}

/// A reference walk of a view's rays as [`Backend::walks_keeping`] left it.
pub struct Kept {
    /// Every walk's steps, summed.
    pub steps: u64,
    /// The picked rays' endings, in their order.
    pub picked: Vec<Walk>,
    /// Every ending, where they were read back (on the CPU, or a batch too large to keep on the
    /// GPU); `None` where they are kept on the GPU ([`Backend::kept_walks`] reads them back).
    pub all: Option<Vec<Walk>>,
}

/// Answers compared with the kept reference walk where they were made ([`Backend::walks_against`],
/// [`Backend::triangles_against`], [`Backend::octree_walks_against`]): their steps summed, and
/// each answer not settled there as ending where the reference ends, by index, in pixel order,
/// with the reference walk's ending (its steps not sent).
pub struct Against<T = Walk> {
    pub steps: u64,
    pub sent: Vec<(usize, T, Walk)>,
}

impl<T> Against<T> {
    /// The same, each answer sent back as `f` says.
    pub(crate) fn map<U>(self, f: impl Fn(T) -> U) -> Against<U> {
        Against {
            steps: self.steps,
            sent: self
                .sent
                .into_iter()
                .map(|(i, a, r)| (i, f(a), r))
                .collect(),
        }
    }
}

/// Answers kept or compared with the kept reference walk where they are made, queued on a GPU and
/// not yet read back: [`Backend::gather`] reads a view's at once, in one wait. Each is read as `R`:
/// a method's answers ([`Against`]), or the reference walk.
pub struct Pending<'a, R = Against> {
    #[cfg(feature = "gpu")]
    queued: gpu::Queued,
    /// The same queued again, where a later one's records were sent over its before they were read.
    #[cfg(feature = "gpu")]
    again: Box<dyn Fn() -> Result<gpu::Queued, GpuError> + 'a>,
    /// The answers from what was read back.
    #[cfg(feature = "gpu")]
    #[allow(clippy::type_complexity)]
    finish: Box<dyn FnOnce(gpu::Dispatched<gpu::shader::Ending>) -> Result<R, BackendError> + 'a>,
    #[cfg(not(feature = "gpu"))]
    never: (std::convert::Infallible, std::marker::PhantomData<&'a R>),
}

impl<'a, R: 'a> Pending<'a, R> {
    #[cfg(feature = "gpu")]
    fn new(
        queued: gpu::Queued,
        again: impl Fn() -> Result<gpu::Queued, GpuError> + 'a,
        finish: impl FnOnce(gpu::Dispatched<gpu::shader::Ending>) -> Result<R, BackendError> + 'a,
    ) -> Self {
        Pending {
            queued,
            again: Box::new(again),
            finish: Box::new(finish),
        }
    }
}

impl<'a, T: 'a> Pending<'a, Against<T>> {
    /// The same, each answer sent back as `f` says.
    #[cfg_attr(not(feature = "gpu"), allow(unused_variables))]
    pub(crate) fn map<U>(self, f: impl Fn(T) -> U + 'a) -> Pending<'a, Against<U>> {
        #[cfg(feature = "gpu")]
        {
            let finish = self.finish;
            Pending {
                queued: self.queued,
                again: self.again,
                finish: Box::new(move |done| Ok(finish(done)?.map(f))),
            }
        }
        #[cfg(not(feature = "gpu"))]
        match self.never.0 {}
    }
}

/// A view's reference walk ([`Backend::keep_walks`]): queued where the methods run (a GPU), to be
/// read back with their answers ([`Backend::gather_view`]), or walked and read back whole.
pub(crate) enum Keeping<'a> {
    /// Kept on the GPU; read back as the walk and the rays it flagged, walked on the CPU (written
    /// over their endings there when read back).
    Queued(Pending<'a, (Kept, Vec<(usize, Walk)>)>),
    Read(Kept),
}

impl Keeping<'_> {
    /// Whether the reference walk's endings are kept where the methods run.
    pub(crate) fn kept_there(&self) -> bool {
        matches!(self, Keeping::Queued(_))
    }
}

/// A view's answers read back ([`Backend::gather_view`]): the reference walk, with what crossed for
/// it where it was queued, and each method's answers with what crossed for them.
pub(crate) struct GatheredView<T> {
    pub(crate) kept: Kept,
    pub(crate) reference: Option<Traffic>,
    pub(crate) answers: Vec<(Against<T>, Traffic)>,
}

impl Backend {
    /// The answers queued ([`Pending`]), read back in one wait, in their order, each with what
    /// crossed for it (the wait counted on the first); refused for answers another backend queued.
    pub fn gather<T>(
        &self,
        pending: Vec<Pending<Against<T>>>,
    ) -> Result<Vec<(Against<T>, Traffic)>, BackendError> {
        Ok(self.gather_all(None, pending)?.1)
    }

    /// A view's reference walk and its methods' answers queued after it, read back in one wait
    /// where the reference is queued: the rays it flagged are walked on the CPU, written over its
    /// endings there, and set as the reference's ending of every answer sent back for them (none
    /// settled there: a flagged ending settles nothing).
    pub(crate) fn gather_view<'a, T>(
        &self,
        reference: Keeping<'a>,
        pending: Vec<Pending<'a, Against<T>>>,
    ) -> Result<GatheredView<T>, BackendError> {
        match reference {
            Keeping::Read(kept) => Ok(GatheredView {
                kept,
                reference: None,
                answers: self.gather(pending)?,
            }),
            Keeping::Queued(r) => {
                let (reference, answers) = self.gather_all(Some(r), pending)?;
                let ((kept, _), traffic) = reference.expect("the reference was queued");
                Ok(GatheredView {
                    kept,
                    reference: Some(traffic),
                    answers,
                })
            }
        }
    }

    /// [`Backend::gather_view`] of a queued reference walk, or [`Backend::gather`] without one.
    #[allow(clippy::type_complexity)]
    fn gather_all<'a, T>(
        &self,
        reference: Option<Pending<'a, (Kept, Vec<(usize, Walk)>)>>,
        pending: Vec<Pending<'a, Against<T>>>,
    ) -> Result<
        (
            Option<((Kept, Vec<(usize, Walk)>), Traffic)>,
            Vec<(Against<T>, Traffic)>,
        ),
        BackendError,
    > {
        if reference.is_none() && pending.is_empty() {
            return Ok((None, Vec::new()));
        }
        #[cfg(feature = "gpu")]
        {
            let Backend::Gpu(g) = self else {
                return Err(BackendError::NotKept);
            };
            // Read back with the others' in one wait; where a later one's records were sent over
            // its own, queued again alone and read whole.
            let resolve = |gathered: gpu::Gathered,
                           again: &dyn Fn() -> Result<gpu::Queued, GpuError>|
             -> Result<_, BackendError> {
                let mut traffic = gathered.traffic;
                let done = match gathered.done {
                    Some(done) => done,
                    None => {
                        let alone = g.gather(vec![again()?])?.remove(0);
                        traffic = traffic.plus(&alone.traffic);
                        alone.done.ok_or(GpuError::Readback(
                            "a comparison's records were sent over before they were read".into(),
                        ))?
                    }
                };
                Ok((done, traffic))
            };
            let mut all: Vec<gpu::Queued> = Vec::with_capacity(pending.len() + 1);
            let reference = reference.map(|r| {
                all.push(r.queued);
                (r.again, r.finish)
            });
            let pending: Vec<_> = pending
                .into_iter()
                .map(|p| {
                    all.push(p.queued);
                    (p.again, p.finish)
                })
                .collect();
            let mut gathered = g.gather(all)?.into_iter();
            let reference = match reference {
                Some((again, finish)) => {
                    let (done, mut traffic) = resolve(gathered.next().expect("one each"), &*again)?;
                    let (kept, flagged) = finish(done)?;
                    traffic.written += g.amend_reference(&flagged)?;
                    Some(((kept, flagged), traffic))
                }
                None => None,
            };
            // The flagged rays' endings as the CPU walked them, by index.
            let flagged: std::collections::HashMap<u32, gpu::shader::Ending> = reference
                .iter()
                .flat_map(|((_, flagged), _)| flagged)
                .map(|(i, w)| (*i as u32, gpu::shader::Ending::of(w)))
                .collect();
            let answers = gathered
                .zip(pending)
                .map(|(gathered, (again, finish))| {
                    let (mut done, traffic) = resolve(gathered, &*again)?;
                    for s in &mut done.sent {
                        if let Some(e) = flagged.get(&s.index) {
                            (s.r_kind, s.r_tet, s.r_x) = (e.kind, e.tet, e.x);
                        }
                    }
                    Ok((finish(done)?, traffic))
                })
                .collect::<Result<_, BackendError>>()?;
            Ok((reference, answers))
        }
        #[cfg(not(feature = "gpu"))]
        // Without a GPU nothing is queued (a `Pending` has no value there).
        match reference {
            Some(r) => match r.never.0 {},
            None => Err(BackendError::NoGpu),
        }
    }
}

/// The records a GPU sent back, in pixel order (it sends them in any order), each as `f` reads its
/// index and ending (refused where it cannot), with the reference walk's ending.
#[cfg(feature = "gpu")]
fn in_pixel_order<T>(
    mut sent: Vec<gpu::shader::Sent>,
    mut f: impl FnMut(usize, gpu::shader::Ending) -> Result<T, GpuError>,
) -> Result<Vec<(usize, T, Walk)>, GpuError> {
    sent.sort_unstable_by_key(|s| s.index);
    sent.iter()
        .map(|s| {
            let reference = s.reference().ok_or(GpuError::BadOutcome(s.r_kind))?;
            Ok((
                s.index as usize,
                f(s.index as usize, s.ending())?,
                reference,
            ))
        })
        .collect()
}

/// Each ray with the address of the octree cell it enters first, from the cube map (seed 001 §4.1;
/// `HULL` for a miss), as the GPU's octree walk starts it.
#[cfg(feature = "gpu")]
fn entry_cells(o: &Octree, rays: &[Ray]) -> Vec<(Ray, u32)> {
    map_all(rays, |r| {
        (
            *r,
            crate::walk::octree::entry(o, r).unwrap_or(crate::mesh::HULL),
        )
    })
}

/// Walks from a backend: the GPU's kernel time where it measures one, and how many rays the GPU
/// flagged for the CPU to walk.
pub struct Walked {
    pub walks: Vec<Walk>,
    pub kernel_seconds: Option<f64>,
    pub(crate) flagged: usize,
}
