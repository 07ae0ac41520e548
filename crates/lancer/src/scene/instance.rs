//! Two-level instancing: one BVH per object (pbrt's `ObjectBegin`/`ObjectEnd`), and a
//! top-level BVH over its placements (`ObjectInstance`), so that memory grows with unique
//! geometry, not with copies.
//!
//! A ray meeting an instance is moved into the object's space (o' = M⁻¹o, d' = M⁻¹d, so that
//! t is the same in both spaces), tested against the object's tree, and the nearest hit is
//! moved back: points and tangents by M, normals by the inverse transpose (M⁻¹)ᵀ.

use super::desc::{Geometry, ObjectDesc};
use super::prim::{BuildError, PrimInfo, check_shape, mesh_bytes};
use crate::accel::{Bvh, MeshBvh};
use crate::math::{Bounds3, Frame, Transform, normalize};
use crate::ray::Ray;
use crate::shape::{
    Shading, ShadingDerivatives, ShapeHit, SurfaceInteraction, Triangle, TriangleMesh, TriangleRay,
    mesh_triangles,
};

/// An object made only of triangle meshes, with its own BVH (object space).
#[derive(Debug)]
pub struct ObjectAccel {
    /// The tree over every triangle of the object.
    bvh: MeshBvh,
    /// The object's meshes, in object space (each shape's own transform applied).
    meshes: Vec<TriangleMesh>,
    /// Per triangle of the tree's input: (mesh, triangle in the mesh).
    tris: Vec<(u32, u32)>,
    /// Per mesh: its index in the scene's [`PrimInfo`] list (material, no emission).
    prim: Vec<u32>,
}

impl ObjectAccel {
    /// The object's accelerator, when the object can be instanced: triangle meshes only,
    /// none emitting or alpha-tested (those are flattened instead, as pbrt-v4 requires for
    /// area lights). `prims` receives one entry per mesh.
    pub(crate) fn build(
        obj: &ObjectDesc,
        prims: &mut Vec<PrimInfo>,
        n_materials: usize,
    ) -> Result<Option<ObjectAccel>, BuildError> {
        let instanceable = obj.shapes.iter().all(|s| {
            matches!(s.geometry, Geometry::TriangleMesh(_))
                && s.area_light.is_none()
                && s.alpha.is_none()
        });
        if !instanceable || obj.shapes.is_empty() {
            return Ok(None);
        }
        let mut meshes = Vec::new();
        let mut tris = Vec::new();
        let mut verts = Vec::new();
        let mut prim = Vec::new();
        for (index, sd) in obj.shapes.iter().enumerate() {
            let Geometry::TriangleMesh(m) = &sd.geometry else {
                continue;
            };
            check_shape(sd, index, n_materials).map_err(|e| match e {
                BuildError::BadMesh { shape, message } => BuildError::BadMesh {
                    shape,
                    message: format!("object \"{}\": {message}", obj.name),
                },
                e => e,
            })?;
            let local = m.transformed(&sd.object_to_world, sd.reverse_orientation);
            let mi = meshes.len() as u32;
            for (p, i) in mesh_triangles(&local) {
                verts.push(p);
                tris.push((mi, i));
            }
            meshes.push(local);
            prim.push(prims.len() as u32);
            prims.push(PrimInfo {
                material: sd.material,
                emission: None,
                alpha: None,
                media: super::prim::prim_media(sd),
            });
        }
        let bvh = MeshBvh::build(&verts);
        Ok(Some(ObjectAccel {
            bvh,
            meshes,
            tris,
            prim,
        }))
    }

    /// Adds `base` to the object's [`PrimInfo`] indices (once they are appended to the
    /// scene's list after its shapes' entries).
    pub(crate) fn offset_prims(&mut self, base: u32) {
        for p in &mut self.prim {
            *p += base;
        }
    }

    /// Bounds of the object, object space.
    pub(crate) fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// The nearest hit of an object-space ray: (triangle, hit).
    #[inline]
    pub(crate) fn intersect(&self, ro: &Ray) -> Option<(u32, ShapeHit)> {
        self.bvh.intersect(ro, &TriangleRay::new(ro))
    }

    /// True if an object-space ray hits the object.
    #[inline]
    pub(crate) fn intersect_any(&self, ro: &Ray) -> bool {
        self.bvh.intersect_any(ro, &TriangleRay::new(ro))
    }

    /// The object-space interaction of triangle `tri`'s hit by `ro`, whether its mesh has
    /// vertex normals, and the mesh's [`PrimInfo`] index.
    pub(crate) fn local_interaction(
        &self,
        ro: &Ray,
        tri: u32,
        hit: &ShapeHit,
    ) -> (SurfaceInteraction, bool, u32) {
        let (mesh, index) = self.tris[tri as usize];
        let m = &self.meshes[mesh as usize];
        let v = m.vertices(index);
        let t = Triangle {
            p: [m.positions[v[0]], m.positions[v[1]], m.positions[v[2]]],
            mesh,
            index,
        };
        let si = t.interaction(ro, hit, m);
        (si, !m.normals.is_empty(), self.prim[mesh as usize])
    }

    /// pbrt-v4's shading derivatives, object space, of triangle `tri`'s hit by `ro`
    /// ([`TriangleMesh::shading_derivatives`]), for a bump map.
    pub(crate) fn local_shading_derivatives(
        &self,
        ro: &Ray,
        tri: u32,
        hit: &ShapeHit,
    ) -> ShadingDerivatives {
        let (si, _, _) = self.local_interaction(ro, tri, hit);
        let (mesh, index) = self.tris[tri as usize];
        self.meshes[mesh as usize].shading_derivatives(index, &si)
    }

    /// Bytes of the tree, the meshes, the triangle table and the record indices.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.tris.capacity() * std::mem::size_of::<(u32, u32)>()
            + self.prim.capacity() * std::mem::size_of::<u32>()
            + self.meshes.capacity() * std::mem::size_of::<TriangleMesh>()
            + self.meshes.iter().map(mesh_bytes).sum::<usize>()
    }
}

/// One placement of an object.
#[derive(Clone, Copy, Debug)]
pub struct Instance {
    /// Index of the object in [`Instances::objects`].
    pub object: u32,
    /// Object space → world space (M).
    pub to_world: Transform,
}

/// A hit on an instance: which, which triangle of its object, and the object-space hit.
#[derive(Clone, Copy, Debug)]
pub struct InstanceHit {
    instance: u32,
    tri: u32,
    hit: ShapeHit,
}

/// Every instanced object and the top-level BVH over their placements.
#[derive(Debug, Default)]
pub struct Instances {
    /// The objects' accelerators.
    pub objects: Vec<ObjectAccel>,
    /// The placements.
    pub instances: Vec<Instance>,
    bvh: Bvh,
}

impl Instances {
    /// The top-level tree over `instances` of `objects`.
    pub fn new(objects: Vec<ObjectAccel>, instances: Vec<Instance>) -> Instances {
        let bounds: Vec<Bounds3> = instances
            .iter()
            .map(|i| i.to_world.bounds(&objects[i.object as usize].bvh.bounds()))
            .collect();
        let bvh = Bvh::build(&bounds);
        Instances {
            objects,
            instances,
            bvh,
        }
    }

    /// True when there is no instance.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }

    /// World bounds of every instance.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// Bytes of the objects' trees and meshes and of the top-level tree: what instancing
    /// costs, which grows with unique geometry (plus a few bytes per placement).
    pub fn memory_bytes(&self) -> usize {
        self.objects.capacity() * std::mem::size_of::<ObjectAccel>()
            + self
                .objects
                .iter()
                .map(ObjectAccel::memory_bytes)
                .sum::<usize>()
            + self.instances.capacity() * std::mem::size_of::<Instance>()
            + self.bvh.memory_bytes()
    }

    /// The ray in instance `i`'s object space: o' = M⁻¹o, d' = M⁻¹d (t unchanged).
    #[inline]
    fn object_ray(&self, i: u32, ray: &Ray) -> Ray {
        let inv = &self.instances[i as usize].to_world.m_inv;
        Ray {
            o: inv.transform_point3a(ray.o),
            d: inv.transform_vector3a(ray.d),
            t_max: ray.t_max,
            time: ray.time,
        }
    }

    /// The nearest instance hit with 0 < t < `ray.t_max`.
    pub fn intersect(&self, ray: &Ray) -> Option<InstanceHit> {
        let mut best = None;
        self.bvh.intersect(ray, |i, r| {
            let ro = self.object_ray(i, r);
            let obj = &self.objects[self.instances[i as usize].object as usize];
            let (tri, hit) = obj.bvh.intersect(&ro, &TriangleRay::new(&ro))?;
            best = Some(InstanceHit {
                instance: i,
                tri,
                hit,
            });
            Some(hit.t)
        });
        best
    }

    /// True if some instance is hit with 0 < t < `ray.t_max`.
    pub fn intersect_any(&self, ray: &Ray) -> bool {
        self.bvh.intersect_any(ray, |i, r| {
            let ro = self.object_ray(i, r);
            let obj = &self.objects[self.instances[i as usize].object as usize];
            obj.bvh.intersect_any(&ro, &TriangleRay::new(&ro))
        })
    }

    /// The full interaction of a hit of `ray` (world space), and the index in the scene's
    /// [`PrimInfo`] list of the mesh hit. The triangle's interaction is computed in object
    /// space and moved to the world: p and its error bound by M, ∂p/∂u and ∂p/∂v by M, the
    /// normals by (M⁻¹)ᵀ (the geometric one turned to the shading one's side, as pbrt does).
    pub fn interaction(&self, ray: &Ray, h: &InstanceHit) -> (SurfaceInteraction, u32) {
        let inst = &self.instances[h.instance as usize];
        let obj = &self.objects[inst.object as usize];
        let (mesh, index) = obj.tris[h.tri as usize];
        let m = &obj.meshes[mesh as usize];
        let v = m.vertices(index);
        let tri = Triangle {
            p: [m.positions[v[0]], m.positions[v[1]], m.positions[v[2]]],
            mesh,
            index,
        };
        let ro = self.object_ray(h.instance, ray);
        let si = tri.interaction(&ro, &h.hit, m);
        let si = to_world(&si, !m.normals.is_empty(), &inst.to_world, ray);
        (si, obj.prim[mesh as usize])
    }

    /// pbrt-v4's shading derivatives of a hit of `ray` (world space): its object's, moved by
    /// the instance's M as pbrt-v4 moves an interaction ([`ShadingDerivatives::transformed`]);
    /// for a bump map.
    pub fn shading_derivatives(&self, ray: &Ray, h: &InstanceHit) -> ShadingDerivatives {
        let inst = &self.instances[h.instance as usize];
        let ro = self.object_ray(h.instance, ray);
        self.objects[inst.object as usize]
            .local_shading_derivatives(&ro, h.tri, &h.hit)
            .transformed(&inst.to_world)
    }
}

/// An object-space interaction moved to the world by `xf` (as an instance's): p and its error
/// bound and ∂p/∂u, ∂p/∂v by M, the normals by (M⁻¹)ᵀ, the geometric normal turned to the
/// shading normal's side for meshes with vertex normals, the shading tangents made
/// perpendicular to the shading normal again.
pub(super) fn to_world(
    si: &SurfaceInteraction,
    normals: bool,
    xf: &Transform,
    ray: &Ray,
) -> SurfaceInteraction {
    let (p, p_error) = xf.point_with_error_in(si.p, si.p_error);
    let mut n = xf.normal(si.n).normalize_or_zero();
    let ns = xf.normal(si.shading.n).normalize_or_zero();
    if normals && n.dot(ns) < 0.0 {
        n = -n;
    }
    let Frame { x: ss, y: ts, .. } = Frame::from_xz(xf.vector(si.shading.dpdu), ns);
    SurfaceInteraction {
        p,
        p_error,
        n,
        uv: si.uv,
        dpdu: xf.vector(si.dpdu),
        dpdv: xf.vector(si.dpdv),
        shading: Shading {
            n: ns,
            dpdu: ss,
            dpdv: ts,
        },
        wo: -normalize(ray.d),
        t: si.t,
        time: si.time,
    }
}

#[cfg(test)]
mod tests {
    use super::super::desc::{InstanceDesc, SceneDesc, ShapeDesc};
    use super::*;
    use crate::Scene;
    use crate::math::Vec3;
    use crate::sampling::Pcg32;
    use std::sync::Arc;

    fn v3(rng: &mut Pcg32) -> Vec3 {
        Vec3::new(rng.uniform(), rng.uniform(), rng.uniform())
    }

    /// A closed-ish blob of random triangles around the origin, with vertex normals.
    fn mesh(rng: &mut Pcg32) -> TriangleMesh {
        let mut m = TriangleMesh::default();
        for i in 0..400u32 {
            let c = (v3(rng) - 0.5).normalize_or_zero();
            for _ in 0..3 {
                let p = c + (v3(rng) - 0.5) * 0.3;
                m.positions.push(p.into());
                m.normals.push(p.normalize_or_zero().into());
            }
            m.indices.extend([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        m
    }

    fn shape(m: &Arc<TriangleMesh>, xf: Transform) -> ShapeDesc {
        ShapeDesc {
            medium_interface: None,
            geometry: Geometry::TriangleMesh(m.clone()),
            object_to_world: xf,
            reverse_orientation: false,
            material: 0,
            area_light: None,
            alpha: None,
        }
    }

    /// `n` placements: rotated, scaled (some mirrored), scattered.
    fn placements(rng: &mut Pcg32, n: usize) -> Vec<Transform> {
        (0..n)
            .map(|k| {
                let s = 0.5 + rng.uniform();
                let mirror = if k % 5 == 0 { -1.0 } else { 1.0 };
                Transform::translate((v3(rng) - 0.5) * 20.0)
                    * Transform::rotate(360.0 * rng.uniform(), v3(rng) + 0.1).unwrap()
                    * Transform::scale(Vec3::new(s * mirror, s, 1.3 * s)).unwrap()
            })
            .collect()
    }

    fn scenes(n: usize) -> (Scene, Scene) {
        let mut rng = Pcg32::new(3, 0);
        let m = Arc::new(mesh(&mut rng));
        let inner = Transform::translate(Vec3::new(0.1, 0.0, 0.2));
        let xfs = placements(&mut rng, n);
        let mut inst = SceneDesc::default();
        inst.objects.push(ObjectDesc {
            name: "blob".into(),
            shapes: vec![shape(&m, inner)],
        });
        inst.instances = xfs
            .iter()
            .map(|&x| InstanceDesc {
                object: 0,
                object_to_world: x,
            })
            .collect();
        let flat = SceneDesc {
            shapes: xfs.iter().map(|&x| shape(&m, x * inner)).collect(),
            ..SceneDesc::default()
        };
        (Scene::build(&inst).unwrap(), Scene::build(&flat).unwrap())
    }

    #[test]
    fn instanced_and_flattened_copies_give_the_same_hits() {
        let (inst, flat) = scenes(50);
        assert!(inst.shapes.is_empty() && inst.instances.instances.len() == 50);
        let mut rng = Pcg32::new(5, 0);
        let (mut hits, mut differ, mut any_differ) = (0, 0, 0);
        let n = 20_000;
        for _ in 0..n {
            let o = (v3(&mut rng) - 0.5) * 30.0;
            let ray = Ray::new(o, (v3(&mut rng) - 0.5) * 20.0 - o);
            let (a, b) = (inst.intersect(&ray), flat.intersect(&ray));
            any_differ += (inst.intersect_p(&ray) != flat.intersect_p(&ray)) as u32;
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    if (a.si.t - b.si.t).abs() > 1e-4 * b.si.t {
                        // A ray grazing an edge may meet another triangle behind it.
                        differ += 1;
                        continue;
                    }
                    assert!(
                        (a.si.p - b.si.p).length() < 1e-3,
                        "{:?} {:?}",
                        a.si.p,
                        b.si.p
                    );
                    assert!(a.si.n.dot(b.si.n) > 0.999, "{:?} {:?}", a.si.n, b.si.n);
                    assert!(a.si.shading.n.dot(b.si.shading.n) > 0.999);
                    assert!(a.si.wo.dot(b.si.wo) > 0.9999);
                    assert!((a.si.uv - b.si.uv).length() < 1e-3);
                    assert!(a.si.p_error.cmpge(Vec3::ZERO).all());
                    assert_eq!(inst.prims[a.prim as usize].material, 0);
                }
                (None, None) => {}
                _ => differ += 1,
            }
        }
        assert!(hits > n / 10, "{hits} hits");
        assert!(differ < n / 500, "{differ} rays differ");
        assert!(any_differ < n / 500, "{any_differ} shadow rays differ");
    }

    #[test]
    fn memory_grows_with_unique_geometry_only() {
        let (one, _) = scenes(1);
        let (fifty, flat) = scenes(50);
        let (m1, m50) = (one.instances.memory_bytes(), fifty.instances.memory_bytes());
        // Each further placement costs its transform and a share of the top-level tree (a
        // few hundred bytes), not another copy of the geometry (tens of KiB here).
        assert!(m1 > 40_000, "one object of 400 triangles: {m1} bytes");
        assert!(m50 < m1 + 49 * 256, "1 instance {m1} bytes, 50: {m50}");
        // Flattened, the copies are plain meshes: 400 triangles each, no shape record.
        assert_eq!(flat.tris.len(), 50 * 400);
        assert!(flat.shapes.is_empty());
    }
}
