//! Bump and normal mapping: the shading frame a material's `displacement` texture or
//! `normalmap` image gives, as pbrt-v4's `BumpMap`, `NormalMap` and `SetShadingGeometry`.
//!
//! Both replace the shading ∂p/∂u and ∂p/∂v; the shading normal is then
//! `normalize(∂p/∂u × ∂p/∂v)`, turned to the geometric normal's side.

use crate::math::{Vec2, Vec3, cross, face_forward, normalize};
use crate::shape::{Shading, SurfaceInteraction};
use crate::texture::{FloatTex, SpectrumTex, TexCoord, TextureEval};

/// The finite-difference step in u and v where the footprint is zero (pbrt-v4's `BumpMap`).
const DELTA: f32 = 0.0005;

/// The shading frame of the new ∂p/∂u, ∂p/∂v: `ns = normalize(∂p/∂u × ∂p/∂v)` on the side of
/// the geometric normal `n` (pbrt-v4's `SetShadingGeometry` without authoritative
/// orientation). `None` when the tangents are degenerate (the old frame is kept).
fn shading_from(dpdu: Vec3, dpdv: Vec3, n: Vec3) -> Option<Shading> {
    let c = cross(dpdu, dpdv);
    let len2 = c.length_squared();
    if len2 == 0.0 || !len2.is_finite() {
        return None;
    }
    Some(Shading {
        n: face_forward(normalize(c), n),
        dpdu,
        dpdv,
    })
}

/// pbrt-v4's `BumpMap`: with d the displacement texture and δ half the footprint's extent in
/// u, `δ = ½(|∂u/∂x| + |∂u/∂y|)` ([`DELTA`] when that is 0),
/// `∂p/∂u' = ∂p/∂u + (d(u + δ) − d(u))/δ · ns`, the texture shifted by δ·∂p/∂u in position
/// and by δ in u (the same in v, with its own δ). `tc` is the hit's lookup point with its
/// footprint. pbrt-v4 also adds `d · ∂n/∂u`; lancer's hits carry no normal derivatives, so
/// that term (a relative change of d/radius on curved surfaces) is left out.
pub fn bump_shading(
    tex: &TextureEval,
    displacement: FloatTex,
    si: &SurfaceInteraction,
    tc: &TexCoord,
) -> Option<Shading> {
    let sh = &si.shading;
    let step = |a: f32, b: f32| {
        let d = 0.5 * (a.abs() + b.abs());
        if d == 0.0 { DELTA } else { d }
    };
    let (du, dv) = (step(tc.dudx, tc.dudy), step(tc.dvdx, tc.dvdy));
    let at = |p: Vec3, uv: Vec2| TexCoord { uv, p, ..*tc };
    let d = tex.float(displacement, tc);
    let d_u = tex.float(
        displacement,
        &at(si.p + du * sh.dpdu, si.uv + Vec2::new(du, 0.0)),
    );
    let d_v = tex.float(
        displacement,
        &at(si.p + dv * sh.dpdv, si.uv + Vec2::new(0.0, dv)),
    );
    let dpdu = sh.dpdu + (d_u - d) / du * sh.n;
    let dpdv = sh.dpdv + (d_v - d) / dv * sh.n;
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
