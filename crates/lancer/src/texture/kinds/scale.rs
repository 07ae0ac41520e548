//! The `scale` texture: a parameter times a float parameter.

use super::{Combining, Inputs, PlainKind};
use crate::texture::FloatTex;

/// `tex · scale`, plain data; `T` is [`FloatTex`] or [`crate::texture::SpectrumTex`].
#[derive(Clone, Debug)]
pub struct ScaleTexture<T> {
    /// The texture scaled.
    pub tex: T,
    /// The factor.
    pub scale: FloatTex,
}

impl<T: Copy> Combining<T> for ScaleTexture<T> {
    /// `tex · scale`, 0 without evaluating `tex` where the scale is 0 (pbrt-v4).
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        let s = at.float(self.scale);
        if s == 0.0 {
            I::ZERO
        } else {
            at.input(self.tex) * s
        }
    }

    #[inline(always)]
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool {
        f(self.tex)
    }
}

/// Its description is what the renderer reads.
impl<T: Clone> PlainKind for ScaleTexture<T> {}
