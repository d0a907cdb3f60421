//! `tetwalk export-kernel certified`: every language written self-contained, and the GLSL and WGSL
//! versions run on a GPU adapter (lavapipe in CI: wgpu's GLSL front end compiles the GLSL text as a
//! user's Vulkan program would take it): on every exit-face stress row at scales 2^-40 to 2^40 each
//! settled answer is an exact exit face, the others -2 (for the host), and of well-shaped cases over
//! 90% settle.

mod common;

use tetwalk::family::{ExitFace, Family, Scale};
use tetwalk::gpu::export::{ENTRY_POINT, Lang, export};

#[test]
fn every_language_holds_the_function_its_constants_and_its_header() {
    for lang in [Lang::Wgsl, Lang::Glsl, Lang::Hlsl, Lang::Msl] {
        let text = export(lang).unwrap();
        assert!(text.contains("tetwalk_certified_exit_face"), "{lang:?}");
        assert!(
            text.contains("CERTIFIED_A") && text.contains("CERTIFIED_TINY"),
            "{lang:?}"
        );
        assert!(
            text.contains("SPDX-License-Identifier: MIT OR Apache-2.0"),
            "{lang:?}"
        );
        // Only what the function calls: no other method's code, no walk.
        assert!(
            !text.contains("plucker") && !text.contains("fn walk"),
            "{lang:?}"
        );
    }
    assert!(export(Lang::Glsl).unwrap().contains("#version 450"));
    assert!(export(Lang::Wgsl).unwrap().contains(ENTRY_POINT));
}

/// The cases of every stress row at each scale, normalized as methods take them, with the exact exit
/// faces in that numbering.
fn cases() -> Vec<([[f32; 4]; 7], Vec<usize>, bool)> {
    let rows = Default::default();
    let mut out = Vec::new();
    for row in ExitFace::rows(&rows) {
        for e in [-40, -8, 0, 8, 40] {
            for i in 0..300 {
                let Some((c, _)) = ExitFace::case(&rows, row, 11, i) else {
                    continue;
                };
                let Some(c) = ExitFace::scaled(&c, Scale::uniform(e)) else {
                    continue;
                };
                let Ok(x) = ExitFace::truth(&c) else { continue };
                if x.exit.to_vec().is_empty() {
                    continue;
                }
                let (tet, entry, map) = tetwalk::cases::normalized(&c);
                let v = |p: glam::Vec3| [p.x, p.y, p.z, 0.0];
                let entry = entry.map_or(-1, |e| e as i32);
                let record = [
                    v(tet[0]),
                    v(tet[1]),
                    v(tet[2]),
                    v(tet[3]),
                    v(c.org),
                    v(c.dir),
                    [f32::from_bits(entry as u32), 0.0, 0.0, 0.0],
                ];
                let right = (0..4).filter(|&f| x.exit.contains(map[f])).collect();
                out.push((record, right, ExitFace::row_name(&row) == "well"));
            }
        }
    }
    out
}

/// The exported module's entry point run over `records` on `device`, from `source`.
fn run(
    (device, queue): &(wgpu::Device, wgpu::Queue),
    source: wgpu::ShaderSource,
    records: &[[[f32; 4]; 7]],
) -> Vec<i32> {
    use wgpu::util::DeviceExt;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("exported"),
        source,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        // The module's one entry point (GLSL names it `main`, the WGSL `tetwalk_certified_main`).
        entry_point: None,
        compilation_options: Default::default(),
        cache: None,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!("the exported shader does not compile: {e}");
    }
    let cases = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(records),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = (records.len() * 4) as u64;
    let faces = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let back = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: cases.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: faces.as_entire_binding(),
            },
        ],
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(records.len().div_ceil(64) as u32, 1, 1);
    }
    enc.copy_buffer_to_buffer(&faces, 0, &back, 0, size);
    queue.submit([enc.finish()]);
    back.slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.unwrap());
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let mapped = back.slice(..).get_mapped_range().unwrap();
    let bytes: &[u8] = &mapped;
    bytemuck::cast_slice::<u8, i32>(bytes).to_vec()
}

#[test]
fn the_exported_glsl_and_wgsl_are_never_wrong_on_a_gpu() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    drop(gpu);
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default())).unwrap();
    println!("adapter: {:?}", adapter.get_info().name);
    let dq = pollster::block_on(adapter.request_device(&Default::default())).unwrap();
    let cases = cases();
    let records: Vec<_> = cases.iter().map(|(r, _, _)| *r).collect();
    let sources = [
        (
            "glsl",
            wgpu::ShaderSource::Glsl {
                shader: export(Lang::Glsl).unwrap().into(),
                stage: wgpu::naga::ShaderStage::Compute,
                defines: Default::default(),
            },
        ),
        (
            "wgsl",
            wgpu::ShaderSource::Wgsl(export(Lang::Wgsl).unwrap().into()),
        ),
    ];
    for (lang, source) in sources {
        let faces = run(&dq, source, &records);
        let (mut settled, mut well, mut well_settled) = (0, 0, 0);
        for ((rec, right, is_well), &f) in cases.iter().zip(&faces) {
            well += *is_well as usize;
            match f {
                -2 => {}
                f => {
                    well_settled += *is_well as usize;
                    assert!(
                        (0..4).contains(&f) && right.contains(&(f as usize)),
                        "{lang}: answered {f}, right {right:?}, case {rec:?}"
                    );
                    settled += 1;
                }
            }
        }
        println!(
            "{lang}: {settled} of {} settled, none wrong; well-shaped: {well_settled} of {well}",
            cases.len()
        );
        assert!(
            well_settled * 10 > well * 9,
            "{lang}: {well_settled} of {well}"
        );
    }
}
