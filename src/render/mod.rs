//! Pictures: shaded renders, per-method failure maps, traversal heat maps and predicate maps, from
//! integer per-pixel data (which the golden tests snapshot) to deterministic PNGs.

use crate::cases::{Case, answer, classify};
use crate::mesh::{HULL, Mesh, bounds};
use crate::methods::{Method, by_name};
use crate::report::count::{judge, view};
use crate::scenes::tets::ulps;
use crate::tet::Ray;
use crate::walk::{Outcome, Walk, default_max_steps, locate};
use rayon::prelude::*;

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

    /// Images side by side, `gap` pixels of white between them.
    pub fn sheet(images: &[Image], gap: u32) -> Image {
        let w = images
            .iter()
            .map(|i| i.width + gap)
            .sum::<u32>()
            .saturating_sub(gap);
        let h = images.iter().map(|i| i.height).max().unwrap_or(0);
        let mut out = Image {
            width: w,
            height: h,
            rgb: vec![255; (w * h * 3) as usize],
        };
        let mut x0 = 0;
        for im in images {
            for y in 0..im.height {
                for x in 0..im.width {
                    let i = ((y * im.width + x) * 3) as usize;
                    out.set(x0 + x, y, [im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]]);
                }
            }
            x0 += im.width + gap;
        }
        out
    }

    /// PNG bytes, with the encoder's settings pinned so the bytes are the same on every run.
    pub fn png(&self) -> Vec<u8> {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Balanced);
        enc.set_filter(png::Filter::NoFilter);
        let mut w = enc.write_header().expect("in-memory PNG header");
        w.write_image_data(&self.rgb).expect("in-memory PNG data");
        w.finish().expect("in-memory PNG end");
        out
    }
}

/// Colours of the failure kinds (wrong face, false miss, no exit face, cycle, step limit).
pub const KIND_COLOURS: [[u8; 3]; 5] = [
    [230, 30, 30],
    [250, 200, 0],
    [30, 120, 255],
    [200, 0, 200],
    [0, 200, 200],
];
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
    /// Per method, per pixel: the kind of wrong (index into [`crate::report::count::KINDS`]) or none.
    pub wrong: Vec<(String, Vec<Option<usize>>)>,
    /// Shading of the exact hit: `|n · d|` in 0..=255, and whether it is a box (hull) face.
    pub shade: Vec<(u8, bool)>,
}

/// Render view `view` of `views` (as `tetwalk count` places them) with the exact walk and `methods`.
pub fn frame(
    mesh: &Mesh,
    view_index: usize,
    views: usize,
    width: u32,
    height: u32,
    methods: &[&Method],
    fma: bool,
) -> Result<Frame, String> {
    let (lo, hi) = bounds(&mesh.points);
    let cam = view(
        lo,
        hi,
        view_index,
        views,
        1,
        40.0,
        width as f32 / height as f32,
    );
    let start = locate(mesh, cam.eye, 0).map_err(|e| e.to_string())?;
    let max = default_max_steps(mesh);
    let rays: Vec<Ray> = (0..height)
        .flat_map(|y| (0..width).map(move |x| cam.ray(x, y, width, height)))
        .collect();
    let exact_m = by_name("exact").expect("registered");
    let exact: Vec<Walk> = rays
        .par_iter()
        .map(|r| exact_m.walk(false)(mesh, r, start, max))
        .collect();
    let wrong = methods
        .iter()
        .map(|m| {
            let w: Vec<Option<usize>> = rays
                .par_iter()
                .zip(&exact)
                .map(|(r, re)| judge(mesh, r, &m.walk(fma)(mesh, r, start, max), re))
                .collect();
            (m.name.to_string(), w)
        })
        .collect();
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
        width,
        height,
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

    /// The shaded render with `method`'s wrong rays coloured by kind ([`KIND_COLOURS`]).
    pub fn failures(&self, method: usize) -> Image {
        let mut im = self.shaded();
        for (i, k) in self.wrong[method].1.iter().enumerate() {
            if let Some(k) = k {
                im.set(
                    i as u32 % self.width,
                    i as u32 / self.width,
                    KIND_COLOURS[*k],
                );
            }
        }
        im
    }

    /// Tetrahedra traversed per pixel by the exact walk, black (few) to yellow (most).
    pub fn heat(&self) -> Image {
        let mut im = Image::new(self.width, self.height);
        let most = self.exact.iter().map(|w| w.steps).max().unwrap_or(1).max(1) as f32;
        for (i, w) in self.exact.iter().enumerate() {
            let t = (w.steps as f32 / most).sqrt();
            let c = [
                (255.0 * t.min(1.0)) as u8,
                (255.0 * (t * t)) as u8,
                (120.0 * (1.0 - t)) as u8,
            ];
            im.set(i as u32 % self.width, i as u32 / self.width, c);
        }
        im
    }
}

/// Exit faces of a batch of cases, from whichever backend.
pub type FacesOf<'a> = dyn Fn(&[Case]) -> Result<Vec<Option<usize>>, String> + Sync + 'a;

/// A predicate map (after Kettner et al.'s classroom examples): the case's origin moved on a
/// `size × size` grid of ulp steps in x and y around itself, each pixel the exit face `face_of` gives.
pub fn predicate_grid(
    case: &Case,
    size: u32,
    face_of: &FacesOf<'_>,
) -> Result<Vec<Option<usize>>, String> {
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
    face_of(&cases)
}

/// The exact exit face of every grid case (ties broken as the `exact` method does).
pub fn exact_faces(cases: &[Case]) -> Result<Vec<Option<usize>>, String> {
    let m = by_name("exact").expect("registered");
    Ok(cases
        .par_iter()
        .map(|c| classify(c).ok().and_then(|_| answer(c, m, false)))
        .collect())
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

/// The legend, as text beside the images.
pub fn legend() -> String {
    let kinds = crate::report::count::KINDS;
    let mut s = String::from("failure maps: ");
    for (k, c) in kinds.iter().zip(KIND_COLOURS) {
        s += &format!("{k} rgb{c:?}; ");
    }
    s += "\npredicate maps: ";
    for (f, c) in FACE_COLOURS.iter().enumerate() {
        s += &format!("face {f} rgb{c:?}; ");
    }
    s + "no exit face black\nheat maps: tetrahedra traversed, black (few) to yellow (most)\n"
}
