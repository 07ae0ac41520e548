//! Cameras: from a point on the film to a ray into the scene.
//!
//! The course's camera sits at the origin looking down −z, its image plane at z = −1 spanning
//! [−1, 1] (see [`Camera::course`]); scene files use pbrt's `perspective` camera, where the same
//! picture comes from a screen window, a field of view and a camera-to-world transform. pbrt-v4's
//! other cameras follow: `orthographic`, `spherical` ([`spherical`]) and `realistic`
//! ([`realistic`], a lens system traced ray by ray).

mod aperture;
pub mod desc;
pub mod footprint;
pub mod importance;
pub mod lens;
mod light_paths;
pub mod realistic;
pub mod spherical;

use crate::math::{AnimatedTransform, Transform, Vec2, Vec3, normalize};
use crate::ray::Ray;
use crate::sampling::sample_uniform_disk_concentric;
pub use desc::{CameraDesc, DEFAULT_DIAGONAL, Projection};
pub use importance::CameraWiSample;
use importance::Importance;
use lens::SphericalMapping;
use realistic::{PUPIL_SAMPLES, RealisticCamera};

/// A camera ray and the weight its radiance gets (1 except through a realistic lens, whose
/// weight is cos⁴θ / (p · z²) times the aperture's transmission).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    /// The ray, world space, unit direction.
    pub ray: Ray,
    /// Multiplies the radiance the ray brings back.
    pub weight: f32,
}

/// How a camera turns film points into camera-space rays.
#[derive(Clone, Debug, PartialEq)]
enum Kind {
    /// pbrt's `perspective` and `orthographic` cameras, with a thin lens.
    Projective {
        /// Raster space (pixels, (0, 0) at the image's top-left corner) → camera space.
        camera_from_raster: Transform,
        /// Perspective or orthographic.
        perspective: bool,
        /// Thin-lens aperture radius (0: pinhole).
        lens_radius: f32,
        /// Distance to the plane in focus.
        focal_distance: f32,
    },
    /// pbrt's `spherical` camera.
    Spherical {
        /// How the image covers the sphere.
        mapping: SphericalMapping,
        /// The full image's size in pixels.
        resolution: Vec2,
    },
    /// pbrt's `realistic` camera (boxed: it holds the lens system and pupil bounds).
    Realistic(Box<RealisticCamera>),
}

/// A camera able to generate primary rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Camera space → world space (at the shutter's opening when the camera moves).
    pub world_from_camera: Transform,
    /// Camera space → world space over time, when the camera moves (motion blur).
    motion: Option<Box<AnimatedTransform>>,
    kind: Kind,
    /// What light paths need to reach the camera (perspective cameras only; boxed, as the
    /// other cameras have none).
    importance: Option<Box<Importance>>,
}

impl Camera {
    /// The camera `desc` describes for a film of `resolution` (full width and height in
    /// pixels) and, for a realistic camera, sensor `diagonal` (mm), or why there is none.
    ///
    /// pbrt's projective cameras: the screen window defaults to [−a, a] × [−1, 1] for a wide
    /// image of aspect a (and [−1, 1] × [−1/a, 1/a] for a tall one), so `fov` spans the shorter
    /// axis. Raster y grows downwards, screen y upwards.
    pub fn from_desc(
        desc: &CameraDesc,
        resolution: (u32, u32),
        diagonal: f32,
    ) -> Result<Camera, String> {
        let (xres, yres) = resolution;
        let kind = match &desc.projection {
            Projection::Perspective { .. } | Projection::Orthographic => {
                Self::projective(desc, xres, yres)
                    .ok_or("the camera's parameters give no valid projection")?
            }
            Projection::Spherical { mapping } => Kind::Spherical {
                mapping: *mapping,
                resolution: Vec2::new(xres as f32, yres as f32),
            },
            Projection::Realistic(lens) => Kind::Realistic(Box::new(RealisticCamera::new(
                lens,
                diagonal,
                xres,
                yres,
                PUPIL_SAMPLES,
            )?)),
        };
        let importance = match (&kind, &desc.projection) {
            (
                Kind::Projective {
                    camera_from_raster,
                    lens_radius,
                    focal_distance,
                    ..
                },
                Projection::Perspective { .. },
            ) => Importance::new(
                camera_from_raster,
                xres,
                yres,
                *lens_radius,
                *focal_distance,
            )
            .map(Box::new),
            _ => None,
        };
        Ok(Camera {
            world_from_camera: desc.camera_from_world.inverse(),
            motion: None,
            kind,
            importance,
        })
    }

    /// Makes the camera move: `world_from_camera` over time (`None`: it stands still).
    pub fn set_motion(&mut self, world_from_camera: Option<AnimatedTransform>) {
        self.motion = world_from_camera
            .filter(AnimatedTransform::is_animated)
            .map(Box::new);
    }

    /// True when the camera moves during the shutter.
    pub fn moves(&self) -> bool {
        self.motion.is_some()
    }

    /// [`Camera::generate_ray`] at `time`: the ray carries the time (and the rays of its path
    /// inherit it), and a moving camera's ray leaves its pose at that time (pbrt-v4's
    /// `CameraTransform` interpolated at the ray's time).
    #[inline]
    pub fn generate_ray_at(&self, p_film: Vec2, p_lens: Vec2, time: f32) -> Option<CameraRay> {
        let mut r = match &self.motion {
            None => self.generate_ray(p_film, p_lens),
            Some(m) => self.ray_from(p_film, p_lens, &m.interpolate(time)),
        }?;
        r.ray.time = time;
        Some(r)
    }

    fn projective(desc: &CameraDesc, xres: u32, yres: u32) -> Option<Kind> {
        let aspect = xres as f32 / yres as f32;
        let sw = desc.screen_window.unwrap_or(if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        });
        let (perspective, screen_from_camera) = match desc.projection {
            Projection::Perspective { fov } => (true, Transform::perspective(fov, 1e-2, 1000.0)?),
            // pbrt's orthographic projection keeps x and y; z does not matter for ray origins.
            _ => (false, Transform::IDENTITY),
        };
        // raster ← screen: translate the window's top-left corner to the origin, scale to
        // pixels, flip y.
        let raster_from_screen = Transform::scale(Vec3::new(xres as f32, -(yres as f32), 1.0))?
            * Transform::scale(Vec3::new(1.0 / (sw[1] - sw[0]), 1.0 / (sw[3] - sw[2]), 1.0))?
            * Transform::translate(Vec3::new(-sw[0], -sw[3], 0.0));
        Some(Kind::Projective {
            camera_from_raster: screen_from_camera.inverse() * raster_from_screen.inverse(),
            perspective,
            lens_radius: desc.lens_radius,
            focal_distance: desc.focal_distance,
        })
    }

    /// The course's pinhole camera for a `width × height` image: eye at the origin, looking
    /// down −z, +y up, +x to the right, image plane z = −1 spanning [−1, 1] on its shorter axis
    /// (exactly [−1, 1]² for a square image).
    pub fn course(width: u32, height: u32) -> Camera {
        let desc = CameraDesc {
            // Camera space looks down +z; mirroring z turns it into the course's −z view with
            // +x still on the right.
            camera_from_world: Transform::scale(Vec3::new(1.0, 1.0, -1.0)).expect("non-zero scale"),
            ..CameraDesc::default()
        };
        Camera::from_desc(&desc, (width, height), DEFAULT_DIAGONAL).expect("valid course camera")
    }

    /// The ray through raster point `p_film` (pixels from the top-left corner), with `p_lens`
    /// a uniform sample for the lens; `None` when a realistic lens blocks it.
    ///
    /// Thin lens (pbrt's `lensradius`, `focaldistance`): the origin moves to a point of the
    /// lens disk and the ray aims at where the pinhole ray meets the plane z = focal distance.
    /// An orthographic camera's lens is centred on its pixel's ray (pbrt-v4 centres it on the
    /// camera's axis, which its own issue tracker reports as a bug).
    #[inline]
    pub fn generate_ray(&self, p_film: Vec2, p_lens: Vec2) -> Option<CameraRay> {
        self.ray_from(p_film, p_lens, &self.world_from_camera)
    }

    /// The ray of [`Camera::generate_ray`] with the camera placed by `world_from_camera`.
    #[inline(always)]
    fn ray_from(
        &self,
        p_film: Vec2,
        p_lens: Vec2,
        world_from_camera: &Transform,
    ) -> Option<CameraRay> {
        let (ray, weight) = match &self.kind {
            Kind::Projective {
                camera_from_raster,
                perspective,
                lens_radius,
                focal_distance,
            } => {
                let p_camera = camera_from_raster.point(Vec3::new(p_film.x, p_film.y, 0.0));
                let mut ray = if *perspective {
                    Ray::new(Vec3::ZERO, normalize(p_camera))
                } else {
                    Ray::new(Vec3::new(p_camera.x, p_camera.y, 0.0), Vec3::Z)
                };
                if *lens_radius > 0.0 {
                    let lens = *lens_radius * sample_uniform_disk_concentric(p_lens);
                    let ft = focal_distance / ray.d.z;
                    let focus = ray.at(ft);
                    ray.o = Vec3::new(lens.x, lens.y, 0.0);
                    if !*perspective {
                        ray.o.x += p_camera.x;
                        ray.o.y += p_camera.y;
                    }
                    ray.d = normalize(focus - ray.o);
                }
                (ray, 1.0)
            }
            Kind::Spherical {
                mapping,
                resolution,
            } => {
                let d = spherical::spherical_direction(*mapping, p_film / *resolution);
                (Ray::new(Vec3::ZERO, d), 1.0)
            }
            Kind::Realistic(lens) => {
                let s = lens.generate(p_film, p_lens)?;
                (Ray::new(s.ray.o, s.ray.d), s.weight)
            }
        };
        let o = world_from_camera.point(ray.o);
        let d = normalize(world_from_camera.vector(ray.d));
        Some(CameraRay {
            ray: Ray::new(o, d),
            weight,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn course_camera_matches_the_lecture() {
        let cam = Camera::course(100, 100);
        // The image centre looks down −z.
        let r = cam
            .generate_ray(Vec2::new(50.0, 50.0), Vec2::ZERO)
            .unwrap()
            .ray;
        assert!(r.o.length() < 1e-6 && (r.d - -Vec3::Z).length() < 1e-5);
        // The top-left corner of the image is the image-plane point (−1, 1, −1).
        let c = cam
            .generate_ray(Vec2::new(0.0, 0.0), Vec2::ZERO)
            .unwrap()
            .ray;
        assert!((c.d - normalize(Vec3::new(-1.0, 1.0, -1.0))).length() < 1e-5);
        // The bottom-right corner is (1, −1, −1).
        let c = cam
            .generate_ray(Vec2::new(100.0, 100.0), Vec2::ZERO)
            .unwrap()
            .ray;
        assert!((c.d - normalize(Vec3::new(1.0, -1.0, -1.0))).length() < 1e-5);
    }

    #[test]
    fn pbrt_lookat_with_mirror_equals_the_course_view() {
        // `Scale -1 1 1  LookAt 0 0 0  0 0 -1  0 1 0  Camera "perspective" "float fov" 90`.
        let m = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap()
            * Transform::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y).unwrap();
        let desc = CameraDesc {
            camera_from_world: m,
            ..CameraDesc::default()
        };
        let a = Camera::from_desc(&desc, (64, 48), DEFAULT_DIAGONAL).unwrap();
        let b = Camera::course(64, 48);
        for p in [
            Vec2::new(0.0, 0.0),
            Vec2::new(10.0, 40.0),
            Vec2::new(64.0, 48.0),
        ] {
            let ra = a.generate_ray(p, Vec2::ZERO).unwrap().ray;
            let rb = b.generate_ray(p, Vec2::ZERO).unwrap().ray;
            assert!((ra.d - rb.d).length() < 1e-5, "{p}: {} vs {}", ra.d, rb.d);
        }
    }
}
