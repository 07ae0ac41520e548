//! Four `f32` lanes: SSE/FMA registers on x86-64 (lancer is built for x86-64-v3), plain arrays
//! elsewhere. Every operation is the IEEE one of the scalar code (fused where named), so a
//! lane computes bit for bit what the scalar expression computes.

#[cfg(all(
    target_arch = "x86_64",
    target_feature = "sse4.1",
    target_feature = "fma"
))]
mod imp {
    //! SAFETY (every `unsafe` block below): the intrinsics need SSE4.1 and FMA, which the
    //! `cfg` of this module guarantees the build enables.
    use std::arch::x86_64::*;

    /// Four floats.
    #[derive(Clone, Copy, Debug)]
    pub struct F4(__m128);

    impl F4 {
        #[inline(always)]
        pub fn splat(v: f32) -> F4 {
            F4(unsafe { _mm_set1_ps(v) })
        }
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> F4 {
            // SAFETY: `a` is four readable floats; the load has no alignment requirement.
            F4(unsafe { _mm_loadu_ps(a.as_ptr()) })
        }
        /// The coordinates of the four positions `p[i[0]]` … `p[i[3]]` as lanes, axis `axes[0]`
        /// first: each position loaded as 16 bytes (x, y, z and the next position's x), the
        /// four transposed by unpacks. (AVX2 gathers did this in fewer instructions, but each
        /// waited tens of cycles.)
        ///
        /// # Safety
        /// Every index is below `p.len() − 1`: the 16 bytes from its position end inside `p`.
        #[inline(always)]
        pub unsafe fn positions_as_lanes(
            p: &[crate::math::PackedVec3],
            i: [u32; 4],
            axes: [usize; 3],
        ) -> [F4; 3] {
            let p = p.as_ptr() as *const f32;
            // SAFETY: the caller's: each load ends inside the slice.
            unsafe {
                let v0 = _mm_loadu_ps(p.add(3 * i[0] as usize));
                let v1 = _mm_loadu_ps(p.add(3 * i[1] as usize));
                let v2 = _mm_loadu_ps(p.add(3 * i[2] as usize));
                let v3 = _mm_loadu_ps(p.add(3 * i[3] as usize));
                // (x0 x1 y0 y1), (x2 x3 y2 y3), (z0 z1 · ·), (z2 z3 · ·)
                let (a, b) = (_mm_unpacklo_ps(v0, v1), _mm_unpacklo_ps(v2, v3));
                let (c, d) = (_mm_unpackhi_ps(v0, v1), _mm_unpackhi_ps(v2, v3));
                let xyz = [
                    _mm_movelh_ps(a, b),
                    _mm_movehl_ps(b, a),
                    _mm_movelh_ps(c, d),
                ];
                [F4(xyz[axes[0]]), F4(xyz[axes[1]]), F4(xyz[axes[2]])]
            }
        }
        /// Lane `i` (0 ≤ i < 4), taken in registers (no round trip through memory).
        #[inline(always)]
        pub fn lane(self, i: usize) -> f32 {
            #[cfg(target_feature = "avx")]
            // SAFETY: AVX is enabled (cfg); the permute reads only the low two bits of `i`.
            unsafe {
                _mm_cvtss_f32(_mm_permutevar_ps(self.0, _mm_cvtsi32_si128(i as i32)))
            }
            #[cfg(not(target_feature = "avx"))]
            self.to_array()[i & 3]
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            let mut out = [0.0f32; 4];
            // SAFETY: `out` is four writable floats; the store has no alignment requirement.
            unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        pub fn add(self, o: F4) -> F4 {
            F4(unsafe { _mm_add_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn sub(self, o: F4) -> F4 {
            F4(unsafe { _mm_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn mul(self, o: F4) -> F4 {
            F4(unsafe { _mm_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn div(self, o: F4) -> F4 {
            F4(unsafe { _mm_div_ps(self.0, o.0) })
        }
        /// −(self·b) + c, rounded once.
        #[inline(always)]
        pub fn neg_mul_add(self, b: F4, c: F4) -> F4 {
            F4(unsafe { _mm_fnmadd_ps(self.0, b.0, c.0) })
        }
        /// self·b − c, rounded once.
        #[inline(always)]
        pub fn mul_sub(self, b: F4, c: F4) -> F4 {
            F4(unsafe { _mm_fmsub_ps(self.0, b.0, c.0) })
        }
        /// Lane-wise `if self > o { self } else { o }` (so `o` when either is NaN).
        #[inline(always)]
        pub fn max(self, o: F4) -> F4 {
            F4(unsafe { _mm_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn abs(self) -> F4 {
            F4(unsafe { _mm_andnot_ps(_mm_set1_ps(-0.0), self.0) })
        }
        #[inline(always)]
        pub fn lt(self, o: F4) -> M4 {
            M4(unsafe { _mm_cmplt_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn le(self, o: F4) -> M4 {
            M4(unsafe { _mm_cmple_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn gt(self, o: F4) -> M4 {
            M4(unsafe { _mm_cmpgt_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn ge(self, o: F4) -> M4 {
            M4(unsafe { _mm_cmpge_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn eq(self, o: F4) -> M4 {
            M4(unsafe { _mm_cmpeq_ps(self.0, o.0) })
        }
    }

    /// Four lane masks.
    #[derive(Clone, Copy, Debug)]
    pub struct M4(__m128);

    impl M4 {
        #[inline(always)]
        pub fn and(self, o: M4) -> M4 {
            M4(unsafe { _mm_and_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn or(self, o: M4) -> M4 {
            M4(unsafe { _mm_or_ps(self.0, o.0) })
        }
        /// `self and not o`.
        #[inline(always)]
        pub fn and_not(self, o: M4) -> M4 {
            M4(unsafe { _mm_andnot_ps(o.0, self.0) })
        }
        /// Bit k set when lane k is true.
        #[inline(always)]
        pub fn bits(self) -> u32 {
            (unsafe { _mm_movemask_ps(self.0) }) as u32
        }
    }

    /// Bit k set when `ids[k]` is not `u32::MAX` (one compare of the four at once).
    #[inline(always)]
    pub fn not_max_bits(ids: &[u32; 4]) -> u32 {
        // SAFETY: `ids` is sixteen readable bytes; the load has no alignment requirement.
        let eq = unsafe {
            let v = _mm_loadu_si128(ids.as_ptr() as *const __m128i);
            _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(v, _mm_set1_epi32(-1))))
        };
        eq as u32 ^ 0xf
    }
}

#[cfg(not(all(
    target_arch = "x86_64",
    target_feature = "sse4.1",
    target_feature = "fma"
)))]
mod imp {
    /// Four floats.
    #[derive(Clone, Copy, Debug)]
    pub struct F4([f32; 4]);

    #[inline(always)]
    fn map2(a: F4, b: F4, f: impl Fn(f32, f32) -> f32) -> F4 {
        F4([
            f(a.0[0], b.0[0]),
            f(a.0[1], b.0[1]),
            f(a.0[2], b.0[2]),
            f(a.0[3], b.0[3]),
        ])
    }
    #[inline(always)]
    fn cmp(a: F4, b: F4, f: impl Fn(f32, f32) -> bool) -> M4 {
        M4([
            f(a.0[0], b.0[0]),
            f(a.0[1], b.0[1]),
            f(a.0[2], b.0[2]),
            f(a.0[3], b.0[3]),
        ])
    }

    impl F4 {
        #[inline(always)]
        pub fn splat(v: f32) -> F4 {
            F4([v; 4])
        }
        /// The coordinates of `p[i[0]]` … `p[i[3]]` as lanes, axis `axes[0]` first (read with
        /// bounds checks).
        ///
        /// # Safety
        /// None here; the SSE version's: every index below `p.len() − 1`.
        #[inline(always)]
        pub unsafe fn positions_as_lanes(
            p: &[crate::math::PackedVec3],
            i: [u32; 4],
            axes: [usize; 3],
        ) -> [F4; 3] {
            axes.map(|a| F4(i.map(|k| p[k as usize][a])))
        }
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> F4 {
            F4(*a)
        }
        /// Lane `i` (0 ≤ i < 4).
        #[inline(always)]
        pub fn lane(self, i: usize) -> f32 {
            self.0[i & 3]
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            self.0
        }
        #[inline(always)]
        pub fn add(self, o: F4) -> F4 {
            map2(self, o, |a, b| a + b)
        }
        #[inline(always)]
        pub fn sub(self, o: F4) -> F4 {
            map2(self, o, |a, b| a - b)
        }
        #[inline(always)]
        pub fn mul(self, o: F4) -> F4 {
            map2(self, o, |a, b| a * b)
        }
        #[inline(always)]
        pub fn div(self, o: F4) -> F4 {
            map2(self, o, |a, b| a / b)
        }
        #[inline(always)]
        pub fn neg_mul_add(self, b: F4, c: F4) -> F4 {
            let mut r = [0.0; 4];
            for k in 0..4 {
                r[k] = (-self.0[k]).mul_add(b.0[k], c.0[k]);
            }
            F4(r)
        }
        #[inline(always)]
        pub fn mul_sub(self, b: F4, c: F4) -> F4 {
            let mut r = [0.0; 4];
            for k in 0..4 {
                r[k] = self.0[k].mul_add(b.0[k], -c.0[k]);
            }
            F4(r)
        }
        #[inline(always)]
        pub fn max(self, o: F4) -> F4 {
            map2(self, o, |a, b| if a > b { a } else { b })
        }
        #[inline(always)]
        pub fn abs(self) -> F4 {
            F4(self.0.map(f32::abs))
        }
        #[inline(always)]
        pub fn lt(self, o: F4) -> M4 {
            cmp(self, o, |a, b| a < b)
        }
        #[inline(always)]
        pub fn le(self, o: F4) -> M4 {
            cmp(self, o, |a, b| a <= b)
        }
        #[inline(always)]
        pub fn gt(self, o: F4) -> M4 {
            cmp(self, o, |a, b| a > b)
        }
        #[inline(always)]
        pub fn ge(self, o: F4) -> M4 {
            cmp(self, o, |a, b| a >= b)
        }
        #[inline(always)]
        pub fn eq(self, o: F4) -> M4 {
            cmp(self, o, |a, b| a == b)
        }
    }

    /// Four lane masks.
    #[derive(Clone, Copy, Debug)]
    pub struct M4([bool; 4]);

    impl M4 {
        #[inline(always)]
        pub fn and(self, o: M4) -> M4 {
            M4([0, 1, 2, 3].map(|k| self.0[k] && o.0[k]))
        }
        #[inline(always)]
        pub fn or(self, o: M4) -> M4 {
            M4([0, 1, 2, 3].map(|k| self.0[k] || o.0[k]))
        }
        #[inline(always)]
        pub fn and_not(self, o: M4) -> M4 {
            M4([0, 1, 2, 3].map(|k| self.0[k] && !o.0[k]))
        }
        #[inline(always)]
        pub fn bits(self) -> u32 {
            (0..4).filter(|&k| self.0[k]).map(|k| 1u32 << k).sum()
        }
    }

    /// Bit k set when `ids[k]` is not `u32::MAX`.
    #[inline(always)]
    pub fn not_max_bits(ids: &[u32; 4]) -> u32 {
        (0..4)
            .filter(|&k| ids[k] != u32::MAX)
            .map(|k| 1u32 << k)
            .sum()
    }
}

pub(crate) use imp::{F4, M4, not_max_bits};

// Eight `f32` lanes (AVX on x86-64-v3, arrays elsewhere): the 8-wide slab test's, and the
// ray packets' (eight rays against one triangle, [`super::tri4`]), each the IEEE operation of
// the scalar code as in `F4`.
#[cfg(all(target_arch = "x86_64", target_feature = "avx", target_feature = "fma"))]
mod imp8 {
    //! SAFETY (every `unsafe` block below): the intrinsics need AVX, which the `cfg` of this
    //! module guarantees the build enables.
    use std::arch::x86_64::*;

    /// Eight floats.
    #[derive(Clone, Copy, Debug)]
    pub struct F8(__m256);

    impl F8 {
        #[inline(always)]
        pub fn splat(v: f32) -> F8 {
            F8(unsafe { _mm256_set1_ps(v) })
        }
        #[inline(always)]
        pub fn load(a: &[f32; 8]) -> F8 {
            // SAFETY: `a` is eight readable floats; the load has no alignment requirement.
            F8(unsafe { _mm256_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 8] {
            let mut out = [0.0f32; 8];
            // SAFETY: `out` is eight writable floats; the store has no alignment requirement.
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        pub fn sub(self, o: F8) -> F8 {
            F8(unsafe { _mm256_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn mul(self, o: F8) -> F8 {
            F8(unsafe { _mm256_mul_ps(self.0, o.0) })
        }
        /// Lane-wise `if self < o { self } else { o }` (so `o` when either is NaN).
        #[inline(always)]
        pub fn min(self, o: F8) -> F8 {
            F8(unsafe { _mm256_min_ps(self.0, o.0) })
        }
        /// Lane-wise `if self > o { self } else { o }` (so `o` when either is NaN).
        #[inline(always)]
        pub fn max(self, o: F8) -> F8 {
            F8(unsafe { _mm256_max_ps(self.0, o.0) })
        }
        /// Bit k set where lane k of `self` ≤ lane k of `o`.
        #[inline(always)]
        pub fn le_bits(self, o: F8) -> u32 {
            (unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) }) as u32
        }
        #[inline(always)]
        pub fn from_array(a: [f32; 8]) -> F8 {
            F8::load(&a)
        }
        /// Lane `i` (0 ≤ i < 8).
        #[inline(always)]
        pub fn lane(self, i: usize) -> f32 {
            // SAFETY: the permute reads only the low three bits of each index.
            unsafe {
                _mm256_cvtss_f32(_mm256_permutevar8x32_ps(
                    self.0,
                    _mm256_set1_epi32(i as i32),
                ))
            }
        }
        #[inline(always)]
        pub fn add(self, o: F8) -> F8 {
            F8(unsafe { _mm256_add_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn div(self, o: F8) -> F8 {
            F8(unsafe { _mm256_div_ps(self.0, o.0) })
        }
        /// −(self·b) + c, rounded once.
        #[inline(always)]
        pub fn neg_mul_add(self, b: F8, c: F8) -> F8 {
            F8(unsafe { _mm256_fnmadd_ps(self.0, b.0, c.0) })
        }
        /// self·b − c, rounded once.
        #[inline(always)]
        pub fn mul_sub(self, b: F8, c: F8) -> F8 {
            F8(unsafe { _mm256_fmsub_ps(self.0, b.0, c.0) })
        }
        #[inline(always)]
        pub fn abs(self) -> F8 {
            F8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
        }
        #[inline(always)]
        pub fn lt(self, o: F8) -> M8 {
            M8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn le(self, o: F8) -> M8 {
            M8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn gt(self, o: F8) -> M8 {
            M8(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn ge(self, o: F8) -> M8 {
            M8(unsafe { _mm256_cmp_ps::<_CMP_GE_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn eq(self, o: F8) -> M8 {
            M8(unsafe { _mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, o.0) })
        }
        /// Lane-wise `if m { a } else { b }`.
        #[inline(always)]
        pub fn select(m: M8, a: F8, b: F8) -> F8 {
            F8(unsafe { _mm256_blendv_ps(b.0, a.0, m.0) })
        }
        /// Bit k set where lane k of `self` < lane k of `o`.
        #[inline(always)]
        pub fn lt_bits(self, o: F8) -> u32 {
            (unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0)) }) as u32
        }
        /// `f` of each lane.
        #[inline(always)]
        pub fn map(self, f: impl Fn(f32) -> f32) -> F8 {
            F8::from_array(self.to_array().map(f))
        }
    }

    /// Eight lane masks.
    #[derive(Clone, Copy, Debug)]
    pub struct M8(__m256);

    impl M8 {
        /// The mask whose lane k is bit k of `bits`.
        #[inline(always)]
        pub fn from_bits(bits: u32) -> M8 {
            // SAFETY: integer and float-mask operations of AVX2 (x86-64-v3).
            unsafe {
                let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
                let set = _mm256_and_si256(_mm256_set1_epi32(bits as i32), lanes);
                M8(_mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lanes)))
            }
        }
        #[inline(always)]
        pub fn and(self, o: M8) -> M8 {
            M8(unsafe { _mm256_and_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn or(self, o: M8) -> M8 {
            M8(unsafe { _mm256_or_ps(self.0, o.0) })
        }
        /// `self and not o`.
        #[inline(always)]
        pub fn and_not(self, o: M8) -> M8 {
            M8(unsafe { _mm256_andnot_ps(o.0, self.0) })
        }
        /// Bit k set when lane k is true.
        #[inline(always)]
        pub fn bits(self) -> u32 {
            (unsafe { _mm256_movemask_ps(self.0) }) as u32
        }
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx", target_feature = "fma")))]
mod imp8 {
    /// Eight floats.
    #[derive(Clone, Copy, Debug)]
    pub struct F8([f32; 8]);

    impl F8 {
        #[inline(always)]
        pub fn splat(v: f32) -> F8 {
            F8([v; 8])
        }
        #[inline(always)]
        pub fn load(a: &[f32; 8]) -> F8 {
            F8(*a)
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 8] {
            self.0
        }
        #[inline(always)]
        pub fn sub(self, o: F8) -> F8 {
            F8(std::array::from_fn(|k| self.0[k] - o.0[k]))
        }
        #[inline(always)]
        pub fn mul(self, o: F8) -> F8 {
            F8(std::array::from_fn(|k| self.0[k] * o.0[k]))
        }
        #[inline(always)]
        pub fn min(self, o: F8) -> F8 {
            F8(std::array::from_fn(|k| {
                if self.0[k] < o.0[k] {
                    self.0[k]
                } else {
                    o.0[k]
                }
            }))
        }
        #[inline(always)]
        pub fn max(self, o: F8) -> F8 {
            F8(std::array::from_fn(|k| {
                if self.0[k] > o.0[k] {
                    self.0[k]
                } else {
                    o.0[k]
                }
            }))
        }
        #[inline(always)]
        pub fn le_bits(self, o: F8) -> u32 {
            (0..8)
                .filter(|&k| self.0[k] <= o.0[k])
                .map(|k| 1u32 << k)
                .sum()
        }
        #[inline(always)]
        pub fn from_array(a: [f32; 8]) -> F8 {
            F8(a)
        }
        #[inline(always)]
        pub fn lane(self, i: usize) -> f32 {
            self.0[i & 7]
        }
        #[inline(always)]
        pub fn add(self, o: F8) -> F8 {
            F8(std::array::from_fn(|k| self.0[k] + o.0[k]))
        }
        #[inline(always)]
        pub fn div(self, o: F8) -> F8 {
            F8(std::array::from_fn(|k| self.0[k] / o.0[k]))
        }
        /// −(self·b) + c, rounded once.
        #[inline(always)]
        pub fn neg_mul_add(self, b: F8, c: F8) -> F8 {
            F8(std::array::from_fn(|k| {
                (-self.0[k]).mul_add(b.0[k], c.0[k])
            }))
        }
        /// self·b − c, rounded once.
        #[inline(always)]
        pub fn mul_sub(self, b: F8, c: F8) -> F8 {
            F8(std::array::from_fn(|k| self.0[k].mul_add(b.0[k], -c.0[k])))
        }
        #[inline(always)]
        pub fn abs(self) -> F8 {
            F8(self.0.map(f32::abs))
        }
        #[inline(always)]
        pub fn lt(self, o: F8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] < o.0[k]))
        }
        #[inline(always)]
        pub fn le(self, o: F8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] <= o.0[k]))
        }
        #[inline(always)]
        pub fn gt(self, o: F8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] > o.0[k]))
        }
        #[inline(always)]
        pub fn ge(self, o: F8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] >= o.0[k]))
        }
        #[inline(always)]
        pub fn eq(self, o: F8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] == o.0[k]))
        }
        /// Lane-wise `if m { a } else { b }`.
        #[inline(always)]
        pub fn select(m: M8, a: F8, b: F8) -> F8 {
            F8(std::array::from_fn(
                |k| if m.0[k] { a.0[k] } else { b.0[k] },
            ))
        }
        /// Bit k set where lane k of `self` < lane k of `o`.
        #[inline(always)]
        pub fn lt_bits(self, o: F8) -> u32 {
            (0..8)
                .filter(|&k| self.0[k] < o.0[k])
                .map(|k| 1u32 << k)
                .sum()
        }
        /// `f` of each lane.
        #[inline(always)]
        pub fn map(self, f: impl Fn(f32) -> f32) -> F8 {
            F8(self.0.map(f))
        }
    }

    /// Eight lane masks.
    #[derive(Clone, Copy, Debug)]
    pub struct M8([bool; 8]);

    impl M8 {
        /// The mask whose lane k is bit k of `bits`.
        #[inline(always)]
        pub fn from_bits(bits: u32) -> M8 {
            M8(std::array::from_fn(|k| bits >> k & 1 != 0))
        }
        #[inline(always)]
        pub fn and(self, o: M8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] && o.0[k]))
        }
        #[inline(always)]
        pub fn or(self, o: M8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] || o.0[k]))
        }
        /// `self and not o`.
        #[inline(always)]
        pub fn and_not(self, o: M8) -> M8 {
            M8(std::array::from_fn(|k| self.0[k] && !o.0[k]))
        }
        /// Bit k set when lane k is true.
        #[inline(always)]
        pub fn bits(self) -> u32 {
            (0..8).filter(|&k| self.0[k]).map(|k| 1u32 << k).sum()
        }
    }
}

pub(crate) use imp8::{F8, M8};

/// The operations the watertight triangle test ([`super::tri4`]) runs on lanes: [`F4`] (one
/// ray against four triangles) and [`F8`] (eight rays against one triangle). Each is the IEEE
/// operation of the scalar code, so a lane's result does not depend on the width.
pub(crate) trait Lanes: Copy {
    /// The lanes' comparison results.
    type Mask: MaskLanes;
    /// Every lane's bit.
    const ALL: u32;
    fn splat(v: f32) -> Self;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    /// −(self·b) + c, rounded once.
    fn neg_mul_add(self, b: Self, c: Self) -> Self;
    /// self·b − c, rounded once.
    fn mul_sub(self, b: Self, c: Self) -> Self;
    /// Lane-wise `if self > o { self } else { o }`.
    fn max(self, o: Self) -> Self;
    fn abs(self) -> Self;
    fn lt(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn ge(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn eq(self, o: Self) -> Self::Mask;
}

/// Lane masks of a [`Lanes`] type.
pub(crate) trait MaskLanes: Copy {
    fn and(self, o: Self) -> Self;
    fn or(self, o: Self) -> Self;
    /// `self and not o`.
    fn and_not(self, o: Self) -> Self;
    /// Bit k set when lane k is true.
    fn bits(self) -> u32;
}

/// [`Lanes`] and [`MaskLanes`] for a vector type and its mask, by its own methods.
macro_rules! lanes {
    ($f:ident, $m:ident, $all:expr) => {
        impl Lanes for $f {
            type Mask = $m;
            const ALL: u32 = $all;
            #[inline(always)]
            fn splat(v: f32) -> Self {
                $f::splat(v)
            }
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                $f::add(self, o)
            }
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                $f::sub(self, o)
            }
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                $f::mul(self, o)
            }
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                $f::div(self, o)
            }
            #[inline(always)]
            fn neg_mul_add(self, b: Self, c: Self) -> Self {
                $f::neg_mul_add(self, b, c)
            }
            #[inline(always)]
            fn mul_sub(self, b: Self, c: Self) -> Self {
                $f::mul_sub(self, b, c)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                $f::max(self, o)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $f::abs(self)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $m {
                $f::lt(self, o)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> $m {
                $f::gt(self, o)
            }
            #[inline(always)]
            fn ge(self, o: Self) -> $m {
                $f::ge(self, o)
            }
            #[inline(always)]
            fn le(self, o: Self) -> $m {
                $f::le(self, o)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> $m {
                $f::eq(self, o)
            }
        }

        impl MaskLanes for $m {
            #[inline(always)]
            fn and(self, o: Self) -> Self {
                $m::and(self, o)
            }
            #[inline(always)]
            fn or(self, o: Self) -> Self {
                $m::or(self, o)
            }
            #[inline(always)]
            fn and_not(self, o: Self) -> Self {
                $m::and_not(self, o)
            }
            #[inline(always)]
            fn bits(self) -> u32 {
                $m::bits(self)
            }
        }
    };
}

lanes!(F4, M4, 0xf);
lanes!(F8, M8, 0xff);
