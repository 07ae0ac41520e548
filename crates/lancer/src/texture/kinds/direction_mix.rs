//! The `directionmix` texture: two parameters blended by how squarely the surface faces a
//! direction.

use super::{Combining, Inputs, PlainKind};
use crate::math::Vec3;

/// `a·tex1 + (1 − a)·tex2` with `a = |n·dir|` (n the geometric normal), plain data; `T` is
/// [`crate::texture::FloatTex`] or [`crate::texture::SpectrumTex`].
#[derive(Clone, Debug)]
pub struct DirectionMixTexture<T> {
    /// Seen along `dir`.
    pub tex1: T,
    /// Seen across it.
    pub tex2: T,
    /// Unit direction, world space.
    pub dir: Vec3,
}

impl<T: Copy> Combining<T> for DirectionMixTexture<T> {
    /// `|n·dir|·tex1 + (1 − |n·dir|)·tex2`.
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        let a = at.tc().n.dot(self.dir).abs();
        at.input(self.tex1) * a + at.input(self.tex2) * (1.0 - a)
    }

    #[inline(always)]
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool {
        f(self.tex1) || f(self.tex2)
    }
}

/// Its description is what the renderer reads.
impl<T: Clone> PlainKind for DirectionMixTexture<T> {}
