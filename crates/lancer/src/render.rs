//! Rendering: tiles of pixels, each pixel's samples taken in order, on all cores.

use crate::film::splat::AtomicSplats;
use crate::film::tile::{FilmKind, FilmSplats, FilmTile, GbufferTile, RgbTile, SpectralTile};
use crate::film::{Film, PixelBounds, PixelSum};
use crate::filter::Filter;
use crate::integrator::Integrator;
use crate::math::{Rgb, SampledSpectrum, Vec2};
use crate::ray::Ray;
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::Scene;
use crate::scene::desc::SceneDesc;
use crate::spectrum::sampled::SampledWavelengths;
use crate::spectrum::sampled::film_rgb;
use rayon::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

pub use crate::counters::{Counts, count_ray, counts, rays_traced};

mod camera_sample;
mod mlt;
pub mod sppm;
pub mod strategies;
#[cfg(test)]
pub(crate) mod testing;
mod vcm;

/// What to render.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Pixels to render (full-image coordinates).
    pub bounds: PixelBounds,
    /// The pixels splats may land on: the whole render's (a part of a split render renders
    /// some of its pixels, but its light paths reach any of them).
    pub splat_bounds: PixelBounds,
    /// Sample indices to take in each pixel: `[start, end)`.
    pub samples: std::ops::Range<u32>,
    /// Samples per pixel of the whole render (the sampler's point set depends on it); for
    /// `mlt`, its chains.
    pub spp: u32,
    /// Seed.
    pub seed: u64,
    /// Point set.
    pub sampler: SamplerKind,
    /// Pixel filter.
    pub filter: Filter,
    /// Light transport.
    pub integrator: Integrator,
    /// Tile edge in pixels.
    pub tile_size: u32,
    /// Largest component a sample may have; brighter samples are scaled down to it, keeping
    /// their colour (pbrt's `maxcomponentvalue`; infinity keeps every sample as it is).
    pub max_component_value: f32,
    /// Spectral mode (the default, as pbrt-v4 renders): each camera sample carries four
    /// wavelengths and the scene's RGB colours are uplifted to spectra (see
    /// [`crate::spectrum::sampled`]); the samples' radiance is converted to linear sRGB before
    /// the film, so the film is the same either way. Applies to the integrators that compute
    /// radiance ([`Integrator::computes_radiance`]); false is plain RGB rendering, as Mitsuba
    /// 3's RGB variants do.
    pub spectral: bool,
}

/// Tile edge, in pixels, that [`RenderSettings::from_desc`] chooses.
pub const DEFAULT_TILE_SIZE: u32 = 16;

impl RenderSettings {
    /// The settings a scene description asks for: the pixels of its film's pixel bounds or
    /// crop window ([`crate::scene::desc::FilmDesc::render_bounds`]; the whole image by
    /// default), every sample index `0..spp` (for `mlt`, every chain:
    /// [`Integrator::sample_indices`]), the description's sampler, seed, filter,
    /// integrator and `maxcomponentvalue`, tiles of [`DEFAULT_TILE_SIZE`] pixels, spectral
    /// rendering (lancer reads pbrt-v4 scenes, and pbrt-v4 renders spectrally). Callers that
    /// render a part of the image or of the samples, or in RGB mode, change those fields
    /// afterwards.
    pub fn from_desc(desc: &SceneDesc) -> RenderSettings {
        RenderSettings {
            bounds: desc.film.render_bounds(),
            splat_bounds: desc.film.render_bounds(),
            samples: 0..desc.integrator.sample_indices(desc.sampler.spp),
            spp: desc.integrator.sample_indices(desc.sampler.spp),
            seed: desc.sampler.seed,
            sampler: desc
                .sampler
                .kind
                .for_film(desc.film.xresolution, desc.film.yresolution),
            filter: Filter::new(desc.filter),
            integrator: desc.integrator,
            tile_size: DEFAULT_TILE_SIZE,
            max_component_value: desc.film.max_component_value,
            spectral: true,
        }
    }
}

/// Totals of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Camera samples taken.
    pub samples: u64,
    /// Rays traced (camera, bounce and shadow rays).
    pub rays: u64,
    /// True if the render stopped early because it was cancelled.
    pub cancelled: bool,
    /// Camera samples whose radiance was NaN or infinite: each is a bug upstream, counted and
    /// dropped (it adds black) so that it cannot poison its pixel.
    pub nonfinite: u64,
    /// The first of them in (row, column, sample index) order, whatever the thread count or
    /// tiling, for `lancer render --check-nan` to replay.
    pub first_nonfinite: Option<SampleId>,
    /// Photons traced (`sppm`), light vertices stored for merging (`vcm`); zero for the other
    /// integrators.
    pub photons: u64,
    /// Light subpaths started (`bdpt`, `lightpath`, `mlt`; zero for the others).
    pub light_paths: u64,
    /// Connections tried between light and camera subpaths (`bdpt`, `lightpath`, `mlt`).
    pub connections: u64,
    /// Merges of a camera vertex with a light vertex within the radius (`vcm`).
    pub merges: u64,
}

impl RenderStats {
    /// Adds what the thread counted since `before` ([`counts`]).
    pub fn add_counts_since(&mut self, before: Counts) {
        let c = counts().since(before);
        self.rays += c.rays;
        self.light_paths += c.light_paths;
        self.connections += c.connections;
    }

    /// Adds the totals of another part of the render.
    pub fn add(&mut self, o: &RenderStats) {
        self.samples += o.samples;
        self.rays += o.rays;
        self.cancelled |= o.cancelled;
        self.nonfinite += o.nonfinite;
        self.photons += o.photons;
        self.light_paths += o.light_paths;
        self.connections += o.connections;
        self.merges += o.merges;
        self.first_nonfinite = match (self.first_nonfinite, o.first_nonfinite) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
    }
}

/// One camera sample: pixel (`x`, `y`) and sample index. Ordered by row, column, then index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct SampleId {
    /// Row.
    pub y: i32,
    /// Column.
    pub x: i32,
    /// Sample index within the pixel.
    pub sample: u32,
}

/// The tiles covering `bounds`, in scanline order.
pub fn tiles(bounds: &PixelBounds, size: u32) -> Vec<PixelBounds> {
    let s = size.max(1) as i32;
    let mut out = Vec::new();
    let mut y = bounds.y0;
    while y < bounds.y1 {
        let mut x = bounds.x0;
        while x < bounds.x1 {
            out.push(PixelBounds {
                x0: x,
                x1: (x + s).min(bounds.x1),
                y0: y,
                y1: (y + s).min(bounds.y1),
            });
            x += s;
        }
        y += s;
    }
    out
}

/// Light transport as the tile loop drives it: the radiance a camera ray brings back, and
/// any light the integrator puts on other pixels of the film through `splats`.
pub trait SampleIntegrator: Sync {
    /// True when [`SampleIntegrator::li`] may splat: the film then gets a splat plane
    /// ([`crate::film::splat`]); false for an integrator that never does, whose render then
    /// has none.
    fn splats(&self) -> bool {
        false
    }

    /// True when the integrator computes radiance, whose camera samples then carry
    /// wavelengths in spectral mode.
    fn computes_radiance(&self) -> bool;

    /// The path tracer's settings (maximum depth, regularisation) when this integrator is the
    /// path tracer on `scene` (see [`Integrator::path_tracer`]): the tile loop then traces a
    /// pixel's camera rays eight at a time and follows each path from its first hit.
    fn path_tracer(&self, _scene: &Scene) -> Option<(u32, bool)> {
        None
    }

    /// The `mlt` settings when the integrator is Metropolis light transport, which renders
    /// Markov chains rather than camera samples (its units of work are ranges of chains).
    fn mlt(&self) -> Option<crate::integrator::mlt::MltOptions> {
        None
    }

    /// The settings of `sppm`, which is not a sum of camera samples: a render then runs
    /// [`sppm::render`]'s iterations instead of the tile loop. `None` for the others.
    fn sppm(&self) -> Option<crate::integrator::sppm::SppmOptions> {
        None
    }

    /// The settings of `vcm`, whose iterations are passes over the whole film (light
    /// subpaths, then camera samples): a render then runs [`vcm::render`] instead of the tile
    /// loop. `None` for the others.
    fn vcm(&self) -> Option<crate::integrator::vcm::VcmOptions> {
        None
    }

    /// The radiance arriving along the camera ray `ray` (at `lambda` in spectral mode, else
    /// RGB in the first three values), drawing from `sampler` after the camera's dimensions.
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
    ) -> SampledSpectrum;

    /// [`SampleIntegrator::li`] for the camera sample `at` (the tile loop's call): the same
    /// unless the integrator puts something per pixel elsewhere (bdpt's strategy images).
    #[inline(always)]
    fn li_at(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
        _at: SampleAt,
    ) -> SampledSpectrum {
        self.li(scene, ray, sampler, lambda, splats)
    }
}

/// Where a camera sample goes on the film: its pixel, and the weight its radiance gets there
/// (the filter's weight times the camera ray's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleAt {
    /// Pixel column (full image).
    pub x: i32,
    /// Pixel row (full image).
    pub y: i32,
    /// Filter weight w of the sample (the pixel is Σw·L/Σw) times the camera ray's weight.
    pub weight: f32,
}

impl SampleIntegrator for Integrator {
    #[inline(always)]
    fn splats(&self) -> bool {
        Integrator::splats(self)
    }

    #[inline(always)]
    fn computes_radiance(&self) -> bool {
        Integrator::computes_radiance(self)
    }

    #[inline(always)]
    fn path_tracer(&self, scene: &Scene) -> Option<(u32, bool)> {
        Integrator::path_tracer(self, scene)
    }

    fn mlt(&self) -> Option<crate::integrator::mlt::MltOptions> {
        match self {
            Integrator::Mlt(o) => Some(*o),
            _ => None,
        }
    }

    fn sppm(&self) -> Option<crate::integrator::sppm::SppmOptions> {
        match self {
            Integrator::Sppm(o) => Some(*o),
            _ => None,
        }
    }

    fn vcm(&self) -> Option<crate::integrator::vcm::VcmOptions> {
        match self {
            Integrator::Vcm(o) => Some(*o),
            _ => None,
        }
    }

    #[inline(always)]
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
    ) -> SampledSpectrum {
        if Integrator::splats(self) {
            // Light paths (lightpath, bdpt) land anywhere on the film.
            self.li_splatting(scene, ray, sampler, lambda, &mut |p, l| {
                splats.add_splat(p, l, lambda)
            })
        } else {
            Integrator::li(self, scene, ray, sampler, lambda)
        }
    }
}

/// Where an integrator puts light on any pixel of the film (pbrt-v4's `Film::AddSplat`):
/// the film's shared splat plane, or nowhere for an integrator that does not splat.
pub struct Splats<'a> {
    scene: &'a Scene,
    max_component_value: f32,
    film: Option<FilmSplats<'a>>,
}

impl<'a> Splats<'a> {
    /// Splats of `scene` rendered with `settings` into `plane` (a film of kind `kind`), or
    /// nowhere without one.
    pub fn new(
        scene: &'a Scene,
        settings: &'a RenderSettings,
        plane: Option<&'a AtomicSplats>,
        kind: FilmKind,
    ) -> Self {
        Splats {
            scene,
            max_component_value: settings.max_component_value,
            film: plane.map(|p| FilmSplats::new(p, &settings.filter, kind)),
        }
    }

    /// Adds radiance `l` (at `lambda` in spectral mode) arriving at film point `p_film`
    /// (pixel units, full image) to the pixels around it, as pbrt-v4's `AddSplat`: turned
    /// into the film's colour as a camera sample is, scaled down to `maxcomponentvalue`, and
    /// spread by the pixel filter ([`FilmSplats::add_splat`]). A non-finite `l` is dropped.
    /// The pixel's final value adds the splat sum over the samples per pixel
    /// ([`crate::film::Film::pixel_rgb`]).
    pub fn add_splat(&self, p_film: Vec2, l: SampledSpectrum, lambda: Option<&SampledWavelengths>) {
        let Some(film) = &self.film else { return };
        if !l.is_finite() {
            return;
        }
        let max = self.max_component_value;
        let rgb = scene_film_rgb(self.scene, lambda, l);
        let m = rgb.max_element();
        let rgb = if m > max { rgb * (max / m) } else { rgb };
        let spectrum = lambda.map(|lambda| {
            let m = l.max_element();
            (if m > max { l * (max / m) } else { l }, lambda)
        });
        film.add_splat(p_film, rgb, spectrum);
    }

    /// [`Splats::add_splat`] of `l` whose film colour is `rgb` (already computed), scaled by
    /// `scale` after the `maxcomponentvalue` clamp: `mlt` clamps its splats L/c as pbrt-v4
    /// does and scales them by b/`mutationsperpixel`, which pbrt-v4 applies to the image.
    pub fn add_splat_scaled(
        &self,
        p_film: Vec2,
        l: SampledSpectrum,
        rgb: Rgb,
        lambda: Option<&SampledWavelengths>,
        scale: f32,
    ) {
        let Some(film) = &self.film else { return };
        if !l.is_finite() || !rgb.is_finite() {
            return;
        }
        let max = self.max_component_value;
        let m = rgb.max_element();
        let rgb = if m > max { rgb * (max / m) } else { rgb };
        let spectrum = lambda.map(|lambda| {
            let m = l.max_element();
            (if m > max { l * (max / m) } else { l } * scale, lambda)
        });
        film.add_splat(p_film, rgb * scale, spectrum);
    }
}

/// Renders sample indices `samples` of every pixel of `tile`, in order, into `film` (a
/// tile's sums of the film's kind), with `integrator`, splatting into `splats`. Returns the
/// tile's totals (samples, rays, non-finite samples). Each sample depends only on (seed,
/// pixel, index), and the sums are fixed-point integers, so any partition of the samples into
/// ranges adds up to the same sums bit for bit. The one tile loop of every film kind: generic
/// over the tile, so each kind's per-sample addition is inlined.
#[allow(clippy::too_many_arguments)] // the loop's inputs, each of its own kind
pub fn render_tile<T: FilmTile, I: SampleIntegrator + ?Sized>(
    scene: &Scene,
    settings: &RenderSettings,
    integrator: &I,
    film: &mut T,
    splats: &Splats<'_>,
    tile: &PixelBounds,
    samples: std::ops::Range<u32>,
) -> RenderStats {
    let counts0 = counts();
    let mut stats = RenderStats::default();
    let mut sampler = Sampler::new(settings.sampler, settings.spp, settings.seed);
    // In spectral mode (radiance integrators only), the sample's wavelengths are drawn from
    // the sampler's next dimension, right after the camera's (so they are, like everything
    // else, a pure function of seed, pixel and sample index), by the film's density. In RGB
    // mode nothing: the dimension layout is the same as before spectral mode existed.
    let spectral = settings.spectral && integrator.computes_radiance();
    if let Some((max_depth, regularize)) = integrator.path_tracer(scene) {
        let path = PathSettings {
            max_depth,
            regularize,
            spectral,
        };
        render_tile_path(
            scene,
            settings,
            &path,
            film,
            &mut sampler,
            tile,
            samples.clone(),
            &mut stats,
        );
    } else {
        render_tile_each(
            scene,
            settings,
            integrator,
            film,
            splats,
            &mut sampler,
            tile,
            samples.clone(),
            spectral,
            &mut stats,
        );
    }
    stats.samples = tile.area() * samples.len() as u64;
    stats.add_counts_since(counts0);
    stats
}

/// [`render_tile`]'s loop for every integrator but the path tracer: each camera sample on its
/// own, in order (with wavelengths when `spectral`).
#[allow(clippy::too_many_arguments)] // render_tile's inputs
#[inline(always)]
fn render_tile_each<T: FilmTile, I: SampleIntegrator + ?Sized>(
    scene: &Scene,
    settings: &RenderSettings,
    integrator: &I,
    film: &mut T,
    splats: &Splats<'_>,
    sampler: &mut Sampler,
    tile: &PixelBounds,
    samples: std::ops::Range<u32>,
    spectral: bool,
    stats: &mut RenderStats,
) {
    let w = tile.width() as usize;
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let i = (y - tile.y0) as usize * w + (x - tile.x0) as usize;
            for s in samples.clone() {
                let (ray, weight, p_film, p_lens) =
                    camera_ray_at(scene, settings, sampler, x, y, s);
                let lambda = spectral.then(|| film.sample_wavelengths(sampler.get_1d()));
                // A ray the camera's lens blocks brings nothing back, but the sample still
                // counts (as pbrt-v4 adds it to the film with its filter weight).
                let l = match &ray {
                    Some(r) => {
                        let at = SampleAt {
                            x,
                            y,
                            weight: weight * r.weight,
                        };
                        integrator.li_at(scene, &r.ray, sampler, lambda.as_ref(), splats, at)
                            * r.weight
                    }
                    None => SampledSpectrum::ZERO,
                };
                let sample = camera_sample::CameraSample {
                    id: SampleId { y, x, sample: s },
                    ray: ray.as_ref(),
                    p_film,
                    p_lens,
                    l,
                    lambda: lambda.as_ref(),
                    weight,
                };
                camera_sample::add(scene, settings, film, stats, i, &sample);
            }
        }
    }
}

/// The path tracer's settings, as [`render_tile_path`] takes them.
struct PathSettings {
    max_depth: u32,
    regularize: bool,
    /// Camera samples carry wavelengths.
    spectral: bool,
}

/// [`render_tile`]'s loop for the path tracer: each pixel's samples in runs of up to eight
/// (aligned on multiples of eight of the sample index, so that a run depends on the sample
/// indices alone), whose camera rays are traced as one packet ([`Scene::intersect_packet`]:
/// the rays of one pixel cross the same boxes); each path then goes on from its first hit,
/// its sampler taken up again where its camera ray left it. Every sample's radiance is what
/// the path tracer ([`crate::integrator::Integrator::li`]) computes for it.
#[allow(clippy::too_many_arguments)] // render_tile's inputs
#[inline(never)]
fn render_tile_path<T: FilmTile>(
    scene: &Scene,
    settings: &RenderSettings,
    path: &PathSettings,
    film: &mut T,
    sampler: &mut Sampler,
    tile: &PixelBounds,
    samples: std::ops::Range<u32>,
    stats: &mut RenderStats,
) {
    use crate::accel::packet::LANES;
    let w = tile.width() as usize;
    let none = Ray::new(crate::math::Vec3::ZERO, crate::math::Vec3::Z);
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let i = (y - tile.y0) as usize * w + (x - tile.x0) as usize;
            // The packets' order: the direction through the pixel's centre (a function of the
            // pixel alone, so that a sample's hit does not depend on which share its packet).
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let order = scene
                .camera()
                .generate_ray(centre, Vec2::splat(0.5))
                .map_or(crate::math::Vec3::Z, |r| r.ray.d);
            let mut s0 = samples.start;
            while s0 < samples.end {
                let s1 = ((s0 / LANES as u32 + 1) * LANES as u32).min(samples.end);
                let n = (s1 - s0) as usize;
                let mut cams: [Option<crate::camera::CameraRay>; LANES] = [None; LANES];
                let mut taken = [(0.0f32, Vec2::ZERO, Vec2::ZERO, 0u32); LANES];
                let mut lambdas: [Option<SampledWavelengths>; LANES] = [None; LANES];
                let mut rays = [none; LANES];
                let mut active = 0u32;
                for k in 0..n {
                    let (ray, weight, p_film, p_lens) =
                        camera_ray_at(scene, settings, sampler, x, y, s0 + k as u32);
                    lambdas[k] = path
                        .spectral
                        .then(|| film.sample_wavelengths(sampler.get_1d()));
                    taken[k] = (weight, p_film, p_lens, sampler.dimension());
                    if let Some(r) = &ray {
                        rays[k] = r.ray;
                        active |= 1 << k;
                    }
                    cams[k] = ray;
                }
                let hits = scene.intersect_packet(&rays, active, order);
                for (k, hit) in hits.iter().enumerate().take(n) {
                    let s = s0 + k as u32;
                    let (weight, p_film, p_lens, dim) = taken[k];
                    let lambda = lambdas[k].as_ref();
                    let l = match &cams[k] {
                        Some(r) => {
                            sampler.resume_pixel_sample(x, y, s as u64, dim);
                            crate::integrator::li_observed::<_, false>(
                                scene,
                                &r.ray,
                                sampler,
                                lambda,
                                path.max_depth,
                                path.regularize,
                                &mut (),
                                Some(hit),
                            ) * r.weight
                        }
                        None => SampledSpectrum::ZERO,
                    };
                    let sample = camera_sample::CameraSample {
                        id: SampleId { y, x, sample: s },
                        ray: cams[k].as_ref(),
                        p_film,
                        p_lens,
                        l,
                        lambda,
                        weight,
                    };
                    camera_sample::add(scene, settings, film, stats, i, &sample);
                }
                s0 = s1;
            }
        }
    }
}

/// The film colour of a camera sample's radiance: the scene's film response (sensor, white
/// balance, output space) when it has one, else the CIE 1931 observer's linear sRGB.
#[inline]
pub(crate) fn scene_film_rgb(
    scene: &Scene,
    lambda: Option<&SampledWavelengths>,
    l: SampledSpectrum,
) -> Rgb {
    match scene.film_response() {
        None => film_rgb(lambda, l),
        Some(r) => r.film_rgb(lambda, l),
    }
}

/// The camera ray of sample `s` of pixel (`x`, `y`) (`None` when a lens blocks it), its
/// filter weight, and the film and lens points it was made from, leaving `sampler` ready for
/// the integrator's dimensions. Inlined: returned from a call, the ray came back through
/// memory in narrow stores that the caller read in wide loads, a store-forwarding stall per
/// camera sample.
#[inline(always)]
fn camera_ray_at(
    scene: &Scene,
    settings: &RenderSettings,
    sampler: &mut Sampler,
    x: i32,
    y: i32,
    s: u32,
) -> (Option<crate::camera::CameraRay>, f32, Vec2, Vec2) {
    sampler.start_pixel_sample(x, y, s as u64);
    let (offset, weight) = settings.filter.sample(sampler.get_pixel_2d());
    let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
    // With motion blur, the sample's time comes next (as in pbrt-v4's GetCameraSample): the
    // camera ray carries it and every ray of its path inherits it; a still scene draws no
    // time, so its dimensions stay as they were.
    let time = scene.motion().map(|m| m.sample_time(sampler.get_1d()));
    let p_lens = sampler.get_2d();
    (
        match time {
            None => scene.camera().generate_ray(p_film, p_lens),
            Some(t) => scene.camera().generate_ray_at(p_film, p_lens, t),
        },
        weight,
        p_film,
        p_lens,
    )
}

/// Replays one camera sample of a film of kind `film`, recording the path the integrator
/// followed (for `--check-nan`): the same radiance as the render computed for it (its
/// wavelengths drawn as the film's tiles draw them), and its vertices.
pub fn trace_sample(
    scene: &Scene,
    settings: &RenderSettings,
    film: FilmKind,
    id: SampleId,
) -> (Rgb, Vec<crate::integrator::PathVertex>) {
    let mut sampler = Sampler::new(settings.sampler, settings.spp, settings.seed);
    let (ray, ..) = camera_ray_at(scene, settings, &mut sampler, id.x, id.y, id.sample);
    let lambda = (settings.spectral && settings.integrator.computes_radiance())
        .then(|| film.sample_wavelengths(sampler.get_1d()));
    let mut path = Vec::new();
    let l = match ray {
        Some(r) => {
            settings
                .integrator
                .li_traced(scene, &r.ray, &mut sampler, lambda.as_ref(), &mut path)
                * r.weight
        }
        None => SampledSpectrum::ZERO,
    };
    // The film's colour, as the render computed it (in spectral mode the path's vertices hold
    // values at the wavelengths).
    (scene_film_rgb(scene, lambda.as_ref(), l), path)
}

/// The film's sums over `tile` (a part of its bounds), row-major.
fn tile_sums(film: &Film, tile: &PixelBounds) -> Vec<PixelSum> {
    let fw = film.bounds.width() as usize;
    let mut out = Vec::with_capacity(tile.area() as usize);
    for y in tile.y0..tile.y1 {
        let row = (y - film.bounds.y0) as usize * fw;
        let a = row + (tile.x0 - film.bounds.x0) as usize;
        out.extend_from_slice(&film.pixels[a..a + tile.width() as usize]);
    }
    out
}

/// Renders `settings.bounds` into `film` on the current rayon pool, tile by tile with all of
/// `settings.samples` at once. `progress(pixels)` is called as tiles finish; `cancel` stops the
/// render between tiles (the film then holds the finished tiles only).
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    progress: &(dyn Fn(u64) + Sync),
    cancel: &AtomicBool,
) -> RenderStats {
    let bounds = settings.bounds.intersect(&film.bounds);
    let units = work_units(
        &bounds,
        settings.tile_size,
        settings.samples.clone(),
        u32::MAX,
    );
    let mut done = vec![false; units.len()];
    render_units(RenderJob {
        scene,
        settings,
        film,
        units: &units,
        done: &mut done,
        on_unit: &|unit, _| progress(unit.tile.area()),
        stop: &|| cancel.load(Ordering::Relaxed),
    })
}

/// Called as each unit of work finishes, with the unit and the film's sums over its tile after
/// the unit was added (row-major over the tile), for progress and live previews. Calls come
/// from the worker threads.
pub type UnitHook<'a> = &'a (dyn Fn(&WorkUnit, &[PixelSum]) + Sync);

/// A piece of work: one tile over one range of sample indices. A render is a list of units;
/// since their sums are added in integer arithmetic, the film does not depend on the order in
/// which units finish, nor on how they are spread over threads, processes or interruptions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorkUnit {
    /// The pixels.
    pub tile: PixelBounds,
    /// The sample indices `[start, end)` taken in each pixel.
    pub samples: std::ops::Range<u32>,
}

/// The units of a render of `bounds` × `samples`: tiles of `tile_size` pixels, sample ranges
/// of at most `pass` samples, pass-major (every tile gets its first pass before any tile gets
/// its second), so an interrupted render holds an evenly converged image.
pub fn work_units(
    bounds: &PixelBounds,
    tile_size: u32,
    samples: std::ops::Range<u32>,
    pass: u32,
) -> Vec<WorkUnit> {
    let tiles = tiles(bounds, tile_size);
    let pass = pass.max(1);
    let mut out = Vec::new();
    let mut s = samples.start;
    while s < samples.end {
        let e = s.saturating_add(pass).min(samples.end);
        out.extend(tiles.iter().map(|t| WorkUnit {
            tile: *t,
            samples: s..e,
        }));
        s = e;
    }
    out
}

/// One call's work, as [`render_units`] (and the renders of mlt, sppm and vcm it hands the
/// work to) take it: the scene and its settings, the film the units are added into, the
/// units and which of them are done, and the two hooks.
pub struct RenderJob<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// What to render.
    pub settings: &'a RenderSettings,
    /// The film the units' sums (and splats) are added into.
    pub film: &'a mut Film,
    /// The units of work (see [`work_units`]).
    pub units: &'a [WorkUnit],
    /// One flag per unit of `units`: true once its sums are in `film`. Units already marked
    /// are skipped (a resumed render).
    pub done: &'a mut [bool],
    /// Called as each unit finishes, with the film's sums over its tile.
    pub on_unit: UnitHook<'a>,
    /// Asked before work starts: once it says yes, no new work starts.
    pub stop: &'a (dyn Fn() -> bool + Sync),
}

impl<'a> RenderJob<'a> {
    /// The job of rendering `units` (those not marked in `done`) of `scene` with `settings`
    /// into `film`, with hooks that do nothing (no report per unit, never stopped).
    pub fn new(
        scene: &'a Scene,
        settings: &'a RenderSettings,
        film: &'a mut Film,
        units: &'a [WorkUnit],
        done: &'a mut [bool],
    ) -> Self {
        RenderJob {
            scene,
            settings,
            film,
            units,
            done,
            on_unit: &|_, _| {},
            stop: &|| false,
        }
    }
}

/// Renders the units of `job.units` not yet marked in `job.done` into `job.film`, marking
/// each one as its sums are added (under the same lock, so the film and `done` always agree).
/// Units run in parallel within a pass (a run of units with the same sample range), passes
/// one after the other. `stop()` is asked before each unit starts: once it says yes, no new
/// unit starts and the call returns when the units in flight have been added (the result's
/// `cancelled` is then true). `on_unit` is called with each finished unit and the film's sums
/// over its tile.
pub fn render_units(job: RenderJob<'_>) -> RenderStats {
    let integrator = &job.settings.integrator;
    render_units_with(job, integrator)
}

/// [`render_units`] with another integrator than the settings' (one that splats, say). The
/// splats of the units rendered are added into the film's splat plane before it returns. An
/// `sppm` integrator ([`SampleIntegrator::sppm`]) is not a sum of units: its iterations run
/// over the whole of `settings.bounds` ([`sppm::render`]), which marks every unit done when
/// they are all finished.
pub fn render_units_with<I: SampleIntegrator + ?Sized>(
    job: RenderJob<'_>,
    integrator: &I,
) -> RenderStats {
    if let Some(options) = integrator.mlt() {
        return mlt::render_chains(job, &options);
    }
    if let Some(options) = integrator.sppm() {
        return sppm::render(job, options);
    }
    if let Some(options) = integrator.vcm() {
        return vcm::render(job, options);
    }
    let RenderJob {
        scene,
        settings,
        film,
        units,
        done,
        on_unit,
        stop,
    } = job;
    let kind = film.kind();
    // One plane shared by the threads, only for an integrator that splats.
    let plane = integrator
        .splats()
        .then(|| AtomicSplats::new(settings.splat_bounds, kind.splat_channels()));
    let splats = Splats::new(scene, settings, plane.as_ref(), kind);
    let state = Mutex::new((&mut *film, done));
    let ctx = UnitContext {
        scene,
        settings,
        integrator,
        splats: &splats,
        state: &state,
        on_unit,
    };
    let totals = Mutex::new(RenderStats::default());
    let mut start = 0;
    while start < units.len() {
        let range = &units[start].samples;
        let len = units[start..]
            .iter()
            .take_while(|u| u.samples == *range)
            .count();
        let pass = start..start + len;
        start += len;
        pass.into_par_iter().for_each(|i| {
            if state.lock().unwrap().1[i] {
                return;
            }
            if stop() {
                totals.lock().unwrap().cancelled = true;
                return;
            }
            let u = &units[i];
            let tile_stats = match kind {
                FilmKind::Rgb => ctx.run(i, u, RgbTile::new(&u.tile)),
                FilmKind::Gbuffer(c) => ctx.run(i, u, GbufferTile::new(c, &u.tile)),
                FilmKind::Spectral(d) => ctx.run(
                    i,
                    u,
                    SpectralTile::new(d, &u.tile, settings.max_component_value),
                ),
            };
            totals.lock().unwrap().add(&tile_stats);
        });
        if totals.lock().unwrap().cancelled {
            break;
        }
    }
    if let Some(p) = plane {
        film.merge_splats(&p.into_plane());
    }
    totals.into_inner().unwrap()
}

/// What every unit of a [`render_units_with`] call shares.
struct UnitContext<'a, I: ?Sized> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    integrator: &'a I,
    splats: &'a Splats<'a>,
    state: &'a Mutex<(&'a mut Film, &'a mut [bool])>,
    on_unit: UnitHook<'a>,
}

impl<I: SampleIntegrator + ?Sized> UnitContext<'_, I> {
    /// Renders unit `i` (`u`) into `sums`, a fresh tile of the film's kind, adds it into the
    /// film and marks it done; returns its totals.
    fn run<T: FilmTile>(&self, i: usize, u: &WorkUnit, mut sums: T) -> RenderStats {
        let stats = render_tile(
            self.scene,
            self.settings,
            self.integrator,
            &mut sums,
            self.splats,
            &u.tile,
            u.samples.clone(),
        );
        let merged = {
            let mut st = self.state.lock().unwrap();
            sums.merge_into(st.0, &u.tile);
            st.1[i] = true;
            tile_sums(st.0, &u.tile)
        };
        (self.on_unit)(u, &merged);
        stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--check-nan`'s replay takes the very sample the render took: on a `spectral` film the
    /// wavelengths are drawn over the buckets' range (not by the visible density), and the
    /// replayed colour is the one the film received, sample by sample.
    #[test]
    fn trace_sample_replays_the_films_wavelengths() {
        use crate::film::spectral::{SpectralDesc, SpectralSums};
        use crate::light::UniformInfiniteDesc;
        use crate::scene::desc::LightDesc;
        let mut d = SceneDesc {
            lights: vec![LightDesc::UniformInfinite(UniformInfiniteDesc {
                l: Rgb::new(0.9, 0.3, 0.1),
            })],
            ..SceneDesc::default()
        };
        d.film.xresolution = 2;
        d.film.yresolution = 1;
        d.sampler.spp = 4;
        let scene = Scene::build(&d).unwrap();
        let settings = RenderSettings::from_desc(&d);
        assert!(settings.spectral && settings.integrator.computes_radiance());
        let spectral = SpectralDesc::default();
        for kind in [FilmKind::Rgb, FilmKind::Spectral(spectral)] {
            for x in 0..2 {
                for s in 0..4 {
                    let pixel = PixelBounds {
                        x0: x,
                        x1: x + 1,
                        y0: 0,
                        y1: 1,
                    };
                    let mut film = Film::new(2, 1, pixel);
                    if let FilmKind::Spectral(desc) = kind {
                        film.spectral = Some(Box::new(SpectralSums::new(desc, 1)));
                    }
                    assert_eq!(film.kind(), kind);
                    let units = work_units(&pixel, 1, s..s + 1, 1);
                    let mut done = vec![false; units.len()];
                    render_units(RenderJob::new(
                        &scene, &settings, &mut film, &units, &mut done,
                    ));
                    let rendered = film.pixels[0].value();
                    let id = SampleId { y: 0, x, sample: s };
                    let (replayed, _) = trace_sample(&scene, &settings, kind, id);
                    assert!(rendered.max_element() > 0.0);
                    assert!(
                        (rendered - replayed).abs().max_element() <= 1e-5 * rendered.max_element(),
                        "{kind:?} {id:?}: rendered {rendered}, replayed {replayed}"
                    );
                }
            }
        }
    }

    #[test]
    fn work_units_cover_every_pixel_sample_once_pass_by_pass() {
        let b = PixelBounds {
            x0: 3,
            x1: 40,
            y0: 1,
            y1: 20,
        };
        let units = work_units(&b, 16, 5..42, 16);
        // Passes 5..21, 21..37, 37..42 over 3 × 2 tiles.
        assert_eq!(units.len(), 3 * 6);
        let mut count = vec![0u32; b.area() as usize * 42];
        let mut last_start = 0;
        for u in &units {
            assert!(u.samples.start >= last_start, "not pass-major");
            last_start = u.samples.start;
            assert!(u.samples.len() <= 16 && !u.samples.is_empty());
            assert_eq!(u.tile.intersect(&b), u.tile);
            for y in u.tile.y0..u.tile.y1 {
                for x in u.tile.x0..u.tile.x1 {
                    let p = ((y - b.y0) * b.width() as i32 + (x - b.x0)) as usize;
                    for s in u.samples.clone() {
                        count[p * 42 + s as usize] += 1;
                    }
                }
            }
        }
        for (i, c) in count.iter().enumerate() {
            let expected = u32::from((5..42).contains(&(i % 42)));
            assert_eq!(*c, expected, "pixel {} sample {}", i / 42, i % 42);
        }
    }
}
