//! A path's memo of the scene's constant spectra at its wavelengths.
//!
//! In spectral mode a constant colour is uplifted once per scene (a sigmoid polynomial, see
//! [`crate::spectrum::dense::PreparedSpectrum`]), but it still has to be evaluated at each
//! path's four wavelengths: s(λ) = ½ + x / (2√(1 + x²)), a square root and a division per
//! lane, at every hit (the material's reflectance) and every light sample (the emitter's
//! spectrum). A path keeps its wavelengths from the camera to its end (terminating the
//! secondary wavelengths changes their densities, not their values), and in most scenes it
//! meets the same few materials and lights again and again, so it evaluates each once and
//! reuses the value: the same numbers, bit for bit, as evaluating it each time.

use crate::math::{Rgb, SampledSpectrum, Vec3, rgb_lanes};
use crate::scene::{Scene, SceneHit};
use crate::spectrum::sampled::SampledWavelengths;

/// Slots of the material memo, chosen by the material's index modulo this.
const MATERIAL_SLOTS: usize = 4;

/// No key: a slot that holds nothing (no scene has 2³² − 1 materials or lights).
const EMPTY: u32 = u32::MAX;

/// The memo of one path (spectral mode only; RGB mode has nothing to evaluate).
pub(crate) struct PathSpectra {
    /// Material index whose reflectance each slot holds.
    material_keys: [u32; MATERIAL_SLOTS],
    /// Those reflectances at the path's wavelengths.
    materials: [SampledSpectrum; MATERIAL_SLOTS],
    /// Key ([`crate::scene::SceneSpectra::light_keys`]) of the lights whose prepared
    /// spectrum `light` holds.
    light_key: u32,
    /// Its emission at the path's wavelengths, before the sample's factor.
    light: SampledSpectrum,
}

impl PathSpectra {
    /// An empty memo, for a new path.
    #[inline]
    pub(crate) fn new() -> PathSpectra {
        PathSpectra {
            material_keys: [EMPTY; MATERIAL_SLOTS],
            materials: [SampledSpectrum::ZERO; MATERIAL_SLOTS],
            light_key: EMPTY,
            light: SampledSpectrum::ZERO,
        }
    }

    /// The constant reflectance of material `m` at the path's wavelengths, evaluated by
    /// `eval` on its first use.
    #[inline(always)]
    pub(crate) fn material(
        &mut self,
        m: u32,
        eval: impl FnOnce() -> SampledSpectrum,
    ) -> SampledSpectrum {
        let slot = m as usize % MATERIAL_SLOTS;
        if self.material_keys[slot] != m {
            self.materials[slot] = eval();
            self.material_keys[slot] = m;
        }
        self.materials[slot]
    }

    /// [`Scene::light_radiance`], remembering the last light's prepared spectrum: with one, the
    /// radiance is that spectrum times `factor` whatever `l` is (`l` is its colour times
    /// `factor`), so the spectrum is evaluated once per path (as `light_radiance` with factor 1,
    /// an exact product). Lights that share their prepared spectrum (the triangles of one
    /// emitting mesh) share one key, so a path alternating between them evaluates it once.
    #[inline(always)]
    pub(crate) fn light_radiance(
        &mut self,
        scene: &Scene,
        i: usize,
        lambda: Option<&SampledWavelengths>,
        l: Rgb,
        factor: f32,
        wi: Vec3,
    ) -> SampledSpectrum {
        // RGB mode: the colour's lanes, as `Scene::light_radiance` gives them (without
        // preparing the scene's spectra, which RGB mode never does).
        if lambda.is_none() {
            return rgb_lanes(l);
        }
        let spectra = scene.spectra();
        if spectra.lights[i].is_none() {
            return scene.light_radiance(i, lambda, l, factor, wi);
        }
        let key = spectra.light_keys[i];
        if self.light_key != key {
            self.light = scene.light_radiance(i, lambda, l, 1.0, wi);
            self.light_key = key;
        }
        self.light * factor
    }

    /// [`super::emitted`], through [`PathSpectra::light_radiance`].
    #[inline(always)]
    pub(crate) fn emitted(
        &mut self,
        scene: &Scene,
        hit: &SceneHit,
        wo: Vec3,
        lambda: Option<&SampledWavelengths>,
    ) -> SampledSpectrum {
        match super::emission::emission_towards(scene, hit, wo) {
            Some((i, l)) => self.light_radiance(scene, i, lambda, l, 1.0, -wo),
            None => SampledSpectrum::ZERO,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each material is evaluated once while it keeps its slot; one that shares the slot
    /// (index + 4) replaces it, and every lookup returns its own material's value.
    #[test]
    fn material_memo_evaluates_once_per_slot_holder() {
        let value = |m: u32| SampledSpectrum::new(m as f32, 0.5, 0.25, 1.0 / (m as f32 + 1.0));
        let mut memo = PathSpectra::new();
        let mut evals = Vec::new();
        for m in [1u32, 1, 2, 1, 5, 5, 1, 0, 2, u32::MAX - 1] {
            let got = memo.material(m, || {
                evals.push(m);
                value(m)
            });
            assert_eq!(got, value(m), "material {m}");
        }
        // 1 and 5 share slot 1 and evict each other; 2 and 0 keep theirs.
        assert_eq!(evals, vec![1, 2, 5, 1, 0, u32::MAX - 1]);
    }
}
