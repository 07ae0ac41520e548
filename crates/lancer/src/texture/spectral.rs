//! Spectrum textures evaluated at the sampled wavelengths, for texture trees that hold a
//! spectrum given as a spectrum (a named spectrum, `blackbody`, an `.spd` file; a
//! [`SpectrumTex::Measured`] leaf). pbrt-v4 evaluates every spectrum texture at the path's
//! wavelengths; lancer evaluates the others in RGB and uplifts the result (see
//! `Material::bxdf`), which is exact for a single leaf but would reduce a measured leaf to its
//! RGB. Here the tree is walked with [`SampledSpectrum`] values: a measured leaf gives its
//! table's values, any other node's RGB value is uplifted as `kind`, and the combining
//! textures (checkerboard, scale, mix, dots, directionmix) combine the sampled values as
//! pbrt-v4 combines them.

use super::kinds::{SampledAt, TextureEval};
use super::{SpectrumTex, TexCoord};
use crate::math::SampledSpectrum;
use crate::spectrum::sampled::{ColourKind, RgbSpectrum, SampledWavelengths};

impl TextureEval<'_> {
    /// Whether `t` holds a [`SpectrumTex::Measured`] leaf, so that
    /// [`TextureEval::spectrum_sampled`] differs from the uplift of [`TextureEval::spectrum`].
    pub fn has_measured(&self, t: SpectrumTex) -> bool {
        let i = match t {
            SpectrumTex::Measured(_) => return true,
            SpectrumTex::Const(_) => return false,
            SpectrumTex::Tex(i) => i,
        };
        self.spectra[i as usize].has_measured(self)
    }

    /// A spectrum texture at `tc` and the wavelengths `lambda` as a material reads it: the
    /// uplift (as `kind`) of its RGB value, or, for a tree holding a spectrum given as a
    /// spectrum, [`TextureEval::spectrum_sampled`].
    #[inline]
    pub fn spectrum_at(
        &self,
        t: SpectrumTex,
        tc: &TexCoord,
        lambda: &SampledWavelengths,
        kind: ColourKind,
    ) -> SampledSpectrum {
        if self.has_measured(t) {
            self.spectrum_sampled(t, tc, lambda, kind)
        } else {
            self.uplifted(t, tc, lambda, kind)
        }
    }

    /// The RGB value of `t` at `tc` uplifted as `kind` and taken at `lambda` (the uplift is
    /// in [0, 1] for an albedo and non-negative for an unbounded colour).
    #[inline]
    pub(super) fn uplifted(
        &self,
        t: SpectrumTex,
        tc: &TexCoord,
        lambda: &SampledWavelengths,
        kind: ColourKind,
    ) -> SampledSpectrum {
        lambda.sample(&RgbSpectrum::new(self.spectrum(t, tc), kind))
    }

    /// The value of `t` at `tc` and the wavelengths `lambda`, its RGB values uplifted as
    /// `kind`; an albedo is clamped to [0, 1] at the end, as pbrt-v4's materials clamp
    /// reflectances.
    pub fn spectrum_sampled(
        &self,
        t: SpectrumTex,
        tc: &TexCoord,
        lambda: &SampledWavelengths,
        kind: ColourKind,
    ) -> SampledSpectrum {
        let s = self.sampled(t, tc, lambda, kind);
        match kind {
            ColourKind::Albedo => s.clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE),
            ColourKind::Unbounded => s.max(SampledSpectrum::ZERO),
        }
    }

    /// The value of `t` at `tc` and `lambda`, not clamped: a measured leaf's table, a
    /// combining texture's combination of its parameters' values (its kind's
    /// [`super::kinds::TextureKind::sampled`]), any other value's uplift.
    pub(super) fn sampled(
        &self,
        t: SpectrumTex,
        tc: &TexCoord,
        lambda: &SampledWavelengths,
        kind: ColourKind,
    ) -> SampledSpectrum {
        let i = match t {
            SpectrumTex::Measured(m) => return m.spectrum.sample(lambda),
            SpectrumTex::Const(_) => return self.uplifted(t, tc, lambda, kind),
            SpectrumTex::Tex(i) => i,
        };
        let at = SampledAt {
            ev: self,
            tc,
            lambda,
            kind,
        };
        self.spectra[i as usize]
            .sampled(&at)
            .unwrap_or_else(|| self.uplifted(t, tc, lambda, kind))
    }
}
