//! Evaluation of texture parameters against the scene's texture lists, as pbrt-v4's textures'
//! `Evaluate`: a parameter's constant inline, a texture's lookup by its kind (`kinds/`).

use super::kinds::{At, TextureEval};
use super::{FloatTex, SpectrumTex, TexCoord};
use crate::math::Rgb;

impl TextureEval<'_> {
    /// The value of a float parameter at `tc`.
    #[inline(always)]
    pub fn float(&self, t: FloatTex, tc: &TexCoord) -> f32 {
        // Constants inline (most parameters), textures out of line.
        match t {
            FloatTex::Const(v) => v,
            FloatTex::Tex(i) => self.float_texture(i, tc),
        }
    }

    /// The value of texture `i` at `tc` ([`super::FloatTexture::evaluate`]).
    #[inline(never)]
    fn float_texture(&self, i: u32, tc: &TexCoord) -> f32 {
        self.floats[i as usize].evaluate(&At { ev: self, tc })
    }

    /// The value of a colour parameter at `tc`.
    #[inline(always)]
    pub fn spectrum(&self, t: SpectrumTex, tc: &TexCoord) -> Rgb {
        // Constants inline (most parameters), textures out of line.
        match t {
            SpectrumTex::Const(v) => v,
            SpectrumTex::Measured(m) => m.rgb,
            SpectrumTex::Tex(i) => self.spectrum_texture(i, tc),
        }
    }

    /// The value of texture `i` at `tc` ([`super::SpectrumTexture::evaluate`]).
    #[inline(never)]
    fn spectrum_texture(&self, i: u32, tc: &TexCoord) -> Rgb {
        self.spectra[i as usize].evaluate(&At { ev: self, tc })
    }
}
