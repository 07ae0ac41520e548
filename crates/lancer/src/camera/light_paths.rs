//! The camera's side of light paths (pbrt-v4's `PerspectiveCamera::We`, `PDF_We` and
//! `SampleWi`, over the [`Importance`] a perspective camera holds): what light tracing, bdpt
//! and the other light-path integrators ask of [`Camera`]. Kept apart from `importance.rs` so
//! that the camera's own module and its importance do not import each other.

use super::importance::CameraWiSample;
use super::{Camera, Kind};
use crate::math::{Vec2, Vec3, normalize};
use crate::sampling::sample_uniform_disk_concentric;

impl Camera {
    /// The camera's importance, or why it has none: pbrt-v4 traces light paths to perspective
    /// cameras only (its `bdpt`, `lightpath`, `mlt`, `sppm` refuse the others), and so does
    /// lancer (a moving camera is taken at its pose at the shutter's opening).
    pub fn light_path_support(&self) -> Result<(), String> {
        if self.importance.is_some() {
            return Ok(());
        }
        let kind = match &self.kind {
            Kind::Projective {
                perspective: false, ..
            } => "orthographic",
            Kind::Projective { .. } => "degenerate perspective",
            Kind::Spherical { .. } => "spherical",
            Kind::Realistic(_) => "realistic",
        };
        Err(format!(
            "light paths reach only a \"perspective\" camera (as in pbrt-v4), not this {kind} one"
        ))
    }

    /// Restricts the importance to the raster points a film of pixel bounds `[x0, x1) ×
    /// [y0, y1)` (out of a full image of `full_area` pixels) reconstructs with a filter of
    /// radius `filter_radius`: pbrt-v4's film `SampleBounds`, [x0 + ½ − r, x1 − ½ + r) × …
    pub fn set_film_extent(&mut self, bounds: [i32; 4], full_area: f32, filter_radius: Vec2) {
        if let Some(imp) = &mut self.importance {
            let [x0, x1, y0, y1] = bounds.map(|v| v as f32);
            let (rx, ry) = (filter_radius.x - 0.5, filter_radius.y - 0.5);
            imp.sample_bounds = [x0 - rx, x1 + rx, y0 - ry, y1 + ry];
            let area = (x1 - x0) * (y1 - y0);
            imp.splat_scale = if area > 0.0 { full_area / area } else { 1.0 };
        }
    }

    /// Full image area over the rendered pixels' area (see [`Importance`]; 1 without a crop).
    pub fn splat_scale(&self) -> f32 {
        self.importance.as_ref().map_or(1.0, |i| i.splat_scale)
    }

    /// The camera's viewing direction (+z of camera space), world space, unit length.
    fn forward(&self) -> Vec3 {
        normalize(self.world_from_camera.vector(Vec3::Z))
    }

    /// The ray (`o`, unit `d`, world space) in camera space.
    fn to_camera(&self, o: Vec3, d: Vec3) -> (Vec3, Vec3) {
        let camera_from_world = self.world_from_camera.inverse();
        (
            camera_from_world.point(o),
            normalize(camera_from_world.vector(d)),
        )
    }

    /// Importance We of the ray leaving lens point `o` in unit direction `d` (world space)
    /// and the raster point it reaches; `None` (zero importance) when it misses the film's
    /// sample bounds or the camera has none. We = 1/(A · A_lens · cos⁴θ).
    pub fn we(&self, o: Vec3, d: Vec3) -> Option<(f32, Vec2)> {
        let imp = self.importance.as_ref()?;
        let (o, d) = self.to_camera(o, d);
        let p = imp.raster(o, d)?;
        let cos2 = d.z * d.z;
        Some((1.0 / (imp.image_area * imp.lens_area() * cos2 * cos2), p))
    }

    /// Densities (p_pos per unit lens area, p_dir per unit solid angle) with which the camera
    /// samples the ray leaving `o` in unit direction `d` (world space): 1/A_lens and
    /// 1/(A cos³θ), both zero outside the film's sample bounds.
    pub fn pdf_we(&self, o: Vec3, d: Vec3) -> (f32, f32) {
        let Some(imp) = self.importance.as_ref() else {
            return (0.0, 0.0);
        };
        let (o, d) = self.to_camera(o, d);
        if imp.raster(o, d).is_none() {
            return (0.0, 0.0);
        }
        (
            1.0 / imp.lens_area(),
            1.0 / (imp.image_area * d.z * d.z * d.z),
        )
    }

    /// Samples a lens point (uniform on the lens disk, from `u`) for the scene point `p_ref`:
    /// the importance arriving there, its density per unit solid angle at `p_ref`,
    /// p = dist² / (|cos θ_lens| · A_lens), and the raster point; `None` when the ray from the
    /// lens misses the film or the camera has no importance.
    pub fn sample_wi(&self, p_ref: Vec3, u: Vec2) -> Option<CameraWiSample> {
        let imp = self.importance.as_ref()?;
        let lens = imp.lens_radius * sample_uniform_disk_concentric(u);
        let p_lens = self.world_from_camera.point(Vec3::new(lens.x, lens.y, 0.0));
        let n_lens = self.forward();
        let to_lens = p_lens - p_ref;
        let dist2 = to_lens.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let wi = to_lens / dist2.sqrt();
        let cos_lens = n_lens.dot(wi).abs();
        if cos_lens == 0.0 {
            return None;
        }
        let (we, p_raster) = self.we(p_lens, -wi)?;
        Some(CameraWiSample {
            wi_importance: we,
            wi,
            pdf: dist2 / (cos_lens * imp.lens_area()),
            p_raster,
            p_lens,
            n_lens,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraDesc, Projection};
    use crate::math::Transform;

    fn camera(fov: f32, lens_radius: f32, xres: u32, yres: u32) -> Camera {
        let desc = CameraDesc {
            camera_from_world: Transform::look_at(
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(0.0, 0.5, 0.0),
                Vec3::Y,
            )
            .unwrap(),
            projection: Projection::Perspective { fov },
            lens_radius,
            focal_distance: 2.5,
            ..CameraDesc::default()
        };
        Camera::from_desc(&desc, (xres, yres), 35.0).unwrap()
    }

    /// ∫ We cos θ dω over the directions through the image, from one lens point, by a
    /// midpoint rule on the film: dω = cos³θ dA on the plane z = 1, and a raster pixel covers
    /// A/(xres·yres) of that plane.
    fn integral_of_importance(cam: &Camera, o_lens: Vec2, n: u32, xres: u32, yres: u32) -> f64 {
        let imp = cam.importance.as_ref().unwrap();
        let o = cam
            .world_from_camera
            .point(Vec3::new(o_lens.x, o_lens.y, 0.0));
        let fwd = cam.forward();
        let da = imp.image_area as f64 / (n * n) as f64;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let r = Vec2::new(
                    (i as f32 + 0.5) / n as f32 * xres as f32,
                    (j as f32 + 0.5) / n as f32 * yres as f32,
                );
                // The point of the plane in focus the pixel sees, and the ray from `o` to it.
                let z = if imp.lens_radius > 0.0 {
                    imp.focal_distance
                } else {
                    1.0
                };
                let Kind::Projective {
                    camera_from_raster, ..
                } = &cam.kind
                else {
                    unreachable!()
                };
                let pc = camera_from_raster.point(Vec3::new(r.x, r.y, 0.0));
                let pc = pc * (z / pc.z);
                let d = normalize(cam.world_from_camera.point(pc) - o);
                let Some((we, p)) = cam.we(o, d) else {
                    continue;
                };
                // The raster point comes back where it was aimed.
                assert!((p - r).length() < 2e-2 * xres as f32 / 100.0, "{p} vs {r}");
                let cos = d.dot(fwd) as f64;
                // dω of this cell, seen from the lens point: on the plane z, a cell of area
                // da·z² at distance z/cos gives cos³/z² · da·z².
                let d_omega = cos.powi(3) * da;
                sum += we as f64 * cos * d_omega;
            }
        }
        sum * imp.lens_area() as f64
    }

    #[test]
    fn importance_integrates_to_one_over_the_image_per_unit_lens_area() {
        // pbrt-v4's normalisation: ∫_lens ∫_image We cos θ dω dA = 1, i.e. A_lens · ∫ We cos dω = 1
        // for every lens point (pinhole: A_lens = 1).
        for (fov, lens, xres, yres) in [
            (45.0, 0.0, 100, 75),
            (90.0, 0.0, 64, 64),
            (30.0, 0.0, 40, 90),
            (50.0, 0.1, 80, 60),
        ] {
            let cam = camera(fov, lens, xres, yres);
            for o in [Vec2::ZERO, Vec2::new(0.05, -0.03)] {
                let o = o * lens * 10.0;
                let i = integral_of_importance(&cam, o, 200, xres, yres);
                assert!((i - 1.0).abs() < 2e-3, "fov {fov} lens {lens}: {i}");
            }
        }
    }

    #[test]
    fn densities_agree_with_importance_and_sampling() {
        let cam = camera(40.0, 0.0, 100, 80);
        let imp = cam.importance.as_ref().unwrap().clone();
        let o = cam.world_from_camera.point(Vec3::ZERO);
        let fwd = cam.forward();
        // A point the camera sees: its sample's direction gives back We and p_dir = We·cos·A_lens
        // (pbrt-v4: We = p_dir / (A_lens cos θ)).
        let target = Vec3::new(0.2, 0.6, 0.1);
        let s = cam.sample_wi(target, Vec2::new(0.3, 0.7)).unwrap();
        assert!((s.p_lens - o).length() < 1e-5);
        let (pos, dir) = cam.pdf_we(s.p_lens, -s.wi);
        let cos = (-s.wi).dot(fwd);
        assert_eq!(pos, 1.0);
        let we = s.wi_importance;
        assert!(
            (dir - we * cos * imp.lens_area()).abs() < 1e-4 * dir,
            "{dir} {we}"
        );
        // Density per solid angle at the target: dist²/cos_lens for a pinhole.
        let d2 = (o - target).length_squared();
        assert!((s.pdf - d2 / cos).abs() < 1e-4 * s.pdf);
        // The raster point is where the camera's own ray for it goes.
        let ray = cam.generate_ray(s.p_raster, Vec2::ZERO).unwrap().ray;
        assert!((ray.d - (-s.wi)).length() < 1e-4, "{} vs {}", ray.d, -s.wi);
        // Behind the camera or outside the image: nothing.
        assert!(cam.we(o, -fwd).is_none());
        assert!(cam.sample_wi(o - fwd, Vec2::ZERO).is_none());
        assert_eq!(cam.pdf_we(o, -fwd), (0.0, 0.0));
    }

    #[test]
    fn sample_bounds_follow_the_film_and_filter() {
        let mut cam = camera(40.0, 0.0, 100, 80);
        let o = cam.world_from_camera.point(Vec3::ZERO);
        // Through raster (-0.5, 40): outside the plain image, inside once the filter's radius
        // of 1.5 widens it by one pixel.
        let d = cam
            .generate_ray(Vec2::new(-0.5, 40.0), Vec2::ZERO)
            .unwrap()
            .ray
            .d;
        assert!(cam.we(o, d).is_none());
        cam.set_film_extent([0, 100, 0, 80], 8000.0, Vec2::splat(1.5));
        assert!(cam.we(o, d).is_some());
        assert_eq!(cam.splat_scale(), 1.0);
        cam.set_film_extent([0, 50, 0, 80], 8000.0, Vec2::splat(0.5));
        assert_eq!(cam.splat_scale(), 2.0);
        let d = cam
            .generate_ray(Vec2::new(60.0, 40.0), Vec2::ZERO)
            .unwrap()
            .ray
            .d;
        assert!(cam.we(o, d).is_none());
    }

    #[test]
    fn only_perspective_cameras_receive_light_paths() {
        assert!(camera(40.0, 0.0, 10, 10).light_path_support().is_ok());
        for projection in [
            Projection::Orthographic,
            Projection::Spherical {
                mapping: Default::default(),
            },
        ] {
            let desc = CameraDesc {
                projection,
                ..CameraDesc::default()
            };
            let cam = Camera::from_desc(&desc, (64, 48), 35.0).unwrap();
            let e = cam.light_path_support().unwrap_err();
            assert!(e.contains("perspective"), "{e}");
            assert!(cam.we(Vec3::ZERO, Vec3::Z).is_none());
            assert!(cam.sample_wi(Vec3::Z, Vec2::ZERO).is_none());
        }
    }
}
