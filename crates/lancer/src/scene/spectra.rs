//! Spectral mode's preparation of a scene: every constant colour of its materials and lights
//! turned into a spectrum once ([`PreparedSpectrum`]: an uplifted RGB colour, or the table of a
//! spectrum the scene gave as one), so that a path only evaluates it at its wavelengths.
//! Textures and image environments keep their texels, uplifted per lookup.

use crate::light::Light;
use crate::material::{COLOUR_SLOTS, Material};
use crate::math::Rgb;
use crate::spectrum::dense::{Measured, PreparedSpectrum};
use crate::spectrum::sampled::{ColourKind, RgbSpectrum};
use crate::texture::SpectrumTex;

/// A scene's constant colours as spectra, made on first use in spectral mode (RGB mode never
/// makes them, so it never builds the uplift's coefficient table for them).
#[derive(Debug)]
pub struct SceneSpectra {
    /// Per light (the indices of [`super::Scene::lights`]): its constant colour
    /// ([`Light::constant_colour`]) as an unbounded spectrum, or the spectrum the scene gave
    /// scaled to that colour's luminance; `None` for image environments.
    pub lights: Vec<Option<PreparedSpectrum>>,
    /// Per material (the indices of [`super::Scene::materials`]): its constant colours by slot
    /// ([`Material::colour_slots`]); slots without a constant hold black.
    pub materials: Vec<[PreparedSpectrum; COLOUR_SLOTS]>,
}

impl SceneSpectra {
    /// Prepares the constant colours of `lights` (with `light_spectra`, per light the spectrum
    /// its colour is a multiple of, if any) and `materials`. Consecutive lights of the same
    /// colour and spectrum (the triangles of one emitting mesh) share one preparation.
    pub fn new(
        lights: &[Light],
        light_spectra: &[Option<Measured>],
        materials: &[Material],
    ) -> SceneSpectra {
        let mut last: Option<(Rgb, Option<Measured>, PreparedSpectrum)> = None;
        let lights = lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let c = l.constant_colour()?;
                let m = light_spectra.get(i).copied().flatten();
                let sp = match last {
                    Some((lc, lm, sp)) if lc == c && lm == m => sp,
                    _ => match &m {
                        Some(m) => PreparedSpectrum::light(c, m),
                        None => PreparedSpectrum::Rgb(RgbSpectrum::new(c, ColourKind::Unbounded)),
                    },
                };
                last = Some((c, m, sp));
                Some(sp)
            })
            .collect();
        let materials = materials
            .iter()
            .map(|m| {
                m.colour_slots().map(|slot| match slot {
                    Some((SpectrumTex::Const(c), kind)) => {
                        PreparedSpectrum::Rgb(RgbSpectrum::new(c, kind))
                    }
                    Some((SpectrumTex::Measured(m), _)) => PreparedSpectrum::Dense {
                        scale: 1.0,
                        spectrum: m.spectrum,
                    },
                    _ => PreparedSpectrum::BLACK,
                })
            })
            .collect();
        SceneSpectra { lights, materials }
    }
}
