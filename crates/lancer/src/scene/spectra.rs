//! Spectral mode's preparation of a scene: every constant colour of its materials and lights
//! turned into a spectrum once ([`RgbSpectrum`]), so that a path only evaluates it at its
//! wavelengths. Textures and image environments keep their texels, uplifted per lookup.

use crate::light::Light;
use crate::material::{COLOUR_SLOTS, Material};
use crate::math::Rgb;
use crate::spectrum::sampled::{ColourKind, RgbSpectrum};
use crate::texture::SpectrumTex;

/// A scene's constant colours as spectra, made on first use in spectral mode (RGB mode never
/// makes them, so it never builds the uplift's coefficient table for them).
#[derive(Debug)]
pub struct SceneSpectra {
    /// Per light (the indices of [`super::Scene::lights`]): its constant colour
    /// ([`Light::constant_colour`]) as an unbounded spectrum; `None` for image environments.
    pub lights: Vec<Option<RgbSpectrum>>,
    /// Per material (the indices of [`super::Scene::materials`]): its constant colours by slot
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
