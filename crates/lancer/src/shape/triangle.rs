//! Triangles and triangle meshes: the watertight ray–triangle test.

use super::hit::{Shading, ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind};
use super::mesh::{RuleError, TriangleMesh};
use super::triangle_ray::TriangleRay;
use crate::math::{
    Bounds3, Frame, PackedVec3, Vec2, Vec3, cross, difference_of_products, gamma, normalize,
};
use crate::ray::Ray;
use crate::sampling::sample_uniform_triangle;
use std::sync::Arc;

impl TriangleMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.face_count()
    }

    /// pbrt-v4's shading derivatives of a hit `si` on triangle `index` of the mesh
    /// ([`triangle_shading_derivatives`] with its vertex normals and (u, v)).
    pub fn shading_derivatives(&self, index: u32, si: &SurfaceInteraction) -> ShadingDerivatives {
        if self.normals.is_empty() {
            return triangle_shading_derivatives(si, None, None);
        }
        let v = self.vertices(index);
        let uvs = (!self.uvs.is_empty()).then(|| v.map(|i| self.uvs[i]));
        triangle_shading_derivatives(si, Some(v.map(|i| self.normal(i))), uvs)
    }
}

/// One triangle of a world-space mesh; its vertex positions are copied in for intersection.
#[derive(Clone, Debug, PartialEq)]
pub struct Triangle {
    /// Vertex positions, world space (packed, so that a triangle stays 44 bytes).
    pub p: [PackedVec3; 3],
    /// Index of the mesh in the scene.
    pub mesh: u32,
    /// Index of the triangle in its mesh.
    pub index: u32,
}

impl Triangle {
    /// The vertex positions, unpacked for computing.
    #[inline]
    pub fn vertices(&self) -> [Vec3; 3] {
        self.p.map(Vec3::from)
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        let [p0, p1, p2] = self.vertices();
        Bounds3::from_point(p0).union_point(p1).union_point(p2)
    }

    /// Nearest hit (see [`intersect_triangle`]); degenerate triangles are left out of scenes
    /// when they are built.
    #[inline]
    pub fn intersect(&self, ray: &Ray, pre: &TriangleRay) -> Option<ShapeHit> {
        let [p0, p1, p2] = self.vertices();
        intersect_triangle_with(ray, pre, p0, p1, p2)
    }

    /// Full interaction (see [`triangle_interaction`]) with the mesh's normals and (u, v).
    /// The triangle's vertex indices are read only when the mesh has either.
    #[inline]
    pub fn interaction(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        mesh: &TriangleMesh,
    ) -> SurfaceInteraction {
        let (normals, uvs) = if mesh.normals.is_empty() && mesh.uvs.is_empty() {
            (None, None)
        } else {
            let v = mesh.vertices(self.index);
            (
                (!mesh.normals.is_empty()).then(|| v.map(|i| mesh.normal(i))),
                (!mesh.uvs.is_empty()).then(|| v.map(|i| mesh.uvs[i])),
            )
        };
        triangle_interaction(ray, hit, self.vertices(), normals, uvs, mesh.flip_normal)
    }

    /// [`Triangle::interaction`] with the triangle's [`TriangleFrame`] made beforehand (by
    /// [`TriangleFrame::new`] on its vertices): the same record, bit for bit, without the two
    /// square roots and divisions that stood in the path of every hit.
    #[inline]
    pub fn interaction_framed(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        mesh: &TriangleMesh,
        frame: &TriangleFrame,
    ) -> SurfaceInteraction {
        if !mesh.uvs.is_empty() {
            // ∂p/∂u then comes from the (u, v), not from the vertices alone.
            return self.interaction(ray, hit, mesh);
        }
        let normals =
            (!mesh.normals.is_empty()).then(|| mesh.vertices(self.index).map(|i| mesh.normal(i)));
        let (n, s) = (Vec3::from(frame.n), Vec3::from(frame.s));
        interaction_with(
            ray,
            hit,
            self.vertices(),
            n,
            Some(s),
            normals,
            None,
            mesh.flip_normal,
        )
    }
}

/// What a triangle's hit record takes from its vertices alone, made once per triangle rather
/// than once per hit: its unit geometric normal n = normalize((p₀ − p₂) × (p₁ − p₂)) (before
/// any flip) and the unit ∂p/∂u of the default (u, v), normalize(p₁ − p₀). Each is computed
/// by the very operations [`triangle_interaction`] performs, so that a record made with it
/// ([`Triangle::interaction_framed`]) is that function's, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleFrame {
    /// The unit geometric normal (zero for a degenerate triangle).
    pub n: PackedVec3,
    /// The unit ∂p/∂u of the default parameterisation (for a degenerate triangle, of the
    /// frame around n that replaces it).
    pub s: PackedVec3,
}

impl TriangleFrame {
    /// The frame of the triangle with vertices `p`.
    pub fn new(p: [Vec3; 3]) -> TriangleFrame {
        let [p0, p1, p2] = p;
        let n = cross(p0 - p2, p1 - p2).normalize_or_zero();
        let dpdu = if n == Vec3::ZERO {
            Frame::from_z(n).x
        } else {
            p1 - p0
        };
        TriangleFrame {
            n: n.into(),
            s: dpdu.normalize_or_zero().into(),
        }
    }
}

/// Full interaction of a triangle with vertices `p`, per-vertex shading `normals` and `uvs`
/// when its mesh has them, and `flip` its mesh's [`super::IndexedMesh::flip_normal`]:
/// p = b₀p₀ + b₁p₁ + b₂p₂ with error ≤ γ₇ Σ|bᵢpᵢ|; ∂p/∂u, ∂p/∂v from the (u, v) of the
/// vertices; geometric normal (p₀ − p₂) × (p₁ − p₂), turned to agree with the interpolated
/// vertex normal when there is one (pbrt's rule).
///
/// Inlined into each caller: its vertices then come in registers, where passed through
/// memory they were read back right after their caller had written them (a stall per hit).
#[inline(always)]
pub fn triangle_interaction(
    ray: &Ray,
    hit: &ShapeHit,
    p: [Vec3; 3],
    normals: Option<[Vec3; 3]>,
    uvs: Option<[Vec2; 3]>,
    flip: bool,
) -> SurfaceInteraction {
    let [p0, p1, p2] = p;
    let n = cross(p0 - p2, p1 - p2).normalize_or_zero();
    interaction_with(ray, hit, p, n, None, normals, uvs, flip)
}

/// [`triangle_interaction`] given the unit geometric normal `n` and, when the caller has it,
/// the unit ∂p/∂u `unit_dpdu` (only for a mesh without (u, v), whose ∂p/∂u depends on the
/// vertices alone: see [`TriangleFrame`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn interaction_with(
    ray: &Ray,
    hit: &ShapeHit,
    p: [Vec3; 3],
    n: Vec3,
    unit_dpdu: Option<Vec3>,
    normals: Option<[Vec3; 3]>,
    uvs: Option<[Vec2; 3]>,
    flip: bool,
) -> SurfaceInteraction {
    let [p0, p1, p2] = p;
    let (b1, b2) = (hit.u, hit.v);
    let b0 = 1.0 - b1 - b2;
    let (dp02, dp12) = (p0 - p2, p1 - p2);
    let mut n = n;
    let (mut dpdu, mut dpdv, uv_hit, degenerate);
    match uvs {
        None => {
            // pbrt's default corners (0, 0), (1, 0), (1, 1): the general formulas below reduce
            // to ∂p/∂u = p₁ − p₀, ∂p/∂v = p₂ − p₁ and (u, v) = (b₁ + b₂, b₂).
            dpdu = p1 - p0;
            dpdv = p2 - p1;
            uv_hit = Vec2::new(b1 + b2, b2);
            degenerate = n == Vec3::ZERO;
        }
        Some(uv) => {
            let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
            let det = difference_of_products(duv02.x, duv12.y, duv02.y, duv12.x);
            let degenerate_uv = det.abs() < 1e-9;
            (dpdu, dpdv) = (Vec3::ZERO, Vec3::ZERO);
            if !degenerate_uv {
                let inv = 1.0 / det;
                dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
                dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
            }
            uv_hit = b0 * uv[0] + b1 * uv[1] + b2 * uv[2];
            degenerate = degenerate_uv || cross(dpdu, dpdv).length_squared() == 0.0;
        }
    }
    if degenerate {
        let f = Frame::from_z(n);
        dpdu = f.x;
        dpdv = f.y;
    }
    let p = b0 * p0 + b1 * p1 + b2 * p2;
    let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());

    let mut ns = n;
    if let Some(vn) = normals {
        let interp = b0 * vn[0] + b1 * vn[1] + b2 * vn[2];
        if let Some(s) = interp.try_normalize() {
            ns = s;
        }
        n = if n.dot(ns) < 0.0 { -n } else { n };
    } else if flip {
        n = -n;
        ns = n;
    }
    // Shading tangents: ∂p/∂u made perpendicular to the shading normal.
    let mut ss = unit_dpdu.unwrap_or_else(|| dpdu.normalize_or_zero());
    let mut ts = cross(ns, ss);
    if ts.length_squared() > 0.0 {
        ss = cross(ts, ns);
    } else {
        let f = Frame::from_z(ns);
        ss = f.x;
        ts = f.y;
    }
    SurfaceInteraction {
        p,
        p_error,
        n,
        uv: uv_hit,
        dpdu,
        dpdv,
        shading: Shading {
            n: ns,
            dpdu: ss,
            dpdv: ts,
        },
        wo: -normalize(ray.d),
        t: hit.t,
        time: ray.time,
    }
}

/// pbrt-v4's shading derivatives of a triangle's hit `si` (its
/// `Triangle::InteractionFromIntersection`), given the triangle's vertex `normals` and `uvs`
/// when its mesh has them. Without normals: the geometric ∂p/∂u, ∂p/∂v, and
/// ∂n/∂u = ∂n/∂v = 0. With them: s = t × n_s and t = n_s × ∂p/∂u (of the length of ∂p/∂u,
/// where [`Shading`] keeps unit tangents; lancer's unit frame around n_s where n_s ∥ ∂p/∂u),
/// and ∂n/∂u, ∂n/∂v of the interpolated normal ([`triangle_normal_derivatives`]).
pub fn triangle_shading_derivatives(
    si: &SurfaceInteraction,
    normals: Option<[Vec3; 3]>,
    uvs: Option<[Vec2; 3]>,
) -> ShadingDerivatives {
    let Some(vn) = normals else {
        return ShadingDerivatives {
            dpdu: si.dpdu,
            dpdv: si.dpdv,
            dndu: Vec3::ZERO,
            dndv: Vec3::ZERO,
        };
    };
    let ns = si.shading.n;
    let t = cross(ns, si.dpdu);
    let (dpdu, dpdv) = if t.length_squared() > 0.0 {
        (cross(t, ns), t)
    } else {
        (si.shading.dpdu, si.shading.dpdv)
    };
    let (dndu, dndv) = triangle_normal_derivatives(vn, uvs);
    ShadingDerivatives {
        dpdu,
        dpdv,
        dndu,
        dndv,
    }
}

/// ∂n/∂u, ∂n/∂v of the vertex normals n₀, n₁, n₂ interpolated linearly over a triangle whose
/// vertices have (u, v) `uvs` (pbrt's (0, 0), (1, 0), (1, 1) when none), as pbrt-v4 computes
/// them: with Δ₀₂ = uv₀ − uv₂, Δ₁₂ = uv₁ − uv₂ and det = Δ₀₂.u·Δ₁₂.v − Δ₀₂.v·Δ₁₂.u,
///
///   ∂n/∂u = (Δ₁₂.v·(n₀ − n₂) − Δ₀₂.v·(n₁ − n₂))/det,
///   ∂n/∂v = (Δ₀₂.u·(n₁ − n₂) − Δ₁₂.u·(n₀ − n₂))/det;
///
/// where |det| < 10⁻⁹, the frame ([`Frame::from_z`], pbrt's `CoordinateSystem`) around
/// (n₂ − n₀) × (n₁ − n₀), or zero when that vanishes.
pub fn triangle_normal_derivatives(n: [Vec3; 3], uvs: Option<[Vec2; 3]>) -> (Vec3, Vec3) {
    let uv = uvs.unwrap_or([Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::ONE]);
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dn1, dn2) = (n[0] - n[2], n[1] - n[2]);
    let det = difference_of_products(duv02.x, duv12.y, duv02.y, duv12.x);
    if det.abs() < 1e-9 {
        let dn = cross(n[2] - n[0], n[1] - n[0]);
        if dn.length_squared() == 0.0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let f = Frame::from_z(dn);
        return (f.x, f.y);
    }
    let inv = 1.0 / det;
    (
        (duv12.y * dn1 - duv02.y * dn2) * inv,
        (duv02.x * dn2 - duv12.x * dn1) * inv,
    )
}

/// The watertight ray–triangle test of Woop, Benthin and Wald (2013), as in PBRT-v4 §6.5.3.
///
/// The triangle is moved into a space where the ray starts at the origin and runs along +z
/// (translate, permute the axes so that the largest direction component is z, shear). There
/// the test is 2D: the edge functions e₀, e₁, e₂ at the origin must share a sign, and a hit is
/// never lost through the gap between two triangles sharing an edge, because both compute
/// that edge's function from the same values. Edge functions that round to zero are redone in
/// double precision. The hit's t is accepted only if it is positive beyond its own rounding
/// error bound.
///
/// Returns t and the barycentrics (b₁, b₂) as (u, v).
#[inline]
pub fn intersect_triangle(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<ShapeHit> {
    // Degenerate (zero-area) triangles are never hit.
    if is_degenerate(p0, p1, p2) {
        return None;
    }
    intersect_triangle_with(ray, &TriangleRay::new(ray), p0, p1, p2)
}

/// True for a triangle of zero area, which no ray can hit.
#[inline]
pub fn is_degenerate(p0: Vec3, p1: Vec3, p2: Vec3) -> bool {
    cross(p2 - p0, p1 - p0).length_squared() == 0.0
}

/// [`intersect_triangle`] with the ray's permutation and shear already computed, for a
/// triangle known not to be degenerate.
#[inline]
pub fn intersect_triangle_with(
    ray: &Ray,
    pre: &TriangleRay,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<ShapeHit> {
    let mut p0t = pre.permute(p0 - ray.o);
    let mut p1t = pre.permute(p1 - ray.o);
    let mut p2t = pre.permute(p2 - ray.o);
    let shear = pre.shear();
    let (sx, sy, sz) = (shear.x, shear.y, shear.z);
    p0t.x += sx * p0t.z;
    p0t.y += sy * p0t.z;
    p1t.x += sx * p1t.z;
    p1t.y += sy * p1t.z;
    p2t.x += sx * p2t.z;
    p2t.y += sy * p2t.z;

    let mut e0 = difference_of_products(p1t.x, p2t.y, p1t.y, p2t.x);
    let mut e1 = difference_of_products(p2t.x, p0t.y, p2t.y, p0t.x);
    let mut e2 = difference_of_products(p0t.x, p1t.y, p0t.y, p1t.x);
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let (p0x, p0y, p1x, p1y, p2x, p2y) = (
            p0t.x as f64,
            p0t.y as f64,
            p1t.x as f64,
            p1t.y as f64,
            p2t.x as f64,
            p2t.y as f64,
        );
        e0 = (p2x * p1y - p2y * p1x) as f32;
        e1 = (p0x * p2y - p0y * p2x) as f32;
        e2 = (p1x * p0y - p1y * p0x) as f32;
        e0 = -e0;
        e1 = -e1;
        e2 = -e2;
    }
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    p0t.z *= sz;
    p1t.z *= sz;
    p2t.z *= sz;
    let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < ray.t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > ray.t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let (b1, b2) = (e1 * inv_det, e2 * inv_det);
    let t = t_scaled * inv_det;

    // Conservative bound on t's rounding error: reject hits that might be at t ≤ 0.
    let max_zt = Vec3::new(p0t.z, p1t.z, p2t.z).abs().max_element();
    let delta_z = gamma(3) * max_zt;
    let max_xt = Vec3::new(p0t.x, p1t.x, p2t.x).abs().max_element();
    let max_yt = Vec3::new(p0t.y, p1t.y, p2t.y).abs().max_element();
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = Vec3::new(e0, e1, e2).abs().max_element();
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(ShapeHit { t, u: b1, v: b2 })
}

/// The triangles of a mesh that a ray can hit (one of zero area never can): each one's three
/// vertex positions and its index in the mesh.
pub fn mesh_triangles(mesh: &TriangleMesh) -> impl Iterator<Item = ([PackedVec3; 3], u32)> + '_ {
    (0..mesh.triangle_count() as u32).filter_map(move |i| {
        let v = mesh.vertices(i);
        let p = [
            mesh.positions[v[0]],
            mesh.positions[v[1]],
            mesh.positions[v[2]],
        ];
        let [a, b, c] = p.map(Vec3::from);
        (!is_degenerate(a, b, c)).then_some((p, i))
    })
}

/// A triangle mesh as a scene gives it (`trianglemesh`, `plymesh`, `objmesh`, glTF, …),
/// shared by its copies.
impl GeometryKind for Arc<TriangleMesh> {
    type Prim = Triangle;

    fn pbrt_name(&self) -> &'static str {
        "trianglemesh"
    }

    /// Its indices and arrays consistent ([`super::IndexedMesh::check`]).
    fn validate(&self) -> Result<(), RuleError> {
        self.check()
    }

    fn is_mesh(&self) -> bool {
        true
    }

    /// The mesh moved to the world and appended to the scene's meshes; its triangles that a
    /// ray can hit ([`mesh_triangles`]) as primitives.
    fn build(&self, at: &mut Placing<'_>, out: &mut impl Extend<Triangle>) -> Result<(), String> {
        let world = self.transformed(&at.to_world, at.reverse_orientation);
        let mesh = at.meshes.len() as u32;
        out.extend(mesh_triangles(&world).map(|(p, index)| Triangle { p, mesh, index }));
        at.meshes.push(world);
        Ok(())
    }
}

impl ShapeKind for Triangle {
    fn bounds(&self) -> Bounds3 {
        Triangle::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, pre: &TriangleRay) -> Option<ShapeHit> {
        Triangle::intersect(self, ray, pre)
    }

    fn interaction(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        meshes: &[TriangleMesh],
    ) -> SurfaceInteraction {
        Triangle::interaction(self, ray, hit, &meshes[self.mesh as usize])
    }

    fn shading_derivatives(
        &self,
        _: &Ray,
        _: &ShapeHit,
        meshes: &[TriangleMesh],
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        meshes[self.mesh as usize].shading_derivatives(self.index, si)
    }

    /// A = |(p₁ − p₀) × (p₂ − p₀)| / 2.
    fn area(&self) -> f32 {
        let [p0, p1, p2] = self.vertices();
        0.5 * cross(p1 - p0, p2 - p0).length()
    }

    /// A point uniform by area (uniform barycentrics), with the normal oriented by the same
    /// rule as [`Triangle::interaction`]: towards the interpolated vertex normal when the mesh
    /// has normals, else flipped by the mesh's orientation.
    fn sample_area(&self, u: Vec2, meshes: &[TriangleMesh]) -> Option<ShapeSample> {
        let [b0, b1, b2] = sample_uniform_triangle(u);
        let [p0, p1, p2] = self.vertices();
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let mesh = &meshes[self.mesh as usize];
        let mut n = cross(p0 - p2, p1 - p2).normalize_or_zero();
        if !mesh.normals.is_empty() {
            let v = mesh.vertices(self.index);
            let ns = b0 * mesh.normal(v[0]) + b1 * mesh.normal(v[1]) + b2 * mesh.normal(v[2]);
            if n.dot(ns) < 0.0 {
                n = -n;
            }
        } else if mesh.flip_normal {
            n = -n;
        }
        Some(ShapeSample { p, n })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_misses_outside() {
        let (a, b, c) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let h = intersect_triangle(&r, a, b, c).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.u - 0.25).abs() < 1e-6 && (h.v - 0.25).abs() < 1e-6);
        let miss = Ray::new(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z);
        assert!(intersect_triangle(&miss, a, b, c).is_none());
        let behind = Ray::new(Vec3::new(0.25, 0.25, -1.0), -Vec3::Z);
        assert!(intersect_triangle(&behind, a, b, c).is_none());
        let short = Ray { t_max: 0.5, ..r };
        assert!(intersect_triangle(&short, a, b, c).is_none());
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Rays through the shared diagonal of a quad hit exactly one of its two triangles or
        // both, never neither.
        let q = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        for i in 0..1000 {
            let s = i as f32 / 1000.0;
            let r = Ray::new(Vec3::new(s, s, 3.0), Vec3::new(0.0, 0.0, -1.0));
            let h = intersect_triangle(&r, q[0], q[1], q[2]).is_some()
                || intersect_triangle(&r, q[0], q[2], q[3]).is_some();
            assert!(h, "leak at {s}");
        }
    }

    /// The mesh of one triangle (0, 0, 0), (1, 0, 0), (0, 1, 0) and that triangle.
    fn one_triangle(normals: Vec<PackedVec3>, flip_normal: bool) -> (TriangleMesh, Triangle) {
        let positions = vec![PackedVec3::ZERO, PackedVec3::X, PackedVec3::Y];
        let tri = Triangle {
            p: [positions[0], positions[1], positions[2]],
            mesh: 0,
            index: 0,
        };
        let mesh = TriangleMesh {
            positions,
            normals,
            indices: vec![0, 1, 2],
            flip_normal,
            ..Default::default()
        };
        (mesh, tri)
    }

    #[test]
    fn interaction_point_normal_and_default_uv() {
        // At (¼, ¼): b₁ = b₂ = ¼, b₀ = ½, t = 1. Normal (p₀ − p₂) × (p₁ − p₂) =
        // (0, −1, 0) × (1, −1, 0) = (0, 0, 1). Default (u, v) = (b₁ + b₂, b₂) = (½, ¼);
        // ∂p/∂u = p₁ − p₀ = +x, ∂p/∂v = p₂ − p₁ = (−1, 1, 0).
        let (mesh, tri) = one_triangle(vec![], false);
        let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let h = tri.intersect(&ray, &TriangleRay::new(&ray)).unwrap();
        let si = tri.interaction(&ray, &h, &mesh);
        assert!((si.t - 1.0).abs() < 1e-6);
        assert!((si.p - Vec3::new(0.25, 0.25, 0.0)).length() < 1e-6);
        assert_eq!(si.n, Vec3::Z);
        assert_eq!(si.shading.n, Vec3::Z);
        assert!((si.uv - Vec2::new(0.5, 0.25)).length() < 1e-6);
        assert_eq!((si.dpdu, si.dpdv), (Vec3::X, Vec3::new(-1.0, 1.0, 0.0)));
        // Reverse orientation flips both normals.
        let (mesh, tri) = one_triangle(vec![], true);
        let si = tri.interaction(&ray, &h, &mesh);
        assert_eq!((si.n, si.shading.n), (-Vec3::Z, -Vec3::Z));
    }

    /// A record made with the triangle's frame made beforehand is the plain one, bit for bit,
    /// with and without vertex normals, flipped or not, and for (u, v) meshes (which fall back).
    #[test]
    fn framed_interaction_is_the_plain_one_bit_for_bit() {
        use crate::sampling::{hash_u64, u32_to_unit_f32};
        let rnd = |i: u64| u32_to_unit_f32(hash_u64(&[i]) as u32) * 4.0 - 2.0;
        for k in 0..200u64 {
            let positions: Vec<PackedVec3> = (0..3)
                .map(|v| {
                    PackedVec3::new(
                        rnd(9 * k + 3 * v),
                        rnd(9 * k + 3 * v + 1),
                        rnd(9 * k + 3 * v + 2),
                    )
                })
                .collect();
            let normals = if k % 3 == 0 {
                positions
                    .iter()
                    .map(|p| PackedVec3::from(normalize(Vec3::from(*p))))
                    .collect()
            } else {
                vec![]
            };
            let uvs = if k % 5 == 0 {
                vec![
                    Vec2::new(0.1, 0.2),
                    Vec2::new(0.9, 0.3),
                    Vec2::new(0.4, 0.8),
                ]
            } else {
                vec![]
            };
            let tri = Triangle {
                p: [positions[0], positions[1], positions[2]],
                mesh: 0,
                index: 0,
            };
            let mesh = TriangleMesh {
                positions,
                normals,
                uvs,
                indices: vec![0, 1, 2],
                flip_normal: k % 2 == 1,
            };
            let frame = TriangleFrame::new(tri.vertices());
            let h = ShapeHit {
                t: 1.5,
                u: 0.25,
                v: 0.375,
            };
            let ray = Ray::new(
                Vec3::new(rnd(5000 + k), 3.0, 0.5),
                Vec3::new(0.1, -1.0, 0.2),
            );
            let want = tri.interaction(&ray, &h, &mesh);
            let got = tri.interaction_framed(&ray, &h, &mesh, &frame);
            let bits = |si: &SurfaceInteraction| {
                [si.p, si.p_error, si.n, si.dpdu, si.dpdv, si.shading.n]
                    .into_iter()
                    .chain([si.shading.dpdu, si.shading.dpdv, si.wo])
                    .flat_map(|v| v.to_array().map(f32::to_bits))
                    .chain([si.uv.x, si.uv.y, si.t].map(f32::to_bits))
                    .collect::<Vec<u32>>()
            };
            assert_eq!(bits(&got), bits(&want), "triangle {k}");
        }
    }

    #[test]
    fn vertex_normals_orient_the_geometric_normal() {
        // Vertex normals all −z tilted differently: the shading normal is their normalised
        // interpolation, and the geometric normal is turned to its side.
        let ns = vec![
            PackedVec3::new(0.0, 0.0, -1.0),
            PackedVec3::new(0.6, 0.0, -0.8),
            PackedVec3::new(0.0, 0.6, -0.8),
        ];
        let (mesh, tri) = one_triangle(ns, false);
        let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let h = tri.intersect(&ray, &TriangleRay::new(&ray)).unwrap();
        let si = tri.interaction(&ray, &h, &mesh);
        assert_eq!(si.n, -Vec3::Z);
        // ½(0, 0, −1) + ¼(0.6, 0, −0.8) + ¼(0, 0.6, −0.8) = (0.15, 0.15, −0.9).
        let want = normalize(Vec3::new(0.15, 0.15, -0.9));
        assert!((si.shading.n - want).length() < 1e-6, "{}", si.shading.n);
        assert!(si.shading.dpdu.dot(si.shading.n).abs() < 1e-6);
    }

    #[test]
    fn mesh_triangles_leave_out_degenerate_ones() {
        let mut m = TriangleMesh::default();
        m.positions.extend(
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0, 0.0, 0.0],
            ]
            .map(PackedVec3::from),
        );
        // Triangle 1 is three points on the x axis: zero area.
        m.indices.extend([0, 1, 2, 0, 1, 3, 2, 1, 0]);
        let tris: Vec<u32> = mesh_triangles(&m).map(|(_, i)| i).collect();
        assert_eq!(tris, [0, 2]);
        let (p, _) = mesh_triangles(&m).nth(1).unwrap();
        assert_eq!(p[0], PackedVec3::new(0.0, 1.0, 0.0));
    }
}
