//! The camera's description: plain data the readers fill in and [`super::Camera::from_desc`]
//! builds the camera from (the scene description re-exports it beside the rest of a scene).

use crate::math::Transform;
use std::sync::Arc;

/// pbrt-v4's default sensor diagonal in millimetres (the film's `diagonal`), which only a
/// realistic camera reads.
pub const DEFAULT_DIAGONAL: f32 = 35.0;

/// Camera projection.
#[derive(Clone, Debug, PartialEq)]
pub enum Projection {
    /// pbrt's `perspective`.
    Perspective {
        /// Full field of view of the shorter image axis, degrees.
        fov: f32,
    },
    /// pbrt's `orthographic`.
    Orthographic,
    /// pbrt's `spherical`: the whole sphere of directions from one point.
    Spherical {
        /// How the image covers the sphere.
        mapping: super::lens::SphericalMapping,
    },
    /// pbrt's `realistic`: a lens system traced ray by ray.
    Realistic(Arc<super::lens::LensDesc>),
}

/// The camera.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// Projection and its parameters.
    pub projection: Projection,
    /// World space → camera space (pbrt's CTM at `Camera`). Camera space is pbrt's: looking
    /// down +z, +y up, left-handed.
    pub camera_from_world: Transform,
    /// Screen window (x_min, x_max, y_min, y_max); `None` for pbrt's default from the aspect
    /// ratio.
    pub screen_window: Option<[f32; 4]>,
    /// Thin-lens aperture radius (0: pinhole).
    pub lens_radius: f32,
    /// Distance to the plane in focus.
    pub focal_distance: f32,
    /// Shutter open and close times (`shutteropen`, `shutterclose`).
    pub shutter: [f32; 2],
}

impl Default for CameraDesc {
    /// pbrt's default: perspective, fov 90, at the origin looking down +z.
    fn default() -> Self {
        CameraDesc {
            projection: Projection::Perspective { fov: 90.0 },
            camera_from_world: Transform::IDENTITY,
            screen_window: None,
            lens_radius: 0.0,
            focal_distance: 1e6,
            shutter: [0.0, 1.0],
        }
    }
}
