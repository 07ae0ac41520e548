//! ∂n/∂u and ∂n/∂v of every curved shape against finite differences of its normal, and the
//! triangles' from their vertex normals (what a bump map reads, pbrt-v4's).

use super::*;
use crate::math::{Vec2, cross, normalize};
use crate::shape::{
    BilinearMesh, Cone, Cylinder, Hyperboloid, Paraboloid, Placement, Sphere,
    triangle_normal_derivatives, triangle_shading_derivatives,
};

/// Asserts that `shape`'s ∂n/∂u, ∂n/∂v where `ray` hits it agree with finite differences of
/// its normal: the hits n± of rays aimed along −n at p ± h·∂p/∂u/|∂p/∂u| (then along ∂p/∂v)
/// must differ by ∂n/∂u·Δu + ∂n/∂v·Δv, (Δu, Δv) the difference of the hits' own (u, v),
/// within `tol` of |∂n/∂u·Δu| + |∂n/∂v·Δv| (and 2·10⁻⁶ for the rounding of the normals).
/// Also returns the derivatives.
#[track_caller]
fn assert_normal_derivatives(shape: &Shape, ray: &Ray, h: f32, tol: f32) -> ShadingDerivatives {
    let hit = shape.intersect(ray).expect("a hit");
    let si = shape.interaction(ray, &hit, &[]);
    let sd = shape.shading_derivatives(ray, &hit, &[], &si);
    // Without vertex normals pbrt-v4's shading tangents are the geometric ones.
    assert_eq!((sd.dpdu, sd.dpdv), (si.dpdu, si.dpdv));
    let at = |q: Vec3| {
        let r = Ray::new(q + 0.05 * si.n, -si.n);
        let hq = shape.intersect(&r).expect("a hit beside");
        shape.interaction(&r, &hq, &[])
    };
    let mut turned = 0.0;
    for t in [si.dpdu, si.dpdv] {
        let step = h * normalize(t);
        let (a, b) = (at(si.p + step), at(si.p - step));
        let (dn, duv) = (a.n - b.n, a.uv - b.uv);
        let want = sd.dndu * duv.x + sd.dndv * duv.y;
        let scale = (sd.dndu * duv.x).length() + (sd.dndv * duv.y).length();
        assert!(
            (dn - want).length() <= tol * scale + 2e-6,
            "Δn {dn} but ∂n/∂u·Δu + ∂n/∂v·Δv = {want} (Δuv {duv})"
        );
        turned += dn.length();
    }
    assert!(turned > 0.1 * h, "the normal hardly turns: {turned}");
    sd
}

/// A rotation about (1, 2, 3) by 40° after a move by (0.5, −1, 2): rigid, so that the world
/// normal's derivatives are the object's turned (pbrt-v4 moves them by (M⁻¹)ᵀ, which for a
/// scaled shape is not the derivative of the unit world normal).
fn placed() -> Placement {
    let m = Transform::translate(Vec3::new(0.5, -1.0, 2.0))
        * Transform::rotate(40.0, Vec3::new(1.0, 2.0, 3.0)).unwrap();
    Placement::new(m, false)
}

/// The ray from `o` towards `target` (both object space), moved to the world by `pl`.
fn ray_at(pl: &Placement, o: Vec3, target: Vec3) -> Ray {
    let (o, t) = (pl.to_world.point(o), pl.to_world.point(target));
    Ray::new(o, t - o)
}

#[test]
fn sphere_normals_turn_as_their_finite_differences() {
    let pl = placed();
    let s = Shape::Sphere(Box::new(Sphere::new(pl, 1.5, -1.2, 1.4, 300.0)));
    let sd = assert_normal_derivatives(
        &s,
        &ray_at(&pl, Vec3::new(3.0, 2.0, 1.0), Vec3::ZERO),
        1e-3,
        5e-3,
    );
    // On a sphere n = p/r: ∂n/∂u = ∂p/∂u / r exactly (the placement is rigid).
    let want = sd.dpdu / 1.5;
    assert!((sd.dndu - want).length() < 1e-4 * want.length());
}

#[test]
fn cylinder_normals_turn_around_the_axis_only() {
    let pl = placed();
    let c = Shape::Cylinder(Box::new(Cylinder::new(pl, 0.7, -1.0, 2.0, 270.0)));
    let sd = assert_normal_derivatives(
        &c,
        &ray_at(&pl, Vec3::new(2.0, 1.5, 0.3), Vec3::new(0.0, 0.0, 0.3)),
        1e-3,
        5e-3,
    );
    // Along the axis the normal does not turn.
    assert!(sd.dndv.length() < 1e-5, "{}", sd.dndv);
    assert!((sd.dndu.length() - sd.dpdu.length() / 0.7).abs() < 1e-4 * sd.dndu.length());
}

#[test]
fn cone_paraboloid_and_hyperboloid_normals_turn_as_their_finite_differences() {
    let pl = placed();
    let hyper = Hyperboloid::new(
        pl,
        Vec3::new(1.0, 0.0, -1.0),
        Vec3::new(0.3, 0.8, 1.0),
        330.0,
    )
    .unwrap();
    let cases = [
        (
            Shape::Cone(Box::new(Cone::new(pl, 1.0, 1.5, 330.0))),
            Vec3::new(0.3, 0.0, 0.6),
        ),
        (
            Shape::Paraboloid(Box::new(Paraboloid::new(pl, 1.0, 0.1, 1.0, 330.0))),
            Vec3::new(0.0, 0.0, 0.5),
        ),
        (
            Shape::Hyperboloid(Box::new(hyper)),
            Vec3::new(0.0, 0.0, 0.2),
        ),
    ];
    for (shape, target) in cases {
        let o = target + Vec3::new(2.0, 1.6, 0.1);
        assert_normal_derivatives(&shape, &ray_at(&pl, o, target), 1e-3, 1e-2);
    }
}

#[test]
fn bilinear_patch_normals_turn_as_their_finite_differences() {
    // A saddle: z = x·y over [0, 1]².
    let corners = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 1.0),
    ];
    let patch = |uvs: Vec<Vec2>| {
        let mesh = std::sync::Arc::new(BilinearMesh {
            positions: corners.map(PackedVec3::from).to_vec(),
            uvs,
            indices: vec![0, 1, 2, 3],
            ..BilinearMesh::default()
        });
        Shape::Bilinear(Box::new(BilinearMesh::patches(&mesh).remove(0)))
    };
    let ray = Ray::new(Vec3::new(0.4, 0.7, 2.0), -Vec3::Z);
    let plain = assert_normal_derivatives(&patch(vec![]), &ray, 1e-3, 1e-2);
    // With (s, t) = (2u, 3v) pbrt-v4 takes e, f, g of (u, v) with E, F, G of (s, t) and then
    // applies the change to (s, t) again: its ∂n/∂s = (b/a)·∂n/∂u and ∂n/∂t = (a/b)·∂n/∂v for
    // s = a·u, t = b·v, where the surface's own are ∂n/∂u/a and ∂n/∂v/b. lancer's are pbrt-v4's.
    let st = patch(vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(2.0, 0.0),
        Vec2::new(0.0, 3.0),
        Vec2::new(2.0, 3.0),
    ]);
    let hit = st.intersect(&ray).unwrap();
    let si = st.interaction(&ray, &hit, &[]);
    let sd = st.shading_derivatives(&ray, &hit, &[], &si);
    assert!(
        (sd.dndu - plain.dndu * 1.5).length() < 1e-5,
        "{} vs {}",
        sd.dndu,
        plain.dndu
    );
    assert!((sd.dndv - plain.dndv * (2.0 / 3.0)).length() < 1e-5);
    assert!((sd.dpdu - plain.dpdu / 2.0).length() < 1e-6);
}

/// b₀x₀ + b₁x₁ + b₂x₂ with b₀ = 1 − b₁ − b₂: a vertex attribute interpolated at (b₁, b₂).
fn lerp3<T: std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T> + Copy>(
    x: [T; 3],
    b1: f32,
    b2: f32,
) -> T {
    x[0] * (1.0 - b1 - b2) + x[1] * b1 + x[2] * b2
}

#[test]
fn triangle_normals_turn_as_their_vertex_normals_interpolate() {
    // Vertex normals of a curved patch, and (u, v) of the vertices (or pbrt's default ones).
    let n = [
        Vec3::new(0.0, 0.0, 1.0),
        normalize(Vec3::new(0.4, 0.0, 0.9)),
        normalize(Vec3::new(-0.1, 0.5, 0.8)),
    ];
    let uv = [
        Vec2::new(0.1, 0.2),
        Vec2::new(0.9, 0.3),
        Vec2::new(0.4, 1.1),
    ];
    let default_uv = [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::ONE];
    for (uvs, corners) in [(Some(uv), uv), (None, default_uv)] {
        let (dndu, dndv) = triangle_normal_derivatives(n, uvs);
        // The interpolated normal is linear in (b₁, b₂), and so in (u, v): any difference
        // of two points is ∂n/∂u·Δu + ∂n/∂v·Δv exactly.
        for (a, b) in [((0.2, 0.3), (0.5, 0.1)), ((0.0, 0.0), (0.3, 0.6))] {
            let dn = lerp3(n, a.0, a.1) - lerp3(n, b.0, b.1);
            let duv = lerp3(corners, a.0, a.1) - lerp3(corners, b.0, b.1);
            let want = dndu * duv.x + dndv * duv.y;
            assert!((dn - want).length() < 1e-5, "{dn} vs {want}");
        }
    }
    // Without (u, v): ∂n/∂u = n₁ − n₀ and ∂n/∂v = n₂ − n₁, as ∂p/∂u = p₁ − p₀.
    let (dndu, dndv) = triangle_normal_derivatives(n, None);
    assert!((dndu - (n[1] - n[0])).length() < 1e-6 && (dndv - (n[2] - n[1])).length() < 1e-6);
    // Equal normals do not turn; a degenerate (u, v) with them neither.
    let flat = [Vec3::Z; 3];
    assert_eq!(
        triangle_normal_derivatives(flat, None),
        (Vec3::ZERO, Vec3::ZERO)
    );
    assert_eq!(
        triangle_normal_derivatives(flat, Some([Vec2::ZERO; 3])),
        (Vec3::ZERO, Vec3::ZERO)
    );
}

#[test]
fn triangle_shading_tangents_are_pbrts() {
    // A hit on the triangle (0, 0, 0), (2, 0, 0), (0, 2, 0) (∂p/∂u = (2, 0, 0) for pbrt's
    // default (u, v)): with vertex normals the tangents are s = (n_s × ∂p/∂u) × n_s and
    // t = n_s × ∂p/∂u, of ∂p/∂u's length when n_s ⟂ ∂p/∂u; without, the geometric ones.
    let p = [
        Vec3::ZERO,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    ];
    let ray = Ray::new(Vec3::new(0.5, 0.5, 1.0), -Vec3::Z);
    let hit = intersect_triangle(&ray, p[0], p[1], p[2]).unwrap();
    let si = triangle_interaction(&ray, &hit, p, None, None, false);
    let sd = triangle_shading_derivatives(&si, None, None);
    assert_eq!((sd.dpdu, sd.dpdv), (si.dpdu, si.dpdv));
    assert_eq!((sd.dndu, sd.dndv), (Vec3::ZERO, Vec3::ZERO));
    let n = [Vec3::Z, Vec3::new(0.0, 0.6, 0.8), Vec3::Z];
    let si = triangle_interaction(&ray, &hit, p, Some(n), None, false);
    let sd = triangle_shading_derivatives(&si, Some(n), None);
    let ns = si.shading.n;
    assert!(sd.dpdu.dot(ns).abs() < 1e-6 && sd.dpdv.dot(ns).abs() < 1e-6);
    assert!((sd.dpdv - cross(ns, si.dpdu)).length() < 1e-6);
    assert!((sd.dpdu.length() - 2.0).abs() < 1e-5, "{}", sd.dpdu);
    // The same directions as lancer's unit shading frame.
    assert!((normalize(sd.dpdu) - si.shading.dpdu).length() < 1e-5);
    assert!((normalize(sd.dpdv) - si.shading.dpdv).length() < 1e-5);
    assert_eq!(sd.dndu, n[1] - n[0]);
}
