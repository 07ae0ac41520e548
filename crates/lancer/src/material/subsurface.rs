//! The `subsurface` material's link to its BSSRDF: which colours it prepares, and the
//! [`TabulatedBssrdf`] it has at a hit (kept out of [`super::bssrdf`] so that the BSSRDF does
//! not depend on the material enum).

use super::bssrdf::{SubsurfaceCoefficients, TabulatedBssrdf, subsurface_from_diffuse};
use super::{COLOUR_SLOTS, Material, SpectralColours};
use crate::math::{SampledSpectrum, Vec3};
use crate::spectrum::sampled::ColourKind;
use crate::texture::{SpectrumTex, TexCoord, TextureEval};

impl SubsurfaceCoefficients {
    /// The colours this prepares in spectral mode, by slot: σa, σs (unbounded), or the mean
    /// free path (unbounded) and the colour (albedo).
    pub fn colour_slots(&self) -> [Option<(SpectrumTex, ColourKind)>; COLOUR_SLOTS] {
        use ColourKind::{Albedo, Unbounded};
        match *self {
            SubsurfaceCoefficients::Coefficients { sigma_a, sigma_s } => [
                Some((sigma_a, Unbounded)),
                Some((sigma_s, Unbounded)),
                None,
                None,
            ],
            SubsurfaceCoefficients::Reflectance { reflectance, mfp } => [
                Some((mfp, Unbounded)),
                Some((reflectance, Albedo)),
                None,
                None,
            ],
        }
    }
}

impl Material {
    /// The BSSRDF of a `subsurface` material entered at `po` (shading normal `ns`), with its
    /// textures evaluated there as pbrt-v4's `SubsurfaceMaterial::GetBSSRDF` does: σa, σs
    /// scaled and clamped at 0, or σa, σs from the clamped colour and the scaled mean free
    /// path ([`subsurface_from_diffuse`]). `None` for every other material.
    pub fn bssrdf<'a>(
        &'a self,
        tex: &TextureEval,
        tc: &TexCoord,
        spectral: Option<SpectralColours>,
        po: Vec3,
        ns: Vec3,
    ) -> Option<TabulatedBssrdf<'a>> {
        let Material::Subsurface(m) = self else {
            return None;
        };
        let (coefficients, scale, eta, table) = (&m.coefficients, &m.scale, &m.eta, &m.table);
        // A slot's colour as [`Material::bxdf`] reads it ([`super::slot_colour`]).
        let colour = |slot: usize, t: SpectrumTex, kind: ColourKind| {
            super::slot_colour(tex, tc, spectral, slot, t, kind)
        };
        let (sigma_a, sigma_s) = match *coefficients {
            SubsurfaceCoefficients::Coefficients { sigma_a, sigma_s } => (
                (colour(0, sigma_a, ColourKind::Unbounded) * *scale).max(SampledSpectrum::ZERO),
                (colour(1, sigma_s, ColourKind::Unbounded) * *scale).max(SampledSpectrum::ZERO),
            ),
            SubsurfaceCoefficients::Reflectance { reflectance, mfp } => {
                let mfree =
                    (colour(0, mfp, ColourKind::Unbounded) * *scale).max(SampledSpectrum::ZERO);
                let r = colour(1, reflectance, ColourKind::Albedo)
                    .clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE);
                subsurface_from_diffuse(table, r, mfree)
            }
        };
        let eta = if *eta == 0.0 { 1.0 } else { *eta };
        Some(TabulatedBssrdf::new(po, ns, eta, sigma_a, sigma_s, table))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::bssrdf::{BssrdfTable, SubsurfaceMaterial};
    use crate::math::Rgb;
    use crate::spectrum::dense::{Measured, PreparedSpectrum};
    use crate::spectrum::sampled::SampledWavelengths;
    use crate::spectrum::{Spectrum, SpectrumKind};
    use crate::texture::{FloatTex, SpectrumTexture};

    /// σa from a texture holding a spectrum (a ramp 0 at 300 nm to 2 at 800 nm, scaled by 1)
    /// is that spectrum at the path's wavelengths, not the uplift of its RGB reduction.
    #[test]
    fn textured_coefficients_are_sampled_at_the_wavelengths() {
        let ramp = Spectrum::PiecewiseLinear {
            lambda: vec![300.0, 800.0],
            values: vec![0.0, 2.0],
        };
        let spectra = vec![SpectrumTexture::Scale {
            tex: SpectrumTex::Measured(Measured::new(
                &ramp,
                Rgb::splat(1.0),
                SpectrumKind::Unbounded,
            )),
            scale: FloatTex::Const(1.0),
        }];
        let tex = TextureEval {
            floats: &[],
            spectra: &spectra,
        };
        let m = Material::Subsurface(SubsurfaceMaterial {
            coefficients: SubsurfaceCoefficients::Coefficients {
                sigma_a: SpectrumTex::Tex(0),
                sigma_s: SpectrumTex::Const(Rgb::ONE),
            },
            scale: 3.0,
            eta: 1.33,
            uroughness: FloatTex::Const(0.0),
            vroughness: FloatTex::Const(0.0),
            remap_roughness: true,
            table: BssrdfTable::shared(0.0, 1.33),
        });
        let lambda = SampledWavelengths::sample_visible(0.3);
        // σs's constant slot: 1 everywhere.
        let mut consts = [PreparedSpectrum::BLACK; COLOUR_SLOTS];
        consts[1] = PreparedSpectrum::Rgb(crate::spectrum::sampled::RgbSpectrum::new(
            Rgb::ONE,
            ColourKind::Unbounded,
        ));
        let spectral = Some(SpectralColours {
            lambda: &lambda,
            consts: &consts,
        });
        let b = m
            .bssrdf(&tex, &TexCoord::default(), spectral, Vec3::ZERO, Vec3::Z)
            .unwrap();
        // σt = 3·(ramp(λ) + 1), ramp(λ) = 2(λ − 300)/500.
        let ramp_at = (lambda.lambda - glam::Vec4::splat(300.0)) * (2.0 / 500.0);
        let want = 3.0 * (ramp_at + glam::Vec4::ONE);
        assert!(
            (b.sigma_t - want).abs().max_element() < 1e-2 * want.max_element(),
            "{} vs {want}",
            b.sigma_t
        );
        // Through RGB (the uplift of the ramp's reduction) it would be off by more.
        let via_rgb = lambda.sample(&crate::spectrum::sampled::RgbSpectrum::new(
            tex.spectrum(SpectrumTex::Tex(0), &TexCoord::default()),
            ColourKind::Unbounded,
        ));
        let old = 3.0 * (via_rgb + glam::Vec4::ONE);
        assert!(
            (old - want).abs().max_element() > 1e-2 * want.max_element(),
            "{old} vs {want}"
        );
    }
}
