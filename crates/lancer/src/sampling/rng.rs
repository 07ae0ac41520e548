//! A small pseudo-random generator for estimators that need a stream of numbers not tied to
//! sampler dimensions (the random walks of layered BSDFs).

use super::hash::u32_to_unit_f32;

/// O'Neill's PCG32 (XSH-RR output of a 64-bit linear congruential generator): state
/// s ← s·6364136223846793005 + inc, output = rotr32(((s ⊕ (s ≫ 18)) ≫ 27), s ≫ 59) taken from
/// the state before the step. `inc` (odd) selects one of 2⁶³ independent streams.
#[derive(Clone, Copy, Debug)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

const PCG_MULT: u64 = 0x5851_f42d_4c95_7f2d;

impl Pcg32 {
    /// The generator on stream `seq`, started at `offset` (the seeding procedure of the PCG
    /// reference: state 0, one step, add the offset, one step).
    pub fn new(seq: u64, offset: u64) -> Pcg32 {
        let mut r = Pcg32 {
            state: 0,
            inc: (seq << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(offset);
        r.next_u32();
        r
    }

    /// The next 32 uniformly distributed bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// A uniform float in [0, 1), never 1.
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        u32_to_unit_f32(self.next_u32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let mut a = Pcg32::new(7, 3);
        let mut b = Pcg32::new(7, 3);
        let mut c = Pcg32::new(8, 3);
        let xa: Vec<u32> = (0..16).map(|_| a.next_u32()).collect();
        let xb: Vec<u32> = (0..16).map(|_| b.next_u32()).collect();
        let xc: Vec<u32> = (0..16).map(|_| c.next_u32()).collect();
        assert_eq!(xa, xb);
        assert_ne!(xa, xc);
    }

    #[test]
    fn uniform_floats_have_the_right_mean_and_variance() {
        // Mean 1/2 and variance 1/12; with 10⁵ draws the standard errors are about 0.0009 and
        // 0.0003, so these bounds are some 5σ wide.
        let mut r = Pcg32::new(1, 2);
        let n = 100_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = r.uniform() as f64;
            assert!((0.0..1.0).contains(&u));
            s += u;
            s2 += u * u;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 0.0015, "variance {var}");
    }
}
