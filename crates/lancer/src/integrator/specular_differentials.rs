//! Ray differentials through perfectly specular bounces, pbrt-v4's
//! `SurfaceInteraction::SpawnRay(ray, bsdf, wi, flags, eta)` (src/pbrt/interaction.cpp): the
//! offset rays one pixel over in x and y, followed through a mirror or a refraction so that a
//! texture seen in a mirror or through glass is filtered over its own footprint.
//!
//! The path integrator ([`super::path`]) carries them through chains of perfectly specular
//! bounces when the scene's textures use footprints (elsewhere every hit's footprint comes
//! from the camera's minimum differentials, `camera/footprint.rs`, as pbrt-v4 does after a
//! non-specular bounce): [`spawn`] after a specular sample, [`apply`] at the next hit.
//! The incoming offset rays are rebuilt from the hit's footprint (the offset ray in x runs
//! from its origin to p + ∂p/∂x; a camera ray's offset rays start at its origin, exact for a
//! pinhole), and ∂n/∂x, ∂n/∂y are taken as zero (lancer's hits do not carry ∂n/∂u, ∂n/∂v):
//! exact for flat mirrors and glass, a footprint too small behind curved ones.

use crate::material::BsdfSample;
use crate::math::{Vec3, normalize};
use crate::ray::Ray;
use crate::scene::{Scene, SceneHit};

/// After a BSDF sample `bs` at `hit` of `ray` (whose own differentials are `incoming`, if it
/// has any): the new ray's differentials when the sample is a perfect specular reflection or
/// transmission and the scene's textures use footprints (pbrt-v4's `SpawnRay` with a BSDF),
/// `None` otherwise.
#[inline(always)]
pub fn spawn(
    scene: &Scene,
    ray: &Ray,
    incoming: Option<&Differentials>,
    hit: &SceneHit,
    bs: &BsdfSample,
) -> Option<Differentials> {
    if scene.footprints().is_none() || !bs.flags.is_specular() {
        return None;
    }
    spawn_specular(ray, incoming, hit, bs)
}

#[cold]
#[inline(never)]
fn spawn_specular(
    ray: &Ray,
    incoming: Option<&Differentials>,
    hit: &SceneHit,
    bs: &BsdfSample,
) -> Option<Differentials> {
    let si = &hit.si;
    let [dpdx, dpdy] = hit.footprint;
    if dpdx == Vec3::ZERO && dpdy == Vec3::ZERO {
        return None;
    }
    let (ox, oy) = incoming.map_or((ray.o, ray.o), |d| (d.rx_origin, d.ry_origin));
    let h = SpecularHit {
        p: si.p,
        dpdx,
        dpdy,
        n: si.shading.n,
        dndx: Vec3::ZERO,
        dndy: Vec3::ZERO,
    };
    let (rx_in, ry_in) = (normalize(si.p + dpdx - ox), normalize(si.p + dpdy - oy));
    let d = if bs.flags.is_reflection() {
        reflected(&h, rx_in, ry_in, si.wo, bs.wi)
    } else {
        refracted(&h, rx_in, ry_in, si.wo, bs.wi, bs.eta)
    };
    // pbrt-v4 drops differentials that blew up.
    let finite = [d.rx_origin, d.ry_origin, d.rx_dir, d.ry_dir]
        .iter()
        .all(|v| v.is_finite() && v.length_squared() < 1e16);
    finite.then_some(d)
}

/// At the hit `found` of a ray whose differentials are `diff`: the hit's footprint from
/// them, where the offset rays meet its tangent plane (pbrt-v4's `ComputeDifferentials`:
/// t = (n·p − n·o)/(n·d)); kept from the camera's approximation when an offset ray runs
/// along the plane.
#[cold]
#[inline(never)]
pub fn apply(found: &mut Option<SceneHit>, diff: Option<&Differentials>) {
    if let (Some(hit), Some(d)) = (found, diff) {
        let (p, n) = (hit.si.p, hit.si.n);
        let at = |o: Vec3, dir: Vec3| {
            let t = (n.dot(p) - n.dot(o)) / n.dot(dir);
            t.is_finite().then(|| o + dir * t - p)
        };
        if let (Some(dx), Some(dy)) = (at(d.rx_origin, d.rx_dir), at(d.ry_origin, d.ry_dir)) {
            hit.footprint = [dx, dy];
        }
    }
}

/// The offset rays of a ray differential: origins and directions one pixel over in x and y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Differentials {
    /// Origin of the x offset ray.
    pub rx_origin: Vec3,
    /// Origin of the y offset ray.
    pub ry_origin: Vec3,
    /// Direction of the x offset ray.
    pub rx_dir: Vec3,
    /// Direction of the y offset ray.
    pub ry_dir: Vec3,
}

/// What the hit gives the specular differentials: the point, its footprint ∂p/∂x, ∂p/∂y,
/// the shading normal and its screen derivatives ∂n/∂x = ∂n/∂u·∂u/∂x + ∂n/∂v·∂v/∂x (and y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularHit {
    /// The hit point.
    pub p: Vec3,
    /// ∂p/∂x, ∂p/∂y.
    pub dpdx: Vec3,
    /// See `dpdx`.
    pub dpdy: Vec3,
    /// The shading normal.
    pub n: Vec3,
    /// ∂n/∂x, ∂n/∂y.
    pub dndx: Vec3,
    /// See `dndx`.
    pub dndy: Vec3,
}

/// The differentials after a perfect mirror bounce: the incoming ray's offset directions
/// `rx_in`, `ry_in`, `wo` (towards where the ray came from) and `wi` (the reflected
/// direction). With ∂ωo/∂x = −rx_in − ωo and ∂(ωo·n)/∂x = ∂ωo/∂x·n + ωo·∂n/∂x:
/// ω_rx = ωi − ∂ωo/∂x + 2((ωo·n)·∂n/∂x + ∂(ωo·n)/∂x·n), and the same in y; origins p + ∂p/∂x.
pub fn reflected(h: &SpecularHit, rx_in: Vec3, ry_in: Vec3, wo: Vec3, wi: Vec3) -> Differentials {
    let (n, won) = (h.n, wo.dot(h.n));
    let dir = |r_in: Vec3, dndx: Vec3| {
        let dwo = -r_in - wo;
        let dwon = dwo.dot(n) + wo.dot(dndx);
        wi - dwo + 2.0 * (won * dndx + dwon * n)
    };
    Differentials {
        rx_origin: h.p + h.dpdx,
        ry_origin: h.p + h.dpdy,
        rx_dir: dir(rx_in, h.dndx),
        ry_dir: dir(ry_in, h.dndy),
    }
}

/// The differentials after a perfect refraction into `wi` with relative index `eta` (the
/// BSDF sample's, as pbrt-v4 passes it). The normal is flipped to ωo's side first; then with
/// μ = (ωo·n)/η − |ωi·n| and ∂μ/∂x = ∂(ωo·n)/∂x · (1/η + (ωo·n)/(η²·(ωi·n))):
/// ω_rx = ωi − η·∂ωo/∂x + μ·∂n/∂x + ∂μ/∂x·n, and the same in y (pbrt-v4's formula as it
/// stands, to match its images).
pub fn refracted(
    h: &SpecularHit,
    rx_in: Vec3,
    ry_in: Vec3,
    wo: Vec3,
    wi: Vec3,
    eta: f32,
) -> Differentials {
    let flip = if wo.dot(h.n) < 0.0 { -1.0 } else { 1.0 };
    let (n, won, win) = (flip * h.n, flip * wo.dot(h.n), flip * wi.dot(h.n));
    let mu = won / eta - win.abs();
    let dir = |r_in: Vec3, dndx: Vec3| {
        let dndx = flip * dndx;
        let dwo = -r_in - wo;
        let dwon = dwo.dot(n) + wo.dot(dndx);
        let dmu = dwon * (1.0 / eta + won / (eta * eta * win));
        wi - eta * dwo + mu * dndx + dmu * n
    };
    Differentials {
        rx_origin: h.p + h.dpdx,
        ry_origin: h.p + h.dpdy,
        rx_dir: dir(rx_in, h.dndx),
        ry_dir: dir(ry_in, h.dndy),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat() -> SpecularHit {
        SpecularHit {
            p: Vec3::ZERO,
            dpdx: Vec3::new(0.01, 0.0, 0.0),
            dpdy: Vec3::new(0.0, 0.01, 0.0),
            n: Vec3::Z,
            dndx: Vec3::ZERO,
            dndy: Vec3::ZERO,
        }
    }

    /// A flat mirror (∂n/∂x = 0) hit head-on: the reflected offset ray is the incoming offset
    /// ray mirrored in the plane. rx_in = (a, 0, −c) with c = √(1 − a²): ∂ωo/∂x = (−a, 0,
    /// c − 1), ∂(ωo·n)/∂x = c − 1, so ω_rx = (0, 0, 1) − (−a, 0, c − 1) + 2(c − 1)(0, 0, 1)
    /// = (a, 0, c).
    #[test]
    fn a_flat_mirror_reflects_the_offset_rays() {
        let a = 0.01f32;
        let c = (1.0 - a * a).sqrt();
        let rx = Vec3::new(a, 0.0, -c);
        let ry = Vec3::new(0.0, a, -c);
        let d = reflected(&flat(), rx, ry, Vec3::Z, Vec3::Z);
        assert!(
            (d.rx_dir - Vec3::new(a, 0.0, c)).length() < 1e-6,
            "{}",
            d.rx_dir
        );
        assert!(
            (d.ry_dir - Vec3::new(0.0, a, c)).length() < 1e-6,
            "{}",
            d.ry_dir
        );
        assert_eq!(d.rx_origin, Vec3::new(0.01, 0.0, 0.0));
    }

    /// A curved mirror adds 2(ωo·n)·∂n/∂x: head-on with ∂n/∂x = (k, 0, 0) and an undeviated
    /// offset ray (rx_in = −ωo), ω_rx = ωi + 2k·x̂.
    #[test]
    fn a_curved_mirror_spreads_the_offset_rays() {
        let h = SpecularHit {
            dndx: Vec3::new(0.5, 0.0, 0.0),
            ..flat()
        };
        let d = reflected(&h, -Vec3::Z, -Vec3::Z, Vec3::Z, Vec3::Z);
        assert!(
            (d.rx_dir - Vec3::new(1.0, 0.0, 1.0)).length() < 1e-6,
            "{}",
            d.rx_dir
        );
        assert!((d.ry_dir - Vec3::Z).length() < 1e-6);
    }

    /// Head-on refraction through a flat surface, η = 1.5: μ = 1/1.5 − 1 = −⅓, and with
    /// rx_in = (a, 0, −c), a = 0.01, c = √(1 − a²): ∂ωo/∂x = (−a, 0, c − 1) with
    /// c − 1 = −5.0001·10⁻⁵, ∂μ/∂x = (c − 1)(1/1.5 − 1/2.25) = −1.11114·10⁻⁵, so
    /// ω_rx = (0, 0, −1) − 1.5(−a, 0, c − 1) + ∂μ/∂x·(0, 0, 1) = (0.015, 0, −0.9999361),
    /// worked out by hand (the z term tells a missing ∂μ/∂x or η·∂ωo/∂x apart by 10⁻⁵).
    #[test]
    fn a_flat_refraction_follows_pbrt_v4s_formula() {
        let (a, eta) = (0.01f32, 1.5f32);
        let c = (1.0 - a * a).sqrt();
        let rx = Vec3::new(a, 0.0, -c);
        let d = refracted(&flat(), rx, rx, Vec3::Z, -Vec3::Z, eta);
        let want = Vec3::new(0.015, 0.0, -0.999_936_1);
        assert!((d.rx_dir - want).length() < 1e-6, "{} {want}", d.rx_dir);
        // From below (ωo·n < 0) the normal is flipped: the mirror-image case gives the
        // mirror-image direction.
        let below = refracted(&flat(), -rx, -rx, -Vec3::Z, Vec3::Z, eta);
        assert!((below.rx_dir + want).length() < 1e-6, "{}", below.rx_dir);
    }
}
