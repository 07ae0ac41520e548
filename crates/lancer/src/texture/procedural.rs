//! pbrt-v4's procedural patterns as pure functions of texture coordinates: polka dots, marble,
//! windy waves, bilinear interpolation. The noise behind them is [`crate::math::noise`].

use crate::math::noise::{fbm, noise};
use crate::math::{Rgb, Vec2, Vec3};

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

/// Bilinear interpolation of four corner values at (s, t) (not clamped: pbrt-v4 extrapolates
/// outside [0, 1]²): `(1−s)(1−t)·v00 + s(1−t)·v10 + (1−s)t·v01 + st·v11`.
#[inline]
pub fn bilerp<T>(st: Vec2, v00: T, v01: T, v10: T, v11: T) -> T
where
    T: std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    let (s, t) = (st.x, st.y);
    v00 * ((1.0 - s) * (1.0 - t)) + v10 * (s * (1.0 - t)) + v01 * ((1.0 - s) * t) + v11 * (s * t)
}

/// pbrt-v4's `WindyTexture`: `|fbm(p/10, ω = ½, 3 octaves)| · fbm(p, ω = ½, 6 octaves)`, wind
/// strength times wave height (no footprint: every octave).
pub fn windy(p: Vec3) -> f32 {
    let z = Vec3::ZERO;
    let wind = fbm(0.1 * p, z, z, 0.5, 3);
    let wave = fbm(p, z, z, 0.5, 6);
    wind.abs() * wave
}

/// The colours of pbrt-v4's marble spline.
const MARBLE: [[f32; 3]; 9] = [
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.5, 0.5, 0.5],
    [0.6, 0.59, 0.58],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.2, 0.2, 0.33],
    [0.58, 0.58, 0.6],
];

/// A cubic Bézier segment at u, by de Casteljau's repeated interpolation.
fn cubic_bezier(cp: [Rgb; 4], u: f32) -> Rgb {
    let l = |a: Rgb, b: Rgb| a + (b - a) * u;
    let (a, b, c) = (l(cp[0], cp[1]), l(cp[1], cp[2]), l(cp[2], cp[3]));
    let (d, e) = (l(a, b), l(b, c));
    l(d, e)
}

/// pbrt-v4's `MarbleTexture` at texture-space point `p`: with `q = scale·p`,
/// `m = q.y + variation · fbm(q, ω, octaves)` and `t = ½ + ½ sin m`, the colour is 1.5 times
/// the cubic spline through [`MARBLE`]'s 9 colours (6 segments) at t.
pub fn marble(p: Vec3, octaves: u32, omega: f32, scale: f32, variation: f32) -> Rgb {
    let q = p * scale;
    let m = q.y + variation * fbm(q, Vec3::ZERO, Vec3::ZERO, omega, octaves);
    let t = 0.5 + 0.5 * m.sin();
    const SEGMENTS: usize = MARBLE.len() - 3;
    let first = ((t * SEGMENTS as f32).floor().max(0.0) as usize).min(SEGMENTS - 1);
    let u = t * SEGMENTS as f32 - first as f32;
    let cp = std::array::from_fn(|i| Rgb::from_array(MARBLE[first + i]));
    1.5 * cubic_bezier(cp, u)
}

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

    #[test]
    fn bilerp_hits_the_corners_and_the_centre_average() {
        let f = |s, t| bilerp(Vec2::new(s, t), 1.0f32, 2.0, 3.0, 4.0);
        assert_eq!(
            (f(0.0, 0.0), f(0.0, 1.0), f(1.0, 0.0), f(1.0, 1.0)),
            (1.0, 2.0, 3.0, 4.0)
        );
        assert_eq!(f(0.5, 0.5), 2.5);
        // v10 at s = 1: red at (1, 0).
        let c = bilerp(Vec2::new(1.0, 0.0), Rgb::X, Rgb::Y, Rgb::Z, Rgb::ONE);
        assert_eq!(c, Rgb::Z);
    }

    #[test]
    fn marble_follows_the_spline() {
        // Where fbm vanishes (variation 0), t = ½ + ½ sin(scale·y). y = 0: t = ½ → segment 3,
        // u = 0 → 1.5 × colour 3 = 0.75 grey.
        let c = marble(Vec3::new(0.3, 0.0, 0.2), 8, 0.5, 1.0, 0.0);
        assert!((c - Rgb::splat(0.75)).abs().max_element() < 1e-6, "{c}");
        // sin = 1: t = 1 → the last segment at u = 1: 1.5 × colour 8.
        let c = marble(
            Vec3::new(0.0, std::f32::consts::FRAC_PI_2, 0.0),
            8,
            0.5,
            1.0,
            0.0,
        );
        assert!(
            (c - 1.5 * Rgb::new(0.58, 0.58, 0.6)).abs().max_element() < 1e-5,
            "{c}"
        );
    }

    #[test]
    fn windy_is_zero_where_the_wind_is() {
        // At the origin every octave of both fbm sums is noise at a lattice point: 0.
        assert_eq!(windy(Vec3::ZERO), 0.0);
        let v = windy(Vec3::new(3.3, 1.2, -0.7));
        assert!(v.is_finite() && v.abs() < 2.0);
    }
}
