//! The `checkerboard` texture: two parameters alternating on a grid, of the mapped (s, t)
//! (`dimension` 2) or of texture space (`dimension` 3).

use super::{Combining, Inputs, PlainKind};
use crate::texture::{Mapping2D, Mapping3D, TexCoord};

/// The 2D checkerboard, plain data; `T` is [`crate::texture::FloatTex`] or
/// [`crate::texture::SpectrumTex`].
#[derive(Clone, Debug)]
pub struct CheckerboardTexture<T> {
    /// Texture-coordinate mapping.
    pub mapping: Mapping2D,
    /// Value on even cells.
    pub tex1: T,
    /// Value on odd cells.
    pub tex2: T,
}

/// The 3D checkerboard (`dimension` 3), plain data.
#[derive(Clone, Debug)]
pub struct Checkerboard3DTexture<T> {
    /// Texture space.
    pub mapping: Mapping3D,
    /// Value on even cells.
    pub tex1: T,
    /// Value on odd cells.
    pub tex2: T,
}

/// True on the even cells of the 2D checkerboard: `⌊s⌋ + ⌊t⌋` even (pbrt-v4's filtered
/// checkerboard with a zero footprint).
fn checker(mapping: &Mapping2D, tc: &TexCoord) -> bool {
    let st = mapping.map(tc);
    (st.x.floor() as i64 + st.y.floor() as i64) & 1 == 0
}

/// True on the even cells of the 3D checkerboard: `⌊x⌋ + ⌊y⌋ + ⌊z⌋` even in texture space.
fn checker_3d(mapping: &Mapping3D, tc: &TexCoord) -> bool {
    let p = mapping.map(tc);
    (p.x.floor() as i64 + p.y.floor() as i64 + p.z.floor() as i64) & 1 == 0
}

impl<T: Copy> Combining<T> for CheckerboardTexture<T> {
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        at.input(if checker(&self.mapping, at.tc()) {
            self.tex1
        } else {
            self.tex2
        })
    }

    #[inline(always)]
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool {
        f(self.tex1) || f(self.tex2)
    }
}

impl<T: Copy> Combining<T> for Checkerboard3DTexture<T> {
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        at.input(if checker_3d(&self.mapping, at.tc()) {
            self.tex1
        } else {
            self.tex2
        })
    }

    #[inline(always)]
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool {
        f(self.tex1) || f(self.tex2)
    }
}

/// Its description is what the renderer reads.
impl<T: Clone> PlainKind for CheckerboardTexture<T> {}

/// Its description is what the renderer reads.
impl<T: Clone> PlainKind for Checkerboard3DTexture<T> {}
