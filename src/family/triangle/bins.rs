//! The triangle count's spatial structure: for one view, the candidate triangles of each tile of
//! pixels (a packet's, at least [`MIN_TILE`]²) — every triangle that any registered ray–triangle method, in any arithmetic model
//! (plain, fused, flushed to zero), could report hit by a primary ray of that tile. Testing only those,
//! in ascending order, gives each ray exactly the brute-force nearest hit. Why none is dropped:
//!
//! **Lemma (every method's hit is near its triangle's cone).** Let `o` be the ray's origin, `d` its
//! direction, `w_k = v_k - o` the triangle's vertices seen from `o`, `R = max |w_k|`, and the side
//! products `s_0 = d·(w_0×w_1)`, `s_1 = d·(w_1×w_2)`, `s_2 = d·(w_2×w_0)` (exact, of the f32 inputs;
//! they sum to `d·N`). Each method's hit that counts (`0 < t < ∞`) needs three computed quantities
//! of one sign `σ` whose exact values are `s_0, s_1, s_2` times one positive factor:
//! - `mt`, `mt-two-sided`: `u = T·(D×E2) = -s_2`, `v = D·(T×E1) = -s_0`, `det - u - v = -s_1`, tested
//!   as `u ≥ 0`, `v ≥ 0`, `u + v ≤ det` (times `1/det` in the two-sided reading, where `det ≠ 0` and a
//!   finite `t` are needed: `1/0 = ±∞` makes `t` infinite or NaN);
//! - `mt-precomputed`, `komatsu-packet`: the same `u`, `v` from `D × S` or `S × E1`, `S × E2`, times
//!   `r = -1/(N·D)`, tested `u ≥ 0`, `v ≥ 0`, `u + v ≤ 1`;
//! - `plucker-packet`: `D·(a'×b')` for the three edges, all `≥ 0` or all `≤ 0`;
//! - `woop-watertight`: `U, V, W`, which are `s_1, s_2, s_0` for the sheared direction `(S_x, S_y, 1)`
//!   divided by `d_kz` (`|d_kz| ≥ |d|/√3`, `|S| ≤ 1`), all of one sign, recomputed in f64 when one is 0.
//!
//! Forward error, term by term (`u = 2^-24`, `γ_n = nu/(1-nu)`), for inputs and results in the normal
//! range: a difference of inputs (1 rounding, relative to the difference), a cross product (2), a dot
//! product (3) give `γ_6` times the sum of the absolute terms, and a triple product's absolute terms
//! sum to at most `‖a‖₁‖b‖₁‖c‖₁ ≤ 3√3 |a||b||c|`. Let `L` be the longest edge (`L ≤ 2R`).
//! - Möller–Trumbore's forms ([`SideError::EdgeScaled`]): `|T|, |S| ≤ R`, `|E1|, |E2| ≤ L`, so `u`,
//!   `v` err by at most `γ_6·5.2|d|RL`, `det = N·D` by `γ_6·5.2|d|L² ≤ γ_6·10.4|d|RL`, and
//!   `det - u - v` (with `fl(u + v)`, or `u + v ≤ 1` after `1/det`: 5 more roundings of at most
//!   `|det|`) by at most `177u|d|RL`.
//! - The Plücker packet test and Woop's ([`SideError::OriginScaled`]): their terms are the vertices
//!   seen from the origin, `|a'|, |b'| ≤ R`, whatever the edge. Plücker: `a' = fl(v - o)` errs by `uR`
//!   a component, `a'×b'` then by `8uR²` a component (inputs `4uR²`, products `2uR²`, difference
//!   `2uR²`), `D·(a'×b')` by `√3·8u|d|R² + 3u·√3|d|R² ≤ 20u|d|R²`. Woop: `A = fl(v - o)` (`uR`),
//!   the shear `A_x - S_x A_z` with `|S_x| ≤ 1` and `S_x` itself rounded errs by `6uR` and is at most
//!   `2R`, so `U = C_x B_y - C_y B_x` errs by `4·6uR·2R + 16uR² = 64uR²` against the exact shear, where
//!   `U = s/d_kz`: times `|d_kz| ≤ |d|` that is `64u|d|R²` on the side products' scale; the f64
//!   recomputation when one is 0 errs less.
//!
//! A fused multiply-add rounds once where two were counted, so the same bounds hold with `--fma`.
//! Underflow: gradual underflow adds at most `2^-150` per product, flushing to zero `2^-126` per
//! input or result (a zero keeps `u ≥ 0` true for a negative `u` only below `2^-126 |det|`, inside the
//! relative bound); each is multiplied by at most two other factors `≤ 1 + 2R + |d|`, and there are
//! fewer than 64, so all of them add at most `η = 2^-118 (1 + 2R + |d|)²`. Overflow: when
//! `(1 + 2R + |d|)³ ≤ 2^120` no product of three factors, nor a sum of six, overflows, and no NaN
//! arises before `t`; beyond that no bound is claimed. So, with `Λ = L` and `K = 2^-14 ≥ 177u`
//! (edge-scaled) or `Λ = R` and `K = 2^-16 ≥ 64u` (origin-scaled), each about 4× its need:
//!
//! > a counted hit implies `σ s_i ≥ -(K |d| R Λ + η)` for `i = 0, 1, 2` and one `σ ∈ {+1, -1}`.
//!
//! **Bins.** A primary ray is `d = fl(F + Rt·sx + Up·sy)` ([`Camera::ray`]); exactly,
//! `ι = F + Rt·sx + Up·sy` with `|d - ι| ≤ γ_3 (|F| + |Rt| + |Up|)` (`|sx|, |sy| < 1`), so
//! `s_i(d) = L_i(sx, sy) + e` with `L_i = m_i·F + sx m_i·Rt + sy m_i·Up` (`m_i` the edge moment above,
//! `|m_i| ≤ R L`) and `|e| ≤ γ_3 D R L`, `D = (1 + γ_3)(|F| + |Rt| + |Up|) ≥ |d|`. Over a tile's
//! rectangle of `(sx, sy)` a linear `σL_i` is at most its value at the centre plus `|m_i·Rt|·half
//! width + |m_i·Up|·half height`, exactly; computed in f64 from f32 inputs, every term errs by under
//! `2^-46 D R²` (their sum's coefficients, added in f64, by under `2^-44 D R²`). A tile is left out for
//! `σ` when the sum's maximum is below `-3B`, or some `i` has that maximum below
//! `-B = -((K + 2^-20) D R Λ + 2^-40 D R² + η)`, which exceeds `K D R Λ + γ_3 D R L + 2^-46 D R² + η`
//! (`L ≤ 2Λ` for both scales and `γ_3 ≤ 2^-22`, so `γ_3 D R L ≤ 2^-21 D R Λ`; `L` is taken from the
//! f32 vertices' differences in f64, each rounded once, and enlarged by `10^-12`): no ray of the tile
//! can satisfy the lemma, so no method of that error scale reports the triangle there. A triangle is binned by halving
//! the image's tiles from the whole down to one, once for both error scales: a sign and scale left
//! out of a rectangle are left out of every rectangle inside it (its maxima are no larger), and a
//! scale whose every ray may meet the lemma keeps every tile inside; one whose `1 + 2R + D` exceeds
//! `2^40` goes in every tile. Methods written outside tetwalk have no such lemma: the count tests every triangle for them.

use crate::methods::triangle::{Among, SideError, Tri};
use crate::scenes::camera::Camera;
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Fewest pixels per tile side: each tile's rays share one list of candidates.
pub(crate) const MIN_TILE: u32 = 2;

/// The lemma's `K` for an error scale (module doc).
fn k(scale: SideError) -> f64 {
    match scale {
        SideError::EdgeScaled => 1.0 / (1u64 << 14) as f64,
        SideError::OriginScaled => 1.0 / (1u64 << 16) as f64,
    }
}
/// Covers the pixel directions' rounding, `2^-20` of `D R Λ` (module doc).
const PIXEL_SLACK: f64 = 1.0 / (1u64 << 20) as f64;
/// Covers f64's rounding of the edge moments and the bounds, `2^-40` of `D R²`.
const F64_SLACK: f64 = 1.0 / (1u64 << 40) as f64;
/// The underflow term's factor, `2^-118`.
const ETA: f64 = 1.0 / (1u128 << 118) as f64;
/// Beyond this `1 + 2R + D` the lemma claims nothing (`2^40`).
const LIMIT: f64 = (1u64 << 40) as f64;

/// Triangles binned per task (small enough for the tasks to even out between threads).
const CHUNK: usize = 64;

/// One view's candidate triangles per tile of `tile²` pixels, tiles row by row (`tiles_x × tiles_y`).
pub struct Bins {
    pub(crate) tile: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// `ids[start[k]..start[k + 1]]`: tile `k`'s triangles, ascending.
    pub(crate) start: Vec<usize>,
    pub ids: Vec<u32>,
}

impl Bins {
    /// Tile `k`'s candidate triangles, ascending.
    pub fn of_tile(&self, k: usize) -> &[u32] {
        &self.ids[self.start[k]..self.start[k + 1]]
    }

    /// The rays of a `width × height` view in [`packet_order`](crate::scenes::camera::packet_order)
    /// with these tiles, each tile's run of rays with its candidates.
    pub(crate) fn among(self, width: u32, height: u32) -> Among {
        let mut groups = Vec::with_capacity(self.start.len() - 1);
        let mut first = 0;
        for ty in 0..self.tiles_y {
            for tx in 0..self.tiles_x {
                let w = (width - tx * self.tile).min(self.tile) as usize;
                let h = (height - ty * self.tile).min(self.tile) as usize;
                let k = (ty * self.tiles_x + tx) as usize;
                groups.push((first..first + w * h, self.start[k]..self.start[k + 1]));
                first += w * h;
            }
        }
        Among {
            ids: self.ids,
            groups,
        }
    }
}

/// The index of the tile of `tile²` pixels holding pixel `(x, y)` of a view `width` wide, tiles row
/// by row ([`Bins::of_tile`], and [`Bins::among`]'s groups in that order).
pub fn tile_of(x: u32, y: u32, width: u32, tile: u32) -> usize {
    ((y / tile) * width.div_ceil(tile) + x / tile) as usize
}

/// The error scales, in the order `Reach::bounds` and [`ByScale`] keep them.
pub(crate) const SCALES: [SideError; 2] = [SideError::EdgeScaled, SideError::OriginScaled];

/// A triangle's three linear side-product functions on the screen, `c + a·sx + b·sy`, their sum
/// (`d·N`: where all three are at least `-B` it is at least `-3B`, a bound one line alone can prove
/// of a whole rectangle near the triangle, for the sign it does not face), and for each error scale
/// ([`SCALES`]) the bound `B` below which a tile is left out; `None` where the lemma claims nothing
/// (in every tile).
struct Reach {
    lines: [[f64; 3]; 3],
    sum: [f64; 3],
    bounds: [f64; 2],
}

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

impl Reach {
    fn of(tri: &Tri, eye: Vec3, axes: &[DVec3; 3], big_d: f64) -> Option<Reach> {
        let w = tri.map(|v| d(v) - d(eye));
        let r = w.iter().map(|x| x.length()).fold(0.0, f64::max) * (1.0 + 1e-12);
        let lambda = |scale| match scale {
            SideError::OriginScaled => r,
            SideError::EdgeScaled => {
                let [a, b, c] = tri.map(d);
                [b - a, c - b, a - c]
                    .iter()
                    .map(|x| x.length())
                    .fold(0.0, f64::max)
                    * (1.0 + 1e-12)
            }
        };
        let size = 1.0 + 2.0 * r + big_d;
        if size.is_nan() || size > LIMIT {
            return None;
        }
        let m = [w[0].cross(w[1]), w[1].cross(w[2]), w[2].cross(w[0])];
        let [f, rt, up] = axes;
        let lines = m.map(|m| [m.dot(*f), m.dot(*rt), m.dot(*up)]);
        Some(Reach {
            lines,
            sum: std::array::from_fn(|k| lines[0][k] + lines[1][k] + lines[2][k]),
            bounds: SCALES.map(|scale| {
                (k(scale) + PIXEL_SLACK) * big_d * r * lambda(scale)
                    + F64_SLACK * big_d * r * r
                    + ETA * size * size
            }),
        })
    }

    /// For the rays in `sx ∈ [x0, x1]`, `sy ∈ [y0, y1]`, for each sign `σ` and error scale whose bit
    /// ([`bit`]) is set in `open`: whether some may meet the lemma (first mask: a bit left unset stays
    /// unset in every smaller rectangle), and whether every one may (second mask: then every tile
    /// inside is a candidate).
    fn reach(&self, open: u8, x0: f64, x1: f64, y0: f64, y1: f64) -> (u8, u8) {
        let (cx, cy, hx, hy) = (
            (x0 + x1) * 0.5,
            (y0 + y1) * 0.5,
            (x1 - x0) * 0.5,
            (y1 - y0) * 0.5,
        );
        let range = |[c, a, b]: [f64; 3]| (c + a * cx + b * cy, a.abs() * hx + b.abs() * hy);
        let (lines, sum) = (self.lines.map(range), range(self.sum));
        let (mut some, mut every) = (0, 0);
        for (i, sigma) in [1.0, -1.0].into_iter().enumerate() {
            if open & (bit(i, 0) | bit(i, 1)) == 0 {
                continue;
            }
            // Each line's maximum and minimum over the rectangle for this sign; a NaN keeps the tile
            // and claims nothing of every ray.
            let high = |(mid, spread): (f64, f64)| {
                let h: f64 = sigma * mid + spread;
                if h.is_nan() { f64::INFINITY } else { h }
            };
            let highest = lines.iter().map(|&l| high(l)).fold(f64::INFINITY, f64::min);
            let low = |(mid, spread): (f64, f64)| {
                let l: f64 = sigma * mid - spread;
                if l.is_nan() { f64::NEG_INFINITY } else { l }
            };
            let lowest = lines.iter().map(|&l| low(l)).fold(f64::INFINITY, f64::min);
            let summed = high(sum);
            for (k, &bound) in self.bounds.iter().enumerate() {
                let b = bit(i, k) & open;
                if highest >= -bound && summed >= -3.0 * bound {
                    some |= b;
                }
                if lowest >= bound {
                    every |= b;
                }
            }
        }
        (some, every)
    }
}

/// The bit of sign `σ` (`i`: 0 for `+1`, 1 for `-1`) and error scale `k` ([`SCALES`]) in
/// [`Reach::reach`]'s masks.
const fn bit(i: usize, k: usize) -> u8 {
    1 << (2 * k + i)
}

/// The bits of error scale `k`, both signs.
const fn of_scale(k: usize) -> u8 {
    bit(0, k) | bit(1, k)
}

/// One view's candidates (or their rays' [`Among`]) for each error scale, in [`SCALES`] order.
pub struct ByScale<T = Bins>([T; 2]);

impl<T> ByScale<T> {
    /// The candidates of methods of error scale `scale`.
    pub fn get(&self, scale: SideError) -> &T {
        &self.0[SCALES
            .iter()
            .position(|&s| s == scale)
            .expect("every scale")]
    }

    /// Each scale with its candidates.
    pub fn into_pairs(self) -> [(SideError, T); 2] {
        let ([a, b], [sa, sb]) = (self.0, SCALES);
        [(sa, a), (sb, b)]
    }
}

impl ByScale {
    /// The rays of a `width × height` view and their candidates, for each scale ([`Bins::among`]).
    pub fn among(self, width: u32, height: u32) -> ByScale<Among> {
        ByScale(self.0.map(|b| b.among(width, height)))
    }
}

/// The candidate triangles of each tile of a `width × height` view from `cam`, for methods of each
/// error scale (module doc), from one descent per triangle.
pub fn bins(cam: &Camera, width: u32, height: u32, tile: u32, tris: &[Tri]) -> ByScale {
    let (tiles_x, tiles_y) = (width.div_ceil(tile), height.div_ceil(tile));
    let sx: Vec<f64> = (0..width)
        .map(|x| Camera::screen(x, 0, width, height).0 as f64)
        .collect();
    let sy: Vec<f64> = (0..height)
        .map(|y| Camera::screen(0, y, width, height).1 as f64)
        .collect();
    let axes = cam.axes().map(d);
    let gamma3 = 3.0 * f64::from(f32::EPSILON) * 0.5 / (1.0 - 1.5 * f64::from(f32::EPSILON));
    let big_d = (1.0 + gamma3) * axes.iter().map(|a| a.length()).sum::<f64>() * (1.0 + 1e-12);
    let every_bit = (1u8 << (2 * SCALES.len())) - 1;
    let scales_of = |bits: u8| {
        (0..SCALES.len())
            .filter(|&k| bits & of_scale(k) != 0)
            .fold(0u8, |m, k| m | 1 << k)
    };
    let all = scales_of(every_bit);
    // (scales, tile, triangle) triples, triangles ascending within each chunk and chunks in order.
    let triples: Vec<(u8, u32, u32)> = tris
        .par_chunks(CHUNK)
        .enumerate()
        .flat_map_iter(|(c, chunk)| {
            let (mut out, mut stack) = (Vec::new(), Vec::new());
            for (k, tri) in chunk.iter().enumerate() {
                let id = (c * CHUNK + k) as u32;
                match Reach::of(tri, cam.eye, &axes, big_d) {
                    None => out.extend((0..tiles_x * tiles_y).map(|t| (all, t, id))),
                    Some(reach) => {
                        stack.clear();
                        stack.push((every_bit, 0, tiles_x, 0, tiles_y));
                        while let Some((open, tx0, tx1, ty0, ty1)) = stack.pop() {
                            // Pixel columns and rows the tiles cover; sy falls as rows go down.
                            let (x0, x1) = (tx0 * tile, (tx1 * tile).min(width) - 1);
                            let (y0, y1) = (ty0 * tile, (ty1 * tile).min(height) - 1);
                            let (a, b) = (sx[x0 as usize], sx[x1 as usize]);
                            let (lo, hi) = (sy[y1 as usize], sy[y0 as usize]);
                            let (some, every) = reach.reach(open, a, b, lo, hi);
                            // The scales for which every tile of the rectangle is a candidate.
                            let one = tx1 - tx0 == 1 && ty1 - ty0 == 1;
                            let whole = scales_of(if one { some } else { every });
                            if whole != 0 {
                                for ty in ty0..ty1 {
                                    out.extend((tx0..tx1).map(|tx| (whole, ty * tiles_x + tx, id)));
                                }
                            }
                            let open = (0..SCALES.len())
                                .filter(|&k| whole & 1 << k == 0)
                                .fold(0, |m, k| m | some & of_scale(k));
                            if open == 0 {
                                continue;
                            }
                            if tx1 - tx0 >= ty1 - ty0 {
                                let mid = (tx0 + tx1) / 2;
                                stack.push((open, tx0, mid, ty0, ty1));
                                stack.push((open, mid, tx1, ty0, ty1));
                            } else {
                                let mid = (ty0 + ty1) / 2;
                                stack.push((open, tx0, tx1, ty0, mid));
                                stack.push((open, tx0, tx1, mid, ty1));
                            }
                        }
                    }
                }
            }
            out
        })
        .collect();
    ByScale(std::array::from_fn(|k| {
        sorted(
            tile,
            tiles_x,
            tiles_y,
            triples.iter().filter(|t| t.0 & (1 << k) != 0),
        )
    }))
}

/// The bins of these (scales, tile, triangle) triples, triangles ascending within each tile as they
/// come.
fn sorted<'a>(
    tile: u32,
    tiles_x: u32,
    tiles_y: u32,
    triples: impl Iterator<Item = &'a (u8, u32, u32)> + Clone,
) -> Bins {
    // A counting sort by tile, stable: each tile's triangles stay ascending.
    let mut start = vec![0; (tiles_x * tiles_y) as usize + 1];
    for &(_, t, _) in triples.clone() {
        start[t as usize + 1] += 1;
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    let mut next = start.clone();
    let mut ids = vec![0; start[start.len() - 1]];
    for &(_, t, id) in triples {
        ids[next[t as usize]] = id;
        next[t as usize] += 1;
    }
    Bins {
        tile,
        tiles_x,
        tiles_y,
        start,
        ids,
    }
}
