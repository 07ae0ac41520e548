//! Spectrum textures evaluated at the sampled wavelengths, for texture trees that hold a
//! spectrum given as a spectrum (a named spectrum, `blackbody`, an `.spd` file; a
//! [`SpectrumTex::Measured`] leaf). pbrt-v4 evaluates every spectrum texture at the path's
//! wavelengths; lancer evaluates the others in RGB and uplifts the result (see
//! `Material::bxdf`), which is exact for a single leaf but would reduce a measured leaf to its
//! RGB. Here the tree is walked with [`SampledSpectrum`] values: a measured leaf gives its
//! table's values, any other node's RGB value is uplifted as `kind`, and the combining
//! textures (checkerboard, scale, mix, dots, directionmix) combine the sampled values as
//! pbrt-v4 combines them.

use super::eval::{checker, checker_3d};
use super::procedural::inside_polka_dot;
use super::{SpectrumTex, SpectrumTexture, TexCoord, TextureEval};
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
        match &self.spectra[i as usize] {
            SpectrumTexture::Checkerboard { tex1, tex2, .. }
            | SpectrumTexture::Checkerboard3D { tex1, tex2, .. }
            | SpectrumTexture::Mix { tex1, tex2, .. }
            | SpectrumTexture::DirectionMix { tex1, tex2, .. } => {
                self.has_measured(*tex1) || self.has_measured(*tex2)
            }
            SpectrumTexture::Dots {
                dot, background, ..
            } => self.has_measured(*dot) || self.has_measured(*background),
            SpectrumTexture::Scale { tex, .. } => self.has_measured(*tex),
            SpectrumTexture::Constant(_)
            | SpectrumTexture::Image(_)
            | SpectrumTexture::Bilerp { .. }
            | SpectrumTexture::Marble { .. } => false,
        }
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
    fn uplifted(
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

    fn sampled(
        &self,
        t: SpectrumTex,
        tc: &TexCoord,
        lambda: &SampledWavelengths,
        kind: ColourKind,
    ) -> SampledSpectrum {
        let uplift = |t: SpectrumTex| self.uplifted(t, tc, lambda, kind);
        let i = match t {
            SpectrumTex::Measured(m) => return m.spectrum.sample(lambda),
            SpectrumTex::Const(_) => return uplift(t),
            SpectrumTex::Tex(i) => i,
        };
        let pick = |cond: bool, a: SpectrumTex, b: SpectrumTex| {
            self.sampled(if cond { a } else { b }, tc, lambda, kind)
        };
        match &self.spectra[i as usize] {
            SpectrumTexture::Checkerboard {
                mapping,
                tex1,
                tex2,
            } => pick(checker(mapping, tc), *tex1, *tex2),
            SpectrumTexture::Checkerboard3D {
                mapping,
                tex1,
                tex2,
            } => pick(checker_3d(mapping, tc), *tex1, *tex2),
            SpectrumTexture::Dots {
                mapping,
                dot,
                background,
            } => pick(inside_polka_dot(mapping.map(tc)), *dot, *background),
            // scale · tex, 0 without evaluating tex when the scale is 0 (pbrt-v4).
            SpectrumTexture::Scale { tex, scale } => {
                let s = self.float(*scale, tc);
                if s == 0.0 {
                    SampledSpectrum::ZERO
                } else {
                    self.sampled(*tex, tc, lambda, kind) * s
                }
            }
            // (1 − a)·tex1 + a·tex2.
            SpectrumTexture::Mix { tex1, tex2, amount } => {
                let a = self.float(*amount, tc);
                self.sampled(*tex1, tc, lambda, kind) * (1.0 - a)
                    + self.sampled(*tex2, tc, lambda, kind) * a
            }
            // |n·dir|·tex1 + (1 − |n·dir|)·tex2.
            SpectrumTexture::DirectionMix { tex1, tex2, dir } => {
                let a = tc.n.dot(*dir).abs();
                self.sampled(*tex1, tc, lambda, kind) * a
                    + self.sampled(*tex2, tc, lambda, kind) * (1.0 - a)
            }
            SpectrumTexture::Constant(_)
            | SpectrumTexture::Image(_)
            | SpectrumTexture::Bilerp { .. }
            | SpectrumTexture::Marble { .. } => uplift(t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Rgb, Vec2, Vec3};
    use crate::spectrum::dense::Measured;
    use crate::spectrum::{Spectrum, SpectrumKind};
    use crate::texture::{FloatTex, Mapping2D};

    /// A ramp 0 at 300 nm to 1 at 800 nm: (λ − 300)/500.
    fn ramp() -> Measured {
        let s = Spectrum::PiecewiseLinear {
            lambda: vec![300.0, 800.0],
            values: vec![0.0, 1.0],
        };
        Measured::new(&s, Rgb::splat(0.5), SpectrumKind::Albedo)
    }

    #[test]
    fn a_measured_leaf_is_sampled_at_the_wavelengths_not_through_rgb() {
        let spectra = vec![
            // 0: checkerboard, the ramp on even cells, grey 0.25 on odd ones.
            SpectrumTexture::Checkerboard {
                mapping: Mapping2D::default(),
                tex1: SpectrumTex::Measured(ramp()),
                tex2: SpectrumTex::Const(Rgb::splat(0.25)),
            },
            // 1: mix of the ramp and black, amount 0.25: 0.75 · ramp.
            SpectrumTexture::Mix {
                tex1: SpectrumTex::Measured(ramp()),
                tex2: SpectrumTex::Const(Rgb::ZERO),
                amount: FloatTex::Const(0.25),
            },
            // 2: a checkerboard of constants only.
            SpectrumTexture::Checkerboard {
                mapping: Mapping2D::default(),
                tex1: SpectrumTex::Const(Rgb::ONE),
                tex2: SpectrumTex::Const(Rgb::ZERO),
            },
        ];
        let ev = TextureEval {
            floats: &[],
            spectra: &spectra,
        };
        let lambda = SampledWavelengths::sample_visible(0.3);
        let want = (lambda.lambda - glam::Vec4::splat(300.0)) / 500.0;
        let tc = |u: f32| TexCoord {
            uv: Vec2::new(u, 0.5),
            n: Vec3::Z,
            ..TexCoord::default()
        };
        let at =
            |i, u| ev.spectrum_sampled(SpectrumTex::Tex(i), &tc(u), &lambda, ColourKind::Albedo);
        // u = 0.5: cell (0, 0), even: the ramp itself.
        assert!(
            (at(0, 0.5) - want).abs().max_element() < 2e-3,
            "{}",
            at(0, 0.5)
        );
        // u = 1.5: cell (1, 0), odd: uplifted grey 0.25, flat.
        let grey = at(0, 1.5);
        assert!(
            (grey - glam::Vec4::splat(0.25)).abs().max_element() < 2e-3,
            "{grey}"
        );
        assert!((at(1, 0.5) - 0.75 * want).abs().max_element() < 2e-3);
        assert!(ev.has_measured(SpectrumTex::Tex(0)) && ev.has_measured(SpectrumTex::Tex(1)));
        assert!(!ev.has_measured(SpectrumTex::Tex(2)));
        // What a material reads (`spectrum_at`) is the ramp, not the uplift of the tree's RGB
        // value (the ramp's RGB is grey 0.5: a flat 0.5 across the wavelengths).
        let read = ev.spectrum_at(SpectrumTex::Tex(0), &tc(0.5), &lambda, ColourKind::Albedo);
        assert_eq!(read, at(0, 0.5));
        let through_rgb = ev.uplifted(SpectrumTex::Tex(0), &tc(0.5), &lambda, ColourKind::Albedo);
        assert!((through_rgb - glam::Vec4::splat(0.5)).abs().max_element() < 2e-3);
        assert!(
            (read - through_rgb).abs().max_element() > 0.1,
            "{read} {through_rgb}"
        );
        // A tree of constants only reads as its uplift.
        let plain = ev.spectrum_at(SpectrumTex::Tex(2), &tc(0.5), &lambda, ColourKind::Albedo);
        assert_eq!(
            plain,
            ev.uplifted(SpectrumTex::Tex(2), &tc(0.5), &lambda, ColourKind::Albedo)
        );
    }
}
