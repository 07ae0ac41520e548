//! MIP-maps: an image texture's pyramid of ever smaller copies and the filters that read it
//! over a lookup's footprint, as pbrt-v4's `MIPMap` (`util/mipmap.cpp`) and
//! `Image::GeneratePyramid` (`util/image.cpp`).
//!
//! Level 0 is the image itself when both sides are powers of two; otherwise it is the image
//! resampled up to the next powers of two with a Lanczos (windowed sinc) filter. Each further
//! level averages 2×2 texels of the one below, down to 1×1: the pyramid costs ⁴⁄₃ of level 0.
//! Lookups take texture coordinates (s, t) with t growing upwards (lancer's and pbrt's
//! texture convention) and the footprint's two axes ∂(s, t)/∂x and ∂(s, t)/∂y.

use crate::image::{Image, WrapMode};
use crate::math::{Mat3, PackedRgb, Rgb, Vec2};
use palette::PaletteLevel;
use std::collections::HashMap;
use std::sync::{Arc, LazyLock};

mod palette;

/// How an image texture is filtered over its footprint (pbrt-v4's `filter`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ImageFilter {
    /// The nearest texel of the level the footprint's width selects.
    Point,
    /// Bilinear interpolation at the level the footprint's width selects.
    Bilinear,
    /// Bilinear lookups at the two levels around the footprint's width, blended.
    Trilinear,
    /// Elliptically weighted average over the footprint's ellipse (pbrt-v4's default).
    Ewa {
        /// The longer axis is at most this many times the shorter (`maxanisotropy`).
        max_anisotropy: f32,
    },
}

impl Default for ImageFilter {
    fn default() -> Self {
        ImageFilter::Ewa {
            max_anisotropy: 8.0,
        }
    }
}

/// Texture coordinates and their screen-space derivatives (pbrt-v4's `TexCoord2D`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StFootprint {
    /// (s, t).
    pub st: Vec2,
    /// ∂s/∂x.
    pub dsdx: f32,
    /// ∂s/∂y.
    pub dsdy: f32,
    /// ∂t/∂x.
    pub dtdx: f32,
    /// ∂t/∂y.
    pub dtdy: f32,
}

/// An image's MIP pyramid, finest level first.
#[derive(Clone, PartialEq)]
pub struct MipMap {
    levels: Vec<Arc<Image>>,
    /// Per level, the same texels at 1 to 8 bits each when the level has at most 256
    /// distinct ones ([`PaletteLevel`]): lookups read these, a twelfth to a ninety-sixth of
    /// the memory traffic.
    palettes: Vec<Option<PaletteLevel>>,
}

/// Level 0 and the number of levels: the others follow from them, and printing them (the
/// command line hashes a scene's description through `Debug`) would cost a third more again.
impl std::fmt::Debug for MipMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MipMap")
            .field("levels", &self.levels.len())
            .field("level0", &self.levels[0])
            .finish()
    }
}

/// The EWA filter's Gaussian weights, `e^(−α r²) − e^(−α)` with α = 2 at r² = i/127 (the table
/// pbrt-v4 ships, `MIPFilterLUT`), indexed by ⌊128 r²⌋.
static EWA_WEIGHTS: LazyLock<[f32; 128]> = LazyLock::new(|| {
    let alpha = 2.0f64;
    std::array::from_fn(|i| ((-alpha * i as f64 / 127.0).exp() - (-alpha).exp()) as f32)
});

impl MipMap {
    /// A single-level map: lookups always read `image` itself, whatever the footprint (image
    /// textures of formats that ask for no MIP filtering, and normal maps).
    pub fn single(image: Arc<Image>) -> MipMap {
        MipMap::from_levels(vec![image])
    }

    /// A map of these levels, with their byte forms where they have few distinct texels.
    fn from_levels(levels: Vec<Arc<Image>>) -> MipMap {
        let palettes = levels.iter().map(|l| PaletteLevel::from_image(l)).collect();
        MipMap { levels, palettes }
    }

    /// [`Image::texel`] of level `i`, read from its byte form when it has one.
    #[inline]
    fn texel(&self, i: usize, x: i64, y: i64, wrap: WrapMode) -> Rgb {
        match &self.palettes[i] {
            Some(p) => p.texel(x, y, wrap),
            None => self.levels[i].texel(x, y, wrap),
        }
    }

    /// [`Image::lookup`] of level `i`, read from its byte form when it has one.
    #[inline]
    fn lookup(&self, i: usize, st: Vec2, wrap: WrapMode, nearest: bool) -> Rgb {
        match &self.palettes[i] {
            Some(p) => p.lookup(st, wrap, nearest),
            None => self.levels[i].lookup(st, wrap, nearest),
        }
    }

    /// Bytes of the levels' byte forms (the images themselves are counted with
    /// [`MipMap::images`]).
    pub fn palette_bytes(&self) -> usize {
        self.palettes
            .iter()
            .flatten()
            .map(PaletteLevel::memory_bytes)
            .sum()
    }

    /// The full pyramid of `image`; `wrap` says what lies beyond its edges when it has to be
    /// resampled to powers of two. A power-of-two image becomes level 0 as it is (shared).
    pub fn new(image: Arc<Image>, wrap: WrapMode) -> MipMap {
        MipMap::with_clamp_space(image, wrap, None)
    }

    /// [`MipMap::new`] for an image whose texels were taken from the file's own RGB space to
    /// linear sRGB by `to_srgb`: the resampling clamps negative values in the file's space
    /// (where pbrt-v4 keeps the texels), not in sRGB's, where a wide-gamut colour may
    /// rightly be negative.
    pub fn with_clamp_space(image: Arc<Image>, wrap: WrapMode, to_srgb: Option<Mat3>) -> MipMap {
        let (w, h) = (image.width, image.height);
        let base = if w.is_power_of_two() && h.is_power_of_two() {
            image
        } else {
            Arc::new(resize_up(
                &image,
                w.next_power_of_two(),
                h.next_power_of_two(),
                wrap,
                to_srgb,
            ))
        };
        let mut levels = vec![base];
        loop {
            let last = levels.last().expect("level 0 is there");
            if last.width == 1 && last.height == 1 {
                break;
            }
            let next = downsample(last);
            levels.push(Arc::new(next));
        }
        MipMap::from_levels(levels)
    }

    /// Number of levels.
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Level `i` (0 the finest).
    pub fn level(&self, i: usize) -> &Image {
        &self.levels[i]
    }

    /// The levels' images, finest first (level 0 may be shared with other users of the file).
    pub fn images(&self) -> impl Iterator<Item = &Arc<Image>> {
        self.levels.iter()
    }

    /// The filtered value at `c` (pbrt-v4's `MIPMap::Filter`). A single-level map ignores the
    /// footprint (point or bilinear lookup of its image).
    pub fn filter(&self, filter: ImageFilter, wrap: WrapMode, c: &StFootprint) -> Rgb {
        let (dst0, dst1) = (Vec2::new(c.dsdx, c.dtdx), Vec2::new(c.dsdy, c.dtdy));
        if self.levels.len() == 1 {
            return self.lookup(0, c.st, wrap, filter == ImageFilter::Point);
        }
        let top = self.levels.len() - 1;
        let max_anisotropy = match filter {
            ImageFilter::Ewa { max_anisotropy } => max_anisotropy,
            _ => {
                // width = 2·max(|∂s/∂x|, |∂t/∂x|, |∂s/∂y|, |∂t/∂y|); the level whose texels are
                // that wide: ℓ = (n − 1) + log₂ width.
                let width = 2.0 * dst0.abs().max(dst1.abs()).max_element();
                let level = top as f32 + width.max(1e-8).log2();
                if level >= top as f32 {
                    return self.texel(top, 0, 0, wrap);
                }
                let il = (level.floor() as i64).max(0) as usize;
                return match filter {
                    ImageFilter::Point => self.lookup(il, c.st, wrap, true),
                    ImageFilter::Bilinear => self.lookup(il, c.st, wrap, false),
                    _ if il == 0 => self.lookup(0, c.st, wrap, false),
                    _ => {
                        let f = level - il as f32;
                        let a = self.lookup(il, c.st, wrap, false);
                        let b = self.lookup(il + 1, c.st, wrap, false);
                        (1.0 - f) * a + f * b
                    }
                };
            }
        };
        // EWA: the longer axis first; the shorter stretched so that the ellipse is at most
        // `max_anisotropy` times longer than wide.
        let (dst0, mut dst1) = if dst0.length_squared() < dst1.length_squared() {
            (dst1, dst0)
        } else {
            (dst0, dst1)
        };
        let longer = dst0.length();
        let mut shorter = dst1.length();
        if shorter * max_anisotropy < longer && shorter > 0.0 {
            let scale = longer / (shorter * max_anisotropy);
            dst1 *= scale;
            shorter *= scale;
        }
        if shorter == 0.0 {
            return self.lookup(0, c.st, wrap, false);
        }
        // The level where the shorter axis spans about a texel: ℓ = max(0, (n − 1) + log₂ |b|).
        let lod = (top as f32 + shorter.log2()).max(0.0);
        let il = lod.floor() as usize;
        let f = lod - il as f32;
        (1.0 - f) * self.ewa(il, wrap, c.st, dst0, dst1)
            + f * self.ewa(il + 1, wrap, c.st, dst0, dst1)
    }

    /// pbrt-v4's `MIPMap::EWA` at one level: the texels inside the ellipse
    /// `A·s² + B·s·t + C·t² < 1` spanned by the axes `a`, `b` (in texels, each widened by one
    /// texel), weighted by the Gaussian table.
    fn ewa(&self, level: usize, wrap: WrapMode, st: Vec2, a: Vec2, b: Vec2) -> Rgb {
        let Some(img) = self.levels.get(level) else {
            return self.texel(self.levels.len() - 1, 0, 0, wrap);
        };
        let res = Vec2::new(img.width as f32, img.height as f32);
        // Image rows run downwards: t flips (its derivatives need not: the ellipse is
        // symmetric).
        let s0 = st.x * res.x - 0.5;
        let t0 = (1.0 - st.y) * res.y - 0.5;
        let (a, b) = (a * res, b * res);
        // Ellipse coefficients (Heckbert): A = a_t² + b_t² + 1, B = −2(a_s a_t + b_s b_t),
        // C = a_s² + b_s² + 1, scaled by 1/F with F = AC − B²/4.
        let mut ea = a.y * a.y + b.y * b.y + 1.0;
        let mut eb = -2.0 * (a.x * a.y + b.x * b.y);
        let mut ec = a.x * a.x + b.x * b.x + 1.0;
        let inv_f = 1.0 / (ea * ec - eb * eb * 0.25);
        ea *= inv_f;
        eb *= inv_f;
        ec *= inv_f;
        // Bounding box: |s| ≤ 2√(det·C)/det, |t| ≤ 2√(A·det)/det with det = 4AC − B².
        let det = -eb * eb + 4.0 * ea * ec;
        let inv_det = 1.0 / det;
        let u_sqrt = (det * ec).max(0.0).sqrt();
        let v_sqrt = (ea * det).max(0.0).sqrt();
        let is0 = (s0 - 2.0 * inv_det * u_sqrt).ceil() as i64;
        let is1 = (s0 + 2.0 * inv_det * u_sqrt).floor() as i64;
        let it0 = (t0 - 2.0 * inv_det * v_sqrt).ceil() as i64;
        let it1 = (t0 + 2.0 * inv_det * v_sqrt).floor() as i64;
        let lut = &*EWA_WEIGHTS;
        let mut sum = Rgb::ZERO;
        let mut sum_w = 0.0f32;
        for it in it0..=it1 {
            let tt = it as f32 - t0;
            for is in is0..=is1 {
                let ss = is as f32 - s0;
                let r2 = ea * ss * ss + eb * ss * tt + ec * tt * tt;
                if r2 < 1.0 {
                    let w = lut[((r2 * 128.0) as usize).min(127)];
                    sum += w * self.texel(level, is, it, wrap);
                    sum_w += w;
                }
            }
        }
        // The widened ellipse always covers a texel centre; the guard is for NaN footprints.
        if sum_w > 0.0 {
            sum / sum_w
        } else {
            self.lookup(level, st, wrap, false)
        }
    }
}

/// What a pyramid depends on: the image (by address), whether it is one at all, the wrap mode
/// when the image is resampled to powers of two (beyond its edges), and the colour space its
/// resampling clamps in (the matrix's bits).
type PyramidKey = (usize, bool, Option<WrapMode>, Option<[u32; 9]>);

/// The MIP pyramids a scene build has made, so that textures of the same image and pyramid
/// settings share one: memory does not grow with the number of textures naming a file.
#[derive(Default)]
pub struct Pyramids {
    made: HashMap<PyramidKey, Arc<MipMap>>,
}

impl Pyramids {
    /// The pyramid of `image`, made on first use: with `mip` [`MipMap::with_clamp_space`] for
    /// `wrap` and `to_srgb`, else [`MipMap::single`].
    pub fn get(
        &mut self,
        image: &Arc<Image>,
        mip: bool,
        wrap: WrapMode,
        to_srgb: Option<Mat3>,
    ) -> Arc<MipMap> {
        let resampled = mip && !(image.width.is_power_of_two() && image.height.is_power_of_two());
        let to_srgb = to_srgb.filter(|_| mip);
        let key = (
            Arc::as_ptr(image) as usize,
            mip,
            resampled.then_some(wrap),
            to_srgb.map(|m| m.to_cols_array().map(f32::to_bits)),
        );
        self.made
            .entry(key)
            .or_insert_with(|| {
                Arc::new(if mip {
                    MipMap::with_clamp_space(image.clone(), wrap, to_srgb)
                } else {
                    MipMap::single(image.clone())
                })
            })
            .clone()
    }

    /// How many distinct pyramids were made.
    pub fn len(&self) -> usize {
        self.made.len()
    }

    /// True before any pyramid is made.
    pub fn is_empty(&self) -> bool {
        self.made.is_empty()
    }
}

/// The next level of a power-of-two image: each texel the mean of the 2×2 texels under it (of
/// 2×1 or 1×2 once a side is down to one texel).
fn downsample(img: &Image) -> Image {
    let (w, h) = (img.width as usize, img.height as usize);
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let (dx, dy) = (usize::from(w > 1), usize::from(h > 1));
    let at = |x: usize, y: usize| -> Rgb { img.texels[y * w + x].into() };
    let mut texels = Vec::with_capacity(nw * nh);
    for y in 0..nh {
        for x in 0..nw {
            let (x0, y0) = (2 * x * dx, 2 * y * dy);
            let c = (at(x0, y0) + at(x0 + dx, y0) + at(x0, y0 + dy) + at(x0 + dx, y0 + dy)) / 4.0;
            texels.push(PackedRgb::from(c));
        }
    }
    Image::new(nw as u32, nh as u32, texels).expect("non-empty level")
}

/// pbrt-v4's resampling weights from `old` to `new ≥ old` texels: for each new texel, four
/// source texels from ⌊c − 2 + ½⌋ (c = (i + ½)·old/new its centre in source texels), weighted
/// by a Lanczos window `sinc(x)·sinc(x/2)` of radius 2 and normalised.
fn resample_weights(old: u32, new: u32) -> Vec<(i64, [f32; 4])> {
    let sinc = |x: f32| {
        let px = std::f32::consts::PI * x;
        if 1.0 - px * px == 1.0 {
            1.0
        } else {
            px.sin() / px
        }
    };
    let windowed = |x: f32| {
        if x.abs() > 2.0 {
            0.0
        } else {
            sinc(x) * sinc(x / 2.0)
        }
    };
    (0..new)
        .map(|i| {
            let centre = (i as f32 + 0.5) * old as f32 / new as f32;
            let first = (centre - 2.0 + 0.5).floor();
            let mut w: [f32; 4] =
                std::array::from_fn(|j| windowed(first + j as f32 + 0.5 - centre));
            let inv = 1.0 / w.iter().sum::<f32>();
            w.iter_mut().for_each(|v| *v *= inv);
            (first as i64, w)
        })
        .collect()
}

/// `img` resampled up to `nw × nh` (pbrt-v4's `Image::FloatResizeUp`): separable, x first,
/// source texels beyond the edges as `wrap` says; results clamped at 0 (in the file's space
/// when `to_srgb` took the texels out of it).
fn resize_up(img: &Image, nw: u32, nh: u32, wrap: WrapMode, to_srgb: Option<Mat3>) -> Image {
    let spaces = to_srgb.map(|m| (m, m.inverse()));
    let clamp = |c: Rgb| match spaces {
        None => c.max(Rgb::ZERO),
        Some((m, inv)) => m * (inv * c).max(Rgb::ZERO),
    };
    let xw = resample_weights(img.width, nw);
    let yw = resample_weights(img.height, nh);
    // x pass: every source row (plus the rows the y pass reaches beyond the edges, read
    // through `texel`'s wrap), resampled to nw texels. Rows are indexed from y_min.
    let y_min = yw.first().map_or(0, |w| w.0);
    let y_max = yw.last().map_or(0, |w| w.0 + 3);
    let rows = (y_max - y_min + 1) as usize;
    let mut xbuf = vec![Rgb::ZERO; rows * nw as usize];
    for (r, y) in (y_min..=y_max).enumerate() {
        for (x, (first, w)) in xw.iter().enumerate() {
            let mut c = Rgb::ZERO;
            for (j, wj) in w.iter().enumerate() {
                c += *wj * img.texel(first + j as i64, y, wrap);
            }
            xbuf[r * nw as usize + x] = c;
        }
    }
    let mut texels = Vec::with_capacity(nw as usize * nh as usize);
    for (first, w) in &yw {
        let r0 = (first - y_min) as usize;
        for x in 0..nw as usize {
            let mut c = Rgb::ZERO;
            for (j, wj) in w.iter().enumerate() {
                c += *wj * xbuf[(r0 + j) * nw as usize + x];
            }
            texels.push(PackedRgb::from(clamp(c)));
        }
    }
    Image::new(nw, nh, texels).expect("non-empty resampled image")
}

#[cfg(test)]
mod tests;
