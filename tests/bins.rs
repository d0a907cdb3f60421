//! The triangle count's candidates (`family::triangle::bins`): no triangle any registered method could report
//! hit is ever left out of a pixel's tile, in every arithmetic model, on scenes drawn from every
//! exponent regime (mixed scales in one scene, triangles in a plane through the eye, vertices on the
//! pixels' rays, slivers, triangles behind and around the camera, subnormal-sized ones, and one beyond
//! the lemma's range); and the binned nearest hits equal the brute-force ones on the default scene.

use glam::Vec3;
use rand::RngExt;
use tetwalk::choice::Model;
use tetwalk::engine::count::located_views;
use tetwalk::family::triangle::bins::{bins, tile_of};
use tetwalk::mesh::surface::{region_of, scene_triangles};
use tetwalk::methods::triangle::Among;
use tetwalk::methods::triangle::SideError::{EdgeScaled, OriginScaled};
use tetwalk::registry::{Named, TRIANGLE_METHODS};
use tetwalk::scenes::camera::{Camera, Views, packet_order};
use tetwalk::scenes::rng;
use tetwalk::tet::{Ray, Tri};

const W: u32 = 18;
const H: u32 = 14;

/// One scene at scale `2^e` around an eye at `2^f`: the adversarial triangles the module doc names.
fn scene(e: i32, f: i32, seed: u64) -> (Camera, Vec<Tri>) {
    let mut r = rng(seed);
    let s = 2f32.powi(e);
    let eye = Vec3::new(1.0, -0.75, 0.5) * 2f32.powi(f);
    // Looking along +x and slightly up: the plane y = eye.y runs through the middle rows.
    let cam = Camera::look_at(
        eye,
        eye + Vec3::new(4.0, 0.001, 0.3) * s,
        50.0,
        W as f32 / H as f32,
    );
    let mut tris = Vec::new();
    let jitter = |r: &mut tetwalk::scenes::Rng| {
        Vec3::new(
            r.random_range(-1.0..1.0),
            r.random_range(-1.0..1.0),
            r.random_range(-1.0..1.0),
        )
    };
    // Small triangles scattered in front.
    for _ in 0..40 {
        let c = eye + (Vec3::new(3.0, 0.0, 0.0) + jitter(&mut r) * 1.5) * s;
        tris.push([
            c,
            c + jitter(&mut r) * 0.3 * s,
            c + jitter(&mut r) * 0.3 * s,
        ]);
    }
    // In the plane y = eye.y, which holds the eye exactly: rays near it are near-coplanar.
    for k in 0..8 {
        let a = eye + Vec3::new(1.0 + k as f32, 0.0, -2.0 + 0.5 * k as f32) * s;
        tris.push([
            a,
            a + Vec3::new(0.5, 0.0, 0.25) * s,
            a + Vec3::new(0.25, 0.0, 0.75) * s,
        ]);
    }
    // Fans around points on pixel rays: every ray passes within rounding of a shared vertex.
    for (x, y) in [(3, 4), (9, 7), (12, 2), (17, 13)] {
        let ray = cam.ray(x, y, W, H);
        let v = ray.org + ray.dir * (2.0 * s);
        let ring: Vec<Vec3> = (0..5)
            .map(|k| {
                let a = k as f32 * 1.2566371;
                v + (cam.axes()[1] * a.cos() + cam.axes()[2] * a.sin()) * (0.05 * s)
            })
            .collect();
        for k in 0..5 {
            tris.push([v, ring[k], ring[(k + 1) % 5]]);
        }
    }
    // Micro triangles far off (edges about 2^-20 of their distance): the Plücker packet test's and
    // Woop's side products err with the distance squared, a pixel or more around them.
    for k in 0..48u32 {
        let ray = cam.ray(k * 7 % W, k * 5 % H, W, H);
        let v = ray.org + ray.dir * (3.0 * s);
        let ulp = |x: f32| f32::from_bits(x.abs().to_bits() + 1) - x.abs();
        let step = Vec3::new(ulp(v.x), ulp(v.y), ulp(v.z)) * 8.0;
        tris.push([
            v,
            v + step * Vec3::new(1.0, 0.0, 1.0),
            v + step * Vec3::new(0.0, 1.0, -1.0),
        ]);
    }
    // Slivers: a vertex one ulp off the opposite edge's midpoint.
    for _ in 0..6 {
        let a = eye + (Vec3::new(2.5, 0.0, 0.0) + jitter(&mut r)) * s;
        let b = a + jitter(&mut r) * s;
        let m = (a + b) * 0.5;
        let c = Vec3::new(f32::from_bits(m.x.to_bits() + 1), m.y, m.z);
        tris.push([a, b, c]);
    }
    // Behind the camera, straddling its plane, and one around it.
    tris.push([
        eye - Vec3::new(2.0, 0.0, 0.0) * s,
        eye + Vec3::new(-2.0, 1.0, 0.0) * s,
        eye + Vec3::new(-2.0, 0.0, 1.0) * s,
    ]);
    tris.push([
        eye + Vec3::new(-1.0, -1.0, -1.0) * s,
        eye + Vec3::new(1.0, 0.5, -1.0) * s,
        eye + Vec3::new(0.2, 0.3, 2.0) * s,
    ]);
    (cam, tris)
}

/// Every hit of every method, in every model, at every pixel, is among the pixel's tile's candidates;
/// and the candidates leave most triangles out where the lemma applies (the check is not vacuous).
#[test]
fn no_triangle_a_method_could_hit_is_left_out() {
    let mut kept = 0usize;
    let mut possible = 0usize;
    let mut hits_seen = 0usize;
    // Eye and triangles at one scale, at mixed scales, tiny (subnormal products), and huge.
    let regimes = [
        (0, 0),
        (-20, -20),
        (20, 20),
        (-12, 8),
        (6, -30),
        (-45, -45),
        (-60, 0),
        (30, 30),
        (45, 45),
    ];
    for (k, &(e, f)) in regimes.iter().enumerate() {
        let (cam, tris) = scene(e, f, k as u64);
        for (tile, scale) in [(2, EdgeScaled), (4, EdgeScaled), (2, OriginScaled)] {
            let both = bins(&cam, W, H, tile, &tris);
            let b = both.get(scale);
            kept += b.ids.len();
            possible += (b.tiles_x * b.tiles_y) as usize * tris.len();
            if e >= 45 {
                assert_eq!(
                    b.ids.len(),
                    (b.tiles_x * b.tiles_y) as usize * tris.len(),
                    "beyond the lemma's range every triangle is in every tile"
                );
            }
            for y in 0..H {
                for x in 0..W {
                    let ray = cam.ray(x, y, W, H);
                    let cands = b.of_tile(tile_of(x, y, W, tile));
                    for m in TRIANGLE_METHODS
                        .iter()
                        .filter(|m| m.side_error == Some(scale))
                    {
                        for model in Model::ALL {
                            for (i, _) in m.hits(model)(&tris, &ray) {
                                hits_seen += 1;
                                assert!(
                                    cands.binary_search(&i).is_ok(),
                                    "{} ({model:?}) hits triangle {i} {:?} at pixel ({x}, {y}) of regime 2^{e}/2^{f}, tile {tile}, but it is not a candidate",
                                    m.name(),
                                    tris[i as usize]
                                );
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(hits_seen > 10_000, "the scenes are hit ({hits_seen})");
    assert!(
        (kept as f64) < 0.5 * possible as f64,
        "the bins leave triangles out ({kept} of {possible} kept)"
    );
}

/// On the default scene, every method's nearest hit over the binned candidates is the brute-force one,
/// bit for bit, in every CPU arithmetic model, at packets of 1, 2 and 4.
#[test]
fn binned_nearest_hits_equal_brute_force_on_the_default_scene() {
    let mesh = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required)
        .unwrap()
        .mesh;
    let views = Views::new(3, 40, 36, 7);
    let mut fewer = 0.0;
    for (_, cam, located) in located_views(&mesh, &views, |_| true, &|| {}) {
        let (tris, _) = scene_triangles(&mesh, &region_of(&mesh, located));
        let rays = views.rays(&cam);
        for packet in [1u32, 2, 4] {
            let tile = packet.max(2);
            let order = packet_order(views.width, views.height, packet, tile);
            let packed: Vec<Ray> = order.iter().map(|&i| rays[i]).collect();
            let binned =
                bins(&cam, views.width, views.height, tile, &tris).among(views.width, views.height);
            let binned = binned.into_pairs();
            for (_, among) in &binned {
                fewer += among.tests() as f64 / (rays.len() * tris.len()) as f64 / 2.0;
            }
            let every = Among::all(tris.len(), packed.len(), packed.len());
            let p = (packet * packet) as usize;
            for m in TRIANGLE_METHODS {
                let among = &binned
                    .iter()
                    .find(|b| Some(b.0) == m.side_error)
                    .expect("every registered method has an error scale")
                    .1;
                for model in Model::ALL {
                    // The scalar test, and in the plain model the 4-wide one (`fastest`).
                    for trace in [m.trace(model), m.fastest(model)] {
                        let brute = trace(&tris, &every.ids, &every.groups, &packed, p);
                        let binned = trace(&tris, &among.ids, &among.groups, &packed, p);
                        let bits = |v: &[Option<(u32, f32)>]| -> Vec<_> {
                            v.iter().map(|h| h.map(|(i, t)| (i, t.to_bits()))).collect()
                        };
                        assert_eq!(
                            bits(&binned),
                            bits(&brute),
                            "{} {model:?} packet {packet}",
                            m.name()
                        );
                    }
                }
            }
        }
    }
    assert!(
        fewer < 3.0 * 3.0 * 0.05,
        "candidates are under 5% of the triangles per ray"
    );
}

/// A method that reports every triangle hit at `t = 1`: its nearest hit by brute force is triangle 0,
/// among a tile's candidates the tile's first; it breaks the lemma, so claiming it obeys it must stop
/// the count at the audit (the audited rays answered both ways), and as an outside method (no claim)
/// it is counted by brute force.
#[test]
fn the_audit_stops_a_count_whose_bins_do_not_hold() {
    use tetwalk::backend::Backend;
    use tetwalk::engine::count::{AnswerSource, CountSettings, ReferenceWalk, Shard, run};
    use tetwalk::family::Triangle;
    use tetwalk::family::count::CountError;
    use tetwalk::family::triangle::TriCountSettings;
    use tetwalk::methods::triangle::SingleRay;
    use tetwalk::registry::TriangleMethod;

    struct Everywhere;
    impl SingleRay for Everywhere {
        fn test<A: tetwalk::methods::Arith>(_: &Tri, _: &Ray) -> Option<f32> {
            Some(1.0)
        }
    }
    let scene = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required).unwrap();
    let settings = CountSettings::<Triangle> {
        views: Views::new(2, 32, 32, 1),
        reference: ReferenceWalk::default(),
        family: TriCountSettings {
            packet: 2,
            brute_force: false,
        },
        audit: 200,
        shard: Shard::ALL,
        answerer: None,
    };
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let outside = TriangleMethod::outside::<Everywhere>("everywhere");
    let counted = run(
        &scene,
        &settings,
        &[AnswerSource::Method(&outside)],
        &cpu,
        &|| {},
        None,
    );
    assert!(
        counted.is_ok(),
        "no claim, brute force: {:?}",
        counted.err()
    );
    let mut claiming = TriangleMethod::outside::<Everywhere>("everywhere");
    claiming.side_error = Some(EdgeScaled);
    match run(
        &scene,
        &settings,
        &[AnswerSource::Method(&claiming)],
        &cpu,
        &|| {},
        None,
    ) {
        Err(CountError::Bins { method, brute, .. }) => {
            assert_eq!(method, "everywhere");
            assert_eq!(brute, Some((0, 1.0)));
        }
        other => panic!("the audit must stop it: {:?}", other.map(|r| r.rays)),
    }
}
