//! pbrt-v4's `SampledGrid`: nx × ny × nz samples over the unit cube [0,1]³, looked up with
//! trilinear interpolation.
//!
//! Sample (x, y, z) sits at the centre of its cell, ((x + ½)/nx, (y + ½)/ny, (z + ½)/nz); a
//! point p ∈ [0,1]³ has continuous sample coordinates s = (p.x·nx − ½, p.y·ny − ½, p.z·nz − ½),
//! and its value is the trilinear blend of the eight samples around s. Samples outside the grid
//! count as zero (`T::default()`), so values fade to zero over the outer half cell, as in pbrt-v4.

use crate::math::Vec3;
use std::ops::{Add, Mul};

/// Values that blend linearly: `lerp(t, a, b) = (1 − t)·a + t·b`.
pub trait Lerp: Copy + Add<Output = Self> + Mul<f32, Output = Self> {}
impl<T: Copy + Add<Output = T> + Mul<f32, Output = T>> Lerp for T {}

/// (1 − t)·a + t·b, pbrt-v4's `Lerp(t, a, b)`.
#[inline]
fn lerp<U: Lerp>(t: f32, a: U, b: U) -> U {
    a * (1.0 - t) + b * t
}

/// A dense grid of samples over [0,1]³ (x fastest, then y, then z).
#[derive(Clone, Debug, PartialEq)]
pub struct SampledGrid<T> {
    values: Vec<T>,
    nx: i32,
    ny: i32,
    nz: i32,
}

impl<T: Copy + Default> SampledGrid<T> {
    /// A grid of `values` (x fastest), or `None` unless every size is ≥ 1 and
    /// `values.len() == nx·ny·nz`.
    pub fn new(values: Vec<T>, nx: i32, ny: i32, nz: i32) -> Option<SampledGrid<T>> {
        if nx < 1 || ny < 1 || nz < 1 {
            return None;
        }
        let n = (nx as u64) * (ny as u64) * (nz as u64);
        (values.len() as u64 == n).then_some(SampledGrid { values, nx, ny, nz })
    }

    /// The grid's resolution (nx, ny, nz).
    pub fn resolution(&self) -> [i32; 3] {
        [self.nx, self.ny, self.nz]
    }

    /// The samples, x fastest.
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// Bytes held by the samples.
    pub fn bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<T>()
    }

    /// The sample at integer coordinates, `T::default()` (zero) outside the grid.
    #[inline]
    pub fn at(&self, x: i32, y: i32, z: i32) -> T {
        if x < 0 || y < 0 || z < 0 || x >= self.nx || y >= self.ny || z >= self.nz {
            return T::default();
        }
        self.values[((z * self.ny + y) * self.nx + x) as usize]
    }

    /// The trilinear blend at p ∈ [0,1]³ of the samples, each first turned into `U` by
    /// `convert` (pbrt-v4 converts RGB samples to spectra before blending them).
    #[inline]
    pub fn lookup_with<U: Lerp>(&self, p: Vec3, convert: impl Fn(T) -> U) -> U {
        // s = p·n − ½: sample coordinates, samples at integers.
        let s = Vec3::new(
            p.x * self.nx as f32 - 0.5,
            p.y * self.ny as f32 - 0.5,
            p.z * self.nz as f32 - 0.5,
        );
        let f = s.floor();
        let d = s - f;
        // Clamping to a range far outside the grid keeps the i32 conversions exact and
        // harmless (those samples are zero anyway).
        let c = f.clamp(Vec3::splat(-4.0), Vec3::splat((1 << 30) as f32));
        let (x, y, z) = (c.x as i32, c.y as i32, c.z as i32);
        let v = |dx: i32, dy: i32, dz: i32| convert(self.at(x + dx, y + dy, z + dz));
        let d00 = lerp(d.x, v(0, 0, 0), v(1, 0, 0));
        let d10 = lerp(d.x, v(0, 1, 0), v(1, 1, 0));
        let d01 = lerp(d.x, v(0, 0, 1), v(1, 0, 1));
        let d11 = lerp(d.x, v(0, 1, 1), v(1, 1, 1));
        lerp(d.z, lerp(d.y, d00, d10), lerp(d.y, d01, d11))
    }

    /// The largest of `key(sample)` over the samples whose trilinear support reaches the box
    /// [lo, hi] ⊂ [0,1]³ (pbrt-v4's `MaxValue`): samples ⌊lo·n − ½⌋ … ⌊hi·n − ½⌋ + 1, clamped to
    /// the grid. A bound for every value `lookup` gives inside the box.
    pub fn max_value_with(&self, lo: Vec3, hi: Vec3, key: impl Fn(T) -> f32) -> f32 {
        let n = [self.nx, self.ny, self.nz];
        let mut a = [0i32; 3];
        let mut b = [0i32; 3];
        for i in 0..3 {
            let s0 = (lo[i] * n[i] as f32 - 0.5).floor().clamp(-1.0, n[i] as f32);
            let s1 = (hi[i] * n[i] as f32 - 0.5).floor().clamp(-1.0, n[i] as f32);
            a[i] = (s0 as i32).max(0);
            b[i] = (s1 as i32 + 1).min(n[i] - 1);
        }
        let mut m = key(self.at(a[0], a[1], a[2]));
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    m = m.max(key(self.at(x, y, z)));
                }
            }
        }
        m
    }
}

impl SampledGrid<f32> {
    /// The trilinear blend at p ∈ [0,1]³.
    #[inline]
    pub fn lookup(&self, p: Vec3) -> f32 {
        self.lookup_with(p, |v| v)
    }

    /// The largest sample that can influence a lookup in [lo, hi].
    pub fn max_value(&self, lo: Vec3, hi: Vec3) -> f32 {
        self.max_value_with(lo, hi, |v| v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> SampledGrid<f32> {
        // 2×2×2 grid, value = x + 2y + 4z (sample index).
        SampledGrid::new((0..8).map(|i| i as f32).collect(), 2, 2, 2).unwrap()
    }

    #[test]
    fn sizes_must_match() {
        assert!(SampledGrid::new(vec![0.0f32; 7], 2, 2, 2).is_none());
        assert!(SampledGrid::new(vec![0.0f32; 0], 0, 1, 1).is_none());
        assert_eq!(ramp().resolution(), [2, 2, 2]);
        assert_eq!(ramp().bytes(), 32);
    }

    #[test]
    fn samples_sit_at_cell_centres() {
        let g = ramp();
        // Cell centres of a 2-grid are ¼ and ¾.
        for i in 0..8 {
            let p = Vec3::new(
                0.25 + 0.5 * (i & 1) as f32,
                0.25 + 0.5 * ((i >> 1) & 1) as f32,
                0.25 + 0.5 * (i >> 2) as f32,
            );
            assert_eq!(g.lookup(p), i as f32);
        }
        // The centre blends all eight equally: mean of 0..7 = 3.5.
        assert!((g.lookup(Vec3::splat(0.5)) - 3.5).abs() < 1e-6);
        // Halfway between samples 0 and 1 on x: 0.5.
        assert!((g.lookup(Vec3::new(0.5, 0.25, 0.25)) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn values_fade_to_zero_outside() {
        let g = SampledGrid::new(vec![2.0f32], 1, 1, 1).unwrap();
        assert_eq!(g.lookup(Vec3::splat(0.5)), 2.0);
        // At x = 0 the sample coordinate is −½: half of the sample, half of the zero beyond.
        assert!((g.lookup(Vec3::new(0.0, 0.5, 0.5)) - 1.0).abs() < 1e-6);
        // A corner: (½)³ of it.
        assert!((g.lookup(Vec3::ZERO) - 0.25).abs() < 1e-6);
        assert_eq!(g.lookup(Vec3::splat(-3.0)), 0.0);
        assert_eq!(g.lookup(Vec3::splat(1e30)), 0.0);
    }

    #[test]
    fn max_value_bounds_every_lookup_in_the_box() {
        let vals: Vec<f32> = (0..5 * 4 * 3)
            .map(|i| ((i * 7919) % 13) as f32 * 0.5)
            .collect();
        let g = SampledGrid::new(vals, 5, 4, 3).unwrap();
        let lo = Vec3::new(0.1, 0.3, 0.0);
        let hi = Vec3::new(0.45, 0.6, 0.5);
        let m = g.max_value(lo, hi);
        let mut seen = 0.0f32;
        for i in 0..=20 {
            for j in 0..=20 {
                for k in 0..=20 {
                    let t = Vec3::new(i as f32, j as f32, k as f32) / 20.0;
                    let v = g.lookup(lo + (hi - lo) * t);
                    assert!(v <= m + 1e-5, "{v} > {m}");
                    seen = seen.max(v);
                }
            }
        }
        assert!(seen > 0.0);
        // The whole grid: its largest sample.
        assert_eq!(g.max_value(Vec3::ZERO, Vec3::ONE), 6.0);
    }
}
