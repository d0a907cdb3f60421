//! A toy arithmetic model, written in this test file as a user would write one: every `a·b + c`
//! computed in f64 and rounded once to f32 (a device that keeps a wider accumulator). Being an
//! [`Arith`] is all a model needs for every exit-face method to compute in it (the methods are
//! generic over it); registering it for `--backend`, `stress` and `count` is one line of
//! `arithmetic_models!` beside it (docs/architecture.md, "An arithmetic model"). Each method's
//! answers in the toy model are judged by the oracle and set beside the fused model's, which rounds
//! the same `a·b + c` once from the exact value.

use tetwalk::exact::classify;
use tetwalk::methods::{
    Aman20, Aman20Scaled, Arith, Certified, ExitMethod, Fused, HalfSpace, Maria17, MomentFirst,
    Ms06, OriginFirst, Plain, Plucker, RayPlane, Stp,
};
use tetwalk::scenes::rng;
use tetwalk::scenes::tets::{TetShape, stabbing_ray, tet};
use tetwalk::tet::{Ray, Tet};

/// `a·b + c` in f64, rounded once to f32 (the product of two f32 values is exact in f64; the sum
/// rounds there, then to f32: a double rounding where the fused model rounds once).
struct Wide;

impl Arith for Wide {
    type Eight = <Plain as Arith>::Eight;
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        (a as f64 * b as f64 + c as f64) as f32
    }
}

/// A method's answer to a case in one model.
type Answer = fn(&Tet, &Ray) -> Option<usize>;

/// The face `M` gives in the starting tetrahedron (no entry face), computed in model `A`.
fn answer<M: ExitMethod, A: Arith>(t: &Tet, r: &Ray) -> Option<usize> {
    M::exit_face::<A>(t, &M::prepare::<A>(r), None)
}

macro_rules! methods {
    ($($name:literal: $m:ty),*) => {
        [$(($name, answer::<$m, Wide> as Answer, answer::<$m, Fused> as Answer)),*]
    };
}

/// On 20,000 well-shaped cases (rays through two random face points), every method computed in the
/// toy model answers a face the oracle allows on at least 99.9% of them, and as the fused model
/// answers on at least 99.9%; the toy model is a model of its own (its `a·b + c` differs from the
/// fused one's on some inputs).
#[test]
fn a_toy_model_is_an_arith_away_from_every_method() {
    let mut r = rng(7);
    let cases: Vec<(Tet, Ray)> = (0..20_000)
        .map(|_| {
            let t = tet(TetShape::Well, 1.0, &mut r);
            let ray = stabbing_ray(&t, &mut r);
            (t, ray)
        })
        .collect();
    let exits: Vec<_> = cases
        .iter()
        .map(|(t, ray)| classify(t, ray).unwrap().exit)
        .collect();
    let all = methods!(
        "ray-plane": RayPlane,
        "halfspace": HalfSpace,
        "plucker": Plucker,
        "stp": Stp,
        "ms06": Ms06,
        "aman20": Aman20,
        "aman20-scaled": Aman20Scaled,
        "maria17": Maria17<MomentFirst>,
        "maria17-translated": Maria17<OriginFirst>,
        "certified": Certified
    );
    for (name, wide, fused) in all {
        let (mut right, mut alike) = (0, 0);
        for ((t, ray), exit) in cases.iter().zip(&exits) {
            let w = wide(t, ray);
            right += w.is_some_and(|f| exit.contains(f)) as usize;
            alike += (w == fused(t, ray)) as usize;
        }
        assert!(right * 1000 >= cases.len() * 999, "{name}: {right} right");
        assert!(alike * 1000 >= cases.len() * 999, "{name}: {alike} alike");
    }
    // a·b = 2^-24 − 2^-60 and c = 1 + 2^-23: the exact sum lies just below the midpoint of two f32
    // values; the fused model rounds it down, the wide one rounds it to the midpoint in f64 first,
    // then to the even neighbour, up.
    let (a, b) = (
        2f32.powi(-12) * (1.0 + 2f32.powi(-18)),
        2f32.powi(-12) * (1.0 - 2f32.powi(-18)),
    );
    let c = 1.0 + f32::EPSILON;
    assert_eq!(Fused::mad(a, b, c), 1.0 + f32::EPSILON);
    assert_eq!(Wide::mad(a, b, c), 1.0 + 2.0 * f32::EPSILON);
}
