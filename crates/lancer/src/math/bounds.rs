//! Axis-aligned bounding boxes.

use super::Vec3;

/// An axis-aligned box `[min, max]`; empty when `min > max` on some axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Bounds3 {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Bounds3 {
    /// The empty box (the identity of `union`).
    pub const EMPTY: Bounds3 = Bounds3 {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box spanned by two points, in any order.
    pub fn new(a: Vec3, b: Vec3) -> Bounds3 {
        Bounds3 {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The box of a single point.
    pub fn from_point(p: Vec3) -> Bounds3 {
        Bounds3 { min: p, max: p }
    }

    /// True when no point is inside.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(&self, o: &Bounds3) -> Bounds3 {
        Bounds3 {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// The smallest box holding this one and `p`.
    #[inline]
    pub fn union_point(&self, p: Vec3) -> Bounds3 {
        Bounds3 {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// `max − min`.
    #[inline]
    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }

    /// The centre.
    #[inline]
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area (0 for an empty box).
    #[inline]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.diagonal();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// The axis of greatest extent (0, 1 or 2).
    pub fn max_extent(&self) -> usize {
        let d = self.diagonal();
        if d.x > d.y && d.x > d.z {
            0
        } else if d.y > d.z {
            1
        } else {
            2
        }
    }

    /// Corner `i` (bit 0: x, bit 1: y, bit 2: z take max).
    pub fn corner(&self, i: usize) -> Vec3 {
        Vec3::new(
            if i & 1 != 0 { self.max.x } else { self.min.x },
            if i & 2 != 0 { self.max.y } else { self.min.y },
            if i & 4 != 0 { self.max.z } else { self.min.z },
        )
    }

    /// Position of `p` relative to the box: 0 at `min`, 1 at `max`, per axis.
    pub fn offset(&self, p: Vec3) -> Vec3 {
        let mut o = p - self.min;
        let d = self.diagonal();
        for i in 0..3 {
            if d[i] > 0.0 {
                o[i] /= d[i];
            }
        }
        o
    }

    /// The centre and radius of a sphere that holds the box.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        if self.is_empty() {
            return (Vec3::ZERO, 0.0);
        }
        let c = self.centroid();
        (c, (self.max - c).length())
    }

    /// True when `p` is inside or on the boundary.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_and_area() {
        let b = Bounds3::from_point(Vec3::ZERO).union_point(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(b.surface_area(), 2.0 * (2.0 + 6.0 + 3.0));
        assert_eq!(b.max_extent(), 2);
        assert!(Bounds3::EMPTY.is_empty());
        assert_eq!(Bounds3::EMPTY.surface_area(), 0.0);
    }
}
