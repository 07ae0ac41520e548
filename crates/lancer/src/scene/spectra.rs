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
    /// Per light, the first light of its run of consecutive lights sharing one preparation
    /// (its own index when it shares none): lights with the same key have the same spectrum.
    pub light_keys: Vec<u32>,
    /// Per material (the indices of [`super::Scene::material`]): its constant colours by slot
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
        let mut last: Option<(Rgb, Option<Measured>, PreparedSpectrum, u32)> = None;
        let mut light_keys = Vec::with_capacity(lights.len());
        let lights = lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let Some(c) = l.constant_colour() else {
                    light_keys.push(i as u32);
                    last = None;
                    return None;
                };
                let m = light_spectra.get(i).copied().flatten();
                let (sp, key) = match last {
                    Some((lc, lm, sp, key)) if lc == c && lm == m => (sp, key),
                    _ => match &m {
                        Some(m) => (PreparedSpectrum::light(c, m), i as u32),
                        None => (
                            PreparedSpectrum::Rgb(RgbSpectrum::new(c, ColourKind::Unbounded)),
                            i as u32,
                        ),
                    },
                };
                last = Some((c, m, sp, key));
                light_keys.push(key);
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
        SceneSpectra {
            lights,
            light_keys,
            materials,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// A run of lights of one colour shares its first light's key and preparation; a light of
    /// another colour, and one of the first colour after it, start runs of their own.
    #[test]
    fn consecutive_lights_of_one_colour_share_a_key() {
        let point = |c: Rgb| {
            Light::Point(crate::light::PointLight {
                p: Vec3::ZERO,
                intensity: c,
            })
        };
        let (a, b) = (Rgb::new(1.0, 0.5, 0.25), Rgb::new(0.2, 0.4, 3.0));
        let s = SceneSpectra::new(
            &[point(a), point(a), point(a), point(b), point(a)],
            &[],
            &[],
        );
        assert_eq!(s.light_keys, vec![0, 0, 0, 3, 4]);
        assert_eq!(s.lights[0], s.lights[2]);
        assert_eq!(s.lights[0], s.lights[4]);
        assert_ne!(s.lights[0], s.lights[3]);
    }
}
