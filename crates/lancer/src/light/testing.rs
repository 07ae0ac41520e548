//! Checks every kind of light's emitted rays pass ([`LightKind::sample_le`],
//! [`LightKind::pdf_le`]), shared by the kinds' tests.

use super::kind::{LightKind, LightType};
use crate::math::{Vec2, Vec3};
use crate::sampling::{Pcg32, sample_uniform_sphere};
use crate::shape::{Shape, TriangleMesh};

/// `n` pairs of 2D samples, stratified (a √n × √n grid jittered) for the first, independent
/// for the second.
fn samples(n: usize, seed: u64) -> impl Iterator<Item = (Vec2, Vec2)> {
    let side = (n as f64).sqrt().ceil() as usize;
    let mut rng = Pcg32::new(seed, 17);
    (0..side * side).map(move |i| {
        let cell = Vec2::new((i % side) as f32, (i / side) as f32);
        let j = Vec2::new(rng.uniform(), rng.uniform());
        let u1 = ((cell + j) / side as f32).min(Vec2::splat(1.0 - f32::EPSILON));
        (u1, Vec2::new(rng.uniform(), rng.uniform()))
    })
}

/// The Monte-Carlo estimate of the light's power from its emitted rays: the mean of
/// avg(L)·|cos θ|/(p_pos·p_dir) (cos θ with the surface's normal for area lights, 1 for the
/// others), which is Φ = ∫∫ L cos θ dA dω for an unbiased sampler (samples that emit
/// nothing count 0).
pub fn le_power(
    light: &impl LightKind,
    shapes: &[Shape],
    meshes: &[TriangleMesh],
    n: usize,
) -> f32 {
    let (mut sum, mut count) = (0.0f64, 0usize);
    for (u1, u2) in samples(n, 5) {
        count += 1;
        let Some(s) = light.sample_le(u1, u2, shapes, meshes) else {
            continue;
        };
        assert!(s.pdf_pos > 0.0 && s.pdf_dir > 0.0, "{s:?}");
        assert!((s.w.length() - 1.0).abs() < 1e-4, "{s:?}");
        let avg = (s.l.x + s.l.y + s.l.z) / 3.0;
        sum += (avg * s.abs_cos() / (s.pdf_pos * s.pdf_dir)) as f64;
    }
    (sum / count as f64) as f32
}

/// Asserts that [`LightKind::pdf_le`] of each emitted ray gives the densities its sample
/// reported (within `tol` relative), a delta part (a point's position, a direction) aside:
/// the sample reports 1 for it, `pdf_le` 0.
pub fn le_pdfs_agree(
    light: &impl LightKind,
    shapes: &[Shape],
    meshes: &[TriangleMesh],
    n: usize,
    tol: f32,
) {
    let ty = light.light_type();
    let close = |a: f32, b: f32| (a - b).abs() <= tol * a.abs().max(b.abs());
    for (u1, u2) in samples(n, 9) {
        let Some(s) = light.sample_le(u1, u2, shapes, meshes) else {
            continue;
        };
        let pdf = light.pdf_le(s.p, s.n, s.w);
        match ty {
            LightType::DeltaPosition => assert!(pdf.pos == 0.0 && s.pdf_pos == 1.0, "{s:?}"),
            _ => assert!(close(pdf.pos, s.pdf_pos), "{pdf:?} {s:?}"),
        }
        match ty {
            LightType::DeltaDirection => assert!(pdf.dir == 0.0 && s.pdf_dir == 1.0, "{s:?}"),
            _ => assert!(close(pdf.dir, s.pdf_dir), "{pdf:?} {s:?}"),
        }
    }
}

/// ∫ p_dir(w) dω over the sphere for rays leaving `p` (normal `n`), by `n` directions
/// uniform on the sphere: 1 when [`LightKind::pdf_le`]'s directions are a density.
pub fn le_dir_integral(light: &impl LightKind, p: Vec3, normal: Vec3, n: usize) -> f32 {
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for (u, _) in samples(n, 13) {
        count += 1;
        sum += light.pdf_le(p, normal, sample_uniform_sphere(u)).dir as f64;
    }
    (4.0 * std::f64::consts::PI * sum / count as f64) as f32
}
