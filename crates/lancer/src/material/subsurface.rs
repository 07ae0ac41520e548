//! The `subsurface` material's link to its BSSRDF: which colours it prepares, and the
//! [`TabulatedBssrdf`] it has at a hit (kept out of [`super::bssrdf`] so that the BSSRDF does
//! not depend on the material enum).

use super::bssrdf::{SubsurfaceCoefficients, TabulatedBssrdf, subsurface_from_diffuse};
use super::{COLOUR_SLOTS, Material, SpectralColours};
use crate::math::{Rgb, SampledSpectrum, Vec3, rgb_lanes};
use crate::spectrum::sampled::{ColourKind, RgbSpectrum};
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
        // A slot's colour as [`Material::bxdf`] reads it: RGB lanes, or the prepared
        // spectrum of a constant, or the uplift of a texel.
        let colour = |slot: usize, t: SpectrumTex, kind: ColourKind| match (spectral, t) {
            (None, _) => {
                let c = tex.spectrum(t, tc);
                rgb_lanes(match kind {
                    ColourKind::Albedo => c.clamp(Rgb::ZERO, Rgb::ONE),
                    ColourKind::Unbounded => c,
                })
            }
            (Some(sc), SpectrumTex::Const(_) | SpectrumTex::Measured(_)) => {
                sc.lambda.sample_prepared(&sc.consts[slot])
            }
            (Some(sc), SpectrumTex::Tex(_)) => sc
                .lambda
                .sample(&RgbSpectrum::new(tex.spectrum(t, tc), kind)),
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
