//! A MIP level of few distinct texels, stored as small indices into a table of them.
//!
//! Lookups are bound by memory traffic: a 1-bit or 8-bit grey image decoded to 12-byte float
//! texels (and the first levels of its pyramid, whose averages take few values) reads twelve
//! to ninety-six times the bytes it holds. When a level has at most 256 distinct texels, each
//! texel becomes its index in a table of those values, packed at 1, 2, 4 or 8 bits (the
//! fewest that count the table): the same floats, bit for bit, so filtered values do not
//! change at all. A 1-bit image's level 0 (which high sample counts read: pbrt-v4 shrinks
//! footprints by 1/√spp) takes an eighth of a byte a texel and stays in cache.

use crate::image::{Image, WrapMode, lookup_in, texel_in};
use crate::math::{PackedRgb, Rgb, Vec2};
use std::collections::HashMap;

/// A level's texels as indices into a table of at most 256 values.
#[derive(Clone, Debug, PartialEq)]
pub struct PaletteLevel {
    width: u32,
    height: u32,
    /// The distinct texels.
    palette: Box<[PackedRgb]>,
    /// log₂ of the bits per index: 0, 1, 2 or 3 (1, 2, 4 or 8 bits).
    log_bits: u32,
    /// Per texel i = `y·width + x`, its index in `palette`: bits [s, s + b) of byte
    /// i / (8/b), with b the bits per index and s = b·(i mod 8/b).
    index: Box<[u8]>,
}

impl PaletteLevel {
    /// `img` as indices into its distinct texels (compared bit for bit), or `None` when it
    /// has more than 256 of them.
    pub fn from_image(img: &Image) -> Option<PaletteLevel> {
        let key = |t: &PackedRgb| [t.x.to_bits(), t.y.to_bits(), t.z.to_bits()];
        let mut palette: Vec<PackedRgb> = Vec::new();
        let mut slots: HashMap<[u32; 3], u8> = HashMap::new();
        let mut index = Vec::with_capacity(img.texels.len());
        // Neighbouring texels are mostly equal: the previous one is checked before the map.
        let mut last: Option<([u32; 3], u8)> = None;
        for t in &img.texels {
            let k = key(t);
            let i = match last {
                Some((lk, li)) if lk == k => li,
                _ => match slots.get(&k) {
                    Some(&i) => i,
                    None => {
                        let i = u8::try_from(palette.len()).ok()?;
                        palette.push(*t);
                        slots.insert(k, i);
                        i
                    }
                },
            };
            last = Some((k, i));
            index.push(i);
        }
        // The fewest bits b ∈ {1, 2, 4, 8} with 2^b ≥ the table's size.
        let log_bits = (0..3)
            .find(|&l| palette.len() <= 1 << (1 << l))
            .unwrap_or(3);
        let per_byte = 8 >> log_bits;
        let packed = index
            .chunks(per_byte)
            .map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0u8, |byte, (k, &i)| byte | i << (k << log_bits))
            })
            .collect();
        Some(PaletteLevel {
            width: img.width,
            height: img.height,
            palette: palette.into_boxed_slice(),
            log_bits,
            index: packed,
        })
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.index.len() + self.palette.len() * std::mem::size_of::<PackedRgb>()
    }

    /// The texel at `i` = y·width + x: its index is bits [s, s + b) of byte i >> (3 − log₂ b),
    /// s = (i mod 8/b)·b.
    #[inline(always)]
    fn fetch(&self, i: usize) -> Rgb {
        let log_per_byte = 3 - self.log_bits;
        let byte = self.index[i >> log_per_byte] as u32;
        let shift = ((i as u32) & ((1 << log_per_byte) - 1)) << self.log_bits;
        let mask = (1u32 << (1 << self.log_bits)) - 1;
        self.palette[((byte >> shift) & mask) as usize].into()
    }

    /// [`Image::texel`] of the image this level was made from.
    #[inline]
    pub fn texel(&self, x: i64, y: i64, wrap: WrapMode) -> Rgb {
        texel_in(self.width, self.height, x, y, wrap, |i| self.fetch(i))
    }

    /// [`Image::lookup`] of the image this level was made from.
    #[inline]
    pub fn lookup(&self, st: Vec2, wrap: WrapMode, nearest: bool) -> Rgb {
        lookup_in(self.width, self.height, st, wrap, nearest, |i| {
            self.fetch(i)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palette_levels_read_the_same_bits_as_their_images() {
        // 7×5 texels of three distinct colours (one of them −0.0, which must stay apart
        // from 0.0), looked up everywhere, in every wrap mode, point and bilinear.
        let colours = [
            PackedRgb::new(0.25, 0.5, 1.0),
            PackedRgb::new(0.0, 0.0, 0.0),
            PackedRgb::new(-0.0, 0.0, 0.0),
        ];
        let texels = (0..35).map(|i| colours[(i * 7 / 3) % 3]).collect();
        let img = Image::new(7, 5, texels).unwrap();
        let p = PaletteLevel::from_image(&img).expect("three colours");
        assert_eq!(p.palette.len(), 3);
        // Two bits a texel: 35 texels in 9 bytes.
        assert_eq!(p.memory_bytes(), 9 + 3 * 12);
        for wrap in WrapMode::ALL {
            for (x, y) in [(0, 0), (6, 4), (-1, 2), (8, -3), (3, 9)] {
                let (a, b) = (p.texel(x, y, wrap), img.texel(x, y, wrap));
                assert_eq!(
                    a.to_array().map(f32::to_bits),
                    b.to_array().map(f32::to_bits)
                );
            }
            for k in 0..50 {
                let st = Vec2::new(k as f32 * 0.037 - 0.4, 1.3 - k as f32 * 0.029);
                for nearest in [false, true] {
                    let (a, b) = (p.lookup(st, wrap, nearest), img.lookup(st, wrap, nearest));
                    assert_eq!(
                        a.to_array().map(f32::to_bits),
                        b.to_array().map(f32::to_bits)
                    );
                }
            }
        }
    }

    #[test]
    fn indices_take_the_fewest_bits_that_count_the_table() {
        // n distinct values (7i mod n, n prime to 7: all of them) in a 13×11 image (143
        // texels, not a whole number of bytes at any width).
        for (n, bits) in [
            (1, 1),
            (2, 1),
            (3, 2),
            (4, 2),
            (5, 4),
            (16, 4),
            (17, 8),
            (128, 8),
        ] {
            let texels: Vec<PackedRgb> = (0..143u32)
                .map(|i| PackedRgb::splat((i * 7 % n) as f32 * 0.5))
                .collect();
            let img = Image::new(13, 11, texels.clone()).unwrap();
            let p = PaletteLevel::from_image(&img).unwrap();
            assert_eq!(p.palette.len(), n as usize);
            assert_eq!(
                p.index.len(),
                (143 * bits as usize).div_ceil(8),
                "{n} values"
            );
            for (i, t) in texels.iter().enumerate() {
                let want = Rgb::from(*t).to_array().map(f32::to_bits);
                assert_eq!(
                    p.fetch(i).to_array().map(f32::to_bits),
                    want,
                    "{n} values, texel {i}"
                );
            }
        }
    }

    #[test]
    fn more_than_256_values_stay_floats() {
        let texels = (0..257).map(|i| PackedRgb::splat(i as f32)).collect();
        assert!(PaletteLevel::from_image(&Image::new(257, 1, texels).unwrap()).is_none());
        let texels = (0..256).map(|i| PackedRgb::splat(i as f32)).collect();
        let p = PaletteLevel::from_image(&Image::new(16, 16, texels).unwrap()).unwrap();
        assert_eq!(p.texel(15, 15, WrapMode::Clamp), Rgb::splat(255.0));
    }
}
