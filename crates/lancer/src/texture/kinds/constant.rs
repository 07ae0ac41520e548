//! The `constant` texture: the same value everywhere.

use super::{At, PlainKind, TextureKind};
use crate::math::Rgb;

impl TextureKind<f32> for f32 {
    #[inline(always)]
    fn evaluate(&self, _: &At) -> f32 {
        *self
    }
}

impl TextureKind<Rgb> for Rgb {
    #[inline(always)]
    fn evaluate(&self, _: &At) -> Rgb {
        *self
    }
}

/// A constant is what the renderer reads.
impl PlainKind for f32 {}

/// A constant is what the renderer reads.
impl PlainKind for Rgb {}
