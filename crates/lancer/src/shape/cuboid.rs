//! lancer's box: the axis-aligned box [min, max] of object space, placed by the CTM.

use super::hit::{ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::Placement;
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Vec2, Vec3, cross, gamma, normalize};
use crate::ray::Ray;

/// lancer's `box` as a scene gives it: the object-space box between `min` and `max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxDesc {
    /// Low corner.
    pub min: Vec3,
    /// High corner (greater than `min` on every axis).
    pub max: Vec3,
}

impl GeometryKind for BoxDesc {
    type Prim = Box<Cuboid>;

    fn pbrt_name(&self) -> &'static str {
        "box"
    }

    /// `min` below `max` on every axis, both finite.
    fn validate(&self) -> Result<(), RuleError> {
        let (min, max) = (self.min, self.max);
        if min.cmplt(max).all() && min.is_finite() && max.is_finite() {
            Ok(())
        } else {
            Err(RuleError::on(
                &["min", "max"],
                format!(
                    "the box's \"min\" {min} must be finite and below its \"max\" {max} on \
                     every axis"
                ),
            ))
        }
    }

    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<Cuboid>>,
    ) -> Result<(), String> {
        out.extend([Box::new(Cuboid::new(at.placement(), self.min, self.max))]);
        Ok(())
    }
}

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

impl ShapeKind for Cuboid {
    fn bounds(&self) -> Bounds3 {
        Cuboid::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Cuboid::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Cuboid::interaction(self, ray, hit)
    }

    /// Exact in world space (see [`Cuboid::area`]), and so its power's area too.
    fn area(&self) -> f32 {
        Cuboid::area(self)
    }

    /// A point sampled in object space, then placed.
    fn sample_area(&self, u: Vec2, _: &[TriangleMesh]) -> Option<ShapeSample> {
        let (p, n) = self.sample_object(u);
        Some(self.placement.place(p, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::shape::testing::{assert_near, assert_rel, identity};

    /// The box [−1, 1] × [−2, 2] × [−3, 3].
    fn box123() -> Cuboid {
        Cuboid::new(
            identity(),
            Vec3::new(-1.0, -2.0, -3.0),
            Vec3::new(1.0, 2.0, 3.0),
        )
    }

    fn hit(b: &Cuboid, ray: &Ray) -> (ShapeHit, SurfaceInteraction) {
        let h = b.intersect(ray).expect("a hit");
        (h, b.interaction(ray, &h))
    }

    #[test]
    fn hit_point_normal_and_uv_on_a_max_face() {
        // From (5, ½, ½) along −x: the face x = 1 at t = 4, n = +x. On a max face of axis 0,
        // (i, j) = (1, 2): u = (½ + 2)/4 = 0.625, v = (½ + 3)/6 = 7/12.
        let (h, si) = hit(&box123(), &Ray::new(Vec3::new(5.0, 0.5, 0.5), -Vec3::X));
        assert_eq!(h.t, 4.0);
        assert_near(si.p, Vec3::new(1.0, 0.5, 0.5), 0.0);
        assert_eq!(si.p.x, 1.0, "the point is put exactly on its face");
        assert_near(si.n, Vec3::X, 0.0);
        assert!((si.uv.x - 0.625).abs() < 1e-6 && (si.uv.y - 7.0 / 12.0).abs() < 1e-6);
    }

    #[test]
    fn faces_have_outward_normals_and_unit_uv() {
        let b = box123();
        for k in 0..3 {
            for side in [1.0f32, -1.0] {
                let mut dir = Vec3::ZERO;
                dir[k] = -side;
                // From outside the face normal to axis k on `side`, aimed at a point off centre.
                let mut target = Vec3::new(0.3, -0.5, 0.7);
                target[k] = side * [1.0, 2.0, 3.0][k];
                let o = target - 5.0 * dir;
                let (h, si) = hit(&b, &Ray::new(o, dir));
                assert_near(si.p, target, 1e-5);
                assert_near(si.n, -dir, 1e-6);
                assert!((h.t - 5.0).abs() < 1e-5);
                // From inside, the same face is hit with the same outward normal.
                let (_, inside) = hit(&b, &Ray::new(Vec3::ZERO, -dir));
                assert_near(inside.n, -dir, 1e-6);
                let uv = si.uv;
                assert!(uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all());
            }
        }
        // A ray parallel to a face, outside the slab, misses.
        assert!(
            b.intersect(&Ray::new(Vec3::new(1.5, 0.0, -10.0), Vec3::Z))
                .is_none()
        );
    }

    #[test]
    fn areas_under_any_affine_placement() {
        // 2(ab + bc + ca) for the 1 × 2 × 3 box: 2(2 + 6 + 3) = 22.
        let b = Cuboid::new(identity(), Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        assert_rel(b.area(), 22.0, 1e-6);
        // Scaled by (2, 1, 1), the 2 × 4 × 6 box becomes 4 × 4 × 6: 2(16 + 24 + 24) = 128.
        let xf = Transform::scale(Vec3::new(2.0, 1.0, 1.0)).unwrap();
        let b = Cuboid::new(
            Placement::new(xf, false),
            Vec3::new(-1.0, -2.0, -3.0),
            Vec3::new(1.0, 2.0, 3.0),
        );
        assert_rel(b.area(), 128.0, 1e-6);
    }

    #[test]
    fn samples_pick_faces_by_area() {
        // Face areas of box123: 4·6 = 24 (x faces), 6·2 = 12 (y), 2·4 = 8 (z); total 88.
        // u₀ = 0.6: 52.8 − 24 − 12 − 8 = 8.8 falls on the max-x face at 8.8/24 of its u:
        // p = (1, −2 + 4·8.8/24, −3 + 6·½) = (1, −0.5333, 0), n = +x.
        let (p, n) = box123().sample_object(Vec2::new(0.6, 0.5));
        assert_near(p, Vec3::new(1.0, -2.0 + 4.0 * 8.8 / 24.0, 0.0), 1e-5);
        assert_eq!(n, Vec3::X);
        // u₀ near 0: the min-x face, normal −x.
        let (p, n) = box123().sample_object(Vec2::new(0.01, 0.5));
        assert_eq!((p.x, n), (-1.0, -Vec3::X));
    }
}
