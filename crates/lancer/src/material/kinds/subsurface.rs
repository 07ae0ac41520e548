//! The `subsurface` material: a dielectric boundary over a scattering medium, rendered with a
//! BSSRDF ([`TabulatedBssrdf`]). Its description gives the medium; the build adds the profile
//! table for the medium's g and η ([`BssrdfTable::shared`]), which the BSSRDF reads at a hit.

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS, nonzero_eta};
use crate::material::bssrdf::{BssrdfTable, TabulatedBssrdf, subsurface_from_diffuse};
use crate::material::{BxDF, DielectricBxdf, Material};
use crate::math::{SampledSpectrum, Vec3};
use crate::spectrum::sampled::ColourKind;
use crate::texture::{FloatTex, SpectrumTex};
use std::sync::Arc;

/// Positions in the material's [`Colours`]: σa, or the mean free path.
const SIGMA_A_OR_MFP: usize = 0;
/// σs, or the colour.
const SIGMA_S_OR_COLOUR: usize = 1;

/// pbrt-v4's `subsurface` material, plain data; built into a [`BuiltSubsurface`].
#[derive(Clone, Debug, PartialEq)]
pub struct SubsurfaceMaterial {
    /// σa and σs, or a colour and mean free path.
    pub coefficients: SubsurfaceCoefficients,
    /// Multiplies σa and σs (or the mean free path).
    pub scale: f32,
    /// Index of refraction of the boundary and the medium.
    pub eta: f32,
    /// Boundary roughness along u.
    pub uroughness: FloatTex,
    /// Boundary roughness along v.
    pub vroughness: FloatTex,
    /// Map roughness to α as pbrt does.
    pub remap_roughness: bool,
    /// Henyey–Greenstein asymmetry of the medium (its profile table's g).
    pub g: f32,
}

/// How a subsurface material gives its medium (pbrt-v4's `subsurface` parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SubsurfaceCoefficients {
    /// σa and σs (per unit length, times `scale`), given or from a named preset.
    Coefficients {
        /// Absorption.
        sigma_a: SpectrumTex,
        /// Scattering.
        sigma_s: SpectrumTex,
    },
    /// The diffuse colour the surface should have, and the mean free path (times `scale`):
    /// σa and σs follow by inverting the table's effective albedo.
    Reflectance {
        /// The colour.
        reflectance: SpectrumTex,
        /// Mean free path 1/σt.
        mfp: SpectrumTex,
    },
}

/// A `subsurface` material ready to render: its description and the profile table of its
/// medium's g and η.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltSubsurface {
    /// What the scene gave.
    pub desc: SubsurfaceMaterial,
    /// The profile table for the medium's g and η ([`BssrdfTable::shared`]).
    pub table: Arc<BssrdfTable>,
}

impl MaterialDescKind for SubsurfaceMaterial {
    type Built = BuiltSubsurface;
    const PBRT_NAME: &'static str = "subsurface";
    fn build(&self) -> BuiltSubsurface {
        BuiltSubsurface {
            desc: self.clone(),
            table: BssrdfTable::shared(self.g, self.eta),
        }
    }
}

impl MaterialKind for BuiltSubsurface {
    /// σa, σs (unbounded), or the mean free path (unbounded) and the colour (albedo).
    #[inline(always)]
    fn colours(&self) -> Colours {
        use ColourKind::{Albedo, Unbounded};
        let mut c = NO_COLOURS;
        let (a, b) = match self.desc.coefficients {
            SubsurfaceCoefficients::Coefficients { sigma_a, sigma_s } => {
                ((sigma_a, Unbounded), (sigma_s, Unbounded))
            }
            SubsurfaceCoefficients::Reflectance { reflectance, mfp } => {
                ((mfp, Unbounded), (reflectance, Albedo))
            }
        };
        c[SIGMA_A_OR_MFP] = Some(a);
        c[SIGMA_S_OR_COLOUR] = Some(b);
        c
    }

    /// The boundary: a dielectric of the medium's index.
    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        let m = &self.desc;
        Some(BxDF::Dielectric(DielectricBxdf {
            eta: nonzero_eta(m.eta),
            distrib: at.distrib(m.uroughness, m.vroughness, m.remap_roughness),
        }))
    }
}

impl BuiltSubsurface {
    /// The BSSRDF entered at `po` (shading normal `ns`), with its textures evaluated through
    /// `at` as pbrt-v4's `SubsurfaceMaterial::GetBSSRDF` does: σa, σs scaled and clamped at 0,
    /// or σa, σs from the clamped colour and the scaled mean free path
    /// ([`subsurface_from_diffuse`]).
    pub fn bssrdf<'a>(&'a self, at: &HitLookup, po: Vec3, ns: Vec3) -> TabulatedBssrdf<'a> {
        let (m, table) = (&self.desc, &self.table);
        let scale = m.scale;
        let (sigma_a, sigma_s) = match m.coefficients {
            SubsurfaceCoefficients::Coefficients { sigma_a, sigma_s } => (
                (at.colour(SIGMA_A_OR_MFP, sigma_a, ColourKind::Unbounded) * scale)
                    .max(SampledSpectrum::ZERO),
                (at.colour(SIGMA_S_OR_COLOUR, sigma_s, ColourKind::Unbounded) * scale)
                    .max(SampledSpectrum::ZERO),
            ),
            SubsurfaceCoefficients::Reflectance { reflectance, mfp } => {
                let mfree = (at.colour(SIGMA_A_OR_MFP, mfp, ColourKind::Unbounded) * scale)
                    .max(SampledSpectrum::ZERO);
                let r = at
                    .colour(SIGMA_S_OR_COLOUR, reflectance, ColourKind::Albedo)
                    .clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE);
                subsurface_from_diffuse(table, r, mfree)
            }
        };
        TabulatedBssrdf::new(po, ns, nonzero_eta(m.eta), sigma_a, sigma_s, table)
    }
}

impl Material {
    /// The BSSRDF of a `subsurface` material entered at `po` (shading normal `ns`)
    /// ([`BuiltSubsurface::bssrdf`]); `None` for every other material.
    pub fn bssrdf<'a>(
        &'a self,
        tex: &crate::texture::TextureEval,
        tc: &crate::texture::TexCoord,
        spectral: Option<crate::material::SpectralColours>,
        po: Vec3,
        ns: Vec3,
    ) -> Option<TabulatedBssrdf<'a>> {
        let Material::Subsurface(m) = self else {
            return None;
        };
        Some(m.bssrdf(&HitLookup { tex, tc, spectral }, po, ns))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::at_hit::COLOUR_SLOTS;
    use crate::material::{MaterialDesc, SpectralColours};
    use crate::math::Rgb;
    use crate::spectrum::dense::{Measured, PreparedSpectrum};
    use crate::spectrum::sampled::SampledWavelengths;
    use crate::spectrum::{Spectrum, SpectrumKind};
    use crate::texture::{FloatTex, ScaleTexture, SpectrumTexture};
    use crate::texture::{TexCoord, TextureEval};

    /// The build gives the material the profile table of its description's g and η (the
    /// description itself holds no table).
    #[test]
    fn the_build_makes_the_table_of_the_media_g_and_eta() {
        let desc = SubsurfaceMaterial {
            coefficients: SubsurfaceCoefficients::Coefficients {
                sigma_a: SpectrumTex::Const(Rgb::ONE),
                sigma_s: SpectrumTex::Const(Rgb::ONE),
            },
            scale: 1.0,
            eta: 1.5,
            uroughness: FloatTex::Const(0.0),
            vroughness: FloatTex::Const(0.0),
            remap_roughness: true,
            g: 0.3,
        };
        let Material::Subsurface(built) = MaterialDesc::Subsurface(desc.clone()).build() else {
            panic!("a subsurface material builds into one")
        };
        assert_eq!((built.table.g, built.table.eta), (0.3, 1.5));
        assert_eq!(built.desc, desc);
    }

    /// σa from a texture holding a spectrum (a ramp 0 at 300 nm to 2 at 800 nm, scaled by 1)
    /// is that spectrum at the path's wavelengths, not the uplift of its RGB reduction.
    #[test]
    fn textured_coefficients_are_sampled_at_the_wavelengths() {
        let ramp = Spectrum::PiecewiseLinear {
            lambda: vec![300.0, 800.0],
            values: vec![0.0, 2.0],
        };
        let spectra = vec![SpectrumTexture::Scale(ScaleTexture {
            tex: SpectrumTex::Measured(Measured::new(
                &ramp,
                Rgb::splat(1.0),
                SpectrumKind::Unbounded,
            )),
            scale: FloatTex::Const(1.0),
        })];
        let tex = TextureEval {
            floats: &[],
            spectra: &spectra,
        };
        let m = MaterialDesc::Subsurface(SubsurfaceMaterial {
            coefficients: SubsurfaceCoefficients::Coefficients {
                sigma_a: SpectrumTex::Tex(0),
                sigma_s: SpectrumTex::Const(Rgb::ONE),
            },
            scale: 3.0,
            eta: 1.33,
            uroughness: FloatTex::Const(0.0),
            vroughness: FloatTex::Const(0.0),
            remap_roughness: true,
            g: 0.0,
        })
        .build();
        let lambda = SampledWavelengths::sample_visible(0.3);
        // σs's constant slot: 1 everywhere.
        let mut consts = [PreparedSpectrum::BLACK; COLOUR_SLOTS];
        consts[SIGMA_S_OR_COLOUR] = PreparedSpectrum::Rgb(
            crate::spectrum::sampled::RgbSpectrum::new(Rgb::ONE, ColourKind::Unbounded),
        );
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
