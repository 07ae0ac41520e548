//! Ray footprints without per-ray state: pbrt-v4's `CameraBase::FindMinimumDifferentials` and
//! `Approximate_dp_dxy`.
//!
//! Texture filters need ∂p/∂x and ∂p/∂y, how far the surface point moves from one pixel to
//! the next. Instead of carrying ray differentials along paths, pbrt-v4 finds once the
//! smallest differentials any camera ray has (their origin and direction offsets, over 512
//! rays along the film's diagonal) and, at a hit p with normal n, intersects a ray from the
//! camera pointing at p, offset by those differentials, with the tangent plane at p. The
//! offsets are scaled by max(⅛, 1/√spp) as pbrt-v4 scales its camera rays' differentials:
//! with more samples per pixel each sample's footprint shrinks.

use super::Camera;
use crate::math::{Frame, Transform, Vec2, Vec3, normalize, rotate_from_to};

/// The camera's minimum differentials and what turns them into a footprint at a hit.
#[derive(Clone, Debug, PartialEq)]
pub struct Footprints {
    camera_from_world: Transform,
    world_from_camera: Transform,
    /// Smallest origin offsets of the x and y differential rays, camera space.
    min_pos: [Vec3; 2],
    /// Smallest direction offsets, in the frame of the ray (+z along it).
    min_dir: [Vec3; 2],
    /// max(⅛, 1/√spp).
    spp_scale: f32,
    /// A pinhole perspective camera's own differentials, for the rays it shoots.
    pinhole: Option<Pinhole>,
}

/// What a pinhole perspective camera's ray differentials are made of (pbrt-v4's
/// `PerspectiveCamera::GenerateRayDifferential` without a lens): the offset rays leave the eye
/// through the film point one pixel over.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pinhole {
    /// The eye, world space, exactly as camera rays carry it (their origin).
    eye: Vec3,
    /// Camera-space z of the plane raster points map to.
    z_film: f32,
    /// One pixel along raster x and y on that plane, camera space.
    step: [Vec3; 2],
}

/// pbrt-v4's scale of camera ray differentials for `spp` samples per pixel: max(⅛, 1/√spp).
pub fn differential_scale(spp: u32) -> f32 {
    (1.0 / (spp.max(1) as f32).sqrt()).max(0.125)
}

impl Footprints {
    /// The footprints of `camera` rendering a `resolution` film at `spp` samples per pixel.
    ///
    /// Each camera ray's differentials are its neighbours one pixel over, as pbrt-v4's
    /// cameras make them: projective cameras step a whole pixel (their
    /// `GenerateRayDifferential`), the others a twentieth of a pixel, scaled up (pbrt-v4's
    /// generic `CameraBase::GenerateRayDifferential`, which tries −0.05 where +0.05 fails).
    /// The lens sample is its centre, the time the middle of the shutter.
    pub fn new(camera: &Camera, resolution: (u32, u32), spp: u32) -> Footprints {
        let world_from_camera = camera.world_from_camera;
        let camera_from_world = world_from_camera.inverse();
        let projective = matches!(camera.kind, super::Kind::Projective { .. });
        let lens = Vec2::splat(0.5);
        let mut min_pos = [Vec3::INFINITY; 2];
        let mut min_dir = [Vec3::INFINITY; 2];
        let n = 512;
        for i in 0..n {
            let f = i as f32 / (n - 1) as f32;
            let p_film = Vec2::new(f * resolution.0 as f32, f * resolution.1 as f32);
            let Some(cr) = camera.generate_ray(p_film, lens) else {
                continue;
            };
            let (o, d) = (
                camera_from_world.point(cr.ray.o),
                normalize(camera_from_world.vector(cr.ray.d)),
            );
            let frame = Frame::from_z(d);
            let df = frame.to_local(d);
            for (axis, step) in [Vec2::X, Vec2::Y].into_iter().enumerate() {
                let steps: &[f32] = if projective { &[1.0] } else { &[0.05, -0.05] };
                let Some((oo, dd)) = steps.iter().find_map(|&eps| {
                    let r = camera.generate_ray(p_film + eps * step, lens)?.ray;
                    let (ro, rd) = (
                        camera_from_world.point(r.o),
                        normalize(camera_from_world.vector(r.d)),
                    );
                    Some((o + (ro - o) / eps, d + (rd - d) / eps))
                }) else {
                    continue;
                };
                let dox = oo - o;
                if dox.length() < min_pos[axis].length() {
                    min_pos[axis] = dox;
                }
                let dxf = normalize(frame.to_local(normalize(dd)));
                if (dxf - df).length() < min_dir[axis].length() {
                    min_dir[axis] = dxf - df;
                }
            }
        }
        // A camera that gave no ray at all has no footprint.
        for v in min_pos.iter_mut().chain(min_dir.iter_mut()) {
            if !v.is_finite() {
                *v = Vec3::ZERO;
            }
        }
        let pinhole = match &camera.kind {
            super::Kind::Projective {
                camera_from_raster,
                perspective: true,
                lens_radius,
                ..
            } if *lens_radius == 0.0 => {
                let o = camera_from_raster.point(Vec3::ZERO);
                Some(Pinhole {
                    eye: world_from_camera.point(Vec3::ZERO),
                    z_film: o.z,
                    step: [
                        camera_from_raster.point(Vec3::X) - o,
                        camera_from_raster.point(Vec3::Y) - o,
                    ],
                })
            }
            _ => None,
        };
        Footprints {
            camera_from_world,
            world_from_camera,
            min_pos,
            min_dir,
            spp_scale: differential_scale(spp),
            pinhole,
        }
    }

    /// ∂p/∂x and ∂p/∂y at the point `p` (normal `n`) that a ray from `origin` hit: the camera
    /// ray's own differentials when the ray came from a pinhole camera's eye (pbrt-v4 carries
    /// them on camera rays), [`Footprints::dp_dxy`]'s approximation otherwise.
    #[inline]
    pub fn at_hit(&self, origin: Vec3, p: Vec3, n: Vec3) -> (Vec3, Vec3) {
        match &self.pinhole {
            Some(ph) if origin == ph.eye => self
                .camera_ray_dp_dxy(ph, p, n)
                .unwrap_or_else(|| self.dp_dxy(p, n)),
            _ => self.dp_dxy(p, n),
        }
    }

    /// pbrt-v4's `ComputeDifferentials` for a pinhole camera's ray to `p`: the ray passes the
    /// film plane at q = p·z_film/p_z (camera space); its offset rays point along
    /// normalize(q + one pixel), scaled towards the ray by max(⅛, 1/√spp), and meet the
    /// tangent plane n·(x − p) = 0 at t = n·p/(n·d'). `None` when p is not in front of the
    /// camera or an offset ray runs along the plane.
    fn camera_ray_dp_dxy(&self, ph: &Pinhole, p: Vec3, n: Vec3) -> Option<(Vec3, Vec3)> {
        let pc = self.camera_from_world.point(p);
        if pc.z <= 0.0 {
            return None;
        }
        let nc = self.camera_from_world.normal(n);
        let d = normalize(pc);
        let q = pc * (ph.z_film / pc.z);
        let offset = |step: Vec3| {
            let dx = d + (normalize(q + step) - d) * self.spp_scale;
            let t = nc.dot(pc) / nc.dot(dx);
            let v = self.world_from_camera.vector(t * dx - pc);
            v.is_finite().then_some(v)
        };
        Some((offset(ph.step[0])?, offset(ph.step[1])?))
    }

    /// ∂p/∂x and ∂p/∂y at world point `p` with normal `n` (pbrt-v4's `Approximate_dp_dxy`).
    ///
    /// In a camera frame rotated so that p lies on +z at distance z, the tangent plane is
    /// n'·q = n'_z·z; a differential ray q(t) = o + t·d with o, d the minimum offsets added to
    /// the origin and +z meets it at t = (n'_z·z − n'·o)/(n'·d), and the footprint is
    /// scale·(q(t) − (0, 0, z)), rotated back to the world. Zero where that ray runs along
    /// the plane.
    pub fn dp_dxy(&self, p: Vec3, n: Vec3) -> (Vec3, Vec3) {
        let pc = self.camera_from_world.point(p);
        let Some(dir) = pc.try_normalize() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        let rot = rotate_from_to(dir, Vec3::Z);
        let apply = |v: Vec3| Vec3::new(rot[0].dot(v), rot[1].dot(v), rot[2].dot(v));
        let unapply = |v: Vec3| rot[0] * v.x + rot[1] * v.y + rot[2] * v.z;
        let p_down = apply(pc);
        let n_down = apply(self.camera_from_world.normal(n));
        let d = n_down.z * p_down.z;
        let offset = |axis: usize| {
            let o = self.min_pos[axis];
            let dir = Vec3::Z + self.min_dir[axis];
            let t = -(n_down.dot(o) - d) / n_down.dot(dir);
            let v = self.spp_scale * self.world_from_camera.vector(unapply(o + t * dir - p_down));
            if v.is_finite() { v } else { Vec3::ZERO }
        };
        (offset(0), offset(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rotation_takes_from_to_to() {
        for from in [
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(-0.8, 0.6, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
            normalize(Vec3::new(0.3, -0.2, 0.9)),
        ] {
            let r = rotate_from_to(from, Vec3::Z);
            let v = Vec3::new(r[0].dot(from), r[1].dot(from), r[2].dot(from));
            assert!((v - Vec3::Z).length() < 1e-5, "{from}: {v}");
            // Orthonormal rows.
            for i in 0..3 {
                for j in 0..3 {
                    let want = f32::from(i == j);
                    assert!((r[i].dot(r[j]) - want).abs() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn a_plane_seen_head_on_has_the_pixel_footprint() {
        // The course camera: 100×100 pixels over [−1, 1]² at distance 1 (a pixel is 0.02
        // wide there). Its smallest direction step is at the ends of the diagonal, where the
        // ray (1, 1, 1)/√3 (camera space) turns by |∂(v/|v|)/∂x|·0.02 = √(1 − ⅓)/√3·0.02 =
        // 0.02·√2/3 ≈ 0.00943 radians a pixel.
        let cam = Camera::course(100, 100);
        let fp = Footprints::new(&cam, (100, 100), 1);
        let step = 0.02 * 2f32.sqrt() / 3.0;
        for axis in 0..2 {
            let dx = fp.min_dir[axis].length();
            assert!((dx - step).abs() < 0.02 * step, "{dx}");
            assert_eq!(fp.min_pos[axis], Vec3::ZERO);
        }
        // The plane z = −4 facing the camera, hit on the axis: a ray turned by that angle
        // meets it 4·tan(0.00943) ≈ 0.0377 away, in the plane.
        let p = Vec3::new(0.0, 0.0, -4.0);
        let (dpdx, dpdy) = fp.dp_dxy(p, Vec3::Z);
        let want = 4.0 * step;
        for d in [dpdx, dpdy] {
            assert!((d.length() - want).abs() < 0.02 * want, "{d}");
            assert!(d.z.abs() < 1e-6, "{d}");
        }
        // 16 spp: a quarter of that; 1024 spp: an eighth at most.
        let fp16 = Footprints::new(&cam, (100, 100), 16);
        let (d16, _) = fp16.dp_dxy(p, Vec3::Z);
        assert!((d16.length() - dpdx.length() / 4.0).abs() < 1e-6);
        assert_eq!(differential_scale(1024), 0.125);
    }

    #[test]
    fn a_camera_ray_hitting_a_plane_head_on_spans_a_pixel() {
        // The course camera's centre ray hits the plane z = −4 head-on: the ray one pixel
        // over (0.02 on the image plane at distance 1) meets it 4·0.02 = 0.08 away; at 16 spp
        // the differentials shrink to ¼: 0.02.
        let cam = Camera::course(100, 100);
        let eye = cam
            .generate_ray(Vec2::new(50.0, 50.0), Vec2::ZERO)
            .unwrap()
            .ray
            .o;
        let p = Vec3::new(0.0, 0.0, -4.0);
        for (spp, want) in [(1, 0.08), (16, 0.02)] {
            let fp = Footprints::new(&cam, (100, 100), spp);
            let (dpdx, dpdy) = fp.at_hit(eye, p, Vec3::Z);
            assert!((dpdx - Vec3::new(want, 0.0, 0.0)).length() < 1e-5, "{dpdx}");
            // Raster y grows downwards: one pixel down is −y.
            assert!(
                (dpdy - Vec3::new(0.0, -want, 0.0)).length() < 1e-5,
                "{dpdy}"
            );
        }
        // Off-axis: the camera ray through pixel (75, 50) hits the plane at x = 2; the next
        // pixel's ray at 4·0.52 = 2.08, so ∂p/∂x = 0.08 there too (a plane parallel to the
        // film).
        let fp = Footprints::new(&cam, (100, 100), 1);
        let (dpdx, _) = fp.at_hit(eye, Vec3::new(2.0, 0.0, -4.0), Vec3::Z);
        assert!((dpdx - Vec3::new(0.08, 0.0, 0.0)).length() < 1e-4, "{dpdx}");
        // A ray from elsewhere gets the approximation.
        let (approx, _) = fp.at_hit(Vec3::new(0.0, 0.0, -1.0), p, Vec3::Z);
        assert_eq!(approx, fp.dp_dxy(p, Vec3::Z).0);
    }

    #[test]
    fn a_tilted_plane_stretches_the_footprint() {
        // The plane through (0, 0, −4) tilted 60° about x: the footprint's area grows by
        // 1/cos 60° = 2 (to first order: the offset rays lean by ~0.0094, which changes it by
        // about 0.0094·tan 60° ≈ 1.6%), and both offsets lie in the plane.
        let cam = Camera::course(100, 100);
        let fp = Footprints::new(&cam, (100, 100), 1);
        let p = Vec3::new(0.0, 0.0, -4.0);
        let area = |(a, b): (Vec3, Vec3)| crate::math::cross(a, b).length();
        let n = Vec3::new(0.0, 60f32.to_radians().sin(), 60f32.to_radians().cos());
        let (dx, dy) = fp.dp_dxy(p, n);
        let ratio = area((dx, dy)) / area(fp.dp_dxy(p, Vec3::Z));
        assert!((ratio - 2.0).abs() < 0.04, "{ratio}");
        assert!(dx.dot(n).abs() < 1e-5 && dy.dot(n).abs() < 1e-5);
    }
}
