//! Fresnel equations, reflection and refraction (Snell's law).

use crate::math::{SampledSpectrum, Vec3, safe_sqrt};

/// Mirror reflection of `wo` about `n`: `wr = −wo + 2(wo·n)n`.
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + 2.0 * wo.dot(n) * n
}

/// Refraction of `wi` through a surface with normal `n` (on `wi`'s side) and relative index
/// `eta` = η_t/η_i (Snell: η_i sin θ_i = η_t sin θ_t). Returns the transmitted direction and
/// the relative index actually used (inverted when `wi` is below the surface), or `None` under
/// total internal reflection.
#[inline]
pub fn refract(wi: Vec3, mut n: Vec3, mut eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    Some((-wi / eta + (cos_i / eta - cos_t) * n, eta))
}

/// Unpolarised Fresnel reflectance of a dielectric interface for incident cosine `cos_i` (may be
/// negative: the ray comes from inside) and relative index `eta`:
/// F = (r∥² + r⊥²)/2 with r∥ = (η cos θᵢ − cos θₜ)/(η cos θᵢ + cos θₜ),
/// r⊥ = (cos θᵢ − η cos θₜ)/(cos θᵢ + η cos θₜ).
#[inline]
pub fn fresnel_dielectric(mut cos_i: f32, mut eta: f32) -> f32 {
    cos_i = cos_i.clamp(-1.0, 1.0);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (r_parl * r_parl + r_perp * r_perp) / 2.0
}

/// Fresnel reflectance of a conductor with complex index `eta + i·k`, per lane (wavelength, or
/// RGB channel as (r, g, b, b)), by the same formulas as [`fresnel_dielectric`] in complex
/// arithmetic (PBRT §9.3.6), the four lanes at once: each lane performs exactly the operations
/// of the one-channel function the tests keep beside it, in the same order, its branches turned
/// into selects, so that each lane's value is that function's bit for bit.
#[inline]
pub fn fresnel_complex(cos_i: f32, eta: SampledSpectrum, k: SampledSpectrum) -> SampledSpectrum {
    type V = SampledSpectrum;
    /// Four complex numbers: real parts, imaginary parts.
    #[derive(Clone, Copy)]
    struct C(V, V);
    impl C {
        fn real(v: f32) -> C {
            C(V::splat(v), V::ZERO)
        }
        fn mul(self, o: C) -> C {
            C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
        }
        fn add(self, o: C) -> C {
            C(self.0 + o.0, self.1 + o.1)
        }
        fn sub(self, o: C) -> C {
            C(self.0 - o.0, self.1 - o.1)
        }
        fn div(self, o: C) -> C {
            let s = V::ONE / (o.0 * o.0 + o.1 * o.1);
            C(
                s * (self.0 * o.0 + self.1 * o.1),
                s * (self.1 * o.0 - self.0 * o.1),
            )
        }
        fn norm(self) -> V {
            self.0 * self.0 + self.1 * self.1
        }
        fn sqrt(self) -> C {
            let n = self.norm().sqrt();
            let t1 = (V::splat(0.5) * (n + self.0.abs())).sqrt();
            let t2 = V::splat(0.5) * self.1 / t1;
            let non_negative = self.0.cmpge(V::ZERO);
            let zero = n.cmpeq(V::ZERO);
            C(
                V::select(zero, V::ZERO, V::select(non_negative, t1, t2.abs())),
                V::select(
                    zero,
                    V::ZERO,
                    V::select(non_negative, t2, t1.copysign(self.1)),
                ),
            )
        }
    }
    let cos_i = cos_i.clamp(0.0, 1.0);
    let eta = C(eta, k);
    let sin2_i = C::real(1.0 - cos_i * cos_i);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = C::real(1.0).sub(sin2_t).sqrt();
    let ci = C::real(cos_i);
    let r_parl = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    (r_parl.norm() + r_perp.norm()) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`fresnel_complex`] for one channel, written with branches: the reference its lanes
    /// are checked against.
    fn fresnel_complex_1(cos_i: f32, eta: f32, k: f32) -> f32 {
        #[derive(Clone, Copy)]
        struct C(f32, f32);
        impl C {
            fn mul(self, o: C) -> C {
                C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
            }
            fn add(self, o: C) -> C {
                C(self.0 + o.0, self.1 + o.1)
            }
            fn sub(self, o: C) -> C {
                C(self.0 - o.0, self.1 - o.1)
            }
            fn div(self, o: C) -> C {
                let s = 1.0 / (o.0 * o.0 + o.1 * o.1);
                C(
                    s * (self.0 * o.0 + self.1 * o.1),
                    s * (self.1 * o.0 - self.0 * o.1),
                )
            }
            fn norm(self) -> f32 {
                self.0 * self.0 + self.1 * self.1
            }
            fn sqrt(self) -> C {
                let n = self.norm().sqrt();
                if n == 0.0 {
                    return C(0.0, 0.0);
                }
                let t1 = (0.5 * (n + self.0.abs())).sqrt();
                let t2 = 0.5 * self.1 / t1;
                if self.0 >= 0.0 {
                    C(t1, t2)
                } else {
                    C(t2.abs(), t1.copysign(self.1))
                }
            }
        }
        let cos_i = cos_i.clamp(0.0, 1.0);
        let eta = C(eta, k);
        let sin2_i = C(1.0 - cos_i * cos_i, 0.0);
        let sin2_t = sin2_i.div(eta.mul(eta));
        let cos_t = C(1.0, 0.0).sub(sin2_t).sqrt();
        let ci = C(cos_i, 0.0);
        let r_parl = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
        let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
        (r_parl.norm() + r_perp.norm()) / 2.0
    }

    #[test]
    fn dielectric_fresnel_known_values() {
        // Normal incidence: ((η − 1)/(η + 1))² = 0.04 for glass.
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Total internal reflection from inside beyond the critical angle.
        assert_eq!(fresnel_dielectric(-0.2, 1.5), 1.0);
        // Grazing incidence reflects everything.
        assert!(fresnel_dielectric(1e-4, 1.5) > 0.99);
    }

    #[test]
    fn complex_fresnel_reduces_to_dielectric_when_k_is_zero() {
        for c in [0.1, 0.5, 0.9, 1.0] {
            let f = fresnel_complex(c, SampledSpectrum::splat(1.5), SampledSpectrum::ZERO);
            assert!((f.x - fresnel_dielectric(c, 1.5)).abs() < 1e-5);
        }
        // Normal incidence: ((η − 1)² + k²)/((η + 1)² + k²).
        let (e, k) = (0.2f32, 3.9f32);
        let f0 = ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
        let f = fresnel_complex(1.0, SampledSpectrum::splat(e), SampledSpectrum::splat(k));
        assert!((f.x - f0).abs() < 1e-5);
    }

    #[test]
    fn complex_fresnel_lanes_are_the_scalar_function_bit_for_bit() {
        let mut checked = 0;
        for c in [0.0, 1e-4, 0.1, 0.5, 0.9, 1.0, 1.5, -0.3] {
            for (e, k) in [
                (0.2f32, 3.9f32),
                (1.5, 0.0),
                (0.05, 0.0),
                (1.0, 0.0),
                (2.5, 1.3),
                (0.9, 1e-6),
                (1e-3, 8.0),
            ] {
                let eta = SampledSpectrum::new(e, 1.0 / e.max(1e-3), e * 2.0, 1.0);
                let kk = SampledSpectrum::new(k, k * 0.5, 0.0, k + 1.0);
                let lanes = fresnel_complex(c, eta, kk).to_array();
                for l in 0..4 {
                    let one = fresnel_complex_1(c, eta[l], kk[l]);
                    assert_eq!(
                        lanes[l].to_bits(),
                        one.to_bits(),
                        "cos {c} eta {} k {}",
                        eta[l],
                        kk[l]
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 8 * 7 * 4);
    }

    #[test]
    fn refraction_obeys_snell() {
        let n = Vec3::Z;
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (wt, _) = refract(wi, n, 1.5).unwrap();
        let sin_i = 0.6f32;
        let sin_t = (1.0 - wt.z * wt.z).sqrt();
        assert!((sin_i - 1.5 * sin_t).abs() < 1e-5);
        assert!(wt.z < 0.0 && wt.x < 0.0);
        assert!(refract(Vec3::new(0.9, 0.0, -0.43589), n, 1.5).is_none());
    }
}
