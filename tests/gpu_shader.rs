//! The WGSL module is generated from the Rust definitions (registry, outcome kinds, face tables, shared
//! buffer structs); the committed `src/gpu/tetwalk.wgsl` must be what the generator writes now
//! (`cargo run --example codegen` rewrites it), and every registered method must have a GPU version or say
//! why not.

use tetwalk::gpu::shader::{self, COMMITTED, generate};
use tetwalk::registry::{GpuVersion, METHODS, Named, TRIANGLE_METHODS};
use tetwalk::walk::OutcomeKind;

#[test]
fn committed_wgsl_is_what_the_generator_writes() {
    assert!(
        COMMITTED == generate(),
        "src/gpu/tetwalk.wgsl is stale: run `cargo run --example codegen`"
    );
}

#[test]
fn every_method_has_a_gpu_version_or_says_why_not() {
    for m in METHODS {
        match m.info.gpu {
            GpuVersion::Wgsl(sources) => {
                let id = m.ident();
                let all = sources.concat();
                for f in [format!("fn {id}_prepare("), format!("fn {id}_exit(")] {
                    assert!(all.contains(&f), "{}: its WGSL lacks `{f}`", m.name());
                }
                for e in shader::entry_points(m) {
                    assert!(
                        COMMITTED.contains(&format!("fn {e}(")),
                        "{}: no entry point {e}",
                        m.name()
                    );
                }
            }
            GpuVersion::CpuOnly(why) => assert!(
                why.len() > 10,
                "{} has no GPU version and must say why",
                m.name()
            ),
        }
    }
}

#[test]
fn every_triangle_method_has_its_wgsl_and_entry_points() {
    for m in TRIANGLE_METHODS {
        let GpuVersion::Wgsl(sources) = m.info.gpu else {
            panic!("{} has no WGSL", m.name());
        };
        let f = format!("fn {}_hit(", m.ident());
        assert!(
            sources.concat().contains(&f),
            "{}: its WGSL lacks `{f}`",
            m.name()
        );
        for e in shader::triangle_entry_points(m) {
            assert!(
                COMMITTED.contains(&format!("fn {e}(")),
                "{}: no {e}",
                m.name()
            );
        }
    }
}

#[test]
fn outcome_codes_and_tables_come_from_the_rust_definitions() {
    for k in OutcomeKind::ALL {
        let line = format!("const {}: u32 = {}u;", k.wgsl_name(), k.code());
        assert!(COMMITTED.contains(&line), "missing {line}");
        assert_eq!(OutcomeKind::from_code(k.code()), Some(k));
    }
    assert_eq!(OutcomeKind::from_code(OutcomeKind::ALL.len() as u32), None);
    assert!(COMMITTED.contains(shader::Params::WGSL));
    assert!(COMMITTED.contains(shader::Case::WGSL));
    assert!(COMMITTED.contains(shader::Ending::WGSL));
    // maria17's Table 1, row 1 (entry face F1): faces 0, 3, 2.
    assert!(COMMITTED.contains("case 1u: { return vec3u(0u, 3u, 2u); }"));
    // No hand-kept method switch: entry points are per method.
    assert!(!COMMITTED.contains("switch method"));
}
