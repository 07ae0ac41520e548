//! The `mix` texture: a linear blend of two parameters.

use super::{Combining, Inputs, PlainKind};
use crate::texture::FloatTex;

/// `(1 − amount)·tex1 + amount·tex2`, plain data; `T` is [`FloatTex`] or
/// [`crate::texture::SpectrumTex`].
#[derive(Clone, Debug)]
pub struct MixTexture<T> {
    /// First.
    pub tex1: T,
    /// Second.
    pub tex2: T,
    /// Blend factor.
    pub amount: FloatTex,
}

impl<T: Copy> Combining<T> for MixTexture<T> {
    /// `(1 − a)·tex1 + a·tex2`.
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        let a = at.float(self.amount);
        at.input(self.tex1) * (1.0 - a) + at.input(self.tex2) * a
    }

    #[inline(always)]
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool {
        f(self.tex1) || f(self.tex2)
    }
}

/// Its description is what the renderer reads.
impl<T: Clone> PlainKind for MixTexture<T> {}
