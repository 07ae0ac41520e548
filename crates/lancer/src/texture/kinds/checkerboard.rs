//! The `checkerboard` texture: two parameters alternating on a grid, of the mapped (s, t)
//! (`dimension` 2) or of texture space (`dimension` 3).

use super::{Combining, Inputs, PlainKind};
use crate::texture::{Mapping2D, Mapping3D, TexCoord};

/// A checkerboard over the cells of its mapping `M` ([`Mapping2D`] or [`Mapping3D`], see
/// [`Cells`]), plain data; `T` is [`crate::texture::FloatTex`] or
/// [`crate::texture::SpectrumTex`].
#[derive(Clone, Debug)]
pub struct Checkerboard<M, T> {
    /// Texture-coordinate mapping (texture space for the 3D checkerboard).
    pub mapping: M,
    /// Value on even cells.
    pub tex1: T,
    /// Value on odd cells.
    pub tex2: T,
}

/// The 2D checkerboard, of the mapped (s, t).
pub type CheckerboardTexture<T> = Checkerboard<Mapping2D, T>;

/// The 3D checkerboard (`dimension` 3), of texture space.
pub type Checkerboard3DTexture<T> = Checkerboard<Mapping3D, T>;

/// A mapping whose unit cells a checkerboard alternates on.
pub trait Cells {
    /// True on the even cells at `tc`.
    fn even_cell(&self, tc: &TexCoord) -> bool;
}

/// `⌊s⌋ + ⌊t⌋` even (pbrt-v4's filtered checkerboard with a zero footprint).
impl Cells for Mapping2D {
    #[inline(always)]
    fn even_cell(&self, tc: &TexCoord) -> bool {
        let st = self.map(tc);
        (st.x.floor() as i64 + st.y.floor() as i64) & 1 == 0
    }
}

/// `⌊x⌋ + ⌊y⌋ + ⌊z⌋` even in texture space.
impl Cells for Mapping3D {
    #[inline(always)]
    fn even_cell(&self, tc: &TexCoord) -> bool {
        let p = self.map(tc);
        (p.x.floor() as i64 + p.y.floor() as i64 + p.z.floor() as i64) & 1 == 0
    }
}

impl<M: Cells, T: Copy> Combining<T> for Checkerboard<M, T> {
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        at.input(if self.mapping.even_cell(at.tc()) {
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
impl<M: Clone, T: Clone> PlainKind for Checkerboard<M, T> {}
