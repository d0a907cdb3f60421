//! The methods and the walk as WGSL compute shaders, run through `wgpu` on whatever adapter there is
//! (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME` respected), headless. The shader and its buffer layouts are
//! generated from the Rust definitions ([`shader`]).

use crate::mesh::Mesh;
use crate::registry::{Gpu as GpuSupport, Method};
use crate::tet::{Ray, Tet};
use crate::walk::{Outcome, OutcomeKind, Walk};
use shader::{Ending, GROUP, Params};
use std::collections::HashMap;
use std::sync::Mutex;
use wgpu::util::DeviceExt;

pub mod shader;

/// What the shader writes for "no exit face".
pub const NONE: i32 = -1;

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
    #[error("method '{method}' has no GPU version: {why}")]
    NoGpuMethod {
        method: &'static str,
        why: &'static str,
    },
    #[error("reading results back from the GPU failed: {0}")]
    Readback(String),
    #[error("the GPU wrote outcome code {0}, which no outcome kind has")]
    BadOutcome(u32),
}

impl shader::Case {
    /// A case as the shader reads it.
    pub fn new(tet: &Tet, ray: &Ray, entry: Option<usize>) -> shader::Case {
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
pub fn adapters() -> Vec<String> {
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

/// A GPU with the shader module; each method's pipelines are compiled when first used.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    module: wgpu::ShaderModule,
    pipelines: Mutex<HashMap<String, wgpu::ComputePipeline>>,
    info: wgpu::AdapterInfo,
    max_groups: u32,
}

impl Gpu {
    /// Open the adapter named by `WGPU_ADAPTER_NAME` (substring, any case), or the default one.
    pub fn new() -> Result<Gpu, GpuError> {
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
        let limits = wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits());
        let limits = wgpu::Limits {
            max_storage_buffers_per_shader_stage: 8,
            ..limits
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tetwalk"),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        // Shader errors become a GpuError, not a panic.
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tetwalk.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader::COMMITTED.into()),
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
        }
        Ok(Gpu {
            max_groups: limits.max_compute_workgroups_per_dimension,
            device,
            queue,
            module,
            pipelines: Mutex::new(HashMap::new()),
            info,
        })
    }

    /// The pipeline of entry point `entry`, compiled once.
    fn pipeline(&self, entry: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        let mut cache = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = cache.get(entry) {
            return Ok(p.clone());
        }
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let p = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(format!("{entry}: {e}")));
        }
        cache.insert(entry.to_string(), p.clone());
        Ok(p)
    }

    /// The entry points of `method`, or why it has none.
    fn entry_points(method: &Method) -> Result<[String; 2], GpuError> {
        match method.gpu {
            GpuSupport::Wgsl(_) => Ok(shader::entry_points(method)),
            GpuSupport::CpuOnly(why) => Err(GpuError::NoGpuMethod {
                method: method.name,
                why,
            }),
        }
    }

    /// Adapter, backend and driver, for reports.
    pub fn describe(&self) -> String {
        describe(&self.info)
    }

    fn storage(&self, data: &[u8]) -> wgpu::Buffer {
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
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
    }

    /// Run `pipeline` over `count` items in batches the adapter allows; `bind` lists (binding, buffer)
    /// besides the parameters; returns the contents of the `out` buffer.
    fn dispatch(
        &self,
        pipeline: &str,
        mut params: Params,
        bind: &[(u32, &wgpu::Buffer)],
        out: &wgpu::Buffer,
    ) -> Result<Vec<u8>, GpuError> {
        let pipeline = self.pipeline(pipeline)?;
        let pipeline = &pipeline;
        let total = params.count;
        let per = self.max_groups.saturating_mul(GROUP).max(GROUP);
        let mut offset = 0;
        while offset < total {
            params.offset = offset;
            params.count = (total - offset).min(per);
            let uniform = self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: None,
                    contents: bytemuck::bytes_of(&params),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            let mut entries = vec![wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }];
            entries.extend(bind.iter().map(|(b, buf)| wgpu::BindGroupEntry {
                binding: *b,
                resource: buf.as_entire_binding(),
            }));
            let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            let mut enc = self.device.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups(params.count.div_ceil(GROUP), 1, 1);
            }
            self.queue.submit([enc.finish()]);
            offset += params.count;
        }
        let read = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: out.size(),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(out, 0, &read, 0, out.size());
        self.queue.submit([enc.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        read.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let bytes = read
            .get_mapped_range(..)
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .to_vec();
        Ok(bytes)
    }

    /// Each case's answer by `method`, as the shader writes it: a face, [`NONE`] for no exit face, or
    /// [`shader::UNSETTLED`] for a case the CPU must answer.
    pub fn exit_faces(
        &self,
        method: &Method,
        cases: &[shader::Case],
    ) -> Result<Vec<i32>, GpuError> {
        let [exit, _] = Self::entry_points(method)?;
        let input = self.storage(bytemuck::cast_slice(cases));
        let out = self.storage(&vec![0u8; 4 * cases.len()]);
        let params = Params {
            count: cases.len() as u32,
            offset: 0,
            max_steps: 0,
            start: 0,
        };
        let bytes = self.dispatch(&exit, params, &[(1, &input), (2, &out)], &out)?;
        let mut faces: Vec<i32> = bytemuck::pod_collect_to_vec(&bytes);
        faces.truncate(cases.len());
        Ok(faces)
    }

    /// Upload a mesh for [`Gpu::walks`].
    pub fn upload(&self, mesh: &Mesh) -> GpuMesh {
        let points: Vec<[f32; 4]> = mesh
            .points
            .iter()
            .map(|p| p.extend(0.0).to_array())
            .collect();
        let info: Vec<u32> = (0..mesh.tets.len())
            .map(|t| {
                let m = mesh.mirror[t];
                let mirror = (0..4).fold(0u32, |acc, f| acc | ((m[f] as u32 & 3) << (2 * f)));
                mirror | (mesh.constrained[t] as u32) << 8
            })
            .collect();
        GpuMesh {
            points: self.storage(bytemuck::cast_slice(&points)),
            tets: self.storage(bytemuck::cast_slice(&mesh.tets)),
            neighbors: self.storage(bytemuck::cast_slice(&mesh.neighbors)),
            info: self.storage(bytemuck::cast_slice(&info)),
            tetrahedra: mesh.tets.len(),
        }
    }

    /// Walk every ray from tetrahedron `start` with `method` on the GPU; `None` for a ray the method
    /// flagged (a step its f32 stage could not settle), which the CPU must walk.
    pub fn walks(
        &self,
        method: &Method,
        mesh: &GpuMesh,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Vec<Option<Walk>>, GpuError> {
        let [_, walk] = Self::entry_points(method)?;
        let r: Vec<[f32; 4]> = rays
            .iter()
            .flat_map(|r| [r.org.extend(0.0).to_array(), r.dir.extend(0.0).to_array()])
            .collect();
        let input = self.storage(bytemuck::cast_slice(&r));
        let out = self.storage(&vec![0u8; std::mem::size_of::<Ending>() * rays.len()]);
        let params = Params {
            count: rays.len() as u32,
            offset: 0,
            max_steps,
            start,
        };
        let bind = [
            (3, &input),
            (4, &mesh.points),
            (5, &mesh.tets),
            (6, &mesh.neighbors),
            (7, &mesh.info),
            (8, &out),
        ];
        let bytes = self.dispatch(&walk, params, &bind, &out)?;
        let endings: Vec<Ending> = bytemuck::pod_collect_to_vec(&bytes);
        endings[..rays.len()]
            .iter()
            .map(|e| {
                if e.kind == shader::FLAGGED {
                    return Ok(None);
                }
                let kind = OutcomeKind::from_code(e.kind).ok_or(GpuError::BadOutcome(e.kind))?;
                Ok(Some(Walk {
                    outcome: Outcome::from_parts(kind, e.tet, e.x),
                    steps: e.steps,
                }))
            })
            .collect()
    }
}

/// A mesh uploaded to the GPU.
pub struct GpuMesh {
    points: wgpu::Buffer,
    tets: wgpu::Buffer,
    neighbors: wgpu::Buffer,
    info: wgpu::Buffer,
    pub tetrahedra: usize,
}

/// Whether tests must have an adapter (`TETWALK_REQUIRE_GPU=1`, as CI sets).
pub fn required() -> bool {
    std::env::var("TETWALK_REQUIRE_GPU").is_ok_and(|v| v == "1")
}
