//! The `dots` texture: polka dots of one parameter on a background of another.

use super::{Combining, Inputs, PlainKind};
use crate::math::noise::noise;
use crate::math::{Vec2, Vec3};
use crate::texture::Mapping2D;

/// Polka dots ([`inside_polka_dot`]), plain data; `T` is [`crate::texture::FloatTex`] or
/// [`crate::texture::SpectrumTex`].
#[derive(Clone, Debug)]
pub struct DotsTexture<T> {
    /// Texture-coordinate mapping.
    pub mapping: Mapping2D,
    /// Value inside a dot (pbrt-v4's `outside` parameter: it swaps the two).
    pub dot: T,
    /// Value between the dots (pbrt-v4's `inside` parameter).
    pub background: T,
}

/// pbrt-v4's `InsidePolkaDot`: cells of side 1 centred on integer (s, t); a cell holds a dot
/// when `noise(s_cell + ½, t_cell + ½, ½) > 0`, of radius 0.35, its centre jittered by up to
/// 0.15 by two more noise values.
pub fn inside_polka_dot(st: Vec2) -> bool {
    let s_cell = (st.x + 0.5).floor();
    let t_cell = (st.y + 0.5).floor();
    if noise(Vec3::new(s_cell + 0.5, t_cell + 0.5, 0.5)) <= 0.0 {
        return false;
    }
    const RADIUS: f32 = 0.35;
    const MAX_SHIFT: f32 = 0.5 - RADIUS;
    let s_centre = s_cell + MAX_SHIFT * noise(Vec3::new(s_cell + 1.5, t_cell + 2.8, 0.5));
    let t_centre = t_cell + MAX_SHIFT * noise(Vec3::new(s_cell + 4.5, t_cell + 9.8, 0.5));
    (st - Vec2::new(s_centre, t_centre)).length_squared() < RADIUS * RADIUS
}

impl<T: Copy> Combining<T> for DotsTexture<T> {
    #[inline(always)]
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value {
        at.input(if inside_polka_dot(self.mapping.map(at.tc())) {
            self.dot
        } else {
            self.background
        })
    }

    #[inline(always)]
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool {
        f(self.dot) || f(self.background)
    }
}

/// Its description is what the renderer reads.
impl<T: Clone> PlainKind for DotsTexture<T> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dots_are_round_and_only_in_cells_whose_noise_is_positive() {
        let mut with_dot = 0;
        for i in -8..8 {
            for j in -8..8 {
                let (s, t) = (i as f32, j as f32);
                let has = noise(Vec3::new(s + 0.5, t + 0.5, 0.5)) > 0.0;
                // Cell corners are never inside (a dot reaches 0.35 + 0.15 = 0.5 from the
                // cell centre at most, the corner is 0.707 away).
                assert!(!inside_polka_dot(Vec2::new(s + 0.5, t + 0.5)));
                // The centre, jittered by at most 0.15 < 0.35, is inside exactly when the cell
                // has a dot.
                assert_eq!(inside_polka_dot(Vec2::new(s, t)), has, "cell ({i}, {j})");
                with_dot += has as i32;
            }
        }
        assert!(with_dot > 40 && with_dot < 216, "{with_dot} of 256 cells");
    }
}
