//! lancer's box: the axis-aligned box [min, max] of object space, placed by the CTM.

use super::hit::{ShapeHit, SurfaceInteraction};
use super::placement::Placement;
use crate::math::{Bounds3, Vec2, Vec3, cross, gamma, normalize};
use crate::ray::Ray;

/// A box, axis-aligned in object space, with outward normals (`Shape "box"`).
#[derive(Clone, Debug, PartialEq)]
pub struct Cuboid {
    /// The low corner, object space.
    pub min: Vec3,
    /// The high corner, object space.
    pub max: Vec3,
    /// Placement in the world.
    pub placement: Placement,
    /// World-space area of one face normal to each object axis (the opposite face is equal).
    face_area: [f32; 3],
}

impl Cuboid {
    /// The box between `min` and `max` (which must satisfy min < max on every axis).
    pub fn new(placement: Placement, min: Vec3, max: Vec3) -> Cuboid {
        let ext = max - min;
        let m = &placement.to_world;
        let face_area = std::array::from_fn(|k| {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let a = m.vector(Vec3::AXES[i] * ext[i]);
            let b = m.vector(Vec3::AXES[j] * ext[j]);
            cross(a, b).length()
        });
        Cuboid {
            min,
            max,
            placement,
            face_area,
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        self.placement
            .to_world
            .bounds(&Bounds3::new(self.min, self.max))
    }

    /// Nearest hit by the slab test, in object space and double precision: on each axis the
    /// ray is between the planes for t ∈ [(min − o)/d, (max − o)/d] (ordered); the box is the
    /// intersection of the three intervals [t_near, t_far]. The hit is t_near when positive
    /// (entering), else t_far (leaving from inside). `u` records the face: axis + 3 for a
    /// max face.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let (lo, hi) = (self.min.as_dvec3(), self.max.as_dvec3());
        let (mut t_near, mut t_far) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut near_face, mut far_face) = (0usize, 0usize);
        for k in 0..3 {
            if d[k] == 0.0 {
                // Parallel to this slab: inside it for every t, or never.
                if o[k] < lo[k] || o[k] > hi[k] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d[k];
            let (t_lo, t_hi) = ((lo[k] - o[k]) * inv, (hi[k] - o[k]) * inv);
            // Entering through the min face when going up the axis, the max face otherwise.
            let (t0, f0, t1, f1) = if inv > 0.0 {
                (t_lo, k, t_hi, k + 3)
            } else {
                (t_hi, k + 3, t_lo, k)
            };
            if t0 > t_near {
                t_near = t0;
                near_face = f0;
            }
            if t1 < t_far {
                t_far = t1;
                far_face = f1;
            }
        }
        if t_near > t_far {
            return None;
        }
        let t_max = ray.t_max as f64;
        let (t, face) = if t_near > 0.0 {
            (t_near, near_face)
        } else {
            (t_far, far_face)
        };
        if t <= 0.0 || t >= t_max {
            return None;
        }
        Some(ShapeHit {
            t: t as f32,
            u: face as f32,
            v: 0.0,
        })
    }

    /// Full interaction. The point is recomputed in double precision and put exactly on its
    /// face (the face's coordinate is an `f32`, so that axis has no error); the other two
    /// coordinates carry γ₃·|p|. On the face normal to axis k with (i, j) = (k + 1, k + 2) mod 3,
    /// a max face has u = (pᵢ − minᵢ)/extᵢ, v = (pⱼ − minⱼ)/extⱼ, ∂p/∂u = extᵢ·eᵢ,
    /// ∂p/∂v = extⱼ·eⱼ (so ∂p/∂u × ∂p/∂v = +e_k), a min face swaps the roles of i and j
    /// (normal −e_k): normals point out of the box.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let face = hit.u as usize;
        let (k, is_max) = (face % 3, face >= 3);
        let mut p = (o + hit.t as f64 * d).as_vec3a().clamp(self.min, self.max);
        p[k] = if is_max { self.max[k] } else { self.min[k] };
        let mut p_err = gamma(3) * p.abs();
        p_err[k] = 0.0;
        let ext = self.max - self.min;
        let (mut i, mut j) = ((k + 1) % 3, (k + 2) % 3);
        if !is_max {
            std::mem::swap(&mut i, &mut j);
        }
        let uv = Vec2::new((p[i] - self.min[i]) / ext[i], (p[j] - self.min[j]) / ext[j]);
        SurfaceInteraction::from_object(
            &self.placement.to_world,
            p,
            p_err,
            uv,
            Vec3::AXES[i] * ext[i],
            Vec3::AXES[j] * ext[j],
            self.placement.flip_normal,
            -normalize(ray.d),
            hit.t,
        )
    }

    /// Surface area, world space (exact under any affine placement: each face maps to a
    /// parallelogram of area |M·extᵢeᵢ × M·extⱼeⱼ|): A = 2·Σ_k A_k.
    pub fn area(&self) -> f32 {
        2.0 * self.face_area.iter().sum::<f32>()
    }

    /// A point uniform by world area and its outward normal, object space: a face chosen with
    /// probability A_face/A by u₀ (then rescaled to [0, 1) within that face's share), and a
    /// point uniform on it (affine maps keep uniform densities uniform).
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let total = self.area();
        let mut x = u.x * total;
        let mut face = 5;
        for f in 0..6 {
            let a = self.face_area[f % 3];
            if x < a || f == 5 {
                face = f;
                x = (x / a).clamp(0.0, 1.0);
                break;
            }
            x -= a;
        }
        let (k, is_max) = (face % 3, face >= 3);
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let mut p = self.min;
        p[i] += x * (self.max[i] - self.min[i]);
        p[j] += u.y * (self.max[j] - self.min[j]);
        p[k] = if is_max { self.max[k] } else { self.min[k] };
        let n = if is_max {
            Vec3::AXES[k]
        } else {
            -Vec3::AXES[k]
        };
        (p, n)
    }
}
