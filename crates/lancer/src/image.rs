//! In-memory images: linear float texels, for textures and environment maps.

use crate::math::{PackedRgb, Rgb, Vec2};

/// How image lookups outside [0, 1] behave (pbrt's `wrap`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum WrapMode {
    /// Tile the image.
    #[default]
    Repeat,
    /// Clamp to the edge texel.
    Clamp,
    /// Black outside.
    Black,
    /// Mirror every other tile.
    Mirror,
    /// pbrt's `octahedralsphere`: the neighbours of an equal-area octahedral map's edge texels
    /// are the texels that touch them on the sphere (mirrored across the edge's midpoint).
    OctahedralSphere,
}

impl WrapMode {
    /// Every mode.
    pub const ALL: [WrapMode; 5] = [
        WrapMode::Repeat,
        WrapMode::Clamp,
        WrapMode::Black,
        WrapMode::Mirror,
        WrapMode::OctahedralSphere,
    ];
}

/// A linear RGB image, row 0 at the top, stored row-major as `width × height` texels.
#[derive(Clone, PartialEq)]
pub struct Image {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels, `y·width + x` (packed: 12 bytes a texel).
    pub texels: Vec<PackedRgb>,
}

impl std::fmt::Debug for Image {
    /// The texels as their count and digest ([`Digest`](crate::math::digest::Digest)).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Image")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("texels", &crate::math::digest::Digest(&self.texels))
            .finish()
    }
}

impl Image {
    /// Bytes of the texels (capacity included).
    pub fn memory_bytes(&self) -> usize {
        self.texels.capacity() * std::mem::size_of::<PackedRgb>()
    }

    /// An image from its texels; `None` if the sizes disagree or the image is empty.
    pub fn new(width: u32, height: u32, texels: Vec<PackedRgb>) -> Option<Image> {
        (width > 0 && height > 0 && texels.len() == width as usize * height as usize).then_some(
            Image {
                width,
                height,
                texels,
            },
        )
    }

    /// The texel at integer coordinates, with the wrap mode applied.
    pub fn texel(&self, x: i64, y: i64, wrap: WrapMode) -> Rgb {
        texel_in(self.width, self.height, x, y, wrap, |i| {
            self.texels[i].into()
        })
    }

    /// Bilinear (or nearest) lookup at texture coordinates `st`, where (0, 0) is the image's
    /// bottom-left corner and (1, 1) its top-right (pbrt's convention: v grows upwards).
    pub fn lookup(&self, st: Vec2, wrap: WrapMode, nearest: bool) -> Rgb {
        lookup_in(self.width, self.height, st, wrap, nearest, |i| {
            self.texels[i].into()
        })
    }
}

/// [`Image::texel`] for any storage of a `width × height` image: `fetch(y·width + x)` gives
/// the texel at (x, y) inside the image.
#[inline(always)]
pub fn texel_in(
    width: u32,
    height: u32,
    x: i64,
    y: i64,
    wrap: WrapMode,
    fetch: impl Fn(usize) -> Rgb,
) -> Rgb {
    let (w, h) = (width as i64, height as i64);
    if wrap == WrapMode::OctahedralSphere {
        // pbrt-v4's rule for equal-area octahedral maps: a step off the left or right edge
        // comes back mirrored in x (about the edge texel, as pbrt writes it: x → −x or
        // 2w − 1 − x) and in y (y → h − 1 − y); off the top or bottom likewise with the
        // roles swapped. The square's edges meet their mirror images on the sphere.
        let (mut x, mut y) = (x, y);
        if x < 0 {
            (x, y) = (-x, h - 1 - y);
        } else if x >= w {
            (x, y) = (2 * w - 1 - x, h - 1 - y);
        }
        if y < 0 {
            (x, y) = (w - 1 - x, -y);
        } else if y >= h {
            (x, y) = (w - 1 - x, 2 * h - 1 - y);
        }
        // Further than one image away (or a 1-texel side) only clamping makes sense.
        let (x, y) = (x.clamp(0, w - 1), y.clamp(0, h - 1));
        return fetch((y * w + x) as usize);
    }
    match (wrap_coord(x, w, wrap), wrap_coord(y, h, wrap)) {
        (Some(x), Some(y)) => fetch((y * w + x) as usize),
        _ => Rgb::ZERO,
    }
}

/// [`Image::lookup`] for any storage of a `width × height` image (`fetch` as for
/// [`texel_in`]).
#[inline(always)]
pub fn lookup_in(
    width: u32,
    height: u32,
    st: Vec2,
    wrap: WrapMode,
    nearest: bool,
    fetch: impl Fn(usize) -> Rgb,
) -> Rgb {
    let x = st.x * width as f32 - 0.5;
    let y = (1.0 - st.y) * height as f32 - 0.5;
    if !x.is_finite() || !y.is_finite() {
        return Rgb::ZERO;
    }
    let texel = |x: i64, y: i64| texel_in(width, height, x, y, wrap, &fetch);
    if nearest {
        // pbrt-v4's point filter: the texel round(s·w − ½), halves rounded away from 0.
        return texel(x.round() as i64, y.round() as i64);
    }
    let (x0, y0) = (x.floor(), y.floor());
    let (dx, dy) = (x - x0, y - y0);
    let (xi, yi) = (x0 as i64, y0 as i64);
    if wrap == WrapMode::OctahedralSphere {
        // Its wrap mixes x and y: each neighbour is wrapped on its own.
        return (1.0 - dx) * (1.0 - dy) * texel(xi, yi)
            + dx * (1.0 - dy) * texel(xi + 1, yi)
            + (1.0 - dx) * dy * texel(xi, yi + 1)
            + dx * dy * texel(xi + 1, yi + 1);
    }
    // The other wraps act on x and y separately: two columns and two rows, wrapped once.
    let (w, h) = (width as i64, height as i64);
    let (cx0, cx1) = wrap_pair(xi, w, wrap);
    let (cy0, cy1) = wrap_pair(yi, h, wrap);
    let t = |x: Option<i64>, y: Option<i64>| -> Rgb {
        match (x, y) {
            (Some(x), Some(y)) => fetch((y * w + x) as usize),
            _ => Rgb::ZERO,
        }
    };
    (1.0 - dx) * (1.0 - dy) * t(cx0, cy0)
        + dx * (1.0 - dy) * t(cx1, cy0)
        + (1.0 - dx) * dy * t(cx0, cy1)
        + dx * dy * t(cx1, cy1)
}

/// Coordinates `v` and `v + 1` of an axis of `n` texels with `wrap` applied: when tiling,
/// v + 1 wraps to 0 past the last texel, (v + 1) mod n without a second division.
#[inline]
fn wrap_pair(v: i64, n: i64, wrap: WrapMode) -> (Option<i64>, Option<i64>) {
    if wrap == WrapMode::Repeat {
        let a = if (0..n).contains(&v) {
            v
        } else {
            v.rem_euclid(n)
        };
        return (Some(a), Some(if a + 1 == n { 0 } else { a + 1 }));
    }
    (wrap_coord(v, n, wrap), wrap_coord(v + 1, n, wrap))
}

/// Coordinate `v` of an axis of `n` texels with `wrap` applied (`None`: black). Coordinates
/// inside the image are returned as they are before any division: every mode leaves them
/// alone, and they are nearly all lookups.
#[inline]
fn wrap_coord(v: i64, n: i64, wrap: WrapMode) -> Option<i64> {
    if (0..n).contains(&v) {
        return Some(v);
    }
    match wrap {
        WrapMode::Repeat => Some(v.rem_euclid(n)),
        WrapMode::Clamp => Some(v.clamp(0, n - 1)),
        WrapMode::Black => None,
        WrapMode::Mirror => {
            let m = v.rem_euclid(2 * n);
            Some(if m < n { m } else { 2 * n - 1 - m })
        }
        // Handled by `Image::texel` before any per-axis wrap.
        WrapMode::OctahedralSphere => Some(v.clamp(0, n - 1)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×3 image whose texel (x, y) holds (x, y, 0).
    fn grid() -> Image {
        let texels = (0..9)
            .map(|i| PackedRgb::new((i % 3) as f32, (i / 3) as f32, 0.0))
            .collect();
        Image::new(3, 3, texels).unwrap()
    }

    #[test]
    fn octahedral_wrap_mirrors_as_pbrt_does() {
        let im = grid();
        let at = |x, y| {
            let t = im.texel(x, y, WrapMode::OctahedralSphere);
            (t.x as i64, t.y as i64)
        };
        assert_eq!(at(1, 1), (1, 1));
        // Off the left edge: x → −x, y → h − 1 − y.
        assert_eq!(at(-1, 0), (1, 2));
        // Off the right edge: x → 2w − 1 − x, y → h − 1 − y.
        assert_eq!(at(3, 1), (2, 1));
        assert_eq!(at(3, 0), (2, 2));
        // Off the top: x → w − 1 − x, y → −y; off the bottom: y → 2h − 1 − y.
        assert_eq!(at(0, -1), (2, 1));
        assert_eq!(at(0, 3), (2, 2));
    }

    #[test]
    fn lookups_flip_v_and_round_like_pbrt() {
        let im = grid();
        // (s, t) = (0.5, 0.5) is the centre texel; t = 1 − ε is the top row.
        let c = im.lookup(Vec2::new(0.5, 0.5), WrapMode::Clamp, false);
        assert!((c - Rgb::new(1.0, 1.0, 0.0)).abs().max_element() < 1e-6);
        let top = im.lookup(Vec2::new(1.0 / 6.0, 5.0 / 6.0), WrapMode::Clamp, true);
        assert_eq!(top, Rgb::new(0.0, 0.0, 0.0));
        // Bilinear half-way between texel columns 0 and 1 of the bottom row.
        let b = im.lookup(Vec2::new(1.0 / 3.0, 1.0 / 6.0), WrapMode::Clamp, false);
        assert!(
            (b - Rgb::new(0.5, 2.0, 0.0)).abs().max_element() < 1e-5,
            "{b}"
        );
        // Point sampling picks round(s·w − ½): s = 0.49/3 → round(−0.01) = 0.
        let p = im.lookup(Vec2::new(0.49 / 3.0, 0.5), WrapMode::Clamp, true);
        assert_eq!(p.x, 0.0);
    }

    #[test]
    fn bilinear_lookups_wrap_each_neighbour_as_texel_does() {
        // The lookup wraps a column pair and a row pair once; the result must be the bilinear
        // blend of the four texels `texel` returns, in every mode, inside and far outside.
        let im = grid();
        for wrap in WrapMode::ALL {
            for (s, t) in [
                (0.5, 0.5),
                (0.9, 0.05),
                (-1.3, 2.71),
                (4.99, -0.4),
                (-0.01, 1.0),
            ] {
                let (x, y) = (s * 3.0 - 0.5f32, (1.0 - t) * 3.0 - 0.5f32);
                let (x0, y0) = (x.floor(), y.floor());
                let (dx, dy) = (x - x0, y - y0);
                let (xi, yi) = (x0 as i64, y0 as i64);
                let want = (1.0 - dx) * (1.0 - dy) * im.texel(xi, yi, wrap)
                    + dx * (1.0 - dy) * im.texel(xi + 1, yi, wrap)
                    + (1.0 - dx) * dy * im.texel(xi, yi + 1, wrap)
                    + dx * dy * im.texel(xi + 1, yi + 1, wrap);
                assert_eq!(
                    im.lookup(Vec2::new(s, t), wrap, false),
                    want,
                    "{wrap:?} {s} {t}"
                );
            }
        }
        // Repeat: texel −1 is the last column, texel 3 the first.
        assert_eq!(im.texel(-1, 0, WrapMode::Repeat).x, 2.0);
        assert_eq!(im.texel(3, 4, WrapMode::Repeat), Rgb::new(0.0, 1.0, 0.0));
    }
}
