//! Vectors, transforms, bounds and the floating-point error bounds that keep rays from finding
//! the surface they start on.
//!
//! Vectors come from [`glam`]; this module adds what a ray tracer needs on top: a [`Transform`]
//! carrying its inverse, axis-aligned [`Bounds3`], orthonormal [`Frame`]s and conservative
//! rounding-error arithmetic ([`gamma`], [`offset_ray_origin`]).

pub mod animated;
mod bounds;
pub mod digest;
mod float;
mod frame;
pub mod noise;
mod transform;
mod vector;

pub use animated::AnimatedTransform;
pub use bounds::Bounds3;
pub use float::{
    INV_2PI, INV_4PI, INV_PI, MACHINE_EPSILON, PI, difference_of_products, gamma, lerp,
    next_float_down, next_float_up, safe_acos, safe_asin, safe_sqrt, smooth_step, solve_quadratic,
    sqr,
};
pub use frame::{Frame, rotate_from_to};
pub use glam::{Mat3, Mat4, UVec2, Vec2, Vec4};
pub use transform::Transform;
pub use vector::{
    PackedRgb, PackedVec3, Rgb, SHADOW_EPSILON, SampledSpectrum, Vec3, cross, face_forward,
    lanes_rgb, luminance, normalize, offset_ray_origin, rgb_lanes, spherical_direction,
};
