//! pbrt-v4's `bilinearmesh`: bilinear patches, the surfaces swept by a line whose ends run
//! along two opposite edges of a quadrilateral,
//!
//!   p(u, v) = (1 − u)(1 − v)·p₀₀ + u(1 − v)·p₁₀ + (1 − u)v·p₀₁ + uv·p₁₁,   (u, v) ∈ [0, 1]²,
//!
//! intersected exactly by Reshetov's method ("Cool Patches", Ray Tracing Gems ch. 8), as pbrt-v4
//! does: the ray meets the segment of constant u, from a(u) = lerp(u, p₀₀, p₁₀) to
//! b(u) = lerp(u, p₀₁, p₁₁), where the triple product (a(u) − o)·(d × (b(u) − a(u))) vanishes,
//! a quadratic in u; v and t then follow from the closest points of the ray and that segment.
//! Planar patches (a parallelogram makes the quadratic linear) need no special case.
//!
//! Patches are kept in world space (the mesh is transformed once when the scene is built).

use super::hit::{Shading, ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, HeldBytes, Placing, ShapeKind};
use super::mesh::{IndexedMesh, RuleError, TriangleMesh};
use super::placement::weingarten;
use super::triangle_ray::TriangleRay;
use crate::math::{
    Bounds3, Frame, PackedVec3, Vec2, Vec3, cross, gamma, normalize, rotate_from_to,
    solve_quadratic,
};
use crate::ray::Ray;
use glam::DVec3;
use std::collections::HashSet;
use std::sync::Arc;

/// A mesh of bilinear patches: shared vertices, four indices per patch (p₀₀, p₁₀, p₀₁, p₁₁);
/// without `uvs`, each patch's own (u, v).
pub type BilinearMesh = IndexedMesh<4>;

impl BilinearMesh {
    /// Number of patches.
    pub fn patch_count(&self) -> usize {
        self.face_count()
    }

    /// Every patch of a world-space mesh, as primitives.
    pub fn patches(mesh: &Arc<BilinearMesh>) -> Vec<BilinearPatch> {
        (0..mesh.patch_count() as u32)
            .map(|i| {
                let v = mesh.vertices(i);
                BilinearPatch::new(
                    [
                        mesh.positions[v[0]],
                        mesh.positions[v[1]],
                        mesh.positions[v[2]],
                        mesh.positions[v[3]],
                    ],
                    mesh.clone(),
                    i,
                )
            })
            .collect()
    }
}

/// One bilinear patch of a world-space mesh; its corners are copied in for intersection.
#[derive(Clone, Debug, PartialEq)]
pub struct BilinearPatch {
    /// Corners p₀₀, p₁₀, p₀₁, p₁₁, world space (packed, as the mesh's vertices).
    pub p: [PackedVec3; 4],
    /// The mesh it belongs to (normals, uvs, orientation).
    pub mesh: Arc<BilinearMesh>,
    /// Its index in the mesh.
    pub index: u32,
    /// Surface area.
    area: f32,
}

/// ∂p/∂u and ∂p/∂v of a patch at (u, v):
/// ∂p/∂u = lerp(v, p₁₀, p₁₁) − lerp(v, p₀₀, p₀₁), ∂p/∂v = lerp(u, p₀₁, p₁₁) − lerp(u, p₀₀, p₁₀).
#[inline]
fn partials(p: &[Vec3; 4], u: f32, v: f32) -> (Vec3, Vec3) {
    let [p00, p10, p01, p11] = *p;
    (
        p10.lerp(p11, v) - p00.lerp(p01, v),
        p01.lerp(p11, u) - p00.lerp(p10, u),
    )
}

/// The point p(u, v) = lerp(u, lerp(v, p₀₀, p₀₁), lerp(v, p₁₀, p₁₁)).
#[inline]
pub fn bilinear_point(p: &[Vec3; 4], u: f32, v: f32) -> Vec3 {
    let [p00, p10, p01, p11] = *p;
    p00.lerp(p01, v).lerp(p10.lerp(p11, v), u)
}

/// The area element |∂p/∂u × ∂p/∂v| at (u, v). The cross product is linear in u and v
/// (the u·v term is (p₁₁ − p₁₀ − p₀₁ + p₀₀) × itself = 0), so its length is convex and
/// largest at a corner.
#[inline]
fn jacobian(p: &[Vec3; 4], u: f32, v: f32) -> f32 {
    let (du, dv) = partials(p, u, v);
    cross(du, dv).length()
}

/// The texture coordinates (s, t) at (u, v) of a patch whose corners have (s, t) `st`
/// (bilinearly interpolated), and ∂u/∂s, ∂v/∂s, ∂u/∂t, ∂v/∂t as pbrt-v4 takes them: the
/// component-wise inverses of ∂(s, t)/∂u and ∂(s, t)/∂v, 0 where a component is below 10⁻⁸.
#[inline(always)]
fn st_at(st: [Vec2; 4], u: f32, v: f32) -> (Vec2, [f32; 4]) {
    let [t00, t10, t01, t11] = st;
    let at = t00.lerp(t01, v).lerp(t10.lerp(t11, v), u);
    let dstdu = t10.lerp(t11, v) - t00.lerp(t01, v);
    let dstdv = t01.lerp(t11, u) - t00.lerp(t10, u);
    let inv = |x: f32| if x.abs() < 1e-8 { 0.0 } else { 1.0 / x };
    (at, [inv(dstdu.x), inv(dstdv.x), inv(dstdu.y), inv(dstdv.y)])
}

/// Nodes and weights of 4-point Gauss–Legendre quadrature on [0, 1].
const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_7, 0.173_927_422_568_726_9),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_1),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_1),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_9),
];

impl BilinearPatch {
    /// A patch from its corners (p₀₀, p₁₀, p₀₁, p₁₁); its area is computed once.
    pub fn new(p: [PackedVec3; 4], mesh: Arc<BilinearMesh>, index: u32) -> BilinearPatch {
        let mut patch = BilinearPatch {
            p,
            mesh,
            index,
            area: 0.0,
        };
        patch.area = patch.compute_area();
        patch
    }

    /// A = ∫∫ |∂p/∂u × ∂p/∂v| du dv over [0, 1]², by 4-point Gauss–Legendre on each of 4 × 4
    /// cells (exact for parallelograms, where the integrand is constant).
    fn compute_area(&self) -> f32 {
        const CELLS: usize = 4;
        let h = 1.0 / CELLS as f64;
        let mut sum = 0.0f64;
        let corners = self.corners();
        for ci in 0..CELLS {
            for cj in 0..CELLS {
                for &(xu, wu) in &GAUSS4 {
                    for &(xv, wv) in &GAUSS4 {
                        let u = (ci as f64 + xu) * h;
                        let v = (cj as f64 + xv) * h;
                        sum += wu * wv * jacobian(&corners, u as f32, v as f32) as f64;
                    }
                }
            }
        }
        (sum * h * h) as f32
    }

    /// The corners, unpacked for computing.
    #[inline]
    pub fn corners(&self) -> [Vec3; 4] {
        self.p.map(Vec3::from)
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        self.area
    }

    /// World-space bounds: the box of the corners (the patch lies in their convex hull).
    pub fn bounds(&self) -> Bounds3 {
        let [p00, p10, p01, p11] = self.corners();
        Bounds3::from_point(p00)
            .union_point(p10)
            .union_point(p01)
            .union_point(p11)
    }

    /// Nearest hit (see [`intersect_bilinear`]); (u, v) are kept for the interaction.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (t, u, v) = intersect_bilinear(ray, &self.corners())?;
        Some(ShapeHit { t, u, v })
    }

    /// Full interaction, with pbrt's conventions: p = p(u, v) with error ≤ γ₆·Σ|pᵢⱼ|; ∂p/∂u,
    /// ∂p/∂v of the patch, or with vertex uvs (s, t) the derivatives with respect to them
    /// (∂p/∂s = ∂p/∂u·∂u/∂s + ∂p/∂v·∂v/∂s, …, turned to keep the side of ∂p/∂u × ∂p/∂v);
    /// n = normalize(∂p/∂u × ∂p/∂v), flipped by reverse orientation / handedness, or turned to
    /// the side of the interpolated vertex normal when there is one.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (u, v) = (hit.u, hit.v);
        let mesh = &*self.mesh;
        let vi = mesh.vertices(self.index);
        let corners = self.corners();
        let p = bilinear_point(&corners, u, v);
        let (mut dpdu, mut dpdv) = partials(&corners, u, v);
        let mut uv = Vec2::new(u, v);
        if !mesh.uvs.is_empty() {
            let (st, [duds, dvds, dudt, dvdt]) = st_at(vi.map(|i| mesh.uvs[i]), u, v);
            uv = st;
            let dpds = dpdu * duds + dpdv * dvds;
            let mut dpdt = dpdu * dudt + dpdv * dvdt;
            let n_st = cross(dpds, dpdt);
            if n_st != Vec3::ZERO {
                if cross(dpdu, dpdv).dot(n_st) < 0.0 {
                    dpdt = -dpdt;
                }
                dpdu = dpds;
                dpdv = dpdt;
            }
        }
        let mut n = cross(dpdu, dpdv).normalize_or_zero();
        if n == Vec3::ZERO {
            // A corner where two edges are parallel: the normal of the whole patch.
            let (du, dv) = partials(&corners, 0.5, 0.5);
            n = cross(du, dv).normalize_or_zero();
        }
        let mut ns = n;
        if let Some(s) = self.shading_normal(u, v) {
            ns = s;
            if n.dot(ns) < 0.0 {
                n = -n;
            }
        } else if mesh.flip_normal {
            n = -n;
            ns = n;
        }
        // Shading tangents: ∂p/∂u made perpendicular to the shading normal.
        let mut ss = dpdu.normalize_or_zero();
        let mut ts = cross(ns, ss);
        if ts.length_squared() > 0.0 {
            ss = cross(ts, ns);
        } else {
            let f = Frame::from_z(ns);
            ss = f.x;
            ts = f.y;
        }
        let p_error = gamma(6) * corners.iter().map(|q| q.abs()).sum::<Vec3>();
        SurfaceInteraction {
            p,
            p_error,
            n,
            uv,
            dpdu,
            dpdv,
            shading: Shading {
                n: ns,
                dpdu: ss,
                dpdv: ts,
            },
            wo: -normalize(ray.d),
            t: hit.t,
            time: 0.0,
        }
    }

    /// pbrt-v4's shading derivatives of the hit `hit` whose interaction is `si` (its
    /// `BilinearPatch::InteractionFromIntersection`). Without vertex normals: the geometric
    /// ∂p/∂u, ∂p/∂v (with respect to (s, t) when the mesh has uvs) and ∂n/∂u, ∂n/∂v by the
    /// Weingarten equations (`weingarten`) with ∂²p/∂u² = ∂²p/∂v² = 0 and
    /// ∂²p/∂u∂v = p₀₀ − p₀₁ + p₁₁ − p₁₀. With them: ∂n/∂u = lerp(v, n₁₀, n₁₁) − lerp(v, n₀₀, n₀₁),
    /// ∂n/∂v = lerp(u, n₀₁, n₁₁) − lerp(u, n₀₀, n₁₀), and ∂p/∂u, ∂p/∂v turned by the rotation
    /// taking the geometric normal (flipped by the mesh's orientation) to the shading one
    /// ([`rotate_from_to`]). Either way ∂n/∂s = ∂n/∂u·∂u/∂s + ∂n/∂v·∂v/∂s and
    /// ∂n/∂t = ∂n/∂u·∂u/∂t + ∂n/∂v·∂v/∂t with uvs.
    pub fn shading_derivatives(
        &self,
        hit: &ShapeHit,
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        let (u, v) = (hit.u, hit.v);
        let mesh = &*self.mesh;
        let vi = mesh.vertices(self.index);
        let [duds, dvds, dudt, dvdt] = if mesh.uvs.is_empty() {
            [1.0, 0.0, 0.0, 1.0]
        } else {
            st_at(vi.map(|i| mesh.uvs[i]), u, v).1
        };
        let (dpdu, dpdv) = (si.dpdu, si.dpdv);
        let shading_normal = self.shading_normal(u, v);
        let (dndu, dndv) = if shading_normal.is_some() {
            let [n00, n10, n01, n11] = vi.map(|i| mesh.normal(i));
            (
                n10.lerp(n11, v) - n00.lerp(n01, v),
                n01.lerp(n11, u) - n00.lerp(n10, u),
            )
        } else {
            let [p00, p10, p01, p11] = self.corners();
            let d2pduv = (p00 - p01) + (p11 - p10);
            weingarten(dpdu, dpdv, Vec3::ZERO, d2pduv, Vec3::ZERO)
        };
        let (dndu, dndv) = (dndu * duds + dndv * dvds, dndu * dudt + dndv * dvdt);
        let (dpdu, dpdv) = match shading_normal {
            Some(ns) => {
                let n = cross(dpdu, dpdv).try_normalize().unwrap_or(si.n);
                let n = if mesh.flip_normal { -n } else { n };
                let r = rotate_from_to(n, ns);
                let turn = |x: Vec3| Vec3::new(r[0].dot(x), r[1].dot(x), r[2].dot(x));
                (turn(dpdu), turn(dpdv))
            }
            None => (dpdu, dpdv),
        };
        ShadingDerivatives {
            dpdu,
            dpdv,
            dndu,
            dndv,
        }
    }

    /// The interpolated vertex normal at (u, v), normalised, if the mesh has normals.
    fn shading_normal(&self, u: f32, v: f32) -> Option<Vec3> {
        let mesh = &*self.mesh;
        if mesh.normals.is_empty() {
            return None;
        }
        let [n00, n10, n01, n11] = mesh.vertices(self.index).map(|i| mesh.normal(i));
        n00.lerp(n01, v).lerp(n10.lerp(n11, v), u).try_normalize()
    }

    /// The geometric normal at (u, v), oriented as [`BilinearPatch::interaction`] orients it.
    pub fn normal_at(&self, u: f32, v: f32) -> Vec3 {
        let corners = self.corners();
        let (du, dv) = partials(&corners, u, v);
        let mut n = cross(du, dv).normalize_or_zero();
        if n == Vec3::ZERO {
            let (du, dv) = partials(&corners, 0.5, 0.5);
            n = cross(du, dv).normalize_or_zero();
        }
        match self.shading_normal(u, v) {
            Some(ns) if n.dot(ns) < 0.0 => -n,
            Some(_) => n,
            None if self.mesh.flip_normal => -n,
            None => n,
        }
    }

    /// A point uniform by area, and its (u, v). Uniform (u, v) has area density 1/J(u, v)
    /// with J = |∂p/∂u × ∂p/∂v|, so (u, v) is drawn uniformly and kept with probability
    /// J(u, v)/J_max (rejection sampling; J_max is a corner's J, J being convex): the kept
    /// (u, v) has density J/A, i.e. uniform by area. The first candidate is `u` itself;
    /// later candidates and the acceptance draws come from a hash of `u`. Parallelograms
    /// (J constant) accept at once.
    pub fn sample_uv(&self, u: Vec2) -> (Vec3, Vec2) {
        // N(u, v) = ∂p/∂u × ∂p/∂v = N₀₀ + u·(N₁₀ − N₀₀) + v·(N₀₁ − N₀₀) (linear); J = |N| is
        // convex, so J_max is a corner's. J is constant only when N is (a parallelogram).
        let corners = self.corners();
        let n_at = |u: f32, v: f32| {
            let (du, dv) = partials(&corners, u, v);
            cross(du, dv)
        };
        let (n00, n10, n01, n11) = (
            n_at(0.0, 0.0),
            n_at(1.0, 0.0),
            n_at(0.0, 1.0),
            n_at(1.0, 1.0),
        );
        let j_max = n00
            .length()
            .max(n10.length())
            .max(n01.length())
            .max(n11.length());
        let constant = (n10 - n00).length() + (n01 - n00).length() <= 1e-6 * j_max;
        let mut cand = u;
        if j_max > 0.0 && !constant {
            let seed = ((u.x.to_bits() as u64) << 32) | u.y.to_bits() as u64;
            for k in 0..256u64 {
                let r = hash_pair(seed, 2 * k);
                if r.x * j_max <= jacobian(&corners, cand.x, cand.y) {
                    break;
                }
                cand = hash_pair(seed, 2 * k + 1);
            }
        }
        (bilinear_point(&corners, cand.x, cand.y), cand)
    }
}

/// Two numbers in [0, 1) from a seed and a counter, by the renderer's hash.
fn hash_pair(seed: u64, k: u64) -> Vec2 {
    use crate::sampling::{hash_u64, u32_to_unit_f32};
    let h = hash_u64(&[seed, k]);
    Vec2::new(u32_to_unit_f32(h as u32), u32_to_unit_f32((h >> 32) as u32))
}

/// Ray ∩ bilinear patch (corners p₀₀, p₁₀, p₀₁, p₁₁), exactly, in double precision:
/// the nearest (t, u, v) with ε < t < t_max, (u, v) ∈ [0, 1]².
///
/// With e₁₀ = p₁₀ − p₀₀, the triple product f(u) = (a(u) − o)·(d × (b(u) − a(u))) is the
/// quadratic A·u² + B·u + C with
///   A = (e₁₀ × (p₀₁ − p₁₁))·d,  C = ((p₀₀ − o) × d)·(p₀₁ − p₀₀),
///   B = ((p₁₀ − o) × d)·(p₁₁ − p₁₀) − A − C   (so that f(1) = A + B + C).
/// For each root u in [0, 1], with Δ = a(u) − o, q = b(u) − a(u) and n = d × q, the closest
/// points of the ray and the segment give v = det[Δ, d, n]/|n|², t = det[Δ, q, n]/|n|².
/// ε = γ₁₀·(max|o| + max|d| + Σ max|pᵢⱼ|), pbrt's bound, keeps rays leaving the patch off it.
pub fn intersect_bilinear(ray: &Ray, p: &[Vec3; 4]) -> Option<(f32, f32, f32)> {
    let [p00, p10, p01, p11] = p.map(|q| q.as_dvec3());
    let o = ray.o.as_dvec3();
    let d = ray.d.as_dvec3();
    let a = (p10 - p00).cross(p01 - p11).dot(d);
    let c = (p00 - o).cross(d).dot(p01 - p00);
    let b = (p10 - o).cross(d).dot(p11 - p10) - a - c;
    let (u1, u2) = solve_quadratic(a, b, c)?;
    let eps = gamma(10) as f64
        * (ray.o.abs().max_element()
            + ray.d.abs().max_element()
            + p.iter().map(|q| q.abs().max_element()).sum::<f32>()) as f64;
    let t_max = ray.t_max as f64;
    let mut best: Option<(f64, f64, f64)> = None;
    let det = |x: DVec3, y: DVec3, z: DVec3| x.dot(y.cross(z));
    for (i, u) in [u1, u2].into_iter().enumerate() {
        if !(0.0..=1.0).contains(&u) || (i == 1 && u2 == u1) {
            continue;
        }
        let uo = p00.lerp(p10, u);
        let q = p01.lerp(p11, u) - uo;
        let delta = uo - o;
        let n = d.cross(q);
        let n2 = n.length_squared();
        if n2 == 0.0 {
            continue;
        }
        let v = det(delta, d, n) / n2;
        let t = det(delta, q, n) / n2;
        if !(0.0..=1.0).contains(&v) || t <= eps || t >= t_max {
            continue;
        }
        if best.is_none_or(|(bt, _, _)| t < bt) {
            best = Some((t, u, v));
        }
    }
    let (t, u, v) = best?;
    let tf = t as f32;
    (tf > 0.0 && tf < ray.t_max).then_some((tf, u as f32, v as f32))
}

/// pbrt's `bilinearmesh` as a scene gives it, shared by its copies.
impl GeometryKind for Arc<BilinearMesh> {
    type Prim = Box<BilinearPatch>;

    fn pbrt_name(&self) -> &'static str {
        "bilinearmesh"
    }

    /// Its indices and arrays consistent ([`IndexedMesh::check`]).
    fn validate(&self) -> Result<(), RuleError> {
        self.check()
    }

    fn is_mesh(&self) -> bool {
        true
    }

    /// The mesh moved to the world once, shared by its patches.
    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<BilinearPatch>>,
    ) -> Result<(), String> {
        let world = Arc::new(self.transformed(&at.to_world, at.reverse_orientation));
        out.extend(BilinearMesh::patches(&world).into_iter().map(Box::new));
        Ok(())
    }
}

impl ShapeKind for BilinearPatch {
    fn bounds(&self) -> Bounds3 {
        BilinearPatch::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        BilinearPatch::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        BilinearPatch::interaction(self, ray, hit)
    }

    fn shading_derivatives(
        &self,
        _: &Ray,
        hit: &ShapeHit,
        _: &[TriangleMesh],
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        BilinearPatch::shading_derivatives(self, hit, si)
    }

    /// A = ∫∫ |∂p/∂u × ∂p/∂v| du dv ([`BilinearPatch::area`]).
    fn area(&self) -> f32 {
        BilinearPatch::area(self)
    }

    /// [`BilinearPatch::sample_uv`], with the normal the intersection gives there.
    fn sample_area(&self, u: Vec2, _: &[TriangleMesh]) -> Option<ShapeSample> {
        let (p, uv) = self.sample_uv(u);
        Some(ShapeSample {
            p,
            n: self.normal_at(uv.x, uv.y),
        })
    }

    /// The mesh its patches share, once.
    fn held_bytes(&self, seen: &mut HashSet<usize>) -> HeldBytes {
        let mesh = Arc::as_ptr(&self.mesh) as usize;
        HeldBytes {
            primitive: 0,
            meshes: if seen.insert(mesh) {
                self.mesh.heap_bytes()
            } else {
                0
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh_of(p: [Vec3; 4]) -> Arc<BilinearMesh> {
        Arc::new(BilinearMesh {
            positions: p.map(PackedVec3::from).to_vec(),
            indices: vec![0, 1, 2, 3],
            ..Default::default()
        })
    }

    #[test]
    fn unit_square_hits_and_uv() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
        ];
        let patch = BilinearPatch::new(p.map(PackedVec3::from), mesh_of(p), 0);
        assert!((patch.area() - 2.0).abs() < 1e-6);
        let r = Ray::new(Vec3::new(0.5, 0.25, 3.0), -Vec3::Z);
        let h = patch.intersect(&r).unwrap();
        assert!((h.t - 3.0).abs() < 1e-6);
        assert!((h.u - 0.25).abs() < 1e-6 && (h.v - 0.25).abs() < 1e-6);
        let si = patch.interaction(&r, &h);
        // n = ∂p/∂u × ∂p/∂v = (2, 0, 0) × (0, 1, 0) ∝ +z.
        assert!((si.n - Vec3::Z).length() < 1e-6);
        assert!((si.p - Vec3::new(0.5, 0.25, 0.0)).length() < 1e-6);
        assert!(
            patch
                .intersect(&Ray::new(Vec3::new(2.5, 0.5, 3.0), -Vec3::Z))
                .is_none()
        );
        assert!(
            patch
                .intersect(&Ray::new(Vec3::new(0.5, 0.5, -3.0), -Vec3::Z))
                .is_none()
        );
        let short = Ray { t_max: 2.0, ..r };
        assert!(patch.intersect(&short).is_none());
    }

    #[test]
    fn hyperbolic_paraboloid_area() {
        // z = xy over the unit square: A = ∫∫ √(1 + x² + y²) dx dy = 1.28079…
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
        ];
        let patch = BilinearPatch::new(p.map(PackedVec3::from), mesh_of(p), 0);
        assert!(
            (patch.area() - 1.280_789_3).abs() < 1e-5,
            "{}",
            patch.area()
        );
    }

    #[test]
    fn saddle_hit_point_and_normal() {
        // The patch p(u, v) = (u, v, uv): from (½, ½, 5) down, z = ¼ at t = 4.75, (u, v) = (½, ½).
        // n ∝ ∂p/∂u × ∂p/∂v = (1, 0, v) × (0, 1, u) = (−v, −u, 1) = (−½, −½, 1)/√1.5.
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
        ];
        let patch = BilinearPatch::new(p.map(PackedVec3::from), mesh_of(p), 0);
        let r = Ray::new(Vec3::new(0.5, 0.5, 5.0), -Vec3::Z);
        let h = patch.intersect(&r).unwrap();
        assert!((h.t - 4.75).abs() < 1e-5, "t {}", h.t);
        let si = patch.interaction(&r, &h);
        assert!((si.p - Vec3::new(0.5, 0.5, 0.25)).length() < 1e-5);
        assert!((si.uv - Vec2::splat(0.5)).length() < 1e-5);
        let want = Vec3::new(-0.5, -0.5, 1.0) / 1.5f32.sqrt();
        assert!((si.n - want).length() < 1e-5, "{}", si.n);
        // The sampler's normal at the same (u, v) agrees.
        assert!((patch.normal_at(0.5, 0.5) - want).length() < 1e-5);
    }
}
