//! The methods and the walk as WGSL compute shaders, run through `wgpu` on whatever adapter there is
//! (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME` respected), headless. Buffer layouts are the `#[repr(C)]`
//! types here, shared with the shader through `bytemuck`.

use crate::mesh::Mesh;
use crate::tet::{Ray, Tet};
use crate::walk::{Outcome, Walk};
use wgpu::util::DeviceExt;

/// The methods the shader implements, in the order of its `exit_face` switch (`exact` stays on the CPU).
pub const GPU_METHODS: [&str; 8] = [
    "ray-plane",
    "halfspace",
    "plucker",
    "stp",
    "ms06",
    "maria17",
    "aman20",
    "aman20-scaled",
];

/// The shader's id for a method, if it has one.
pub fn method_id(name: &str) -> Option<u32> {
    GPU_METHODS
        .iter()
        .position(|&m| m == name)
        .map(|i| i as u32)
}

/// Why the GPU cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found{0} (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe)"
    )]
    NoAdapter(String),
    #[error("the GPU device could not be opened: {0}")]
    Device(String),
    #[error("method '{0}' has no GPU version (the GPU runs {GPU_METHODS:?})")]
    NoGpuMethod(String),
    #[error("reading results back from the GPU failed: {0}")]
    Readback(String),
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    method: u32,
    count: u32,
    offset: u32,
    max_steps: u32,
    start: u32,
    pad: [u32; 3],
}

/// One exit-face case as the shader reads it (a positively oriented tetrahedron).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuCase {
    v: [[f32; 4]; 4],
    org: [f32; 4],
    dir: [f32; 4],
    entry: i32,
    pad: [i32; 3],
}

impl GpuCase {
    pub fn new(tet: &Tet, ray: &Ray, entry: Option<usize>) -> GpuCase {
        GpuCase {
            v: tet.map(|p| p.extend(0.0).to_array()),
            org: ray.org.extend(0.0).to_array(),
            dir: ray.dir.extend(0.0).to_array(),
            entry: entry.map_or(-1, |e| e as i32),
            pad: [0; 3],
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

/// A GPU with the two pipelines.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    exit: wgpu::ComputePipeline,
    walk: wgpu::ComputePipeline,
    info: wgpu::AdapterInfo,
    max_groups: u32,
}

/// Threads per workgroup in the shader.
const GROUP: u32 = 64;

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
        // Shader or pipeline errors become a GpuError, not a panic.
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("methods.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("methods.wgsl").into()),
        });
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let (exit, walk) = (pipeline("exit_cases"), pipeline("walk_rays"));
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(e.to_string()));
        }
        Ok(Gpu {
            max_groups: limits.max_compute_workgroups_per_dimension,
            device,
            queue,
            exit,
            walk,
            info,
        })
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
        pipeline: &wgpu::ComputePipeline,
        mut params: Params,
        bind: &[(u32, &wgpu::Buffer)],
        out: &wgpu::Buffer,
    ) -> Result<Vec<u8>, GpuError> {
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

    /// Each case's exit face (`None` for no exit face) by method `method` (a [`GPU_METHODS`] name).
    pub fn exit_faces(
        &self,
        method: &str,
        cases: &[GpuCase],
    ) -> Result<Vec<Option<usize>>, GpuError> {
        let id = method_id(method).ok_or_else(|| GpuError::NoGpuMethod(method.into()))?;
        let input = self.storage(bytemuck::cast_slice(cases));
        let out = self.storage(&vec![0u8; 4 * cases.len()]);
        let params = Params {
            method: id,
            count: cases.len() as u32,
            offset: 0,
            max_steps: 0,
            start: 0,
            pad: [0; 3],
        };
        let bytes = self.dispatch(&self.exit, params, &[(1, &input), (2, &out)], &out)?;
        let faces: &[i32] = bytemuck::cast_slice(&bytes);
        Ok(faces[..cases.len()]
            .iter()
            .map(|&f| (f >= 0).then_some(f as usize))
            .collect())
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

    /// Walk every ray from tetrahedron `start` with `method` on the GPU.
    pub fn walks(
        &self,
        method: &str,
        mesh: &GpuMesh,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Vec<Walk>, GpuError> {
        let id = method_id(method).ok_or_else(|| GpuError::NoGpuMethod(method.into()))?;
        let r: Vec<[f32; 4]> = rays
            .iter()
            .flat_map(|r| [r.org.extend(0.0).to_array(), r.dir.extend(0.0).to_array()])
            .collect();
        let input = self.storage(bytemuck::cast_slice(&r));
        let out = self.storage(&vec![0u8; 16 * rays.len()]);
        let params = Params {
            method: id,
            count: rays.len() as u32,
            offset: 0,
            max_steps,
            start,
            pad: [0; 3],
        };
        let bind = [
            (3, &input),
            (4, &mesh.points),
            (5, &mesh.tets),
            (6, &mesh.neighbors),
            (7, &mesh.info),
            (8, &out),
        ];
        let bytes = self.dispatch(&self.walk, params, &bind, &out)?;
        let o: &[[u32; 4]] = bytemuck::cast_slice(&bytes);
        Ok(o[..rays.len()]
            .iter()
            .map(|&[kind, tet, x, steps]| {
                let outcome = match kind {
                    0 => Outcome::Hit { tet, face: x as u8 },
                    1 => Outcome::LeftMesh { tet, face: x as u8 },
                    2 => Outcome::NoExitFace { tet },
                    3 => Outcome::Cycle { tet, period: x },
                    _ => Outcome::StepLimit { tet },
                };
                Walk { outcome, steps }
            })
            .collect())
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
