//! Pictures: shaded renders, per-method failure maps, traversal heat maps and predicate maps, from
//! integer per-pixel data (which the golden tests snapshot) to deterministic PNGs.

pub mod text;

use crate::backend::{Backend, BackendError};
use crate::cases::{Case, HitCase};
use crate::mesh::{HULL, Mesh, bounds};
use crate::methods::Model;
use crate::registry::{Method, Named, OctreeMethod, TriangleMethod, reference};
use crate::scenes::camera::Views;
use crate::scenes::closed::{self, MeshShape, TriPlace};
use crate::scenes::tets::ulps;
use crate::walk::{LocateError, Outcome, OutcomeKind, Walk, default_max_steps, judge, locate};
use rayon::prelude::*;

/// Why a picture could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error("view {view}'s camera is not inside the mesh: {why}")]
    Outside { view: usize, why: LocateError },
    #[error("view {view} does not exist: views are numbered 0 to {} ({views} in all)", views - 1)]
    NoSuchView { view: usize, views: usize },
    #[error("octree: {0}")]
    Octree(String),
    #[error("an image of {width}x{height} pixels cannot be written as PNG: {why}")]
    Png {
        width: u32,
        height: u32,
        why: String,
    },
}

/// An RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Image {
        Image {
            width,
            height,
            rgb: vec![0; (width * height * 3) as usize],
        }
    }

    pub fn set(&mut self, x: u32, y: u32, c: [u8; 3]) {
        let i = ((y * self.width + x) * 3) as usize;
        self.rgb[i..i + 3].copy_from_slice(&c);
    }

    /// [`Image::set`], doing nothing outside the image.
    pub fn set_clipped(&mut self, x: u32, y: u32, c: [u8; 3]) {
        if x < self.width && y < self.height {
            self.set(x, y, c);
        }
    }

    /// `im` copied in with its top-left corner at `(x0, y0)` (what falls outside is left out).
    pub fn paste(&mut self, im: &Image, x0: u32, y0: u32) {
        for y in 0..im.height {
            for x in 0..im.width {
                let i = ((y * im.width + x) * 3) as usize;
                self.set_clipped(x0 + x, y0 + y, [im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]]);
            }
        }
    }

    /// A scale for markers and labels: 1 up to 256 pixels on the short side, then one more per 256.
    pub fn scale(&self) -> u32 {
        (self.width.min(self.height) / 256).max(1)
    }

    /// Images side by side, `gap` pixels of white between them.
    pub fn sheet(images: &[Image], gap: u32) -> Image {
        Image::arranged(images, gap, true)
    }

    /// Images side by side (`across`) or one above another, top-left aligned, `gap` pixels of white
    /// between them.
    fn arranged(images: &[Image], gap: u32, across: bool) -> Image {
        let along = |i: &Image| if across { i.width } else { i.height };
        let beside = |i: &Image| if across { i.height } else { i.width };
        let long = images
            .iter()
            .map(|i| along(i) + gap)
            .sum::<u32>()
            .saturating_sub(gap);
        let wide = images.iter().map(beside).max().unwrap_or(0);
        let (w, h) = if across { (long, wide) } else { (wide, long) };
        let mut out = Image {
            width: w,
            height: h,
            rgb: vec![255; (w * h * 3) as usize],
        };
        let mut at = 0;
        for im in images {
            let (x, y) = if across { (at, 0) } else { (0, at) };
            out.paste(im, x, y);
            at += along(im) + gap;
        }
        out
    }

    /// PNG bytes, with the encoder's settings pinned so the bytes are the same on every run; an error
    /// for an image PNG cannot hold (no pixels).
    pub fn png(&self) -> Result<Vec<u8>, RenderError> {
        let fail = |e: png::EncodingError| RenderError::Png {
            width: self.width,
            height: self.height,
            why: e.to_string(),
        };
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Balanced);
        enc.set_filter(png::Filter::NoFilter);
        let mut w = enc.write_header().map_err(fail)?;
        w.write_image_data(&self.rgb).map_err(fail)?;
        w.finish().map_err(fail)?;
        Ok(out)
    }
}

/// Dark, as behind labels.
const DARK: [u8; 3] = [16, 16, 16];

/// `im` under a dark bar holding `title` in white.
pub fn titled(im: &Image, title: &str) -> Image {
    let scale = im.scale();
    let bar = text::line_height(scale);
    let width = im.width.max(text::width(title, scale) + 2 * scale);
    let mut out = Image::new(width, im.height + bar);
    for v in out.rgb.iter_mut() {
        *v = DARK[0];
    }
    text::label(&mut out, 0, 0, title, scale, [255, 255, 255]);
    out.paste(im, 0, bar);
    out
}

/// Images one above another, left-aligned, `gap` pixels of white between them.
pub fn stacked(images: &[Image], gap: u32) -> Image {
    Image::arranged(images, gap, false)
}

/// A legend `width` pixels wide (at least its widest entry): for each entry a swatch of its colour
/// (outlined, so that black shows) and its words, as many to a line as fit.
pub fn legend(entries: &[(&str, [u8; 3])], width: u32, scale: u32) -> Image {
    let line = text::line_height(scale);
    let entry_w = |words: &str| line + text::width(words, scale) + 4 * scale;
    let width = entries
        .iter()
        .map(|(w, _)| entry_w(w))
        .max()
        .unwrap_or(0)
        .max(width);
    let mut places = Vec::new();
    let (mut x, mut y) = (0, 0);
    for (words, _) in entries {
        if x > 0 && x + entry_w(words) > width {
            (x, y) = (0, y + line);
        }
        places.push((x, y));
        x += entry_w(words);
    }
    let mut im = Image::new(width, y + line);
    for v in im.rgb.iter_mut() {
        *v = DARK[0];
    }
    for ((words, colour), (x, y)) in entries.iter().zip(places) {
        let (s0, s1) = (x + scale, x + line - scale);
        for yy in y + scale..y + line - scale {
            for xx in s0..s1 {
                let edge =
                    yy == y + scale || yy == y + line - scale - 1 || xx == s0 || xx == s1 - 1;
                im.set(xx, yy, if edge { [160, 160, 160] } else { *colour });
            }
        }
        text::label(&mut im, x + line, y, words, scale, [255, 255, 255]);
    }
    im
}

/// A method's sheet: its name, its panels side by side each under its title, and the legend.
pub fn sheet(heading: &str, panels: &[(String, Image)], key: &[(&str, [u8; 3])]) -> Image {
    let row: Vec<Image> = panels.iter().map(|(t, im)| titled(im, t)).collect();
    let row = Image::sheet(&row, 4);
    let scale = row.scale();
    stacked(&[titled(&row, heading), legend(key, row.width, scale)], 0)
}

/// A panel's title for a backend: its kind, and a GPU's adapter up to its first parenthesis.
pub fn backend_title(b: &Backend) -> String {
    let ran = b.ran();
    match ran.adapter {
        Some(a) => format!(
            "{}: {}",
            crate::choice::Choice::name(ran.kind),
            a.split(" (").next().unwrap_or(&a)
        ),
        None => crate::choice::Choice::name(ran.kind).to_string(),
    }
}

/// Colours of faces 0..3 in predicate maps; black for no exit face.
pub const FACE_COLOURS: [[u8; 3]; 4] =
    [[228, 26, 28], [55, 126, 184], [77, 175, 74], [255, 127, 0]];

/// What a view of a scene shows, per pixel (row-major): the exact walk and each method's verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// The exact walk of every pixel.
    pub exact: Vec<Walk>,
    /// Per method, per pixel: the kind of wrong ending, or none.
    pub wrong: Vec<(String, Vec<Option<OutcomeKind>>)>,
    /// Shading of the exact hit: `|n · d|` in 0..=255, and whether it is a box (hull) face.
    pub shade: Vec<(u8, bool)>,
}

/// View `index`'s camera (placed as `tetwalk count` places it) and the tetrahedron holding it.
fn view(
    mesh: &Mesh,
    views: &Views,
    index: usize,
) -> Result<(crate::scenes::camera::Camera, u32), RenderError> {
    if index >= views.views {
        return Err(RenderError::NoSuchView {
            view: index,
            views: views.views,
        });
    }
    let (lo, hi) = bounds(&mesh.points);
    let cam = views.camera(lo, hi, index);
    let start =
        locate(mesh, cam.eye, 0).map_err(|why| RenderError::Outside { view: index, why })?;
    Ok((cam, start))
}

/// Render view `index` of `views` (placed as `tetwalk count` places them) with the exact walk and
/// `methods` on `backend`.
pub fn frame(
    mesh: &Mesh,
    views: &Views,
    index: usize,
    methods: &[&Method],
    backend: &Backend,
) -> Result<Frame, RenderError> {
    let (cam, start) = view(mesh, views, index)?;
    let max = default_max_steps(mesh);
    let rays = views.rays(&cam);
    let on = backend.mesh(mesh);
    let exact = backend.walks(reference(), &on, &rays, start, max)?;
    let mut wrong = Vec::new();
    for m in methods {
        let walks = backend.walks(m, &on, &rays, start, max)?;
        let w: Vec<Option<OutcomeKind>> = rays
            .par_iter()
            .zip(&walks)
            .zip(&exact)
            .map(|((r, w), re)| judge(mesh, r, w, re))
            .collect();
        wrong.push((m.name().to_string(), w));
    }
    let shade = rays
        .iter()
        .zip(&exact)
        .map(|(r, w)| match w.outcome {
            Outcome::Hit { tet, face } => {
                let [a, b, c] = mesh
                    .face(tet, face as usize)
                    .map(|i| mesh.points[i as usize]);
                let n = (b - a).cross(c - a).normalize_or_zero();
                let s = (n.dot(r.dir.normalize()).abs() * 205.0 + 50.0) as u8;
                (s, mesh.neighbors[tet as usize][face as usize] == HULL)
            }
            _ => (0, false),
        })
        .collect();
    Ok(Frame {
        width: views.width,
        height: views.height,
        exact,
        wrong,
        shade,
    })
}

impl Frame {
    /// Flat shading: the model in warm grey, the box walls in blue-grey.
    pub fn shaded(&self) -> Image {
        let mut im = Image::new(self.width, self.height);
        for (i, &(s, hull)) in self.shade.iter().enumerate() {
            let k = |num: u32, den: u32| (s as u32 * num / den) as u8;
            let c = if hull {
                [k(1, 2), k(1, 2), k(2, 3)]
            } else {
                [s, k(9, 10), k(4, 5)]
            };
            im.set(i as u32 % self.width, i as u32 / self.width, c);
        }
        im
    }

    /// The shaded render, dimmed, with each of `method`'s wrong rays marked by a ring in the colour of
    /// its kind ([`OutcomeKind::colour`]), large enough to see at the image's size; the method's name
    /// and its count of wrong rays in the top-left corner, and a legend of the kinds drawn at the
    /// bottom.
    pub fn failures(&self, method: usize) -> Image {
        let mut im = self.shaded();
        for v in &mut im.rgb {
            *v = (*v as u32 * 2 / 5) as u8;
        }
        let scale = im.scale();
        let r = (self.width.min(self.height) / 40).max(3) as i64;
        let (name, wrong) = &self.wrong[method];
        for (i, k) in wrong.iter().enumerate() {
            let Some(k) = k else { continue };
            let (cx, cy) = (
                (i as u32 % self.width) as i64,
                (i as u32 / self.width) as i64,
            );
            for dy in -r - 1..=r + 1 {
                for dx in -r - 1..=r + 1 {
                    let d2 = dx * dx + dy * dy;
                    let ring = d2 <= (r + 1) * (r + 1) && d2 >= (r - 1) * (r - 1);
                    if ring || d2 == 0 {
                        let (x, y) = (cx + dx, cy + dy);
                        if x >= 0 && y >= 0 {
                            im.set_clipped(x as u32, y as u32, k.colour());
                        }
                    }
                }
            }
        }
        let n = wrong.iter().flatten().count();
        text::label(
            &mut im,
            0,
            0,
            &format!("{name}: {n} wrong"),
            scale,
            [255, 255, 255],
        );
        let mut x = 0;
        let y = self.height.saturating_sub(text::line_height(scale));
        for k in OutcomeKind::ALL {
            if wrong.contains(&Some(k)) {
                text::label(&mut im, x, y, k.wrong(), scale, k.colour());
                x += text::width(k.wrong(), scale) + 4 * scale;
            }
        }
        im
    }

    /// Tetrahedra traversed per pixel by the exact walk ([`heat_map`]).
    pub fn heat(&self) -> Image {
        let steps: Vec<u32> = self.exact.iter().map(|w| w.steps).collect();
        heat_map(
            self.width,
            self.height,
            &steps,
            "tetrahedra per pixel (exact walk)",
        )
    }
}

/// A count per pixel (row-major), black (few) to yellow (most), with a colour scale on the right
/// labelled with the fewest and the most, under `title` (what is counted, and per what: its unit).
pub fn heat_map(width: u32, height: u32, counts: &[u32], title: &str) -> Image {
    let (fewest, most) = (
        counts.iter().copied().min().unwrap_or(0),
        counts.iter().copied().max().unwrap_or(1).max(1),
    );
    let colour = |t: f32| {
        let t = t.clamp(0.0, 1.0).sqrt();
        [
            (255.0 * t) as u8,
            (255.0 * (t * t)) as u8,
            (120.0 * (1.0 - t)) as u8,
        ]
    };
    let probe = Image::new(width, height);
    let scale = probe.scale();
    let labels = [most.to_string(), fewest.to_string()];
    let label_w = labels
        .iter()
        .map(|l| text::width(l, scale))
        .max()
        .unwrap_or(0);
    let bar = 6 * scale;
    let mut im = Image::new(width + bar + label_w + 6 * scale, height);
    for (i, &n) in counts.iter().enumerate() {
        im.set(
            i as u32 % width,
            i as u32 / width,
            colour(n as f32 / most as f32),
        );
    }
    let x0 = width + 2 * scale;
    for y in 0..height {
        let t = 1.0 - y as f32 / (height.max(2) - 1) as f32;
        for x in x0..x0 + bar {
            im.set(x, y, colour(t));
        }
    }
    let lx = x0 + bar + scale;
    text::label(&mut im, lx, 0, &labels[0], scale, [255, 255, 255]);
    let bottom = height.saturating_sub(text::line_height(scale));
    text::label(&mut im, lx, bottom, &labels[1], scale, [255, 255, 255]);
    titled(&im, title)
}

/// Seed 001's octree cells traversed per pixel of view `index` by octree method `method` (each leaf's
/// triangles tested with `hit`), the octree built as `settings` says over the scene's constrained
/// faces facing the camera ([`heat_map`]).
pub fn octree_heat(
    mesh: &Mesh,
    views: &Views,
    index: usize,
    method: &OctreeMethod,
    hit: crate::registry::HitFn,
    settings: crate::octree::Settings,
) -> Result<Image, RenderError> {
    let (cam, start) = view(mesh, views, index)?;
    let region = crate::mesh::surface::region_of(mesh, start);
    let (tris, _) = crate::mesh::surface::scene_triangles(mesh, &region);
    let octree = crate::octree::Octree::build(&tris, settings)
        .map_err(|e| RenderError::Octree(e.to_string()))?;
    let cap = crate::walk::octree::default_max_steps(&octree);
    let walk = method.walk(Model::Plain);
    let cells: Vec<u32> = views
        .rays(&cam)
        .par_iter()
        .map(|r| walk(&octree, &tris, hit, r, cap).cells)
        .collect();
    Ok(heat_map(
        views.width,
        views.height,
        &cells,
        &format!("octree cells per pixel ({})", method.name()),
    ))
}

/// A predicate map (after Kettner et al.'s classroom examples): the case's origin moved on a
/// `size × size` grid of ulp steps in x and y around itself, each pixel the exit face `method` gives on
/// `backend` (the reference gives the exact one, ties broken as it breaks them).
pub fn predicate_grid(
    case: &Case,
    size: u32,
    method: &Method,
    backend: &Backend,
) -> Result<Vec<Option<usize>>, RenderError> {
    let half = (size / 2) as i32;
    let cases: Vec<Case> = (0..size)
        .flat_map(|y| (0..size).map(move |x| (x, y)))
        .map(|(x, y)| {
            let mut c = *case;
            c.org.x = ulps(c.org.x, x as i32 - half);
            c.org.y = ulps(c.org.y, half - y as i32);
            c
        })
        .collect();
    Ok(backend.exit_faces(method, &cases)?)
}

/// Which of the two triangles sharing an edge report a hit: a leak map's cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeHit {
    First,
    Second,
    /// Both: a double hit (right where the ray meets the edge itself).
    Both,
    /// A leak, judged against every triangle of the mesh: the ray crosses the surface and no triangle
    /// around the crossing reports it.
    Neither,
    /// Neither, as the exact ray: it passes beside both.
    Beside,
    /// Neither of the two, but another triangle around the crossing (the ray passes beside the pair
    /// onto a neighbour): not a leak.
    Other,
}

impl EdgeHit {
    fn of(first: bool, second: bool) -> EdgeHit {
        match (first, second) {
            (true, true) => EdgeHit::Both,
            (true, false) => EdgeHit::First,
            (false, true) => EdgeHit::Second,
            (false, false) => EdgeHit::Neither,
        }
    }

    pub const ALL: [EdgeHit; 6] = [
        EdgeHit::First,
        EdgeHit::Second,
        EdgeHit::Both,
        EdgeHit::Neither,
        EdgeHit::Beside,
        EdgeHit::Other,
    ];

    /// Its letter in the golden text and its colour in the PNG.
    pub fn letter(self) -> char {
        ['a', 'b', '2', '0', '.', 'o'][self as usize]
    }

    pub fn colour(self) -> [u8; 3] {
        [
            [40, 110, 255],
            [40, 200, 80],
            [250, 210, 0],
            [230, 30, 30],
            [0, 0, 0],
            [150, 90, 200],
        ][self as usize]
    }

    /// What it means, for the legend.
    pub fn words(self) -> &'static str {
        [
            "the first triangle only",
            "the second only",
            "both (a double hit)",
            "a leak (no triangle of the mesh catches the ray)",
            "neither, as the exact ray",
            "a neighbouring triangle (not a leak)",
        ][self as usize]
    }
}

/// A leak map's grid of `size × size` rays around the triangle case's, which passes exactly through
/// the edge the triangles `pair` share: across (x) the origin moved parallel to the edge by a power-of-
/// two fraction of it, so that the middle row's rays cross the edge line at points of its middle half
/// (exactly, where the moved origins are f32 values: the far places), as the stress rows' exact-edge
/// rays do; down (y) the direction moved by ulp steps in its component, other than the largest, across
/// which the edge runs least, so that the other rows pass beside the edge by a few ulps. Each cell
/// says which of the two triangles report a hit, or a leak. The exact cells are judged once, when the
/// grid is made; every method's are set beside them.
pub struct LeakGrid {
    cases: Vec<HitCase>,
    pair: [u32; 2],
    exact: Vec<EdgeHit>,
    /// Each cell's exact first crossings, against which a leak is judged.
    truths: Vec<Option<crate::exact::hit::HitTruth>>,
}

impl LeakGrid {
    pub fn new(case: &HitCase, pair: [u32; 2], size: u32) -> LeakGrid {
        let half = (size / 2) as i32;
        // Along x, the origin moves parallel to the edge, so that the middle row's rays pass exactly
        // through the edge line (where the moved origins are f32 values exactly: the far places);
        // the stress rows' exact-edge rays, at points from one end of the edge's middle half to the
        // other.
        let [t, u] = pair.map(|i| case.tris()[i as usize]);
        let shared: Vec<glam::Vec3> = t.iter().copied().filter(|p| u.contains(p)).collect();
        let edge = match shared[..] {
            [a, b] => b - a,
            _ => glam::Vec3::ZERO,
        };
        // Points from a quarter of the edge before its midpoint to a quarter after, at steps of
        // edge · 2^-m: the finest that keeps every moved origin an f32 value exactly (so every ray of
        // the middle row passes exactly through the edge line), at most one point a column.
        let exact = |m: i32| {
            let step = edge * 2f32.powi(-m);
            (-(1i32 << (m - 2))..=1 << (m - 2)).all(|j| {
                let o = case.org + step * j as f32;
                (0..3).all(|a| {
                    o[a] as f64 == case.org[a] as f64 + step[a] as f64 * j as f64
                        && step[a] as f64 == edge[a] as f64 * 2f64.powi(-m)
                })
            })
        };
        let finest = (4 * half.max(1) as u32)
            .next_power_of_two()
            .trailing_zeros() as i32;
        let m = (2..=finest).rev().find(|&m| exact(m)).unwrap_or(2);
        let (step, points) = (edge * 2f32.powi(-m), 1i32 << (m - 2));
        let along = |x: i32| step * ((x - half) as i64 * points as i64 / half.max(1) as i64) as f32;
        // Along y, the direction moves by ulp steps in the component (not the largest) across which
        // the edge runs least.
        let k = case.dir.abs().max_position();
        let (a1, a2) = ((k + 1) % 3, (k + 2) % 3);
        let ay = if edge[a1].abs() <= edge[a2].abs() {
            a1
        } else {
            a2
        };
        let step = ulps(case.dir[ay].abs(), 1) - case.dir[ay].abs();
        let cases: Vec<HitCase> = (0..size)
            .flat_map(|y| (0..size).map(move |x| (x, y)))
            .map(|(x, y)| {
                let mut c = *case;
                c.org += along(x as i32);
                c.dir[ay] += (half - y as i32) as f32 * step;
                c
            })
            .collect();
        let truths = cases
            .par_iter()
            .map(|c| crate::exact::hit::judge_hit(c.tris(), c.closed, &c.ray()).ok())
            .collect();
        let exact = cases
            .par_iter()
            .map(|c| {
                let ray = c.ray();
                let hit = |i: u32| {
                    crate::exact::hit::ray_triangle(c.tris()[i as usize], &ray).is_ok_and(|h| h.hit)
                };
                match EdgeHit::of(hit(pair[0]), hit(pair[1])) {
                    EdgeHit::Neither => EdgeHit::Beside,
                    e => e,
                }
            })
            .collect();
        LeakGrid {
            cases,
            pair,
            exact,
            truths,
        }
    }

    /// The exact cells (both on the edge itself).
    pub fn exact(&self) -> &[EdgeHit] {
        &self.exact
    }

    /// `method`'s cells on `backend`: a leak where, judged against every triangle of the mesh, the
    /// ray crosses the surface and no triangle around the crossing reports it; else which of the two
    /// it hits, or another around the crossing.
    pub fn of(
        &self,
        method: &TriangleMethod,
        backend: &Backend,
    ) -> Result<Vec<EdgeHit>, RenderError> {
        let [p, q] = self.pair;
        Ok(backend
            .triangle_hits(method, &self.cases)?
            .iter()
            .zip(self.exact.iter().zip(&self.truths))
            .map(|(h, (e, truth))| {
                let ids: Vec<u32> = h.iter().map(|&(k, _)| k).collect();
                if truth.as_ref().is_some_and(|t| t.leaks(&ids)) {
                    return EdgeHit::Neither;
                }
                match (EdgeHit::of(ids.contains(&p), ids.contains(&q)), e) {
                    (EdgeHit::Neither, EdgeHit::Beside) => EdgeHit::Beside,
                    (EdgeHit::Neither, _) => EdgeHit::Other,
                    (c, _) => c,
                }
            })
            .collect())
    }
}

/// A leak map's case: a case of the triangle stress rows' `edge` row of `shape` at `place` (the same
/// generator: a closed mesh, a ray from a lattice point outside it exactly through the midpoint of an
/// edge) whose ray crosses the surface there, between the edge's two triangles (the pair): the first
/// under `seed` that one of `leaking` leaks through on the CPU (plain f32), else the first; `None` if
/// 1,000 draws found none.
pub fn leak_case(
    shape: MeshShape,
    place: TriPlace,
    seed: u64,
    leaking: &[&TriangleMethod],
) -> Option<(HitCase, [u32; 2])> {
    let candidates = (0..1000u64).filter_map(|i| {
        let mut rng = crate::scenes::rng(seed.wrapping_mul(1000).wrapping_add(i));
        let (mesh, ray) = closed::case(shape, closed::TriAim::Edge, place, 1e-3, 4, &mut rng);
        let case = HitCase::closed(&mesh, ray).ok()?;
        let truth = crate::exact::hit::judge_hit(case.tris(), case.closed, &case.ray()).ok()?;
        let first = truth.first()?;
        let [p, q] = first.holding[..] else {
            return None;
        };
        first.crosses.then_some((case, [p, q], truth))
    });
    let mut fallback = None;
    for (case, pair, truth) in candidates {
        let leaks = leaking.iter().any(|m| {
            Backend::Cpu {
                model: Model::Plain,
            }
            .triangle_hits(m, std::slice::from_ref(&case))
            .is_ok_and(|h| truth.leaks(&h[0].iter().map(|&(k, _)| k).collect::<Vec<_>>()))
        });
        if leaks || leaking.is_empty() {
            return Some((case, pair));
        }
        fallback.get_or_insert((case, pair));
    }
    fallback
}

/// A leak map as an image ([`EdgeHit::colour`]).
pub fn leak_image(cells: &[EdgeHit], size: u32) -> Image {
    let mut im = Image::new(size, size);
    for (i, c) in cells.iter().enumerate() {
        im.set(i as u32 % size, i as u32 / size, c.colour());
    }
    im
}

/// The leak maps' key: each kind of cell, its words and colour.
pub fn leak_key() -> Vec<(&'static str, [u8; 3])> {
    EdgeHit::ALL
        .iter()
        .map(|c| (c.words(), c.colour()))
        .collect()
}

/// The predicate maps' key: each face's colour, black for none.
pub fn predicate_key() -> Vec<(&'static str, [u8; 3])> {
    const FACES: [&str; 4] = ["face 0", "face 1", "face 2", "face 3"];
    FACES
        .iter()
        .zip(FACE_COLOURS)
        .map(|(f, c)| (*f, c))
        .chain([("no exit face", [0, 0, 0])])
        .collect()
}

/// A key in words, for standard output: `name: words rgb(…); …`.
pub fn key_line(name: &str, key: &[(&str, [u8; 3])]) -> String {
    let parts: Vec<String> = key.iter().map(|(w, c)| format!("{w} rgb{c:?}")).collect();
    format!("{name}: {}\n", parts.join("; "))
}

/// The leak maps' legend, in words.
pub fn leak_legend() -> String {
    key_line(
        "leak maps: hits on the two triangles sharing the edge",
        &leak_key(),
    )
}

/// A grid of faces as an image ([`FACE_COLOURS`], black for none).
pub fn face_image(faces: &[Option<usize>], size: u32) -> Image {
    let mut im = Image::new(size, size);
    for (i, f) in faces.iter().enumerate() {
        im.set(
            i as u32 % size,
            i as u32 / size,
            f.map_or([0, 0, 0], |f| FACE_COLOURS[f]),
        );
    }
    im
}

/// The failure maps' legend, naming only the kinds in `drawn`.
pub fn failure_legend(drawn: &[OutcomeKind]) -> String {
    let mut s = String::from("failure maps (rings over the dimmed view): ");
    if drawn.is_empty() {
        s += "no wrong ray";
    }
    let kinds: Vec<String> = OutcomeKind::ALL
        .iter()
        .filter(|k| drawn.contains(k))
        .map(|k| format!("{} rgb{:?}", k.wrong(), k.colour()))
        .collect();
    s + &kinds.join("; ") + "\n"
}

/// The predicate maps' legend, in words.
pub fn predicate_legend() -> String {
    key_line("predicate maps", &predicate_key())
}

/// The heat maps' legend.
pub const HEAT_LEGEND: &str = "heat maps: tetrahedra traversed by the exact walk, black (few) to yellow (most); the scale on the right is labelled with the fewest and the most\n";

/// What an octree heat map shows.
pub const OCTREE_HEAT_LEGEND: &str = "octree heat maps: seed 001's octree cells visited per pixel, black (few) to yellow (most); the scale on the right is labelled with the fewest and the most\n";
