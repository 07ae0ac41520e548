//! What moves while the shutter is open (pbrt's `ActiveTransform` and `TransformTimes`): the
//! camera, shapes and object instances whose transformation differs between the two times.
//! Everything else in the [`super::SceneDesc`] stands still.

use super::ShapeDesc;
use crate::math::AnimatedTransform;

/// The moving parts of a scene; empty (the default) for a still scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MotionDesc {
    /// Camera space → world space over time, when the camera moves (pbrt-v4 interpolates the
    /// camera-to-world transformation, the inverse of the CTM at `Camera`). Its start is the
    /// inverse of [`super::CameraDesc::camera_from_world`].
    pub camera: Option<AnimatedTransform>,
    /// Shapes that move.
    pub shapes: Vec<MovingShapeDesc>,
    /// Object instances that move.
    pub instances: Vec<MovingInstanceDesc>,
}

impl MotionDesc {
    /// True when nothing moves.
    pub fn is_empty(&self) -> bool {
        self.camera.is_none() && self.shapes.is_empty() && self.instances.is_empty()
    }
}

/// A shape whose placement changes over time.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingShapeDesc {
    /// The shape; its `object_to_world` applies first (identity from the pbrt reader).
    pub shape: ShapeDesc,
    /// Then this moving transformation into the world.
    pub world_from_object: AnimatedTransform,
}

/// A placement of an object that changes over time.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingInstanceDesc {
    /// Index into [`super::SceneDesc::objects`].
    pub object: u32,
    /// Object space → world space over time.
    pub object_to_world: AnimatedTransform,
}
