//! Spectral mode's preparation of a scene: every constant colour of its materials and lights
//! turned into a spectrum once ([`RgbSpectrum`]), so that a path only evaluates it at its
//! wavelengths. Textures and image environments keep their texels, uplifted per lookup.

use super::Scene;
use crate::light::Light;
use crate::material::{COLOUR_SLOTS, Material};
use crate::math::{Rgb, SampledSpectrum, rgb_lanes};
use crate::spectrum::sampled::{ColourKind, RgbSpectrum, SampledWavelengths};
use crate::texture::SpectrumTex;

/// A scene's constant colours as spectra, made on first use in spectral mode (RGB mode never
/// makes them, so it never builds the uplift's coefficient table for them).
#[derive(Debug)]
pub struct SceneSpectra {
    /// Per light (the indices of [`Scene::lights`]): its constant colour
    /// ([`Light::constant_colour`]) as an unbounded spectrum; `None` for image environments.
    pub lights: Vec<Option<RgbSpectrum>>,
    /// Per material (the indices of [`Scene::materials`]): its constant colours by slot
    /// ([`Material::colour_slots`]); slots without a constant hold black.
    pub materials: Vec<[RgbSpectrum; COLOUR_SLOTS]>,
}

const BLACK: RgbSpectrum = RgbSpectrum {
    scale: 0.0,
    s: crate::spectrum::uplift::SigmoidSpectrum::Constant(0.0),
};

impl SceneSpectra {
    /// Uplifts the constant colours of `lights` and `materials`. Consecutive lights of the
    /// same colour (the triangles of one emitting mesh) share one uplift.
    pub fn new(lights: &[Light], materials: &[Material]) -> SceneSpectra {
        let mut last: Option<(Rgb, RgbSpectrum)> = None;
        let lights = lights
            .iter()
            .map(|l| {
                let c = l.constant_colour()?;
                let sp = match last {
                    Some((lc, sp)) if lc == c => sp,
                    _ => RgbSpectrum::new(c, ColourKind::Unbounded),
                };
                last = Some((c, sp));
                Some(sp)
            })
            .collect();
        let materials = materials
            .iter()
            .map(|m| {
                m.colour_slots().map(|slot| match slot {
                    Some((SpectrumTex::Const(c), kind)) => RgbSpectrum::new(c, kind),
                    _ => BLACK,
                })
            })
            .collect();
        SceneSpectra { lights, materials }
    }
}

impl Scene {
    /// The scene's constant colours as spectra, prepared on the first call.
    pub fn spectra(&self) -> &SceneSpectra {
        self.spectra
            .get_or_init(|| SceneSpectra::new(&self.lights, &self.materials))
    }

    /// Emission `l` of light `i`, which is its constant colour times `factor` (see
    /// [`crate::light::LightLiSample::factor`]), as transport lanes: in spectral mode the
    /// light's prepared spectrum as an illuminant, times `factor` (lights without a constant
    /// colour uplift `l` itself); in RGB mode `l`'s lanes (r, g, b, b).
    #[inline]
    pub fn light_radiance(
        &self,
        i: usize,
        lambda: Option<&SampledWavelengths>,
        l: Rgb,
        factor: f32,
    ) -> SampledSpectrum {
        match lambda {
            None => rgb_lanes(l),
            Some(w) => match &self.spectra().lights[i] {
                Some(sp) => w.sample_illuminant(sp) * factor,
                None => w.illuminant(l),
            },
        }
    }
}
