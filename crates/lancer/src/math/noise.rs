//! Perlin noise, fractional Brownian motion and turbulence, as pbrt-v4 defines them (its
//! `Noise`, `FBm` and `Turbulence`), so that procedural textures and clouds match its images.
//!
//! Noise is Perlin's gradient noise on the integer lattice: each lattice point gets one of 12
//! edge gradients (16 with 4 repeated) from a hash of its coordinates through a fixed
//! permutation, each corner of the cell containing p contributes `g · (p − corner)`, and the
//! eight contributions are blended with the quintic `6t⁵ − 15t⁴ + 10t³`. Noise is 0 at every
//! lattice point and lies in [−1, 1].

use super::{Vec3, lerp, smooth_step};

/// Ken Perlin's permutation of 0..255, the one pbrt-v4 uses.
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// pbrt-v4's 512-entry table: the permutation, then the permutation again. Its initialiser
/// lists only 507 values, so entries 507..511 are zero; indices up to 511 are reached
/// (`perm[x] + y` with y ≤ 256), so the zeros are kept to match its images.
#[inline]
fn perm(i: usize) -> usize {
    match i {
        0..=255 => PERM[i] as usize,
        256..=506 => PERM[i - 256] as usize,
        _ => 0,
    }
}

/// The gradient of lattice point (x, y, z) dotted with the offset (dx, dy, dz): the hash
/// `h = perm[perm[perm[x] + y] + z] mod 16` picks two of the offset's components and their
/// signs (h < 8 or h ∈ {12, 13}: u = dx else dy; h < 4 or h ∈ {12, 13}: v = dy else dz;
/// bit 0 negates u, bit 1 negates v).
#[inline]
fn grad(x: usize, y: usize, z: usize, dx: f32, dy: f32, dz: f32) -> f32 {
    let h = perm(perm(perm(x) + y) + z) & 15;
    let u = if h < 8 || h == 12 || h == 13 { dx } else { dy };
    let v = if h < 4 || h == 12 || h == 13 { dy } else { dz };
    (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
}

/// The quintic blend `6t⁵ − 15t⁴ + 10t³` (zero first and second derivatives at 0 and 1).
#[inline]
fn weight(t: f32) -> f32 {
    let t3 = t * t * t;
    let t4 = t3 * t;
    6.0 * t4 * t - 15.0 * t4 + 10.0 * t3
}

/// Perlin noise at p, in [−1, 1], zero at integer points.
///
/// Coordinates are first reduced modulo 2³⁰ (as pbrt-v4, to keep the cell index in an i32).
pub fn noise(p: Vec3) -> f32 {
    const WRAP: f32 = (1u32 << 30) as f32;
    let (x, y, z) = (p.x % WRAP, p.y % WRAP, p.z % WRAP);
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let (dx, dy, dz) = (x - fx, y - fy, z - fz);
    // Cell index modulo 256 (two's complement `& 255`, as pbrt-v4, also for negative cells).
    let ix = (fx as i32 & 255) as usize;
    let iy = (fy as i32 & 255) as usize;
    let iz = (fz as i32 & 255) as usize;
    let w000 = grad(ix, iy, iz, dx, dy, dz);
    let w100 = grad(ix + 1, iy, iz, dx - 1.0, dy, dz);
    let w010 = grad(ix, iy + 1, iz, dx, dy - 1.0, dz);
    let w110 = grad(ix + 1, iy + 1, iz, dx - 1.0, dy - 1.0, dz);
    let w001 = grad(ix, iy, iz + 1, dx, dy, dz - 1.0);
    let w101 = grad(ix + 1, iy, iz + 1, dx - 1.0, dy, dz - 1.0);
    let w011 = grad(ix, iy + 1, iz + 1, dx, dy - 1.0, dz - 1.0);
    let w111 = grad(ix + 1, iy + 1, iz + 1, dx - 1.0, dy - 1.0, dz - 1.0);
    let (wx, wy, wz) = (weight(dx), weight(dy), weight(dz));
    let x00 = lerp(wx, w000, w100);
    let x10 = lerp(wx, w010, w110);
    let x01 = lerp(wx, w001, w101);
    let x11 = lerp(wx, w011, w111);
    let y0 = lerp(wy, x00, x10);
    let y1 = lerp(wy, x01, x11);
    lerp(wz, y0, y1)
}

/// The gradient of [`noise`] by forward differences with step 0.01 (pbrt-v4's `DNoise`).
pub fn dnoise(p: Vec3) -> Vec3 {
    const DELTA: f32 = 0.01;
    let n = noise(p);
    Vec3::new(
        noise(p + Vec3::new(DELTA, 0.0, 0.0)) - n,
        noise(p + Vec3::new(0.0, DELTA, 0.0)) - n,
        noise(p + Vec3::new(0.0, 0.0, DELTA)) - n,
    ) / DELTA
}

/// The number of octaves an antialiased sum keeps: `clamp(−1 − log₂(max(|dpdx|², |dpdy|²))/2,
/// 0, max_octaves)` — octaves whose frequency exceeds the Nyquist limit of the footprint are
/// dropped, the last one faded in.
#[inline]
fn octaves(dpdx: Vec3, dpdy: Vec3, max_octaves: u32) -> f32 {
    let len2 = dpdx.length_squared().max(dpdy.length_squared());
    (-1.0 - len2.log2() / 2.0).clamp(0.0, max_octaves as f32)
}

/// Fractional Brownian motion: `Σᵢ ωⁱ · noise(λᵢ p)` with λᵢ = 1.99ⁱ, over the octaves the
/// footprint (dpdx, dpdy) allows; the fractional last octave is faded in by
/// `smoothstep(0.3, 0.7, frac)`. Zero footprint keeps all `max_octaves`.
pub fn fbm(p: Vec3, dpdx: Vec3, dpdy: Vec3, omega: f32, max_octaves: u32) -> f32 {
    let n = octaves(dpdx, dpdy, max_octaves);
    let n_int = n.floor() as u32;
    let (mut sum, mut lambda, mut o) = (0.0f32, 1.0f32, 1.0f32);
    for _ in 0..n_int {
        sum += o * noise(lambda * p);
        lambda *= 1.99;
        o *= omega;
    }
    let partial = n - n_int as f32;
    sum + o * smooth_step(partial, 0.3, 0.7) * noise(lambda * p)
}

/// Turbulence: `Σᵢ ωⁱ · |noise(λᵢ p)|` with λᵢ = 1.99ⁱ; the fractional octave blends from 0.2
/// (the mean of |noise|) to its value, and every octave dropped by the footprint adds
/// `ωⁱ · 0.2`, so the average brightness does not change with distance.
pub fn turbulence(p: Vec3, dpdx: Vec3, dpdy: Vec3, omega: f32, max_octaves: u32) -> f32 {
    let n = octaves(dpdx, dpdy, max_octaves);
    let n_int = n.floor() as u32;
    let (mut sum, mut lambda, mut o) = (0.0f32, 1.0f32, 1.0f32);
    for _ in 0..n_int {
        sum += o * noise(lambda * p).abs();
        lambda *= 1.99;
        o *= omega;
    }
    let partial = n - n_int as f32;
    sum += o * lerp(smooth_step(partial, 0.3, 0.7), 0.2, noise(lambda * p).abs());
    for _ in n_int..max_octaves {
        sum += o * 0.2;
        o *= omega;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn noise_matches_pbrt_v4_reference_values() {
        // Values from an independent double-precision transcription of pbrt-v4's Noise.
        for (p, want) in [
            (v(0.5, 0.25, 0.75), -0.375_078_68),
            (v(1.3, -2.7, 4.1), 0.168_821_48),
            (v(-0.6, 0.1, 255.5), -0.346_736_34),
            (v(100.25, 37.5, -12.125), -0.139_909_94),
        ] {
            let got = noise(p);
            assert!((got - want).abs() < 2e-5, "noise({p}) = {got}, want {want}");
        }
    }

    #[test]
    fn noise_keeps_pbrt_v4s_zero_table_tail() {
        // This cell reaches table entries 507..511, which are 0 in pbrt-v4 (a full second
        // copy of the permutation would give 0.0 here instead of −0.25).
        assert!((noise(v(0.5, 18.5, 255.5)) + 0.25).abs() < 1e-6);
    }

    #[test]
    fn noise_vanishes_on_the_lattice_and_stays_in_range() {
        for i in -3..4 {
            for j in -3..4 {
                let p = v(i as f32, j as f32, (i * j) as f32);
                assert_eq!(noise(p), 0.0, "noise at lattice point {p}");
            }
        }
        let mut max = 0.0f32;
        for k in 0..20_000 {
            let t = k as f32 * 0.013_7;
            let n = noise(v(t, 1.7 * t.sin() * 9.0, 0.37 * t));
            assert!((-1.0..=1.0).contains(&n));
            max = max.max(n.abs());
        }
        assert!(max > 0.4, "noise should vary, max |n| = {max}");
    }

    #[test]
    fn noise_is_continuous_across_cells() {
        let eps = 1e-3;
        for x in [0.0f32, 1.0, 7.0, 255.0] {
            let a = noise(v(x - eps, 0.3, 0.6));
            let b = noise(v(x + eps, 0.3, 0.6));
            assert!((a - b).abs() < 1e-2, "jump at x = {x}: {a} vs {b}");
        }
    }

    #[test]
    fn dnoise_is_the_forward_difference_gradient() {
        // The x component against a central difference of the same function.
        let p = v(0.3, 0.4, 0.55);
        let d = dnoise(p);
        let h = 1e-3;
        let cx = (noise(p + v(h, 0.0, 0.0)) - noise(p - v(h, 0.0, 0.0))) / (2.0 * h);
        assert!((d.x - cx).abs() < 0.1, "{} vs {cx}", d.x);
    }

    #[test]
    fn fbm_and_turbulence_match_pbrt_v4_reference_values() {
        let p = v(0.3, 1.7, -2.2);
        let zero = Vec3::ZERO;
        // Footprint |dpdx|² = 0.01: n = −1 − log₂(0.01)/2 ≈ 2.32 octaves.
        let small = v(0.1, 0.0, 0.0);
        for (got, want) in [
            (fbm(p, zero, zero, 0.5, 8), -0.572_996),
            (fbm(p, small, zero, 0.5, 8), -0.635_716),
            (turbulence(p, zero, zero, 0.5, 8), 0.711_997),
            (turbulence(p, small, zero, 0.5, 8), 0.783_935),
        ] {
            assert!((got - want).abs() < 1e-4, "{got} vs {want}");
        }
    }

    #[test]
    fn huge_footprints_keep_turbulence_at_its_mean() {
        // No octave survives: fbm is 0 and turbulence is Σ ωⁱ · 0.2 (+ the faded octave 0.2).
        let p = v(3.3, 2.1, 0.7);
        let big = v(100.0, 0.0, 0.0);
        assert_eq!(fbm(p, big, big, 0.5, 4), 0.0);
        let want = 0.2 + 0.2 * (1.0 + 0.5 + 0.25 + 0.125);
        assert!((turbulence(p, big, big, 0.5, 4) - want).abs() < 1e-6);
    }
}
