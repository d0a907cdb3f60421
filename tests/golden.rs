//! Golden images (insta, stored in `golden/`): the exact per-pixel data and the PNGs of a bunny view and
//! of every method's predicate map. A change in any method, the walk or the oracle shows up here as a
//! changed picture; review with `cargo insta review`. Under CI=true a change fails without writing.

mod common;

use tetwalk::backend::Backend;
use tetwalk::family::exit_face::engine::predicate_grid;
use tetwalk::family::walk::engine::frame;
use tetwalk::methods::Model;
use tetwalk::registry::Named;
use tetwalk::registry::{METHODS, reference};
use tetwalk::render::{self, Image, face_image};
use tetwalk::scenes::camera::Views;
use tetwalk::scenes::tets::{Target, TetShape, through};
use tetwalk::tet::Case;

use common::settings;

fn rows(width: u32, cells: impl Iterator<Item = String>) -> String {
    let cells: Vec<String> = cells.collect();
    cells
        .chunks(width as usize)
        .map(|r| r.join(" "))
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn bunny_view_is_unchanged() {
    let mesh = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required)
        .unwrap()
        .mesh;
    let methods: Vec<_> = METHODS.iter().filter(|m| !m.is_reference()).collect();
    let views = Views::new(160, 64, 48, 1);
    let f = frame(
        &mesh,
        &views,
        3,
        &methods,
        &Backend::Cpu {
            model: Model::Plain,
        },
    )
    .unwrap();
    // Exact walk per pixel: h (hit a model face), b (hit the box), - (left), with the steps.
    let exact = rows(
        f.width,
        f.exact.iter().zip(&f.shade).map(|(w, &(_, hull))| {
            let k = match w.outcome {
                tetwalk::walk::Outcome::Hit { .. } if hull => "b",
                tetwalk::walk::Outcome::Hit { .. } => "h",
                _ => "-",
            };
            format!("{k}{}", w.steps)
        }),
    );
    let mut wrong = String::new();
    for (name, w) in &f.wrong {
        let bad: Vec<String> = w
            .iter()
            .enumerate()
            .filter_map(|(i, k)| k.map(|k| format!("{i}:{}", k.code())))
            .collect();
        wrong += &format!("{name}: {}\n", bad.join(" "));
    }
    settings().bind(|| {
        insta::assert_snapshot!("bunny_view3_exact", exact);
        insta::assert_snapshot!("bunny_view3_wrong", wrong);
        insta::assert_binary_snapshot!("bunny_view3_shaded.png", f.shaded().png().unwrap());
        insta::assert_binary_snapshot!("bunny_view3_heat.png", f.heat().png().unwrap());
        let maps: Vec<Image> = (0..methods.len()).map(|i| f.failures(i)).collect();
        insta::assert_binary_snapshot!(
            "bunny_view3_failures.png",
            Image::sheet(&maps, 2).png().unwrap()
        );
    });
}

fn predicate_case() -> Case {
    let (tet, ray) = through(
        TetShape::Sliver,
        0.05,
        Target::Edge,
        &mut tetwalk::scenes::rng(7),
    )
    .unwrap();
    Case {
        tet,
        org: ray.org,
        dir: ray.dir,
        entry: None,
    }
}

const GRID: u32 = 48;

fn faces_text(faces: &[Option<usize>]) -> String {
    rows(
        GRID,
        faces
            .iter()
            .map(|f| f.map_or("-".into(), |f| f.to_string())),
    )
}

#[test]
fn predicate_maps_are_unchanged() {
    let case = predicate_case();
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let exact = predicate_grid(&case, GRID, reference(), &cpu).unwrap();
    settings().bind(|| {
        insta::assert_snapshot!("predicate_exact", faces_text(&exact));
        for m in METHODS.iter().filter(|m| !m.is_reference()) {
            let mut sheet = vec![face_image(&exact, GRID)];
            for model in [Model::Plain, Model::Fused] {
                let faces = predicate_grid(&case, GRID, m, &Backend::Cpu { model }).unwrap();
                let tag = if model == Model::Fused { "fma" } else { "cpu" };
                insta::assert_snapshot!(
                    format!("predicate_{}_{tag}", m.name()),
                    faces_text(&faces)
                );
                sheet.push(face_image(&faces, GRID));
            }
            insta::assert_binary_snapshot!(
                &format!("predicate_{}.png", m.name()),
                Image::sheet(&sheet, 2).png().unwrap()
            );
        }
    });
}

/// Predicate maps with the entry face given, one for each entry face 0..3 (so every column of every
/// method's face table is drawn), as text.
#[test]
fn predicate_maps_from_each_entry_face_are_unchanged() {
    let mut r = tetwalk::scenes::rng(17);
    let mut cases: Vec<Option<Case>> = vec![None; 4];
    while cases.iter().any(Option::is_none) {
        let (tet, ray) = through(TetShape::Well, 1.0, Target::Edge, &mut r).unwrap();
        let c = tetwalk::exact::classify(&tet, &ray).unwrap();
        // One exact entry face, with the origin behind it: the ray really enters there.
        if c.entry.0.count_ones() == 1 {
            let e = c.entry.first().unwrap();
            if cases[e].is_none() {
                cases[e] = Some(Case {
                    tet,
                    org: ray.org - ray.dir,
                    dir: ray.dir,
                    entry: Some(e as u8),
                });
            }
        }
    }
    const SMALL: u32 = 24;
    settings().bind(|| {
        for m in METHODS.iter().filter(|m| !m.is_reference()) {
            let mut text = String::new();
            for (e, case) in cases.iter().enumerate() {
                let faces = predicate_grid(
                    case.as_ref().unwrap(),
                    SMALL,
                    m,
                    &Backend::Cpu {
                        model: Model::Plain,
                    },
                )
                .unwrap();
                text += &format!("entry {e}\n");
                text += &rows(
                    SMALL,
                    faces
                        .iter()
                        .map(|f| f.map_or("-".into(), |f| f.to_string())),
                );
            }
            insta::assert_snapshot!(format!("predicate_entries_{}", m.name()), text);
        }
    });
}

/// GPU predicate maps against the CPU's golden data, with a tolerance per adapter: none on llvmpipe
/// (it does not contract), 10% of the pixels elsewhere. A failure writes the difference image to
/// `tetwalk-golden-diff-<method>.png` in the temporary directory (which always exists).
#[test]
fn gpu_predicate_maps_are_within_tolerance() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    let tolerance = if gpu.describe().contains("llvmpipe") {
        0
    } else {
        (GRID * GRID / 10) as usize
    };
    let case = predicate_case();
    for m in METHODS.iter().filter(|m| !m.is_reference()) {
        let cpu = predicate_grid(
            &case,
            GRID,
            m,
            &Backend::Cpu {
                model: Model::Plain,
            },
        )
        .unwrap();
        let on_gpu = predicate_grid(&case, GRID, m, &gpu).unwrap();
        let differ: Vec<bool> = cpu.iter().zip(&on_gpu).map(|(a, b)| a != b).collect();
        let n = differ.iter().filter(|&&d| d).count();
        if n > tolerance {
            let mut diff = Image::new(GRID, GRID);
            for (i, &d) in differ.iter().enumerate() {
                diff.set(
                    i as u32 % GRID,
                    i as u32 / GRID,
                    if d { [255, 0, 0] } else { [40, 40, 40] },
                );
            }
            let path = std::env::temp_dir().join(format!("tetwalk-golden-diff-{}.png", m.name()));
            let path = path.display();
            std::fs::write(path.to_string(), diff.png().unwrap()).unwrap();
            panic!(
                "{} on {}: {n} pixels differ from the CPU (tolerance {tolerance}); see {path}",
                m.name(),
                gpu.describe()
            );
        }
    }
}

/// A failure map with every kind of wrong ray on it (a frame made by hand), so that every kind's
/// colour and marker is held by a golden image; its legend names exactly the kinds drawn.
#[test]
fn a_failure_map_with_every_kind_is_unchanged() {
    use tetwalk::walk::{Outcome, OutcomeKind, Walk};
    let (w, h) = (64u32, 48u32);
    let n = (w * h) as usize;
    let mut wrong = vec![None; n];
    for (k, kind) in OutcomeKind::ALL.iter().enumerate() {
        wrong[(10 + 8 * k as u32 + w * (12 + 6 * k as u32)) as usize] = Some(*kind);
    }
    let f = tetwalk::engine::view::Frame {
        width: w,
        height: h,
        exact: (0..n)
            .map(|i| Walk {
                outcome: Outcome::LeftMesh { tet: 0, face: 0 },
                steps: 1 + (i as u32 % w) / 4,
            })
            .collect(),
        wrong: vec![("every-kind".into(), wrong)],
        shade: (0..n).map(|i| ((60 + i % 150) as u8, i % 7 == 0)).collect(),
    };
    let legend = render::failure_legend(&OutcomeKind::ALL);
    for k in OutcomeKind::ALL {
        assert!(legend.contains(k.wrong()), "{legend}");
    }
    assert!(!render::failure_legend(&[OutcomeKind::Cycle]).contains("wrong face"));
    settings().bind(|| {
        insta::assert_binary_snapshot!("every_kind_failures.png", f.failures(0).png().unwrap());
        insta::assert_binary_snapshot!("every_kind_heat.png", f.heat().png().unwrap());
    });
}

/// A small fixed stress run with known answers, every number pinned (`golden/stress_small.snap`):
/// wrong faces and "no exit face" each reached, `exact` never wrong.
#[test]
fn a_small_stress_table_is_unchanged() {
    use tetwalk::engine::stress::{self, StressSettings};
    use tetwalk::family::ExitFace;
    use tetwalk::report::Formats;
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let s = StressSettings::<ExitFace> {
        contract: Default::default(),
        cases: 1500,
        rows: Default::default(),
        seed: 5,
        backend: cpu.ran(),
        scale: Default::default(),
    };
    let methods: Vec<_> = METHODS.iter().collect();
    let report = stress::run(
        &s,
        &stress::Who::methods(&methods),
        &cpu,
        &|_| {},
        &mut |_| {},
    )
    .unwrap();
    let all = report.rows.iter().flat_map(|r| &r.tallies);
    assert!(all.clone().any(|t| t.counts.wrong_face > 0));
    assert!(all.clone().any(|t| t.counts.no_exit_face > 0));
    assert!(
        all.filter(|t| t.method == "exact")
            .all(|t| t.counts.wrong_face == 0 && t.counts.no_exit_face == 0)
    );
    settings().bind(|| insta::assert_snapshot!("stress_small", ExitFace::stress_table(&report)));
}

/// Leak maps (seed 004's question, pictured): around an edge shared by two triangles of a closed
/// octahedron at Embree's offset (the first case of the stress rows' `edge` row there), which of the
/// two each ray–triangle method reports for rays exactly through the edge at points along it (the
/// middle row) and with the direction moved by ulp steps off it — one (a, b), both (2), neither but
/// another triangle around the crossing (o, not a leak), none where the ray crosses the surface (0, a
/// leak, judged against every triangle of the mesh), neither as the exact ray (.) — on the CPU plain
/// and fused, beside the exact map; as text and as a PNG sheet (exact | cpu | cpu-fma).
#[test]
fn leak_maps_are_unchanged() {
    use tetwalk::family::triangle::engine::{EdgeHit, LeakGrid, leak_case};
    use tetwalk::render::grid_image;
    use tetwalk::scenes::closed::{MeshShape, TriPlace};
    const SIZE: u32 = 48;
    let (case, pair) = leak_case(MeshShape::Octahedron, TriPlace::Embree, 1, &[]).unwrap();
    let grid = LeakGrid::new(&case, pair, SIZE);
    let exact = grid.exact();
    let image = |cells: &[EdgeHit]| grid_image(SIZE, cells.iter().map(|c| c.colour()));
    let text = |cells: &[EdgeHit]| rows(SIZE, cells.iter().map(|c| c.letter().to_string()));
    settings().bind(|| {
        insta::assert_snapshot!("leak_exact", text(exact));
        for m in tetwalk::registry::TRIANGLE_METHODS {
            let mut sheet = vec![image(exact)];
            for model in [Model::Plain, Model::Fused] {
                let cells = grid.of(m, &Backend::Cpu { model }).unwrap();
                let tag = if model == Model::Fused { "fma" } else { "cpu" };
                insta::assert_snapshot!(format!("leak_{}_{tag}", m.name()), text(&cells));
                sheet.push(image(&cells));
            }
            insta::assert_binary_snapshot!(
                &format!("leak_{}.png", m.name()),
                Image::sheet(&sheet, 2).png().unwrap()
            );
        }
    });
}

/// Seed 001's octree cells per pixel on the bunny's view 3 (`portalez16-direction`, leaves tested with
/// `mt`, depth 8, capacity 6): the heat map of the paper's Figure 6.
#[test]
fn octree_heat_is_unchanged() {
    let mesh = tetwalk::scenes::load("bunny-quality", tetwalk::mesh::Faces::Required)
        .unwrap()
        .mesh;
    let views = Views::new(160, 96, 96, 1);
    let method =
        tetwalk::family::by_name::<tetwalk::family::OctreeCells>("portalez16-direction").unwrap();
    let hit = tetwalk::family::by_name::<tetwalk::family::Triangle>("mt")
        .unwrap()
        .hit(Model::Plain);
    let cells = tetwalk::family::octree::engine::cells_per_pixel(
        &mesh,
        &views,
        3,
        method,
        hit,
        tetwalk::octree::Settings::PAPER,
    )
    .unwrap();
    let im = render::octree_heat(96, 96, &cells, method.name());
    settings().bind(|| {
        insta::assert_binary_snapshot!("bunny_view3_octree_heat.png", im.png().unwrap());
    });
}

/// A leak map paints the leaks the stress rows count: its case is an `edge` row case (the first that
/// a listed method leaks through), its middle row rays exactly through the edge at points along it,
/// and its centre that very case, so `mt`'s map shows leaks there (the stress rows count it leaking
/// through 11% of exact edges of tetrahedra) and its centre is a leak as `mt`'s answer to the case is;
/// `woop-watertight`, as written, leaks nowhere on it. A leak is judged against every triangle of the
/// mesh, as the stress rows judge it.
#[test]
fn a_leak_map_paints_the_leaks_the_stress_rows_count() {
    use tetwalk::family::triangle::engine::{EdgeHit, LeakGrid, leak_case};
    use tetwalk::family::{Family, Triangle};
    use tetwalk::scenes::closed::{MeshShape, TriPlace};
    const SIZE: u32 = 64;
    let mt = tetwalk::family::by_name::<Triangle>("mt").unwrap();
    let woop = tetwalk::family::by_name::<Triangle>("woop-watertight").unwrap();
    let plain = Backend::Cpu {
        model: Model::Plain,
    };
    let (case, pair) = leak_case(MeshShape::Tetrahedron, TriPlace::Embree, 1, &[mt]).unwrap();
    let grid = LeakGrid::new(&case, pair, SIZE);
    let middle = (SIZE / 2 * SIZE) as usize..(SIZE / 2 * SIZE + SIZE) as usize;
    // Every middle-row ray passes exactly through the edge: both triangles, exactly.
    assert!(
        grid.exact()[middle.clone()]
            .iter()
            .all(|c| *c == EdgeHit::Both)
    );
    let cells = grid.of(mt, &plain).unwrap();
    assert!(cells[middle.clone()].contains(&EdgeHit::Neither));
    // The centre is the case itself, judged as the stress rows judge it.
    let truth = Triangle::truth(&case).unwrap();
    let answer = Triangle::answers(&plain, mt, &[case]).unwrap()[0];
    assert!(truth.leaks(&answer.ids()));
    assert_eq!(
        cells[(SIZE / 2 * SIZE + SIZE / 2) as usize],
        EdgeHit::Neither
    );
    let woop_cells = grid.of(woop, &plain).unwrap();
    assert!(!woop_cells.contains(&EdgeHit::Neither));
}
