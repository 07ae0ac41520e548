//! What one camera sample adds to a tile of the film (the tile loop's, and `vcm`'s, which
//! takes its camera samples in its own passes): its colour under the rules for NaN and
//! `maxcomponentvalue`, its sensor colour and visible surface when the tile reads them.

use super::{RenderSettings, RenderStats, SampleId, scene_film_rgb};
use crate::film::tile::{FilmSample, FilmTile};
use crate::gbuffer::{RayDifferentials, visible_surface};
use crate::math::{Rgb, SampledSpectrum, Vec2};
use crate::scene::Scene;
use crate::spectrum::sampled::SampledWavelengths;

/// One camera sample as the film takes it: which it is, its camera ray (`None`: the lens
/// blocked it), the film and lens points it was made from, its radiance (camera weight
/// included) at its wavelengths, and its filter weight.
pub(crate) struct CameraSample<'a> {
    /// Pixel and sample index.
    pub id: SampleId,
    /// The camera ray.
    pub ray: Option<&'a crate::camera::CameraRay>,
    /// Film point (raster space).
    pub p_film: Vec2,
    /// Lens sample.
    pub p_lens: Vec2,
    /// Radiance, the camera's weight included.
    pub l: SampledSpectrum,
    /// Wavelengths (spectral mode).
    pub lambda: Option<&'a SampledWavelengths>,
    /// Filter weight.
    pub weight: f32,
}

/// Adds camera sample `c` to pixel `i` of `film` (a tile's sums): its film colour (black if
/// not finite, counted in `stats`; scaled down to `maxcomponentvalue`), its sensor colour and
/// visible surface when the tile reads them. The tile loop's, and `vcm`'s.
#[inline(always)]
pub(super) fn add<T: FilmTile>(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut T,
    stats: &mut RenderStats,
    i: usize,
    c: &CameraSample<'_>,
) {
    let rgb = scene_film_rgb(scene, c.lambda, c.l);
    let sensor_rgb = if T::NEEDS_SENSOR_RGB {
        crate::gbuffer::variance_rgb(scene, rgb, settings.max_component_value)
    } else {
        Rgb::ZERO
    };
    let rgb = film_sample(settings, stats, rgb, c.id);
    let surface = if T::NEEDS_SURFACE {
        c.ray.and_then(|r| {
            // The denoiser's surface (through specular surfaces) needs no footprint.
            let follow = film.follows_specular();
            let scale = film.differential_scale();
            let diff = (!follow)
                .then(|| RayDifferentials::of(scene, &r.ray, c.p_film, c.p_lens, scale))
                .flatten();
            visible_surface(scene, &r.ray, diff.as_ref(), follow)
        })
    } else {
        None
    };
    let sample = FilmSample {
        rgb,
        sensor_rgb,
        l: c.l,
        lambda: c.lambda,
        surface: surface.as_ref(),
    };
    film.add_sample(i, &sample, c.weight);
}

/// What a camera sample's colour adds to the film: black for a non-finite sample (a bug
/// upstream, counted in `stats`; it must not poison the pixel), and scaled down to
/// `maxcomponentvalue` when brighter.
#[inline(always)]
fn film_sample(settings: &RenderSettings, stats: &mut RenderStats, l: Rgb, id: SampleId) -> Rgb {
    let l = if l.is_finite() {
        l
    } else {
        stats.nonfinite += 1;
        if stats.first_nonfinite.is_none() {
            stats.first_nonfinite = Some(id);
        }
        Rgb::ZERO
    };
    let m = l.max_element();
    if m > settings.max_component_value {
        l * (settings.max_component_value / m)
    } else {
        l
    }
}
