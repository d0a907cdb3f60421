//! `certified` where f32 products underflow (issue 24): the smallest counterexample to its old bound,
//! right on every backend now; and certified right on cases scaled by exact powers of two across f32's
//! range, in every CPU model.

mod common;

use common::{any_case, config, gpu_or_skip, model};
use glam::Vec3;
use proptest::prelude::*;
use tetwalk::backend::Backend;
use tetwalk::cases::classify;
use tetwalk::engine::found::Found;
use tetwalk::exact::side;
use tetwalk::family::ExitFace;
use tetwalk::methods::certified::{Bound, GRADUAL, f32_stage};
use tetwalk::methods::maria17::FACE_VERTICES;
use tetwalk::registry::by_name;
use tetwalk::tet::{Case, Ray};

/// The register's counterexample (README, "What the papers claim and what we found"): every coordinate
/// a power of two (or 1.5 times one); the line enters through face 0 and leaves through face 3 only.
/// `(V_f − o) × d` underflows to 2^-149 in one component and to 0 in another, and `|e| = 2^42`
/// multiplies that loss past the old bound.
const UNDERFLOW_CASE: &str = r#"{"tet":[[8.673617379884035e-19,0.0,0.0],[-1099511627776.0,0.0,-1099511627776.0],[8.673617379884035e-19,1099511627776.0,4398046511104.0],[0.0,-1099511627776.0,-4398046511104.0]],"org":[0.0,0.0,0.0],"dir":[0.0,4.0389678347315804e-28,1.2116903504194741e-27],"entry":0}"#;

fn underflow_case() -> Case {
    Found::<ExitFace>::parse(UNDERFLOW_CASE).unwrap().case
}

#[test]
fn the_old_bound_decides_the_counterexample_wrongly() {
    let c = underflow_case();
    let ray = c.ray();
    let (apex, first) = (c.tet[0], c.tet[FACE_VERTICES[0][2]]);
    // Before issue 24: O3DERRBOUND_A-like relative part, 2^-120 absolute, nothing carried from w.
    let old = Bound {
        mu: 0.0,
        c: 2f32.powi(-120),
        ..GRADUAL
    };
    let exact = side(first, apex, &ray);
    assert_eq!(exact, 1);
    assert_eq!(
        f32_stage(first, apex, &ray, old, false),
        Some(-1),
        "the old bound settles it wrongly"
    );
    assert_eq!(
        f32_stage(first, apex, &ray, GRADUAL, false),
        None,
        "the new one hands it on"
    );
}

#[test]
fn certified_is_right_on_the_counterexample_on_every_backend() {
    let c = underflow_case();
    let truth = classify(&c).unwrap();
    assert_eq!(truth.exit.to_vec(), vec![3]);
    let certified = by_name("certified").unwrap();
    let mut backends: Vec<Backend> = tetwalk::methods::Model::ALL
        .into_iter()
        .map(|m| Backend::open(m.backend()).unwrap())
        .collect();
    backends.extend(gpu_or_skip());
    for b in &backends {
        assert_eq!(
            b.exit_face(certified, &c).unwrap(),
            Some(3),
            "{}",
            b.describe()
        );
    }
}

/// `v · 2^k` for every point, exactly unless it leaves f32's normal range.
fn scaled(t: [Vec3; 4], ray: Ray, k: i32) -> Option<([Vec3; 4], Ray)> {
    let s = 2f32.powi(k);
    let t = t.map(|v| v * s);
    let ray = Ray {
        org: ray.org * s,
        dir: ray.dir * s,
    };
    (tetwalk::tet::orientation(&t) != 0
        && ray.dir != Vec3::ZERO
        && ray.dir.is_finite()
        && t.iter().all(|v| v.is_finite()))
    .then_some((t, ray))
}

proptest! {
    #![proptest_config(config("certified_scaled", 3000))]
    /// `certified` is right on every case of every family scaled by 2^k, k from -140 to 100 (into the
    /// subnormal range and near overflow), from every exact entry face and from none, in every CPU model.
    #[test]
    fn certified_is_correct_on_scaled_cases(case in any_case(), k in -140i32..=100, model in model()) {
        let Some((t, ray)) = scaled(case.0, case.1, k) else { return Ok(()) };
        let probe = Case { tet: t, org: ray.org, dir: ray.dir, entry: None };
        let c = classify(&probe).unwrap();
        let m = by_name("certified").unwrap();
        let entries: Vec<Option<u8>> =
            std::iter::once(None).chain(c.entry.iter().map(|f| Some(f as u8))).collect();
        for entry in entries {
            let case = Case { entry, ..probe };
            let j = common::judge(&case, &c, m, model);
            prop_assert_ne!(j.correct, Some(false), "2^{} {:?} entry {:?}: answered {:?}, exact exits {:?}", k, model, entry, j.face, j.exact_exit);
        }
    }
}
