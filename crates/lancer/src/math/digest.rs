//! Debug output for large arrays: their length and a digest of their values' bits instead of
//! every value. A scene description's debug form is what the CLI hashes to tell scenes apart
//! (split parts, checkpoints); printing a million-vertex mesh number by number cost more time
//! than building its BVH, while a digest of the bits distinguishes the same scenes.

use std::fmt;

/// Values made of 32-bit words, visited in order.
pub trait BitWords {
    /// Calls `f` with each 32-bit word of the value (floats by their bits).
    fn words(&self, f: &mut impl FnMut(u32));
}

impl BitWords for u32 {
    fn words(&self, f: &mut impl FnMut(u32)) {
        f(*self)
    }
}

impl BitWords for u8 {
    fn words(&self, f: &mut impl FnMut(u32)) {
        f(*self as u32)
    }
}

impl BitWords for f32 {
    fn words(&self, f: &mut impl FnMut(u32)) {
        f(self.to_bits())
    }
}

impl BitWords for glam::Vec2 {
    fn words(&self, f: &mut impl FnMut(u32)) {
        f(self.x.to_bits());
        f(self.y.to_bits())
    }
}

impl BitWords for glam::Vec3A {
    fn words(&self, f: &mut impl FnMut(u32)) {
        f(self.x.to_bits());
        f(self.y.to_bits());
        f(self.z.to_bits())
    }
}

impl BitWords for glam::Vec3 {
    fn words(&self, f: &mut impl FnMut(u32)) {
        f(self.x.to_bits());
        f(self.y.to_bits());
        f(self.z.to_bits())
    }
}

/// A slice printed by `{:?}` as `[len; digest]`: FNV-1a over its 32-bit words,
/// h ← (h ⊕ w) · 1099511628211 from h = 14695981039346656037.
pub struct Digest<'a, T>(pub &'a [T]);

impl<T: BitWords> Digest<'_, T> {
    /// The FNV-1a digest of the slice's words.
    pub fn value(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for v in self.0 {
            v.words(&mut |w| h = (h ^ w as u64).wrapping_mul(0x0000_0100_0000_01b3));
        }
        h
    }
}

impl<T: BitWords> fmt::Debug for Digest<'_, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}; {:016x}]", self.0.len(), self.value())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digest_tells_values_apart_by_their_bits() {
        let a = [glam::Vec3::new(1.0, 2.0, 3.0)];
        let b = [glam::Vec3::new(1.0, 2.0, 3.000_000_2)];
        let z = [glam::Vec3::new(0.0, 0.0, 0.0)];
        let nz = [glam::Vec3::new(-0.0, 0.0, 0.0)];
        assert_ne!(Digest(&a).value(), Digest(&b).value());
        assert_ne!(Digest(&z).value(), Digest(&nz).value());
        assert_eq!(
            format!("{:?}", Digest(&a)),
            format!("{:?}", Digest(&Vec::from(a)))
        );
        assert!(format!("{:?}", Digest(&a)).starts_with("[1; "));
        // Order matters: [1, 2] and [2, 1] differ.
        assert_ne!(Digest(&[1u32, 2]).value(), Digest(&[2u32, 1]).value());
        // The empty slice is FNV's offset basis.
        assert_eq!(Digest::<u32>(&[]).value(), 0xcbf2_9ce4_8422_2325);
    }
}
