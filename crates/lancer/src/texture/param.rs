//! A material's texture parameters: a constant, or the index of one of the scene's textures.

use crate::math::Rgb;
use crate::spectrum::dense::Measured;

/// A float-valued material parameter: a constant, or the index of a float texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FloatTex {
    /// The same value everywhere.
    Const(f32),
    /// Index into the scene's float textures.
    Tex(u32),
}

/// A colour-valued material parameter: a constant, or the index of a spectrum texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpectrumTex {
    /// The same colour everywhere.
    Const(Rgb),
    /// The same spectrum everywhere, given as a spectrum (a named spectrum, `blackbody`, an
    /// `.spd` file): RGB mode reads its reduction, spectral mode its table.
    Measured(Measured),
    /// Index into the scene's spectrum textures.
    Tex(u32),
}
