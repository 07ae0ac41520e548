//! Bump and normal mapping: the shading frame a material's `displacement` texture or
//! `normalmap` image gives, as pbrt-v4's `BumpMap`, `NormalMap` and `SetShadingGeometry`.
//!
//! Both replace the shading ∂p/∂u and ∂p/∂v; the shading normal is then
//! `normalize(∂p/∂u × ∂p/∂v)`, turned to the geometric normal's side. A bump map reads the
//! hit's shading derivatives, ∂n/∂u and ∂n/∂v among them, which the shapes compute only for
//! it ([`crate::shape::Shape::shading_derivatives`]).

use crate::math::{Vec2, Vec3, cross, face_forward, normalize};
use crate::shape::{Shading, ShadingDerivatives, SurfaceInteraction};
use crate::texture::{FloatTex, SpectrumTex, TexCoord, TextureEval};

/// The finite-difference step in u and v where the footprint is zero (pbrt-v4's `BumpMap`).
const DELTA: f32 = 0.0005;

/// The shading frame of the new ∂p/∂u, ∂p/∂v: `ns = normalize(∂p/∂u × ∂p/∂v)` on the side of
/// the geometric normal `n` (pbrt-v4's `SetShadingGeometry` without authoritative
/// orientation, which also divides both tangents by 10⁸ while either's squared length is
/// over 10¹⁶). `None` when the tangents are degenerate (the old frame is kept).
fn shading_from(mut dpdu: Vec3, mut dpdv: Vec3, n: Vec3) -> Option<Shading> {
    let c = cross(dpdu, dpdv);
    let len2 = c.length_squared();
    if len2 == 0.0 || !len2.is_finite() {
        return None;
    }
    while dpdu.length_squared() > 1e16 || dpdv.length_squared() > 1e16 {
        dpdu /= 1e8;
        dpdv /= 1e8;
    }
    Some(Shading {
        n: face_forward(normalize(c), n),
        dpdu,
        dpdv,
    })
}

/// pbrt-v4's `BumpMap`: with d the displacement texture and `sd` the hit's shading
/// derivatives (pbrt-v4's, [`ShadingDerivatives`]), δ half the footprint's extent in u,
/// `δ = ½(|∂u/∂x| + |∂u/∂y|)` ([`DELTA`] when that is 0), the texture looked up again at the
/// point moved by δ·∂p/∂u (shading) with u moved by δ,
///
///   ∂p/∂u' = ∂p/∂u + (d(u + δ) − d(u))/δ · n_s + d · ∂n/∂u,
///
/// and the same in v with its own δ; the new shading normal is
/// normalize(∂p/∂u' × ∂p/∂v') on the geometric normal's side. `tc` is the hit's lookup point
/// with its footprint.
pub fn bump_shading(
    tex: &TextureEval,
    displacement: FloatTex,
    si: &SurfaceInteraction,
    tc: &TexCoord,
    sd: &ShadingDerivatives,
) -> Option<Shading> {
    let step = |a: f32, b: f32| {
        let d = 0.5 * (a.abs() + b.abs());
        if d == 0.0 { DELTA } else { d }
    };
    let (du, dv) = (step(tc.dudx, tc.dudy), step(tc.dvdx, tc.dvdy));
    let at = |p: Vec3, uv: Vec2| TexCoord { uv, p, ..*tc };
    let d_u = tex.float(
        displacement,
        &at(si.p + du * sd.dpdu, si.uv + Vec2::new(du, 0.0)),
    );
    let d_v = tex.float(
        displacement,
        &at(si.p + dv * sd.dpdv, si.uv + Vec2::new(0.0, dv)),
    );
    let d = tex.float(displacement, tc);
    let ns = si.shading.n;
    let dpdu = sd.dpdu + (d_u - d) / du * ns + d * sd.dndu;
    let dpdv = sd.dpdv + (d_v - d) / dv * ns + d * sd.dndv;
    shading_from(dpdu, dpdv, si.n)
}

/// pbrt-v4's `NormalMap`: the image's colour c at (u, 1 − v) (bilinear, repeat; the texture
/// `normal_map` is such an image, read linear) gives the tangent-space normal
/// `normalize(2c − 1)` in the frame (∂p/∂u, ns × ∂p/∂u, ns); then
/// `∂p/∂u' = |∂p/∂u| · normalize(∂p/∂u − (∂p/∂u·n')n')` and
/// `∂p/∂v' = |∂p/∂v| · normalize(n' × ∂p/∂u')`.
pub fn normal_map_shading(
    tex: &TextureEval,
    normal_map: u32,
    si: &SurfaceInteraction,
) -> Option<Shading> {
    let sh = &si.shading;
    let tc = TexCoord {
        uv: si.uv,
        p: si.p,
        n: si.n,
        ..TexCoord::default()
    };
    let c = tex.spectrum(SpectrumTex::Tex(normal_map), &tc);
    let local = (2.0 * c - Vec3::ONE).try_normalize()?;
    let x = sh.dpdu.try_normalize()?;
    let z = sh.n;
    let ns = x * local.x + cross(z, x) * local.y + z * local.z;
    let (ulen, vlen) = (sh.dpdu.length(), sh.dpdv.length());
    let dpdu = (sh.dpdu - sh.dpdu.dot(ns) * ns).try_normalize()? * ulen;
    let dpdv = cross(ns, dpdu).try_normalize()? * vlen;
    shading_from(dpdu, dpdv, si.n)
}

#[cfg(test)]
pub(crate) mod tests;
