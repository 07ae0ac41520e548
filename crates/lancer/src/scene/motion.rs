//! Motion blur in the built scene: the shutter interval, the time of the path being traced,
//! and the moving primitives, kept apart from the still ones.
//!
//! Each moving shape or object instance is one primitive of a small top-level BVH whose boxes
//! are motion bounds (every pose over the shutter, [`AnimatedTransform::motion_bounds`]). A ray
//! meeting one is moved into its object space by the transformation interpolated at the ray's
//! time, tested against the object-space geometry (a triangle tree for meshes and mesh objects,
//! the shapes themselves otherwise), and the hit is moved back, as for instances. Still
//! geometry pays nothing: the main BVH and its triangle packets know nothing of time.
//!
//! Every ray of a path shares its camera ray's time (pbrt-v4's spawned rays inherit it): the
//! ray carries it ([`Ray::time`]), and the moving primitives are posed at it.

use super::desc::{Geometry, ObjectDesc, SceneDesc, ShapeDesc};
use super::instance::{ObjectAccel, to_world};
use super::prim::{BuildError, PrimInfo, check_shape, prim_media};
use crate::accel::Bvh;
use crate::math::{AnimatedTransform, Bounds3, Rgb, Transform};
use crate::ray::Ray;
use crate::shape::{Shape, ShapeHit, SurfaceInteraction, TriangleMesh, TriangleRay};
use std::ops::Range;

/// The moving parts of a scene and its shutter interval.
#[derive(Debug)]
pub struct Motion {
    /// Shutter open and close times: a camera sample's time is `lerp(u, open, close)`.
    pub shutter: [f32; 2],
    prims: Vec<MovingPrim>,
    /// Shared triangle trees of moving meshes and moving instances' objects.
    objects: Vec<ObjectAccel>,
    /// Object-space shapes of the other moving primitives, and each one's record.
    shapes: Vec<(Shape, u32)>,
    /// The object-space meshes those shapes' triangles refer to.
    meshes: Vec<TriangleMesh>,
    bvh: Bvh,
}

#[derive(Debug)]
struct MovingPrim {
    xf: AnimatedTransform,
    what: What,
}

#[derive(Debug)]
enum What {
    /// A triangle tree of [`Motion::objects`].
    Object(u32),
    /// A range of [`Motion::shapes`], tested one by one.
    Shapes(Range<u32>),
}

/// How the build turns a shape into its primitives (appending a mesh's to the meshes): passed
/// in by the build, which owns that conversion.
pub(crate) type ShapesOf =
    fn(&ShapeDesc, usize, &mut Vec<TriangleMesh>, &mut Vec<Shape>) -> Result<(), BuildError>;

/// A hit on a moving primitive: which, which part, the object-space hit and the pose.
#[derive(Clone, Copy, Debug)]
pub struct MovingHit {
    prim: u32,
    part: u32,
    /// The object-space hit (t is the same in both spaces).
    pub hit: ShapeHit,
    xf: Transform,
}

impl Motion {
    /// The moving parts of `desc` with their records appended to `prims`; `None` when
    /// nothing moves. `n_materials` bounds the material indices; `shapes_of` makes the
    /// object-space primitives of the shapes that are not plain meshes.
    pub(crate) fn build(
        desc: &SceneDesc,
        n_materials: usize,
        prims: &mut Vec<PrimInfo>,
        shapes_of: ShapesOf,
    ) -> Result<Option<Motion>, BuildError> {
        let m = &desc.motion;
        if m.is_empty() {
            return Ok(None);
        }
        let mut motion = Motion {
            shutter: desc.camera.shutter,
            prims: Vec::new(),
            objects: Vec::new(),
            shapes: Vec::new(),
            meshes: Vec::new(),
            bvh: Bvh::default(),
        };
        for (k, ms) in m.shapes.iter().enumerate() {
            let index = desc.shapes.len() + k;
            check_shape(&ms.shape, index, n_materials)?;
            let obj = ObjectDesc {
                name: format!("moving shape {index}"),
                shapes: vec![ms.shape.clone()],
            };
            let what = match ObjectAccel::build(&obj, prims, n_materials)? {
                Some(acc) => motion.add_object(acc),
                None => motion.add_shapes(&ms.shape, index, prims, shapes_of)?,
            };
            motion.prims.push(MovingPrim {
                xf: ms.world_from_object,
                what,
            });
        }
        let mut made: Vec<Option<What>> = (0..desc.objects.len()).map(|_| None).collect();
        for inst in &m.instances {
            let obj = desc.objects.get(inst.object as usize).ok_or_else(|| {
                BuildError::Invalid(format!("moving instance of unknown object {}", inst.object))
            })?;
            let what = match &made[inst.object as usize] {
                Some(What::Object(o)) => What::Object(*o),
                Some(What::Shapes(r)) => What::Shapes(r.clone()),
                None => {
                    let what = match ObjectAccel::build(obj, prims, n_materials)? {
                        Some(acc) => motion.add_object(acc),
                        None => {
                            let start = motion.shapes.len() as u32;
                            for sd in &obj.shapes {
                                check_shape(sd, desc.shapes.len(), n_materials)?;
                                motion.add_shapes(sd, desc.shapes.len(), prims, shapes_of)?;
                            }
                            What::Shapes(start..motion.shapes.len() as u32)
                        }
                    };
                    made[inst.object as usize] = Some(match &what {
                        What::Object(o) => What::Object(*o),
                        What::Shapes(r) => What::Shapes(r.clone()),
                    });
                    what
                }
            };
            motion.prims.push(MovingPrim {
                xf: inst.object_to_world,
                what,
            });
        }
        let bounds: Vec<Bounds3> = motion
            .prims
            .iter()
            .map(|p| p.xf.motion_bounds(&motion.local_bounds(&p.what)))
            .collect();
        motion.bvh = Bvh::build(&bounds);
        Ok(Some(motion))
    }

    fn add_object(&mut self, acc: ObjectAccel) -> What {
        self.objects.push(acc);
        What::Object(self.objects.len() as u32 - 1)
    }

    /// The object-space primitives of a shape that is not a plain mesh, each with a record
    /// in `prims`. A moving shape does not emit (pbrt-v4 refuses moving area lights) and is
    /// not alpha-tested.
    fn add_shapes(
        &mut self,
        sd: &ShapeDesc,
        index: usize,
        prims: &mut Vec<PrimInfo>,
        shapes_of: ShapesOf,
    ) -> Result<What, BuildError> {
        if matches!(sd.geometry, Geometry::Plane(_)) {
            return Err(BuildError::Invalid(format!(
                "shape {index}: an infinite plane cannot move"
            )));
        }
        let mut made = Vec::new();
        shapes_of(sd, index, &mut self.meshes, &mut made)?;
        let record = prims.len() as u32;
        prims.push(PrimInfo {
            material: sd.material,
            emission: None,
            alpha: None,
            media: prim_media(sd),
        });
        let start = self.shapes.len() as u32;
        self.shapes.extend(made.into_iter().map(|s| (s, record)));
        Ok(What::Shapes(start..self.shapes.len() as u32))
    }

    fn local_bounds(&self, what: &What) -> Bounds3 {
        match what {
            What::Object(o) => self.objects[*o as usize].bounds(),
            What::Shapes(r) => self.shapes[r.start as usize..r.end as usize]
                .iter()
                .fold(Bounds3::EMPTY, |b, (s, _)| b.union(&s.bounds())),
        }
    }

    /// Adds `base` to the records' indices (once they follow the scene's other records).
    pub(crate) fn offset_prims(&mut self, base: u32) {
        for o in &mut self.objects {
            o.offset_prims(base);
        }
        for (_, r) in &mut self.shapes {
            *r += base;
        }
    }

    /// World bounds of every moving primitive over the whole shutter.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// A camera sample's time from the uniform `u`: `(1 − u)·open + u·close`.
    #[inline]
    pub fn sample_time(&self, u: f32) -> f32 {
        let [open, close] = self.shutter;
        crate::math::lerp(u, open, close)
    }

    /// The nearest hit with 0 < t < `ray.t_max` at `time`.
    pub fn intersect(&self, ray: &Ray, time: f32) -> Option<MovingHit> {
        if self.prims.is_empty() {
            return None;
        }
        let mut best = None;
        self.bvh.intersect(ray, |i, r| {
            let xf = self.prims[i as usize].xf.interpolate(time);
            let mut ro = xf.inverse().ray(r);
            let (part, hit) = match &self.prims[i as usize].what {
                What::Object(o) => self.objects[*o as usize].intersect(&ro)?,
                What::Shapes(range) => {
                    let pre = TriangleRay::new(&ro);
                    let mut found = None;
                    for k in range.clone() {
                        if let Some(h) = self.shapes[k as usize].0.intersect_with(&ro, &pre) {
                            ro.t_max = h.t;
                            found = Some((k, h));
                        }
                    }
                    found?
                }
            };
            best = Some(MovingHit {
                prim: i,
                part,
                hit,
                xf,
            });
            Some(hit.t)
        });
        best
    }

    /// True if a moving primitive is hit with 0 < t < `ray.t_max` at `time`.
    pub fn intersect_any(&self, ray: &Ray, time: f32) -> bool {
        if self.prims.is_empty() {
            return false;
        }
        self.bvh.intersect_any(ray, |i, r| {
            let p = &self.prims[i as usize];
            let ro = p.xf.interpolate(time).inverse().ray(r);
            match &p.what {
                What::Object(o) => self.objects[*o as usize].intersect_any(&ro),
                What::Shapes(range) => {
                    let pre = TriangleRay::new(&ro);
                    range.clone().any(|k| {
                        self.shapes[k as usize]
                            .0
                            .intersect_with(&ro, &pre)
                            .is_some()
                    })
                }
            }
        })
    }

    /// The world interaction of a hit of `ray`, the index of its record, and the reflectance
    /// the shape itself gives (voxels).
    pub fn interaction(&self, ray: &Ray, h: &MovingHit) -> (SurfaceInteraction, u32, Option<Rgb>) {
        let ro = h.xf.inverse().ray(ray);
        let (si, normals, record, albedo) = match &self.prims[h.prim as usize].what {
            What::Object(o) => {
                let (si, normals, record) =
                    self.objects[*o as usize].local_interaction(&ro, h.part, &h.hit);
                (si, normals, record, None)
            }
            What::Shapes(_) => {
                let (shape, record) = &self.shapes[h.part as usize];
                let si = shape.interaction(&ro, &h.hit, &self.meshes);
                let normals = matches!(shape, Shape::Triangle(t)
                    if !self.meshes[t.mesh as usize].normals.is_empty());
                (si, normals, *record, shape.hit_albedo(&h.hit))
            }
        };
        (to_world(&si, normals, &h.xf, ray), record, albedo)
    }

    /// pbrt-v4's shading derivatives of a hit of `ray` (world space): the object-space
    /// shape's or object's, moved by the hit's transform
    /// ([`crate::shape::ShadingDerivatives::transformed`]); for a bump map.
    pub fn shading_derivatives(
        &self,
        ray: &Ray,
        h: &MovingHit,
    ) -> crate::shape::ShadingDerivatives {
        let ro = h.xf.inverse().ray(ray);
        let local = match &self.prims[h.prim as usize].what {
            What::Object(o) => {
                self.objects[*o as usize].local_shading_derivatives(&ro, h.part, &h.hit)
            }
            What::Shapes(_) => {
                let shape = &self.shapes[h.part as usize].0;
                let si = shape.interaction(&ro, &h.hit, &self.meshes);
                shape.shading_derivatives(&ro, &h.hit, &self.meshes, &si)
            }
        };
        local.transformed(&h.xf)
    }
}

#[cfg(test)]
mod tests;
