//! The film interface: what the tile loop ([`crate::render`]) adds camera samples to, one
//! implementation per film kind (`rgb`, `gbuffer`, `spectral`), and the splats any film takes.
//!
//! A render gives each unit of work a fresh [`FilmTile`] of the film's kind ([`Film::kind`],
//! matched once per unit by [`crate::render::render_units_with`]); the loop adds every camera
//! sample of the tile's pixels to it with [`FilmTile::add_sample`], then the tile's sums are
//! added into the film ([`FilmTile::merge_into`]). The loop is generic over the tile type,
//! so each kind gets its own compiled loop: no dynamic call per sample, and what a kind does
//! not use (the visible surface, the wavelength buckets) costs it nothing. Light landing on any pixel goes through
//! [`FilmSplats::add_splat`] instead ([`super::splat`]).
//!
//! A new per-pixel channel (a denoiser's albedo and normal, say) is a new `FilmTile`: its
//! sums beside the colour sums, `NEEDS_SURFACE` if it reads the first surface the camera ray
//! meets, and its merge into a field of [`Film`].

use super::gsums::{GPixel, GbufferConfig, VisibleSurface};
use super::spectral::{SpectralDesc, SpectralSums};
use super::splat::AtomicSplats;
use super::{Film, PixelBounds, PixelSum};
use crate::filter::Filter;
use crate::math::{Rgb, SampledSpectrum, Vec2};
use crate::spectrum::sampled::{N_SPECTRUM_SAMPLES, SampledWavelengths};

/// What one camera sample brings to its pixel.
#[derive(Clone, Copy, Debug)]
pub struct FilmSample<'a> {
    /// Its colour (the scene's film response of its radiance), after the rules for NaN
    /// (black) and `maxcomponentvalue` (scaled down to it).
    pub rgb: Rgb,
    /// Its colour in the sensor's RGB, with those rules applied there
    /// ([`crate::gbuffer::variance_rgb`]); only for a tile whose
    /// [`FilmTile::NEEDS_SENSOR_RGB`] is true (black otherwise).
    pub sensor_rgb: Rgb,
    /// Its radiance at its wavelengths, as the integrator returned it (spectral mode).
    pub l: SampledSpectrum,
    /// Its wavelengths (none in RGB mode, or for an integrator that computes no radiance).
    pub lambda: Option<&'a SampledWavelengths>,
    /// The first surface its camera ray meets, world space; only for a tile whose
    /// [`FilmTile::NEEDS_SURFACE`] is true (and none where the ray meets nothing).
    pub surface: Option<&'a VisibleSurface>,
}

/// A film kind's sums over one tile of pixels: what camera samples are added to.
pub trait FilmTile: Send {
    /// True when [`FilmTile::add_sample`] reads [`FilmSample::surface`]; the loop traces the
    /// camera ray's first surface only then.
    const NEEDS_SURFACE: bool = false;

    /// True when [`FilmTile::add_sample`] reads [`FilmSample::sensor_rgb`].
    const NEEDS_SENSOR_RGB: bool = false;

    /// The scale of the camera ray differentials the visible surface is found with (only
    /// read when `NEEDS_SURFACE`).
    #[inline]
    fn differential_scale(&self) -> f32 {
        1.0
    }

    /// True when the visible surface is the denoiser's: the first one that is not perfectly
    /// specular ([`crate::gbuffer::visible_surface`]'s `follow_specular`).
    #[inline]
    fn follows_specular(&self) -> bool {
        false
    }

    /// A camera sample's wavelengths from one uniform number: by default pbrt-v4's density
    /// over the visible range ([`FilmKind::sample_wavelengths`], which replays draw with).
    #[inline]
    fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        FilmKind::Rgb.sample_wavelengths(u)
    }

    /// Adds a camera sample of pixel `pixel` (row-major index within the tile) with filter
    /// weight `weight`.
    fn add_sample(&mut self, pixel: usize, sample: &FilmSample<'_>, weight: f32);

    /// Adds the tile's sums (over `tile`) into `film` (exact integer sums; the g-buffer's
    /// floating-point sums are added pixel by pixel, in the order the tiles are merged).
    fn merge_into(&self, film: &mut Film, tile: &PixelBounds);
}

/// An `rgb` film's tile: the colour sums only.
#[derive(Clone, Debug)]
pub struct RgbTile {
    sums: Vec<PixelSum>,
}

impl RgbTile {
    /// Zero sums over `tile`.
    pub fn new(tile: &PixelBounds) -> RgbTile {
        RgbTile {
            sums: vec![PixelSum::default(); tile.area() as usize],
        }
    }
}

impl FilmTile for RgbTile {
    #[inline(always)]
    fn add_sample(&mut self, pixel: usize, sample: &FilmSample<'_>, weight: f32) {
        self.sums[pixel].add(sample.rgb, weight);
    }

    fn merge_into(&self, film: &mut Film, tile: &PixelBounds) {
        film.merge_tile(tile, &self.sums);
    }
}

/// A `gbuffer` film's tile: the colour sums and the auxiliary ones
/// ([`crate::gbuffer`]), in the configuration's output space.
#[derive(Clone, Debug)]
pub struct GbufferTile {
    config: GbufferConfig,
    /// The ray differentials' scale for the configuration's spp.
    differential_scale: f32,
    sums: Vec<PixelSum>,
    aux: Vec<GPixel>,
}

impl GbufferTile {
    /// Zero sums over `tile`.
    pub fn new(config: GbufferConfig, tile: &PixelBounds) -> GbufferTile {
        let n = tile.area() as usize;
        GbufferTile {
            config,
            differential_scale: crate::camera::footprint::differential_scale(config.spp),
            sums: vec![PixelSum::default(); n],
            aux: vec![GPixel::default(); n],
        }
    }
}

impl FilmTile for GbufferTile {
    const NEEDS_SURFACE: bool = true;
    // pbrt-v4's variance is of the sensor's RGB.
    const NEEDS_SENSOR_RGB: bool = true;

    #[inline]
    fn differential_scale(&self) -> f32 {
        self.differential_scale
    }

    #[inline]
    fn follows_specular(&self) -> bool {
        self.config.for_denoiser
    }

    fn add_sample(&mut self, pixel: usize, sample: &FilmSample<'_>, weight: f32) {
        self.sums[pixel].add(sample.rgb, weight);
        let vs = sample.surface.map(|v| self.config.to_output(v));
        self.aux[pixel].add(sample.sensor_rgb, weight, vs.as_ref());
    }

    fn merge_into(&self, film: &mut Film, tile: &PixelBounds) {
        film.merge_tile(tile, &self.sums);
        film.merge_gbuffer_tile(tile, &self.aux);
    }
}

/// A `spectral` film's tile: the colour sums and the wavelength buckets
/// ([`super::spectral`]); its wavelengths are drawn uniformly over the buckets' range.
#[derive(Clone, Debug)]
pub struct SpectralTile {
    sums: Vec<PixelSum>,
    buckets: SpectralSums,
    max_component_value: f32,
}

impl SpectralTile {
    /// Zero sums over `tile`; samples are scaled down to `max_component_value` in the buckets
    /// as in the colour.
    pub fn new(desc: SpectralDesc, tile: &PixelBounds, max_component_value: f32) -> SpectralTile {
        let n = tile.area() as usize;
        SpectralTile {
            sums: vec![PixelSum::default(); n],
            buckets: SpectralSums::new(desc, n),
            max_component_value,
        }
    }
}

impl FilmTile for SpectralTile {
    #[inline]
    fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        FilmKind::Spectral(self.buckets.desc).sample_wavelengths(u)
    }

    fn add_sample(&mut self, pixel: usize, sample: &FilmSample<'_>, weight: f32) {
        self.sums[pixel].add(sample.rgb, weight);
        if let Some(lambda) = sample.lambda {
            self.buckets
                .add(pixel, sample.l, lambda, weight, self.max_component_value);
        }
    }

    fn merge_into(&self, film: &mut Film, tile: &PixelBounds) {
        film.merge_tile(tile, &self.sums);
        film.merge_spectral_tile(tile, &self.buckets);
    }
}

/// A film's kind, as the tile loop dispatches on it (once per unit of work).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilmKind {
    /// Colour only.
    Rgb,
    /// Colour and the g-buffer channels.
    Gbuffer(GbufferConfig),
    /// Colour and wavelength buckets.
    Spectral(SpectralDesc),
}

impl FilmKind {
    /// A camera sample's wavelengths from one uniform number, as this kind's tiles draw them
    /// ([`FilmTile::sample_wavelengths`]): uniformly over the buckets' range for a spectral
    /// film, else by pbrt-v4's density over the visible range.
    pub fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        match self {
            FilmKind::Spectral(d) => d.sample_wavelengths(u),
            _ => SampledWavelengths::sample_visible(u),
        }
    }

    /// Splat values per pixel: the colour, and one per bucket for a spectral film.
    pub fn splat_channels(&self) -> usize {
        match self {
            FilmKind::Spectral(d) => 3 + d.nbuckets as usize,
            _ => 3,
        }
    }
}

/// Where the threads of a render put their splats: the film's shared splat plane, with what
/// a splat needs to spread over the pixels (the filter) and to reach the buckets of a spectral
/// film.
#[derive(Debug)]
pub struct FilmSplats<'a> {
    plane: &'a AtomicSplats,
    filter: &'a Filter,
    /// 1/∫f.
    inv_integral: f32,
    spectral: Option<SpectralDesc>,
}

impl<'a> FilmSplats<'a> {
    /// Splats into `plane` through `filter`, for a film of `kind`.
    pub fn new(plane: &'a AtomicSplats, filter: &'a Filter, kind: FilmKind) -> FilmSplats<'a> {
        let integral = filter.integral();
        FilmSplats {
            plane,
            filter,
            inv_integral: if integral != 0.0 { 1.0 / integral } else { 0.0 },
            spectral: match kind {
                FilmKind::Spectral(d) => Some(d),
                _ => None,
            },
        }
    }

    /// Adds colour `rgb` (already the film's colour, scaled down to `maxcomponentvalue`) at
    /// film point `p` (pixel units, full image) to every pixel within the filter's radius, as
    /// pbrt-v4's `RGBFilm::AddSplat`: the pixels i with ⌊p + ½ − r⌋ ≤ i ≤ ⌊p + ½ + r⌋ get
    /// f(p − i − ½)/∫f · rgb. For a spectral film, `spectrum` (radiance at its wavelengths,
    /// scaled down to `maxcomponentvalue`) adds f/∫f · L(λₖ)/(pdf(λₖ)·Δλ·N) to the bucket of
    /// each λₖ, Δλ the bucket width and N = 4 the wavelengths per sample: an unbiased estimate
    /// of the bucket's mean radiance per camera sample, so that its splat value S/n is in the
    /// units of its sample value Σw·L/Σw (pbrt-v4 divides by pdf·N only).
    pub fn add_splat(
        &self,
        p: Vec2,
        rgb: Rgb,
        spectrum: Option<(SampledSpectrum, &SampledWavelengths)>,
    ) {
        let r = self.filter.radius();
        let (x0, x1) = ((p.x + 0.5 - r.x).floor(), (p.x + 0.5 + r.x).floor());
        let (y0, y1) = ((p.y + 0.5 - r.y).floor(), (p.y + 0.5 + r.y).floor());
        let b = self.plane.bounds();
        let (x0, x1) = ((x0 as i32).max(b.x0), (x1 as i32).min(b.x1 - 1));
        let (y0, y1) = ((y0 as i32).max(b.y0), (y1 as i32).min(b.y1 - 1));
        let buckets = match (self.spectral, spectrum) {
            (Some(d), Some((l, lambda))) => {
                let width = (d.lambda_max - d.lambda_min) / d.nbuckets as f32;
                let mut v = [(0usize, 0.0f32); N_SPECTRUM_SAMPLES];
                for (k, slot) in v.iter_mut().enumerate() {
                    let pdf = lambda.pdf[k];
                    let val = if pdf > 0.0 {
                        l[k] / (pdf * width * N_SPECTRUM_SAMPLES as f32)
                    } else {
                        0.0
                    };
                    *slot = (3 + d.bucket(lambda.lambda[k]), val);
                }
                Some(v)
            }
            _ => None,
        };
        for y in y0..=y1 {
            for x in x0..=x1 {
                let w = self
                    .filter
                    .evaluate(Vec2::new(p.x - x as f32 - 0.5, p.y - y as f32 - 0.5))
                    * self.inv_integral;
                if w == 0.0 {
                    continue;
                }
                self.plane.add(x, y, &[w * rgb.x, w * rgb.y, w * rgb.z]);
                if let Some(v) = &buckets {
                    for &(c, val) in v {
                        self.plane.add_channel(x, y, c, w * val);
                    }
                }
            }
        }
    }
}
