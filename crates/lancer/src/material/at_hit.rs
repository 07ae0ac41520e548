//! What a material reads at a hit ([`HitLookup`]): its float textures, its colours (RGB mode's
//! lanes, or spectral mode's values at the path's wavelengths, constants prepared once per scene
//! by the colour list its kind gives, [`super::MaterialKind::colours`]), indices of refraction
//! and microfacet distributions, each the same way for every kind.

use super::TrowbridgeReitz;
use crate::math::{Rgb, SampledSpectrum, rgb_lanes};
use crate::spectrum::Ior;
use crate::spectrum::dense::PreparedSpectrum;
use crate::spectrum::sampled::{ColourKind, SampledWavelengths};
use crate::texture::{FloatTex, SpectrumTex, TexCoord, TextureEval};

/// How many constant colours a material can have ([`Colours`]).
pub const COLOUR_SLOTS: usize = 4;

/// A material's colour parameters in the order its kind lists them, with what each describes
/// ([`super::MaterialKind::colours`]); spectral mode turns the constant ones into spectra once
/// per scene ([`SpectralColours`]), and the kind reads them back by the same position, which
/// only its own file knows.
pub type Colours = [Option<(SpectrumTex, ColourKind)>; COLOUR_SLOTS];

/// The colours of a material that has none.
pub const NO_COLOURS: Colours = [None; COLOUR_SLOTS];

/// Spectral mode's view of a material at a hit: the path's wavelengths and the material's
/// constant colours, prepared once per scene ([`PreparedSpectrum`], from its [`Colours`]).
#[derive(Clone, Copy, Debug)]
pub struct SpectralColours<'a> {
    /// The path's wavelengths.
    pub lambda: &'a SampledWavelengths,
    /// The material's constant colours as spectra, by position (unused ones are anything).
    pub consts: &'a [PreparedSpectrum; COLOUR_SLOTS],
}

impl SpectralColours<'_> {
    /// The constant colour at position `slot` of the material's [`Colours`], at the path's
    /// wavelengths.
    #[inline(always)]
    pub fn constant(&self, slot: usize) -> SampledSpectrum {
        self.lambda.sample_prepared(&self.consts[slot])
    }
}

/// RGB mode's value of a colour `c` as transport uses it, as lanes (r, g, b, b): an albedo
/// clamped to [0, 1], an unbounded colour as it is.
#[inline(always)]
pub(crate) fn rgb_colour(c: Rgb, kind: ColourKind) -> SampledSpectrum {
    rgb_lanes(match kind {
        ColourKind::Albedo => c.clamp(Rgb::ZERO, Rgb::ONE),
        ColourKind::Unbounded => c,
    })
}

/// A material's colour `t` (position `slot` of its [`Colours`]) at a hit, as every material
/// reads its colours. RGB mode: [`rgb_colour`] of the texture's value. Spectral mode: the
/// prepared spectrum of a constant ([`SpectralColours::constant`]), or a texture's value at the
/// wavelengths (the uplift of its RGB value, which clamps an albedo the same way first, or for
/// a tree holding spectra its sampled values, as pbrt-v4 evaluates spectrum textures).
#[inline(always)]
pub(crate) fn slot_colour(
    tex: &TextureEval,
    tc: &TexCoord,
    spectral: Option<SpectralColours>,
    slot: usize,
    t: SpectrumTex,
    kind: ColourKind,
) -> SampledSpectrum {
    match (spectral, t) {
        (None, _) => rgb_colour(tex.spectrum(t, tc), kind),
        (Some(sc), SpectrumTex::Const(_) | SpectrumTex::Measured(_)) => sc.constant(slot),
        (Some(sc), SpectrumTex::Tex(_)) => tex.spectrum_at(t, tc, sc.lambda, kind),
    }
}

/// pbrt's treatment of an index of refraction of 0 (unset or meaningless): 1.
#[inline]
pub(crate) fn nonzero_eta(eta: f32) -> f32 {
    if eta == 0.0 { 1.0 } else { eta }
}

/// What a material reads at one hit: the scene's textures at the hit's coordinates and, in
/// spectral mode, the path's wavelengths with the material's prepared constant colours.
#[derive(Clone, Copy)]
pub struct HitLookup<'a> {
    /// The scene's textures.
    pub tex: &'a TextureEval<'a>,
    /// Where they are looked up.
    pub tc: &'a TexCoord,
    /// Spectral mode's wavelengths and prepared colours; `None` in RGB mode.
    pub spectral: Option<SpectralColours<'a>>,
}

impl HitLookup<'_> {
    /// A float parameter's value at the hit.
    #[inline(always)]
    pub fn float(&self, t: FloatTex) -> f32 {
        self.tex.float(t, self.tc)
    }

    /// The colour `t`, position `slot` of the material's [`Colours`], at the hit
    /// ([`slot_colour`]): in spectral mode its values at the path's wavelengths (`kind` says
    /// how a texel is uplifted), in RGB mode its lanes (an albedo clamped to [0, 1]).
    #[inline(always)]
    pub fn colour(&self, slot: usize, t: SpectrumTex, kind: ColourKind) -> SampledSpectrum {
        slot_colour(self.tex, self.tc, self.spectral, slot, t, kind)
    }

    /// [`HitLookup::colour`] of an albedo.
    #[inline(always)]
    pub fn albedo(&self, slot: usize, t: SpectrumTex) -> SampledSpectrum {
        self.colour(slot, t, ColourKind::Albedo)
    }

    /// A dielectric's index: RGB mode's single value, or the value at the hero wavelength λ₀
    /// (the only one a dispersive path keeps, see [`super::Material::disperses`]).
    #[inline(always)]
    pub fn ior(&self, eta: Ior) -> f32 {
        match self.spectral {
            None => eta.constant_value(),
            Some(sc) => eta.at(sc.lambda.lambda[0]),
        }
    }

    /// The Trowbridge–Reitz distribution of roughness `u`, `v` at the hit (remapped to α as
    /// pbrt does when `remap`).
    #[inline(always)]
    pub fn distrib(&self, u: FloatTex, v: FloatTex, remap: bool) -> TrowbridgeReitz {
        TrowbridgeReitz::from_roughness(self.float(u), self.float(v), remap)
    }

    /// The path's wavelengths in spectral mode.
    #[inline(always)]
    pub fn lambda(&self) -> Option<&SampledWavelengths> {
        self.spectral.map(|sc| sc.lambda)
    }
}
