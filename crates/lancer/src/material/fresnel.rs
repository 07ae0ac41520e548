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
///
/// ωt = −ωi/η + (cos θi/η − cos θt)·n with sin²θt = sin²θi/η²: one division, for 1/η (the
/// walks of layered BSDFs refract at every pass through an interface).
#[inline]
pub fn refract(wi: Vec3, mut n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    // From below, the relative index is 1/η.
    let (eta, inv) = if cos_i < 0.0 {
        cos_i = -cos_i;
        n = -n;
        (1.0 / eta, eta)
    } else {
        (eta, 1.0 / eta)
    };
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i * (inv * inv);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    Some((-wi * inv + (cos_i * inv - cos_t) * n, eta))
}

/// Unpolarised Fresnel reflectance of a dielectric interface for incident cosine `cos_i` (may be
/// negative: the ray comes from inside) and relative index `eta`:
/// F = (r∥² + r⊥²)/2 with r∥ = (η cos θᵢ − cos θₜ)/(η cos θᵢ + cos θₜ),
/// r⊥ = (cos θᵢ − η cos θₜ)/(cos θᵢ + η cos θₜ).
///
/// With w = η cos θₜ = √(η² − sin²θᵢ) (Snell: sin θₜ = sin θᵢ/η; total internal reflection
/// when η² ≤ sin²θᵢ) and A = η² cos θᵢ, r∥ = (A − w)/(A + w) and r⊥ = (cos θᵢ − w)/(cos θᵢ + w),
/// so F = ((A − w)²(cos θᵢ + w)² + (cos θᵢ − w)²(A + w)²) / (2(A + w)²(cos θᵢ + w)²): one
/// division where the textbook form takes three (the walks of layered BSDFs call this at
/// every interface event, on their critical path).
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(-1.0, 1.0);
    // From inside, the relative index is 1/η.
    let (c, eta2) = if cos_i < 0.0 {
        (-cos_i, 1.0 / (eta * eta))
    } else {
        (cos_i, eta * eta)
    };
    let w2 = eta2 - (1.0 - c * c);
    if w2 <= 0.0 {
        return 1.0;
    }
    let w = w2.sqrt();
    let a = eta2 * c;
    let (ap, am, cp, cm) = (a + w, a - w, c + w, c - w);
    let (ap2, cp2) = (ap * ap, cp * cp);
    (am * am * cp2 + cm * cm * ap2) / (2.0 * ap2 * cp2)
}

/// Fresnel reflectance of a conductor with complex index `eta + i·k`, per lane (wavelength, or
/// RGB channel as (r, g, b, b)), by the same formulas as [`fresnel_dielectric`] in complex
/// arithmetic (PBRT §9.3.6), the four lanes at once, the branches of the complex square root
/// √z = (t, y/2t) for x ≥ 0, (|y|/2t, ±t) otherwise, t = √((|z| + |x|)/2), as selects.
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

    /// The conductor Fresnel in double precision, r∥ and r⊥ in complex arithmetic on pairs
    /// (principal square root: re = √((|z| + x)/2), im = ±√((|z| − x)/2) with the sign of y).
    fn fresnel_complex_f64(cos_i: f64, eta: f64, k: f64) -> f64 {
        type Z = (f64, f64);
        let mul = |p: Z, q: Z| (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0);
        let quot = |p: Z, q: Z| {
            let m = q.0 * q.0 + q.1 * q.1;
            ((p.0 * q.0 + p.1 * q.1) / m, (p.1 * q.0 - p.0 * q.1) / m)
        };
        let root = |p: Z| {
            let m = p.0.hypot(p.1);
            (
                ((m + p.0) / 2.0).sqrt(),
                ((m - p.0) / 2.0).max(0.0).sqrt().copysign(p.1),
            )
        };
        let c = cos_i.clamp(0.0, 1.0);
        let n = (eta, k);
        let n2 = mul(n, n);
        let sin2_t = quot((1.0 - c * c, 0.0), n2);
        let cos_t = root((1.0 - sin2_t.0, -sin2_t.1));
        let nc = (n.0 * c, n.1 * c);
        let n_cos_t = mul(n, cos_t);
        let r_parl = quot(
            (nc.0 - cos_t.0, nc.1 - cos_t.1),
            (nc.0 + cos_t.0, nc.1 + cos_t.1),
        );
        let r_perp = quot((c - n_cos_t.0, -n_cos_t.1), (c + n_cos_t.0, n_cos_t.1));
        let norm = |z: Z| z.0 * z.0 + z.1 * z.1;
        (norm(r_parl) + norm(r_perp)) / 2.0
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

    /// The one-division form against the textbook formula in f64, from both sides, up to
    /// grazing angles and across total internal reflection.
    #[test]
    fn dielectric_fresnel_matches_the_textbook_in_f64() {
        let textbook = |cos_i: f64, eta: f64| -> f64 {
            let (c, e) = if cos_i < 0.0 {
                (-cos_i, 1.0 / eta)
            } else {
                (cos_i, eta)
            };
            let sin2_t = (1.0 - c * c) / (e * e);
            if sin2_t >= 1.0 {
                return 1.0;
            }
            let ct = (1.0 - sin2_t).sqrt();
            let rp = (e * c - ct) / (e * c + ct);
            let rs = (c - e * ct) / (c + e * ct);
            (rp * rp + rs * rs) / 2.0
        };
        for eta in [1.1f32, 1.33, 1.5, 2.4, 0.8, 1.0 / 1.5] {
            for i in -1000..=1000 {
                let cos_i = i as f32 / 1000.0;
                // At the edge of total internal reflection F has an infinite slope in
                // cos θᵢ: there any f32 form is only as good as its rounding of sin²θᵢ.
                let e2 = if cos_i < 0.0 {
                    1.0 / (eta as f64).powi(2)
                } else {
                    (eta as f64).powi(2)
                };
                if (e2 - (1.0 - (cos_i as f64).powi(2))).abs() < 1e-3 {
                    continue;
                }
                let (got, want) = (
                    fresnel_dielectric(cos_i, eta),
                    textbook(cos_i as f64, eta as f64),
                );
                assert!(
                    (got as f64 - want).abs() <= 2e-5 + 1e-5 * want,
                    "eta {eta} cos {cos_i}: {got} vs {want}"
                );
            }
        }
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
    fn complex_fresnel_lanes_agree_with_double_precision() {
        let mut checked = 0;
        // Not at grazing incidence, where 1 − cos² rounds to 1 in single precision.
        for c in [0.05f32, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0, 1.5] {
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
                    let want = fresnel_complex_f64(c as f64, eta[l] as f64, kk[l] as f64);
                    assert!(
                        (lanes[l] as f64 - want).abs() < 2e-5,
                        "cos {c} eta {} k {}: {} vs {want}",
                        eta[l],
                        kk[l],
                        lanes[l]
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
