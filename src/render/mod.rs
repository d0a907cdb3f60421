//! Pictures: shaded renders, per-method failure maps, traversal heat maps, predicate and leak maps,
//! from integer per-pixel data that runs returned (which the golden tests snapshot) to deterministic
//! PNGs. Formatting only: the views are walked and judged by the families' engines.

pub mod text;

use crate::backend::Backend;
use crate::engine::view::Frame;
use crate::walk::OutcomeKind;

/// Why a picture could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
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
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) rgb: Vec<u8>,
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
    pub(crate) fn set_clipped(&mut self, x: u32, y: u32, c: [u8; 3]) {
        if x < self.width && y < self.height {
            self.set(x, y, c);
        }
    }

    /// Pixel `(x, y)` marked to be seen at any scale the image is shown: the pixel itself and a ring
    /// around it (radius a fortieth of the image's smaller side, at least 3), in `c`, clipped.
    pub(crate) fn ring(&mut self, x: u32, y: u32, c: [u8; 3]) {
        let r = (self.width.min(self.height) / 40).max(3) as i64;
        let (cx, cy) = (x as i64, y as i64);
        for dy in -r - 1..=r + 1 {
            for dx in -r - 1..=r + 1 {
                let d2 = dx * dx + dy * dy;
                let ring = d2 <= (r + 1) * (r + 1) && d2 >= (r - 1) * (r - 1);
                let (x, y) = (cx + dx, cy + dy);
                if (ring || d2 == 0) && x >= 0 && y >= 0 {
                    self.set_clipped(x as u32, y as u32, c);
                }
            }
        }
    }

    /// `im` copied in with its top-left corner at `(x0, y0)` (what falls outside is left out).
    pub(crate) fn paste(&mut self, im: &Image, x0: u32, y0: u32) {
        for y in 0..im.height {
            for x in 0..im.width {
                let i = ((y * im.width + x) * 3) as usize;
                self.set_clipped(x0 + x, y0 + y, [im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]]);
            }
        }
    }

    /// A scale for markers and labels: 1 up to 256 pixels on the short side, then one more per 256.
    pub(crate) fn scale(&self) -> u32 {
        (self.width.min(self.height) / 256).max(1)
    }

    /// Images side by side, `gap` pixels of white between them.
    pub fn sheet(images: &[Image], gap: u32) -> Image {
        Image::arranged(images, gap, true)
    }

    /// Images in rows of as many as make the grid about square (`ceil(sqrt(n))` to a row), left to
    /// right then top to bottom, `gap` pixels of white between them.
    pub fn tiled(images: &[Image], gap: u32) -> Image {
        let across = (images.len() as f64).sqrt().ceil().max(1.0) as usize;
        let rows: Vec<Image> = images
            .chunks(across)
            .map(|row| Image::sheet(row, gap))
            .collect();
        Image::arranged(&rows, gap, false)
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
pub(crate) fn titled(im: &Image, title: &str) -> Image {
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
pub(crate) fn stacked(images: &[Image], gap: u32) -> Image {
    Image::arranged(images, gap, false)
}

/// A legend `width` pixels wide (at least its widest entry): for each entry a swatch of its colour
/// (outlined, so that black shows) and its words, as many to a line as fit.
pub(crate) fn legend(entries: &[(&str, [u8; 3])], width: u32, scale: u32) -> Image {
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
pub(crate) fn sheet(heading: &str, panels: &[(String, Image)], key: &[(&str, [u8; 3])]) -> Image {
    let row: Vec<Image> = panels.iter().map(|(t, im)| titled(im, t)).collect();
    let row = Image::sheet(&row, 4);
    let scale = row.scale();
    stacked(&[titled(&row, heading), legend(key, row.width, scale)], 0)
}

/// A panel's title for a backend: its kind, and a GPU's adapter up to its first parenthesis.
pub(crate) fn backend_title(b: &Backend) -> String {
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
pub(crate) const FACE_COLOURS: [[u8; 3]; 4] =
    [[228, 26, 28], [55, 126, 184], [77, 175, 74], [255, 127, 0]];

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
        let (name, wrong) = &self.wrong[method];
        for (i, k) in wrong.iter().enumerate() {
            let Some(k) = k else { continue };
            im.ring(i as u32 % self.width, i as u32 / self.width, k.colour());
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
pub(crate) fn heat_map(width: u32, height: u32, counts: &[u32], title: &str) -> Image {
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

/// Seed 001's octree cells visited per pixel by octree method `method` ([`heat_map`]).
pub fn octree_heat(width: u32, height: u32, cells: &[u32], method: &str) -> Image {
    heat_map(
        width,
        height,
        cells,
        &format!("octree cells per pixel ({method})"),
    )
}

/// The predicate maps' key: each face's colour, black for none.
pub(crate) fn predicate_key() -> Vec<(&'static str, [u8; 3])> {
    const FACES: [&str; 4] = ["face 0", "face 1", "face 2", "face 3"];
    FACES
        .iter()
        .zip(FACE_COLOURS)
        .map(|(f, c)| (*f, c))
        .chain([("no exit face", [0, 0, 0])])
        .collect()
}

/// A key in words, for standard output: `name: words rgb(…); …`.
pub(crate) fn key_line(name: &str, key: &[(&str, [u8; 3])]) -> String {
    let parts: Vec<String> = key.iter().map(|(w, c)| format!("{w} rgb{c:?}")).collect();
    format!("{name}: {}\n", parts.join("; "))
}

/// A grid of faces as an image ([`FACE_COLOURS`], black for none).
pub fn face_image(faces: &[Option<usize>], size: u32) -> Image {
    grid_image(
        size,
        faces
            .iter()
            .map(|f| f.map_or([0, 0, 0], |f| FACE_COLOURS[f])),
    )
}

/// A `size × size` grid of cells (row-major) as an image, each cell its colour.
pub fn grid_image(size: u32, colours: impl Iterator<Item = [u8; 3]>) -> Image {
    let mut im = Image::new(size, size);
    for (i, c) in colours.enumerate() {
        im.set(i as u32 % size, i as u32 / size, c);
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
pub(crate) fn predicate_legend() -> String {
    key_line("predicate maps", &predicate_key())
}

/// The heat maps' legend.
pub(crate) const HEAT_LEGEND: &str = "heat maps: tetrahedra traversed by the exact walk, black (few) to yellow (most); the scale on the right is labelled with the fewest and the most\n";

/// What an octree heat map shows.
pub(crate) const OCTREE_HEAT_LEGEND: &str = "octree heat maps: seed 001's octree cells visited per pixel, black (few) to yellow (most); the scale on the right is labelled with the fewest and the most\n";

#[cfg(test)]
mod tests {
    use super::Image;

    /// Ten failure maps of 512² make a sheet four to a row (2,060 px wide, three rows), not one row
    /// 5,156 px wide; a ring marks a pixel at a fortieth of the side around it.
    #[test]
    fn a_sheet_is_tiled_about_square_and_a_ring_shows() {
        let maps = vec![Image::new(512, 512); 10];
        let sheet = Image::tiled(&maps, 4);
        assert_eq!(
            (sheet.width, sheet.height),
            (4 * 512 + 3 * 4, 3 * 512 + 2 * 4)
        );
        let mut im = Image::new(512, 512);
        im.ring(100, 200, [255, 0, 0]);
        let at = |x: u32, y: u32| {
            let i = ((y * 512 + x) * 3) as usize;
            [im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]]
        };
        assert_eq!(at(100, 200), [255, 0, 0]);
        assert_eq!(at(100 + 12, 200), [255, 0, 0]);
        assert_eq!(at(100, 200 - 12), [255, 0, 0]);
        assert_ne!(at(100 + 6, 200), [255, 0, 0]);
    }
}
