//! `certified` where a user's shaders live (`tetwalk export-kernel`): the one WGSL module
//! ([`shader::certified_kernel`]: only what the function calls) parsed and validated by naga, and
//! written as it is (WGSL) or translated by naga to GLSL (Vulkan, 450), HLSL (shader model 5.1) or
//! MSL (2.1).

use super::shader;

/// A shader language `export-kernel` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lang {
    Wgsl,
    Glsl,
    Hlsl,
    Msl,
}

crate::choice!(Lang { Wgsl => "wgsl", Glsl => "glsl", Hlsl => "hlsl", Msl => "msl" });

/// Why a translation failed (a bug of tetwalk's: the module is fixed).
#[derive(Debug, thiserror::Error)]
#[error("export-kernel ({lang}): {why}")]
pub struct ExportError {
    lang: &'static str,
    why: String,
}

/// The compute entry point of the exported module (one case an invocation).
pub const ENTRY_POINT: &str = "tetwalk_certified_main";

/// `certified`'s exit face in `lang`, self-contained: its constants, tables and helpers, the f32
/// stage, `tetwalk_certified_exit_face`, and [`ENTRY_POINT`] over a buffer of cases (binding 0) and
/// one of faces (binding 1), under a header saying what it returns.
pub fn export(lang: Lang) -> Result<String, ExportError> {
    use crate::choice::Choice;
    let err = |why: String| ExportError {
        lang: lang.name(),
        why,
    };
    let source = shader::certified_kernel();
    let mut module =
        naga::front::wgsl::parse_str(&source).map_err(|e| err(e.emit_to_string(&source)))?;
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| err(e.emit_to_string(&source)))?;
    let stage = naga::ShaderStage::Compute;
    let body = match lang {
        // The assembled source itself, validated above: its comments and exact hexadecimal constants
        // kept.
        Lang::Wgsl => source,
        Lang::Glsl => {
            let options = naga::back::glsl::Options {
                version: naga::back::glsl::Version::Desktop(450),
                writer_flags: naga::back::glsl::WriterFlags::empty(),
                // Vulkan GLSL's `layout(binding = N)`, as the WGSL binds them (group 0).
                binding_map: (0..2)
                    .map(|b| {
                        (
                            naga::ResourceBinding {
                                group: 0,
                                binding: b,
                            },
                            b as u8,
                        )
                    })
                    .collect(),
                ..Default::default()
            };
            let pipeline = naga::back::glsl::PipelineOptions {
                shader_stage: stage,
                entry_point: ENTRY_POINT.into(),
                multiview: None,
            };
            let mut out = String::new();
            naga::back::glsl::Writer::new(
                &mut out,
                &module,
                &info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .and_then(|mut w| w.write())
            .map_err(|e| err(e.to_string()))?;
            out
        }
        Lang::Hlsl => {
            let options = naga::back::hlsl::Options {
                shader_model: naga::back::hlsl::ShaderModel::V5_1,
                fake_missing_bindings: true,
                ..Default::default()
            };
            let pipeline = naga::back::hlsl::PipelineOptions {
                entry_point: Some((stage, ENTRY_POINT.into())),
            };
            let mut out = String::new();
            naga::back::hlsl::Writer::new(&mut out, &options, &pipeline)
                .write(&module, &info, None)
                .map_err(|e| err(e.to_string()))?;
            out
        }
        Lang::Msl => {
            let options = naga::back::msl::Options {
                lang_version: (2, 1),
                fake_missing_bindings: true,
                ..Default::default()
            };
            let pipeline = naga::back::msl::PipelineOptions {
                entry_point: Some((stage, ENTRY_POINT.into())),
                ..Default::default()
            };
            naga::back::msl::write_string(&module, &info, &options, &pipeline)
                .map_err(|e| err(e.to_string()))?
                .0
        }
    };
    Ok(header(lang) + &body)
}

/// What the exported file is, in the language's comment syntax (all four take `//`).
fn header(lang: Lang) -> String {
    use crate::choice::Choice;
    format!(
        "// tetwalk certified exit face, {} (`tetwalk export-kernel certified --lang {}`: {}).\n\
         // SPDX-License-Identifier: MIT OR Apache-2.0.\n\
         // tetwalk_certified_exit_face(tet[4], org, dir, entry): the face 0..3 (face i opposite vertex i) through\n\
         // which the ray leaves the positively oriented tetrahedron entered through `entry` (-1 where none\n\
         // is known); -2 where f32 cannot settle it, the line only touches or misses the tetrahedron, or an\n\
         // input is gated: finish those on the host with kernels/c/certified.h. Sound under any rounding\n\
         // within one ulp, fused multiply-adds or not, subnormals flushed or not (src/methods/certified.md).\n\
         // {ENTRY_POINT}: one case per invocation, cases at binding 0 (four vertices, origin,\n\
         // direction as vec4 with w unused, then the entry face in an ivec4's x), faces at binding 1.\n\
         // {}\n\n",
        match lang {
            Lang::Wgsl => "WGSL",
            Lang::Glsl => "GLSL 450 (Vulkan)",
            Lang::Hlsl => "HLSL (shader model 5.1)",
            Lang::Msl => "Metal Shading Language 2.1",
        },
        lang.name(),
        match lang {
            Lang::Wgsl => "the WGSL tetwalk runs, validated by naga",
            _ => "translated by naga from the WGSL tetwalk runs",
        },
        match lang {
            Lang::Wgsl | Lang::Glsl => {
                "Not covered: a compiler that reassociates sums or assumes no NaN (WGSL and Vulkan GLSL do neither)."
            }
            Lang::Hlsl => {
                "Compile with IEEE strictness (dxc/fxc -Gis): the bound does not cover reassociated sums."
            }
            Lang::Msl => {
                "Compile without fast math (metal -fno-fast-math; Metal's default is fast math, which may reassociate sums and assume no NaN: not covered)."
            }
        }
    )
}
