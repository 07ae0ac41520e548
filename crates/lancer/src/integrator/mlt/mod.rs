//! Metropolis light transport in primary sample space over bidirectional path tracing
//! (pbrt-v4's `mlt`; Kelemen et al. 2002, Veach & Guibas 1997): a path is a function of a
//! vector of numbers in [0, 1) ([`sampler::PssSampler`]), and Markov chains wander over those
//! vectors with a stationary density proportional to the luminance c the path brings, so that
//! bright paths are explored more.
//!
//! A vector evaluates one bdpt strategy: its camera stream picks the strategy (s, t) of a path
//! of the chain's depth d (one of the d + 2), the wavelengths, the film point (uniform over the
//! film's sample bounds) and the lens point, then draws the camera subpath of t vertices; its
//! light stream draws the light subpath of s vertices; its connection stream the connection.
//! The contribution is the strategy's, MIS-weighted as bdpt weights it, times d + 2 (the
//! inverse of the strategy's probability): L(u). A t = 1 strategy lands where its light path
//! meets the lens, not on the film point the vector chose.
//!
//! The render ([`crate::render`]): bootstrap vectors (`bootstrapsamples` per depth 0 …
//! `maxdepth`) estimate b = (maxdepth + 1)·mean c(L(u)), the integral of c over the vectors
//! of all depths; each chain starts from a bootstrap vector chosen in proportion to its c (so
//! its depth too), and makes its share of `mutationsperpixel` × (sample bounds' area)
//! mutations. At every mutation both the current and the proposed states are splatted,
//! weighted by their expected values (1 − a and a, a = min(1, c_proposed/c_current)), each as
//! L/c; the image is those sums × b / `mutationsperpixel`.

pub mod sampler;

use super::bdpt;
use crate::film::tile::FilmKind;
use crate::math::{SampledSpectrum, Vec2};
use crate::sampling::SampleSource;
use crate::scene::Scene;
use crate::spectrum::sampled::SampledWavelengths;
use sampler::PssSampler;

pub use super::desc::MltOptions;

/// The camera stream of a vector.
pub const CAMERA_STREAM: usize = 0;
/// The light stream.
pub const LIGHT_STREAM: usize = 1;
/// The connection stream.
pub const CONNECTION_STREAM: usize = 2;

/// What one vector gives: the MIS-weighted contribution times the number of strategies, the
/// film point it lands on, and its wavelengths (spectral mode).
#[derive(Clone, Copy, Debug)]
pub struct PathSample {
    /// L(u), in the lanes of the render.
    pub l: SampledSpectrum,
    /// Film point (raster space, full image).
    pub p_film: Vec2,
    /// The wavelengths (spectral mode).
    pub lambda: Option<SampledWavelengths>,
}

/// The film as the vectors see it.
#[derive(Clone, Copy, Debug)]
pub struct MltFilm {
    /// The film kind whose density draws the wavelengths, in spectral mode (`None`: RGB).
    pub wavelengths: Option<FilmKind>,
    /// [x0, x1, y0, y1]: the film points the camera stream's film point covers (pbrt-v4's
    /// film sample bounds, the rendered pixels grown by the filter's radius less ½).
    pub sample_bounds: [f32; 4],
    /// The rendered pixels' area.
    pub pixel_area: f32,
}

impl MltFilm {
    /// The factor of a t = 1 strategy's contribution, pixel area / sample bounds' area. A
    /// vector's film point is uniform over the sample bounds, so the image, b/mpp × the
    /// splats of area(sample bounds) × mpp mutations, is area(sample bounds) × E[h·L]: for
    /// the t ≥ 2 strategies, whose L is radiance at that film point, that is the pixel's
    /// filtered radiance; a t = 1 strategy's L is bdpt's light-tracing estimate, whose image
    /// is (rendered pixels) × E[h·L] (one light path per pixel sample), so it takes this
    /// factor. (pbrt-v4 leaves it out: its t = 1 strategies come out brighter by the ratio,
    /// 0.8 % on a 256 × 256 film with a radius-1 filter.)
    pub fn light_path_scale(&self) -> f32 {
        let [x0, x1, y0, y1] = self.sample_bounds;
        let area = (x1 - x0) * (y1 - y0);
        if area > 0.0 {
            self.pixel_area / area
        } else {
            0.0
        }
    }
}

/// L(u) for the current state of `x`, a path of `depth` bounces (see the module's
/// documentation), on `film`.
pub fn path_sample(
    scene: &Scene,
    options: &MltOptions,
    depth: u32,
    x: &mut PssSampler,
    film: &MltFilm,
) -> PathSample {
    let (wavelengths, sample_bounds) = (film.wavelengths, film.sample_bounds);
    x.start_stream(CAMERA_STREAM);
    let mut out = PathSample {
        l: SampledSpectrum::ZERO,
        p_film: Vec2::new(sample_bounds[0], sample_bounds[2]),
        lambda: None,
    };
    if scene.lights().is_empty() {
        return out;
    }
    // Strategy (s, t) out of the d + 2 of depth d; depth 0 has only s = 0, t = 2.
    let (s, t, n) = if depth == 0 {
        (0, 2, 1)
    } else {
        let n = depth as usize + 2;
        let s = ((x.get_1d() * n as f32) as usize).min(n - 1);
        (s, n - s, n)
    };
    out.lambda = wavelengths.map(|k| k.sample_wavelengths(x.get_1d()));
    let u = x.get_2d();
    let [x0, x1, y0, y1] = sample_bounds;
    out.p_film = Vec2::new(x0 + u.x * (x1 - x0), y0 + u.y * (y1 - y0));
    let time = scene.motion().map(|m| m.sample_time(x.get_1d()));
    let p_lens = x.get_2d();
    let camera = scene.camera();
    let ray = match time {
        None => camera.generate_ray(out.p_film, p_lens),
        Some(time) => camera.generate_ray_at(out.p_film, p_lens, time),
    };
    let Some(ray) = ray.filter(|r| r.weight != 0.0) else {
        return out;
    };
    let mut next = LIGHT_STREAM;
    let c = bdpt::strategy(
        scene,
        &ray.ray,
        out.lambda.as_ref(),
        options.regularize,
        s,
        t,
        x,
        &mut |x: &mut PssSampler| {
            x.start_stream(next);
            next += 1;
        },
    );
    out.l = c.l * (n as f32 * ray.weight);
    if let Some(p) = c.p_raster {
        out.p_film = p;
        out.l *= film.light_path_scale();
    }
    out
}
