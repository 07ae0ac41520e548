//! The film: per-pixel accumulators of weighted radiance, exact under any summation order.
//!
//! Each sample adds `w·L` and `w` to its pixel. The sums are kept in 64-bit fixed point (24
//! fractional bits), so addition is associative: a render split by tiles or by sample ranges,
//! across threads or machines, and merged in any order gives bit-identical pixels.

pub mod gsums;
pub mod part;
pub mod spectral;
pub mod spectral_write;
pub mod splat;
pub mod tile;

use crate::math::Rgb;

/// Fractional bits of the fixed-point accumulators (resolution 2⁻²⁴ ≈ 6·10⁻⁸).
pub const FIXED_FRAC_BITS: u32 = 24;
/// Largest magnitude of one sample's weighted value (2²⁰ ≈ 10⁶): larger values are clamped so
/// that 2¹⁹ samples at the limit still cannot overflow a pixel's 64-bit sum.
pub const MAX_SAMPLE_VALUE: f32 = (1u64 << 20) as f32;

/// Converts a value to fixed point (rounded to nearest), clamping to ±[`MAX_SAMPLE_VALUE`].
/// NaN becomes 0.
#[inline]
pub fn to_fixed(v: f32) -> i64 {
    let v = if v.is_nan() {
        0.0
    } else {
        v.clamp(-MAX_SAMPLE_VALUE, MAX_SAMPLE_VALUE)
    };
    (v as f64 * (1u64 << FIXED_FRAC_BITS) as f64).round() as i64
}

/// [`to_fixed`] of four values at once, with the same results, in a form the compiler turns
/// into 4-lane vector code: the rounded value r is an integer with |r| ≤ 2⁴⁴, so r + 1.5·2⁵²
/// is exact and lies in [2⁵², 2⁵³), where one unit is one ulp: its bits minus those of
/// 1.5·2⁵² are r (no float → integer conversion, which AVX2 has only one lane at a time).
#[inline]
pub fn to_fixed4(v: [f32; 4]) -> [i64; 4] {
    const MAGIC: f64 = (3u64 << 51) as f64;
    v.map(|v| {
        let v = if v.is_nan() {
            0.0
        } else {
            v.clamp(-MAX_SAMPLE_VALUE, MAX_SAMPLE_VALUE)
        };
        let r = (v as f64 * (1u64 << FIXED_FRAC_BITS) as f64).round();
        (r + MAGIC).to_bits() as i64 - MAGIC.to_bits() as i64
    })
}

/// Converts a fixed-point sum back to a float.
#[inline]
pub fn from_fixed(v: i64) -> f64 {
    v as f64 / (1u64 << FIXED_FRAC_BITS) as f64
}

/// One pixel's running sums.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelSum {
    /// Σ w·L per channel, fixed point.
    pub rgb: [i64; 3],
    /// Σ w, fixed point.
    pub weight: i64,
    /// Number of samples added.
    pub samples: u32,
}

impl PixelSum {
    /// Adds a sample of radiance `l` with filter weight `w`.
    #[inline]
    pub fn add(&mut self, l: Rgb, w: f32) {
        let [r, g, b, w] = to_fixed4([w * l[0], w * l[1], w * l[2], w]);
        for (s, v) in self.rgb.iter_mut().zip([r, g, b]) {
            *s = s.saturating_add(v);
        }
        self.weight = self.weight.saturating_add(w);
        self.samples += 1;
    }

    /// Adds another pixel's sums (exact).
    #[inline]
    pub fn merge(&mut self, o: &PixelSum) {
        for c in 0..3 {
            self.rgb[c] = self.rgb[c].saturating_add(o.rgb[c]);
        }
        self.weight = self.weight.saturating_add(o.weight);
        self.samples += o.samples;
    }

    /// The pixel's value: Σ w·L / Σ w (black with no weight).
    #[inline]
    pub fn value(&self) -> Rgb {
        if self.weight == 0 {
            return Rgb::ZERO;
        }
        let w = from_fixed(self.weight);
        Rgb::new(
            (from_fixed(self.rgb[0]) / w) as f32,
            (from_fixed(self.rgb[1]) / w) as f32,
            (from_fixed(self.rgb[2]) / w) as f32,
        )
    }
}

/// A rectangle of pixels `[x0, x1) × [y0, y1)` in full-image coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PixelBounds {
    /// First column.
    pub x0: i32,
    /// One past the last column.
    pub x1: i32,
    /// First row (rows count from the top).
    pub y0: i32,
    /// One past the last row.
    pub y1: i32,
}

impl PixelBounds {
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        (self.x1 - self.x0).max(0) as u32
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        (self.y1 - self.y0).max(0) as u32
    }

    /// Number of pixels.
    pub fn area(&self) -> u64 {
        self.width() as u64 * self.height() as u64
    }

    /// The common part of two rectangles (possibly empty).
    pub fn intersect(&self, o: &PixelBounds) -> PixelBounds {
        PixelBounds {
            x0: self.x0.max(o.x0),
            x1: self.x1.min(o.x1),
            y0: self.y0.max(o.y0),
            y1: self.y1.min(o.y1),
        }
    }

    /// True when it holds no pixel.
    pub fn is_empty(&self) -> bool {
        self.x1 <= self.x0 || self.y1 <= self.y0
    }

    /// The row-major index of pixel (`x`, `y`) (full-image coordinates) among the
    /// rectangle's pixels, (y − y0)·width + (x − x0); `None` outside it.
    #[inline]
    pub fn index(&self, x: i32, y: i32) -> Option<usize> {
        if x < self.x0 || x >= self.x1 || y < self.y0 || y >= self.y1 {
            return None;
        }
        Some((y - self.y0) as usize * self.width() as usize + (x - self.x0) as usize)
    }
}

/// The film: sums for every pixel of `bounds`, part of a `full_width × full_height` image.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Full image width.
    pub full_width: u32,
    /// Full image height.
    pub full_height: u32,
    /// The pixels this film holds.
    pub bounds: PixelBounds,
    /// Sums, row-major over `bounds`.
    pub pixels: Vec<PixelSum>,
    /// The auxiliary sums of a `gbuffer` film (none for an `rgb` film).
    pub gbuffer: Option<Box<gsums::GbufferFilm>>,
    /// The wavelength-bucket sums of a `spectral` film (none for other films).
    pub spectral: Option<Box<spectral::SpectralSums>>,
    /// The splat sums ([`splat`]), over the whole render's pixels; none until an integrator
    /// that splats has rendered into the film.
    pub splats: Option<Box<splat::SplatPlane>>,
}

impl Film {
    /// An empty film over `bounds` of a `full_width × full_height` image.
    pub fn new(full_width: u32, full_height: u32, bounds: PixelBounds) -> Film {
        Film {
            full_width,
            full_height,
            bounds,
            pixels: vec![PixelSum::default(); bounds.area() as usize],
            gbuffer: None,
            spectral: None,
            splats: None,
        }
    }

    /// The EXR layer window of its pixels: its bounds' size inside the full image.
    pub fn layer_size(&self) -> crate::image_io::LayerSize {
        crate::image_io::LayerSize {
            size: (self.bounds.width() as usize, self.bounds.height() as usize),
            full: (self.full_width, self.full_height),
        }
    }

    /// The film's kind: what its tiles accumulate ([`tile::FilmTile`]).
    pub fn kind(&self) -> tile::FilmKind {
        match (&self.gbuffer, &self.spectral) {
            (Some(g), _) => tile::FilmKind::Gbuffer(g.config),
            (None, Some(s)) => tile::FilmKind::Spectral(s.desc),
            (None, None) => tile::FilmKind::Rgb,
        }
    }

    /// Adds splat sums into the film's (exact; the film takes a copy if it has none).
    pub fn merge_splats(&mut self, o: &splat::SplatPlane) {
        match &mut self.splats {
            Some(s) => s.merge(o),
            None => self.splats = Some(Box::new(o.clone())),
        }
    }

    /// What the splat sums are divided by: the film's camera samples per pixel n (the most
    /// any of its pixels has taken; every pixel of a finished render has the same), as
    /// pbrt-v4's `splatScale` = 1/spp; 1 for a film of splats alone (`mlt`'s, which takes no
    /// camera sample and whose splats carry their own normalisation). `None` without splats.
    pub fn splat_divisor(&self) -> Option<f64> {
        self.splats.as_ref()?;
        let n = self.pixels.iter().map(|p| p.samples).max().unwrap_or(0);
        Some(n.max(1) as f64)
    }

    /// The colour of the film's pixel `i` (row-major over `bounds`), before the film's scale:
    /// Σw·L/Σw, plus S/n with the pixel's splat sum S ([`splat`]) when the film has splats
    /// (`divisor` = [`Film::splat_divisor`]).
    #[inline]
    pub fn pixel_rgb(&self, i: usize, divisor: Option<f64>) -> Rgb {
        let v = self.pixels[i].value();
        let (Some(s), Some(n)) = (&self.splats, divisor) else {
            return v;
        };
        let (x, y) = self.pixel_xy(i);
        let splat = |c: usize| (v[c] as f64 + s.value(x, y, c) / n) as f32;
        Rgb::new(splat(0), splat(1), splat(2))
    }

    /// The wavelength-bucket values of a `spectral` film's pixel `i` (row-major over
    /// `bounds`): Σw·L/Σw per bucket ([`spectral::SpectralSums::values`]), plus S/n with the
    /// bucket's splat sum S as [`Film::pixel_rgb`] adds the colour's (`divisor` =
    /// [`Film::splat_divisor`]). Empty for other films.
    pub fn bucket_values(&self, i: usize, divisor: Option<f64>) -> Vec<f32> {
        let Some(s) = &self.spectral else {
            return Vec::new();
        };
        let mut values = s.values(i);
        if let (Some(sp), Some(n)) = (&self.splats, divisor) {
            let (x, y) = self.pixel_xy(i);
            for (b, v) in values.iter_mut().enumerate() {
                *v += (sp.value(x, y, 3 + b) / n) as f32;
            }
        }
        values
    }

    /// The full-image coordinates of pixel `i` (row-major over `bounds`).
    #[inline]
    fn pixel_xy(&self, i: usize) -> (i32, i32) {
        let w = self.bounds.width().max(1) as usize;
        (
            self.bounds.x0 + (i % w) as i32,
            self.bounds.y0 + (i / w) as i32,
        )
    }

    /// Adds a tile's wavelength-bucket sums, if the film is a spectral one.
    pub fn merge_spectral_tile(&mut self, tile: &PixelBounds, sums: &spectral::SpectralSums) {
        if let Some(s) = &mut self.spectral {
            s.merge_tile(&self.bounds, tile, sums);
        }
    }

    /// Adds a tile's g-buffer sums (pixels of `tile`, row-major), if the film has a g-buffer.
    pub fn merge_gbuffer_tile(&mut self, tile: &PixelBounds, sums: &[gsums::GPixel]) {
        let Some(g) = &mut self.gbuffer else { return };
        let (w, fw) = (tile.width() as usize, self.bounds.width() as usize);
        let t = tile.intersect(&self.bounds);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let s = &sums[(y - tile.y0) as usize * w + (x - tile.x0) as usize];
                let i = (y - self.bounds.y0) as usize * fw + (x - self.bounds.x0) as usize;
                g.pixels[i].merge(s);
            }
        }
    }

    /// The sums of pixel `(x, y)` (full-image coordinates), if the film holds it.
    #[inline]
    pub fn pixel_mut(&mut self, x: i32, y: i32) -> Option<&mut PixelSum> {
        let i = self.bounds.index(x, y)?;
        self.pixels.get_mut(i)
    }

    /// Adds a tile's sums (pixels of `tile`, row-major) into the film.
    pub fn merge_tile(&mut self, tile: &PixelBounds, sums: &[PixelSum]) {
        let w = tile.width() as usize;
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let s = &sums[(y - tile.y0) as usize * w + (x - tile.x0) as usize];
                if let Some(p) = self.pixel_mut(x, y) {
                    p.merge(s);
                }
            }
        }
    }

    /// Adds every pixel of `other` that this film also holds (exact integer sums), as
    /// `merge_tile` does for one tile, its splat sums, and its g-buffer sums if both films
    /// have them.
    pub fn merge_film(&mut self, other: &Film) {
        self.merge_tile(&other.bounds, &other.pixels);
        if let Some(s) = &other.splats {
            self.merge_splats(s);
        }
        if let Some(g) = &other.gbuffer {
            self.merge_gbuffer_tile(&other.bounds, &g.pixels);
        }
    }

    /// The image: each pixel's colour ([`Film::pixel_rgb`]: Σ w·L / Σ w, and its splats) times
    /// `scale`, row-major over `bounds`.
    pub fn image(&self, scale: f32) -> Vec<Rgb> {
        (0..self.pixels.len())
            .map(self.scaled_pixels(scale))
            .collect()
    }

    /// Pixel `i` of [`Film::image`], computed when asked for: a writer reads the film through
    /// it without an image of it beside it.
    pub fn scaled_pixels(&self, scale: f32) -> impl Fn(usize) -> Rgb + Sync + '_ {
        let n = self.splat_divisor();
        move |i| self.pixel_rgb(i, n) * scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_sums_do_not_depend_on_order() {
        let vals: Vec<f32> = (0..1000)
            .map(|i| ((i * 7919) % 1013) as f32 * 0.0137 + 1e-3)
            .collect();
        let mut a = PixelSum::default();
        for v in &vals {
            a.add(Rgb::splat(*v), 1.0);
        }
        let (mut b1, mut b2) = (PixelSum::default(), PixelSum::default());
        for v in vals.iter().rev().take(400) {
            b2.add(Rgb::splat(*v), 1.0);
        }
        for v in vals.iter().take(600) {
            b1.add(Rgb::splat(*v), 1.0);
        }
        b2.merge(&b1);
        assert_eq!(a, b2);
        let mean: f64 = vals.iter().map(|&v| v as f64).sum::<f64>() / vals.len() as f64;
        assert!((a.value().x as f64 - mean).abs() < 1e-6);
    }

    /// The four-lane conversion gives `to_fixed`'s integers: halves (rounded away from zero),
    /// the clamp limits, infinities, NaN, signed zeros, tiny and pseudo-random values.
    #[test]
    fn to_fixed4_matches_to_fixed() {
        let step = 1.0 / (1u64 << FIXED_FRAC_BITS) as f32;
        let mut vals = vec![
            0.0,
            -0.0,
            0.5 * step,
            -0.5 * step,
            1.5 * step,
            -2.5 * step,
            MAX_SAMPLE_VALUE,
            -MAX_SAMPLE_VALUE,
            2.0 * MAX_SAMPLE_VALUE,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MIN_POSITIVE,
            1e-30,
            123.456,
        ];
        let mut x = 0x1234_5678u32;
        for _ in 0..4000 {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            // Random bit patterns: every exponent, sign and mantissa.
            vals.push(f32::from_bits(x));
        }
        for c in vals.chunks(4) {
            let v = [c[0], c[1 % c.len()], c[2 % c.len()], c[3 % c.len()]];
            assert_eq!(to_fixed4(v), v.map(to_fixed), "{v:?}");
        }
        assert_eq!(to_fixed4([0.5 * step; 4])[0], 1);
        assert_eq!(to_fixed4([-2.5 * step; 4])[0], -3);
    }

    /// Row-major within the rectangle, one past each end outside it.
    #[test]
    fn pixel_bounds_index_is_row_major_inside_only() {
        let b = PixelBounds {
            x0: -2,
            x1: 3,
            y0: 4,
            y1: 6,
        };
        assert_eq!(b.index(-2, 4), Some(0));
        assert_eq!(b.index(2, 4), Some(4));
        assert_eq!(b.index(-2, 5), Some(5));
        assert_eq!(b.index(2, 5), Some(9));
        for (x, y) in [(-3, 4), (3, 4), (0, 3), (0, 6)] {
            assert_eq!(b.index(x, y), None, "({x}, {y})");
        }
    }

    #[test]
    fn non_finite_samples_are_contained() {
        let mut p = PixelSum::default();
        p.add(Rgb::new(f32::NAN, f32::INFINITY, 1.0), 1.0);
        let v = p.value();
        assert!(v.is_finite());
        assert_eq!(v.x, 0.0);
        assert_eq!(v.y, MAX_SAMPLE_VALUE);
    }
}
