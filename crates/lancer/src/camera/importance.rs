//! The camera as a receiver of light: the importance a perspective camera emits, its sampling
//! densities and the sampling of the lens towards a point of the scene, as pbrt-v4's
//! `PerspectiveCamera::We`, `PDF_We` and `SampleWi` define them. Light tracing and
//! bidirectional path tracing connect their light subpaths to the camera with these.
//!
//! Normalisation (pbrt-v4's): on the plane z = 1 of camera space the image covers an area A,
//! and the lens (radius r, a pinhole when r = 0) an area A_lens = πr² (1 for a pinhole). A ray
//! leaving the lens at angle θ from the axis through a point of the image carries
//!
//! ```text
//! We = 1 / (A · A_lens · cos⁴θ)
//! ```
//!
//! so that ∫_image We cos θ dω = 1 for every lens point (dω = cos³θ dA at z = 1). The ray is
//! sampled with densities p_pos = 1/A_lens (on the lens) and p_dir = 1/(A cos³θ) (per unit solid
//! angle). Only perspective cameras have an importance, as in pbrt-v4; the others say so
//! through [`Camera::light_path_support`].

use crate::math::{PI, Transform, Vec2, Vec3};

/// What the importance of a perspective camera needs, made once with the camera.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Importance {
    /// Camera space → raster space (the projection, with its divide).
    pub(super) raster_from_camera: Transform,
    /// Area A of the image on the plane z = 1 of camera space (the full image).
    pub(super) image_area: f32,
    /// Thin-lens radius (0: pinhole).
    pub(super) lens_radius: f32,
    /// Distance to the plane in focus.
    pub(super) focal_distance: f32,
    /// Raster points that count (pbrt-v4's film `SampleBounds`: the pixel bounds grown by the
    /// filter's radius less half a pixel): x0, x1, y0, y1.
    pub(super) sample_bounds: [f32; 4],
    /// Full image area over the rendered pixel bounds' area (1 without a crop window): light
    /// paths are traced once per camera sample of the rendered pixels, but importance spreads
    /// over the whole image, so what they splat is scaled up by this (pbrt-v4 issue #347).
    pub(super) splat_scale: f32,
}

/// A point on the lens chosen for a point of the scene ([`Camera::sample_wi`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraWiSample {
    /// Importance arriving at the reference point from the lens point.
    pub wi_importance: f32,
    /// Unit direction from the reference point towards the lens point.
    pub wi: Vec3,
    /// Density of the lens point, per unit solid angle at the reference point.
    pub pdf: f32,
    /// Where the ray lands on the film, raster space.
    pub p_raster: Vec2,
    /// The lens point, world space.
    pub p_lens: Vec3,
    /// The lens' normal (the camera's viewing direction), world space.
    pub n_lens: Vec3,
}

impl Importance {
    /// The importance of a perspective camera with `camera_from_raster` over an
    /// `xres × yres` image; `None` when the projection is degenerate.
    pub(super) fn new(
        camera_from_raster: &Transform,
        xres: u32,
        yres: u32,
        lens_radius: f32,
        focal_distance: f32,
    ) -> Option<Importance> {
        // A: the image's corners projected onto z = 1.
        let p_min = camera_from_raster.point(Vec3::ZERO);
        let p_max = camera_from_raster.point(Vec3::new(xres as f32, yres as f32, 0.0));
        let (p_min, p_max) = (p_min / p_min.z, p_max / p_max.z);
        let image_area = ((p_max.x - p_min.x) * (p_max.y - p_min.y)).abs();
        (image_area > 0.0 && image_area.is_finite()).then(|| Importance {
            raster_from_camera: camera_from_raster.inverse(),
            image_area,
            lens_radius,
            focal_distance,
            sample_bounds: [0.0, xres as f32, 0.0, yres as f32],
            splat_scale: 1.0,
        })
    }

    /// A_lens: πr², or 1 for a pinhole.
    pub(super) fn lens_area(&self) -> f32 {
        if self.lens_radius > 0.0 {
            PI * self.lens_radius * self.lens_radius
        } else {
            1.0
        }
    }

    /// The raster point a camera-space ray (origin on the lens, unit direction `d` with
    /// cos θ = d.z > 0) goes through, if it lies inside the sample bounds: the ray meets the
    /// plane in focus (z = focal distance; z = 1 for a pinhole) at t = z/cos θ, and that point
    /// projects to the raster point.
    pub(super) fn raster(&self, o: Vec3, d: Vec3) -> Option<Vec2> {
        let cos = d.z;
        if cos <= 0.0 {
            return None;
        }
        let z = if self.lens_radius > 0.0 {
            self.focal_distance
        } else {
            1.0
        };
        let p_focus = o + d * (z / cos);
        let r = self.raster_from_camera.point(p_focus);
        let [x0, x1, y0, y1] = self.sample_bounds;
        (r.x >= x0 && r.x < x1 && r.y >= y0 && r.y < y1).then(|| Vec2::new(r.x, r.y))
    }
}
