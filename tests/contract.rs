//! Every case made under a contract holds it, decided exactly and apart from the code that made it:
//! every exit-face row under every contract (origin placements alone and together, each orientation,
//! unit directions or not, entry faces given, left out or either), each case checked with the
//! oracle's exit and entry faces and robust's `orient3d` on the f32 points as they are; unit
//! directions checked in rationals to be the f32 rounding of a unit vector.

mod common;

use glam::Vec3;
use rug::Rational;
use tetwalk::backend::CPU;
use tetwalk::cases::classify;
use tetwalk::engine::stress::{StressSettings, row_cases};
use tetwalk::family::contract::{Contract, EntryGiven, Orientation, Origin, Origins};
use tetwalk::family::{ExitFace, Family};
use tetwalk::tet::{Case, FACE_VERTICES};

/// `orient3d(a, b, c, d)`'s sign, exactly (robust's adaptive predicate on the f32 values).
fn orient(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    let p = |v: Vec3| robust::Coord3D {
        x: v.x as f64,
        y: v.y as f64,
        z: v.z as f64,
    };
    let o = robust::orient3d(p(a), p(b), p(c), p(d));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// The side of face `f`'s plane `p` is on: as the opposite vertex (+1), the other (-1), on it (0).
fn side(c: &Case, f: usize, p: Vec3) -> i8 {
    let [a, b, d] = FACE_VERTICES[f].map(|i| c.tet[i]);
    orient(a, b, d, p) * orient(a, b, d, c.tet[f])
}

/// The sign of `n_f · dir`, `n_f` face `f`'s outward normal, in rationals.
fn facing(c: &Case, f: usize) -> i8 {
    let q = |v: Vec3| v.to_array().map(|x| Rational::from_f32(x).unwrap());
    let [a, b, d] = FACE_VERTICES[f].map(|i| q(c.tet[i]));
    let (u, v, w) = (
        [0, 1, 2].map(|i| Rational::from(&b[i] - &a[i])),
        [0, 1, 2].map(|i| Rational::from(&d[i] - &a[i])),
        [0, 1, 2].map(|i| Rational::from(&q(c.tet[f])[i] - &a[i])),
    );
    let n = [0, 1, 2].map(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        Rational::from(&u[j] * &v[k]) - Rational::from(&u[k] * &v[j])
    });
    let dot = |x: &[Rational; 3], y: &[Rational; 3]| {
        (0..3).fold(Rational::new(), |s, i| s + Rational::from(&x[i] * &y[i]))
    };
    // Outward: away from the opposite vertex.
    let inward = dot(&n, &w).cmp0() as i8;
    -inward * dot(&n, &q(c.dir)).cmp0() as i8
}

/// The f32 points next to `p` (each coordinate a step down, kept, a step up), `p` itself left out.
fn around(p: Vec3) -> Vec<Vec3> {
    let steps = |x: f32| [x.next_down(), x, x.next_up()];
    let mut out = Vec::new();
    for x in steps(p.x) {
        for y in steps(p.y) {
            for z in steps(p.z) {
                let q = Vec3::new(x, y, z);
                if q != p {
                    out.push(q);
                }
            }
        }
    }
    out
}

/// Whether `d` is the f32 rounding of a unit vector: the box of reals rounding to it meets the unit
/// sphere, in rationals.
fn rounds_a_unit_vector(d: Vec3) -> bool {
    let (mut near, mut far) = (Rational::new(), Rational::new());
    for x in d.to_array() {
        let q = |v: f32| Rational::from_f32(v).unwrap();
        let lo = (q(x) + q(x.next_down())) / 2u32;
        let hi = (q(x) + q(x.next_up())) / 2u32;
        let (a, b) = (lo.clone().abs(), hi.clone().abs());
        let n = if lo.cmp0().is_le() && hi.cmp0().is_ge() {
            Rational::new()
        } else {
            a.clone().min(b.clone())
        };
        near += n.clone() * n;
        let f = a.max(b);
        far += f.clone() * f;
    }
    near <= 1 && far >= 1
}

/// Why case `c` breaks `k`, checked apart from tetwalk's contract code; where it holds, the
/// placements of `k` its origin holds, and whether it lies on an entry face itself.
fn broken(k: &Contract, c: &Case) -> Result<(Vec<Origin>, bool), String> {
    let x = classify(c).map_err(|e| e.to_string())?;
    if !x.meets() {
        return Err("the line misses the tetrahedron".into());
    }
    let o = c.org;
    let closed = (0..4).all(|f| side(c, f, o) >= 0);
    let inside = (0..4).all(|f| side(c, f, o) > 0);
    let on_entry = |p: Vec3| {
        (0..4).all(|f| side(c, f, p) >= 0) && (0..4).any(|f| side(c, f, p) == 0 && facing(c, f) < 0)
    };
    let placed = |p: Origin| match p {
        Origin::Anywhere => (0..4).all(|f| facing(c, f) <= 0 || side(c, f, o) >= 0),
        Origin::Inside => inside,
        Origin::Before => x.entry.iter().all(|f| side(c, f, o) < 0),
        Origin::Entry => {
            closed
                && (on_entry(o)
                    || (inside
                        && !around(o).into_iter().any(on_entry)
                        && around(o)
                            .into_iter()
                            .any(|p| (0..4).any(|f| facing(c, f) < 0 && side(c, f, p) < 0))))
        }
    };
    let held: Vec<Origin> = k
        .origin
        .placements()
        .into_iter()
        .filter(|&p| placed(p))
        .collect();
    if held.is_empty() {
        return Err(format!("origin not {}", k.origin.name()));
    }
    let orientation = orient(c.tet[0], c.tet[1], c.tet[2], c.tet[3]);
    match k.orientation {
        Orientation::Positive if orientation <= 0 => return Err("not positive".into()),
        Orientation::Negative if orientation >= 0 => return Err("not negative".into()),
        _ => {}
    }
    if k.unit_direction && !rounds_a_unit_vector(c.dir) {
        return Err("the direction rounds no unit vector".into());
    }
    match (k.entry, c.entry) {
        (EntryGiven::Given, None) => return Err("no entry face".into()),
        (EntryGiven::None, Some(_)) => return Err("an entry face".into()),
        (_, Some(e)) if !x.entry.contains(e as usize) => {
            return Err(format!("entry {e} is not one of {:?}", x.entry.to_vec()));
        }
        _ => {}
    }
    Ok((held, on_entry(o)))
}

/// Every contract the flags can state, but the tolerance: 5 origin sets × 3 orientations × unit or
/// not, the entry face given, left out or either in turn.
fn contracts() -> Vec<Contract> {
    let origins = [
        Origins::ANYWHERE,
        Origin::Before.into(),
        Origin::Entry.into(),
        Origin::Inside.into(),
        Origins::of(&[Origin::Inside, Origin::Entry]),
    ];
    let mut out = Vec::new();
    for origin in origins {
        for orientation in [
            Orientation::Positive,
            Orientation::Negative,
            Orientation::Any,
        ] {
            for unit_direction in [false, true] {
                let entry = [EntryGiven::Any, EntryGiven::Given, EntryGiven::None][out.len() % 3];
                out.push(Contract {
                    origin,
                    unit_direction,
                    entry,
                    orientation,
                    tolerance: 0.0,
                });
            }
        }
    }
    out
}

/// Every case of every exit-face row under every contract holds it, and every row has all its
/// cases; both placements of `inside,entry` are made, each origin on an entry face wherever f32 has
/// a point there.
#[test]
fn every_case_of_every_row_holds_every_contract_exactly() {
    let rows = ExitFace::rows(&Default::default());
    // Of `inside,entry`'s cases: on (or as near as f32 allows) an entry face, and not; and of every
    // entry placement, on the face itself.
    let (mut both, mut on_face, mut entries) = ([0u64; 2], 0, 0);
    for k in contracts() {
        for &row in &rows {
            let s = StressSettings::<ExitFace> {
                contract: k,
                cases: 60,
                rows: Default::default(),
                seed: 11,
                backend: CPU.ran(),
                scale: Default::default(),
            };
            let (cases, _) = row_cases(&s, row);
            let name = ExitFace::row_name(&row);
            assert_eq!(cases.len(), 60, "{name} under {}", k.describe());
            for (c, _) in &cases {
                let (held, on) = broken(&k, c)
                    .unwrap_or_else(|why| panic!("{name} under {}: {why}: {c:?}", k.describe()));
                let entry = held.contains(&Origin::Entry);
                if k.origin.placements().len() == 2 {
                    both[entry as usize] += 1;
                }
                entries += entry as u64;
                on_face += (entry && on) as u64;
            }
        }
    }
    assert!(both[0] > 200 && both[1] > 200, "{both:?}");
    // A plane in general position holds almost no f32 point: nearly every entry origin is the
    // nearest inside.
    assert!(
        entries > 1000 && on_face < entries,
        "{on_face} of {entries}"
    );
    eprintln!("entry origins on the entry face itself: {on_face} of {entries}");
}

/// Where f32 has points on the entry face, the entry origin is one of them (exactly on it, the line
/// entering there); where the face holds none near the entry point, it is the nearest point inside.
#[test]
fn an_entry_origin_lies_on_the_entry_face_where_f32_can_place_it_there() {
    let entry = Contract {
        origin: Origin::Entry.into(),
        entry: EntryGiven::Given,
        ..Contract::default()
    };
    let made = |tet: [Vec3; 4], org: Vec3, dir: Vec3| {
        let c = Case {
            tet,
            org,
            dir,
            entry: None,
        };
        let c = ExitFace::contracted(&entry, &c, 0).expect("a case within the contract");
        assert_eq!(
            broken(&entry, &c).map(|(h, _)| h),
            Ok(vec![Origin::Entry]),
            "{c:?}"
        );
        c
    };
    // Face 3 (opposite vertex 3) in the plane z = 0: the entry point (0.25, 0.25, 0) is an f32 point.
    let flat = [Vec3::X, Vec3::ZERO, Vec3::Y, Vec3::Z];
    let c = made(flat, Vec3::new(0.25, 0.25, -1.0), Vec3::Z);
    assert_eq!((c.org, c.entry), (Vec3::new(0.25, 0.25, 0.0), Some(3)));
    // The slanted face x + y + z = 1 and the entry point (1/3, 1/3, 1/3), which no f32 point
    // equals: one next to it lies on the face exactly (1/3 rounded up twice and down once sums to 1).
    let c = made(flat, Vec3::splat(1.0), -Vec3::ONE);
    assert_eq!(c.entry, Some(1));
    assert!(broken(&entry, &c).unwrap().1, "on the face: {c:?}");
    assert!(
        (c.org - Vec3::splat(1.0 / 3.0)).abs().max_element() <= 1e-7,
        "{c:?}"
    );
    // Faces in general position: on the face where a point next to the entry point is, else the
    // nearest inside (held by `broken`); about as often as f32 allows, on the face itself.
    let mut on = 0;
    for k in 0..200 {
        let j = k as f32 * 0.013;
        let tet = [
            Vec3::new(1.1 + j, 0.2, 0.05),
            Vec3::new(0.0, j, 0.0),
            Vec3::new(0.1, 1.3, 0.2 + j),
            Vec3::new(0.05 + j, 0.1, 1.7),
        ];
        let c = made(tet, Vec3::new(2.0, 2.1, 1.9), Vec3::new(-1.0, -1.1, -0.9));
        on += broken(&entry, &c).unwrap().1 as u32;
    }
    assert!(on < 100, "{on} of 200 on the face itself");
}

/// An exit-face case as a JSON line holds it (`tet`, `org`, `dir`, `entry`).
fn case_of(v: &serde_json::Value) -> Case {
    let p = |v: &serde_json::Value| {
        Vec3::from_array(serde_json::from_value::<[f32; 3]>(v.clone()).unwrap())
    };
    Case {
        tet: [0, 1, 2, 3].map(|i| p(&v["tet"][i])),
        org: p(&v["org"]),
        dir: p(&v["dir"]),
        entry: v["entry"].as_u64().map(|e| e as u8),
    }
}

/// An answerer in JSON Lines that writes every case it is sent to the file `$1` (one JSON line each)
/// and answers each with the face a ray-plane test in f64 gives (Python, standard library only).
const RECORDING: &str = r#"python3 -c '
import json, sys
out = open(sys.argv[1], "a")
def sub(a, b): return [a[i] - b[i] for i in range(3)]
def dot(a, b): return sum(a[i] * b[i] for i in range(3))
def cross(a, b): return [a[1]*b[2] - a[2]*b[1], a[2]*b[0] - a[0]*b[2], a[0]*b[1] - a[1]*b[0]]
for line in sys.stdin:
    if not line.strip():
        sys.stdout.flush()
        continue
    c = json.loads(line)
    out.write(line)
    t, o, d = c["tet"], c["org"], c["dir"]
    best, face = None, -1
    for f in range(4):
        a, b, e = [t[i] for i in range(4) if i != f]
        n = cross(sub(b, a), sub(e, a))
        if dot(n, sub(t[f], a)) > 0:
            n = [-x for x in n]
        nd = dot(n, d)
        if nd > 0:
            s = dot(n, sub(a, o)) / nd
            if best is None or s < best:
                best, face = s, f
    print(json.dumps({"line": c["line"], "face": face if face >= 0 else None}))
    out.flush()
' "#;

/// `count --answerer` under a contract sends every step of every walk as a case that holds it,
/// decided exactly (after a crossing: on the entry face where the contract allows it), walks on
/// from each step's case, and judges each step when asked; a count's report records the contract.
#[test]
fn a_count_asks_every_step_of_every_walk_within_its_contract() {
    let dir = tempfile::tempdir().unwrap();
    for (flags, k) in [
        (
            &[
                "--origin",
                "inside,entry",
                "--unit-direction",
                "--entry",
                "given",
            ][..],
            Contract {
                origin: Origins::of(&[Origin::Inside, Origin::Entry]),
                unit_direction: true,
                entry: EntryGiven::Given,
                ..Contract::default()
            },
        ),
        (
            &[
                "--origin",
                "entry",
                "--orientation",
                "negative",
                "--entry",
                "none",
            ][..],
            Contract {
                origin: Origin::Entry.into(),
                orientation: Orientation::Negative,
                entry: EntryGiven::None,
                ..Contract::default()
            },
        ),
        (
            &["--origin", "before", "--unit-direction"][..],
            Contract {
                origin: Origin::Before.into(),
                unit_direction: true,
                ..Contract::default()
            },
        ),
    ] {
        let sent = dir.path().join(format!("{}.jsonl", k.describe().len()));
        let json = dir.path().join("count.json");
        let answerer = format!("{RECORDING}{}", sent.display());
        let mut args = vec![
            "count",
            "--views",
            "2",
            "--size",
            "24x24",
            "--answerer",
            &answerer,
            "--json",
            json.to_str().unwrap(),
        ];
        args.extend(flags);
        let (code, out, err) = common::run_tetwalk(&args, b"");
        assert_eq!(code, 0, "{flags:?}: {err}");
        assert!(out.contains("each step asked under the contract"), "{out}");
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert_eq!(report["settings"]["answerer"]["contract"], k.describe());
        let row = &report["methods"][1];
        let rays = report["rays"].as_u64().unwrap();
        assert!(row["left_out"].as_u64().unwrap() < rays / 10, "{row}");
        let (mut steps, mut on_entry) = (0u64, 0u64);
        for line in std::fs::read_to_string(&sent).unwrap().lines() {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            let c = case_of(&v);
            let (held, _) =
                broken(&k, &c).unwrap_or_else(|why| panic!("{} sent {c:?}: {why}", k.describe()));
            steps += 1;
            on_entry += held.contains(&Origin::Entry) as u64;
        }
        // Walks of many steps, every step asked: the bunny scene's rays cross tens of tetrahedra.
        assert!(steps > 10 * rays, "{steps} steps for {rays} rays");
        if k.origin.allows(Origin::Entry) {
            assert!(on_entry > steps / 2, "{on_entry} of {steps}");
        }
    }
}

/// A contract is the answerer's: refused without one; and one that leaves every ray's walk a step
/// without a case judged nothing, an error.
#[test]
fn a_count_contract_without_an_answerer_or_leaving_no_ray_is_an_error() {
    let (code, _, err) = common::run_tetwalk(&["count", "--views", "1", "--origin", "entry"], b"");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("give --answerer"), "{err}");
    let answerer = format!("{RECORDING}/dev/null");
    let (code, _, err) = common::run_tetwalk(
        &[
            "count",
            "--views",
            "1",
            "--size",
            "8x8",
            "--answerer",
            &answerer,
            "--tolerance",
            "0.99",
        ],
        b"",
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("judged no ray") && err.contains("tolerance 0.99"),
        "{err}"
    );
}

/// An entry origin strictly inside is within the contract only where f32 has no point on the entry
/// face next to it: one step inside a face that holds f32 points (and one step from outside it) is
/// refused, the point on it held (the rule `holds` applies to every case a shrink tries).
#[test]
fn an_entry_origin_inside_next_to_a_point_on_the_face_is_outside_the_contract() {
    let entry = Contract {
        origin: Origin::Entry.into(),
        ..Contract::default()
    };
    // Face 1 (opposite vertex 1, the origin) in the plane x + y + z = 1, the line entering it along
    // -(1, 1, 1).
    let flat = [Vec3::X, Vec3::ZERO, Vec3::Y, Vec3::Z];
    let at = |z: f32| Case {
        tet: flat,
        org: Vec3::new(0.25, 0.25, z),
        dir: -Vec3::ONE,
        entry: Some(1),
    };
    let holds = |c: &Case| ExitFace::holds(&entry, c, &classify(c).unwrap());
    assert!(holds(&at(0.5)), "on the face");
    // One step below 0.5: strictly inside; (0.25, 0.25, 0.5) beside it lies on the face, and
    // (0.25 stepped up, 0.25, 0.5) outside it.
    let inside = at(0.5f32.next_down());
    assert!(
        broken(&entry, &inside).is_err(),
        "the checker refuses it too"
    );
    assert!(!holds(&inside), "next to a point on the face: {inside:?}");
}

/// Shards of a count asked under a contract add up to the unsharded count, the rays each left out
/// by its contract too (a tolerance that leaves some steps no case).
#[test]
fn a_contract_counts_shards_add_up_with_their_rays_left_out() {
    let dir = tempfile::tempdir().unwrap();
    let answerer = format!("{RECORDING}/dev/null");
    let run = |shard: &str, json: &std::path::Path| {
        let (code, _, err) = common::run_tetwalk(
            &[
                "count",
                "--views",
                "2",
                "--size",
                "16x16",
                "--answerer",
                &answerer,
                "--origin",
                "entry",
                "--tolerance",
                "0.0001",
                "--shard",
                shard,
                "--json",
                json.to_str().unwrap(),
            ],
            b"",
        );
        assert_eq!(code, 0, "{err}");
    };
    let (whole, a, b, merged) = (
        dir.path().join("whole.json"),
        dir.path().join("a.json"),
        dir.path().join("b.json"),
        dir.path().join("merged.json"),
    );
    run("0/1", &whole);
    run("0/2", &a);
    run("1/2", &b);
    let (code, _, err) = common::run_tetwalk(
        &[
            "count",
            "merge",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--json",
            merged.to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let read = |p: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let left = |p: &std::path::Path| read(p)["methods"][1]["left_out"].as_u64().unwrap();
    assert!(left(&whole) > 0, "the tolerance leaves some rays out");
    assert_eq!(left(&a) + left(&b), left(&whole));
    assert_eq!(left(&merged), left(&whole));
    assert_eq!(
        read(&merged)["methods"][1]["wrong_total"],
        read(&whole)["methods"][1]["wrong_total"]
    );
}

/// Under a contract each step is judged when asked: a program answering face 0 to every step is
/// wrong on rays whose dump lines each hold the step's case as sent, a case inside the contract
/// whose exact exit faces are not face 0.
#[test]
fn a_count_under_a_contract_judges_each_step_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let dump = dir.path().join("dump.jsonl");
    let face_zero = r#"python3 -c '
import json, sys
for line in sys.stdin:
    if line.strip():
        print(json.dumps({"line": json.loads(line)["line"], "face": 0}))
    else:
        sys.stdout.flush()
'"#;
    let (code, out, err) = common::run_tetwalk(
        &[
            "count",
            "--views",
            "1",
            "--size",
            "8x8",
            "--answerer",
            face_zero,
            "--origin",
            "entry",
            "--dump",
            dump.to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let k = Contract {
        origin: Origin::Entry.into(),
        ..Contract::default()
    };
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&dump)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(lines.len() > 10, "{out}");
    for v in &lines {
        let case = case_of(&v["case"]);
        broken(&k, &case).unwrap_or_else(|why| panic!("{case:?}: {why}"));
        let x = classify(&case).unwrap();
        assert!(!x.exit.contains(0), "face 0 is right for {case:?}");
        assert_eq!(v["divergence"]["face"], 0, "{v}");
    }
}
