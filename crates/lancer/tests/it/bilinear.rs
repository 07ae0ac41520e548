//! Bilinear patches through the whole scene: hits lie on the patch (the (u, v) found again by
//! Newton's method from the hit point), agree with a fine triangle tessellation, carry the
//! normal ∂p/∂u × ∂p/∂v with pbrt's orientation rules; areas are right and area sampling is
//! uniform by area (chi-square) on the surface.

use crate::common;

use crate::common::shapes::uniform3;

use crate::common::chi2::{chi2_survival, pooled_chi2, sidak};
use lancer::Scene;
use lancer::math::{PackedVec3, Transform, Vec2, Vec3, cross, normalize};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::Geometry;
use lancer::shape::{BilinearMesh, bilinear_point, intersect_triangle};
use std::sync::Arc;

/// Test patches (p₀₀, p₁₀, p₀₁, p₁₁), written independently of the shape code.
fn patches() -> Vec<(&'static str, [Vec3; 4])> {
    vec![
        (
            "saddle z = xy",
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(1.0, 1.0, 1.0),
            ],
        ),
        (
            "skew",
            [
                Vec3::new(-1.0, -0.5, 0.2),
                Vec3::new(1.2, -0.8, -0.3),
                Vec3::new(-0.7, 1.1, 0.5),
                Vec3::new(0.9, 1.3, -0.6),
            ],
        ),
        (
            "strong twist",
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(0.0, 1.0, 1.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
        ),
        (
            "planar rectangle",
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(2.0, 0.0, 1.0),
            ],
        ),
        (
            "planar trapezoid",
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.5, 1.0, 0.0),
                Vec3::new(1.2, 1.0, 0.0),
            ],
        ),
        (
            "triangle (p₁₀ = p₁₁)",
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.5, 0.3),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(1.0, 0.5, 0.3),
            ],
        ),
    ]
}

fn mesh(p: [Vec3; 4], normals: Vec<Vec3>) -> BilinearMesh {
    BilinearMesh {
        positions: p.map(PackedVec3::from).to_vec(),
        normals: normals.into_iter().map(PackedVec3::from).collect(),
        uvs: vec![],
        indices: vec![0, 1, 2, 3],
        flip_normal: false,
    }
}

fn scene_of(m: BilinearMesh, to_world: Transform, reverse: bool) -> Scene {
    common::shapes::scene_of(Geometry::BilinearMesh(Arc::new(m)), to_world, reverse)
}

/// p(u, v) and its partial derivatives, in double precision, from the definition
/// p = (1−u)(1−v)p₀₀ + u(1−v)p₁₀ + (1−u)v p₀₁ + uv p₁₁.
fn eval(p: &[Vec3; 4], u: f64, v: f64) -> (glam::DVec3, glam::DVec3, glam::DVec3) {
    let [a, b, c, d] = p.map(|q| q.as_dvec3());
    let pt = (1.0 - u) * (1.0 - v) * a + u * (1.0 - v) * b + (1.0 - u) * v * c + u * v * d;
    let du = (1.0 - v) * (b - a) + v * (d - c);
    let dv = (1.0 - u) * (c - a) + u * (d - b);
    (pt, du, dv)
}

/// The (u, v) whose p(u, v) is nearest to x, by Gauss–Newton from a 3 × 3 grid of starts:
/// (u, v, residual).
fn invert(p: &[Vec3; 4], x: Vec3) -> (f64, f64, f64) {
    let x = x.as_dvec3();
    let mut best = (0.0, 0.0, f64::INFINITY);
    for s in 0..9 {
        let (mut u, mut v) = (0.1 + 0.4 * (s % 3) as f64, 0.1 + 0.4 * (s / 3) as f64);
        for _ in 0..30 {
            let (pt, du, dv) = eval(p, u, v);
            let r = x - pt;
            // Normal equations of min |r − du·δu − dv·δv|².
            let (a, b, c) = (du.dot(du), du.dot(dv), dv.dot(dv));
            let (e, f) = (du.dot(r), dv.dot(r));
            let det = a * c - b * b;
            if det.abs() < 1e-300 {
                break;
            }
            let (su, sv) = ((c * e - b * f) / det, (a * f - b * e) / det);
            u += su;
            v += sv;
            if su.abs() + sv.abs() < 1e-13 {
                break;
            }
        }
        let res = (eval(p, u, v).0 - x).length();
        if res < best.2 {
            best = (u, v, res);
        }
        if best.2 < 1e-9 {
            break;
        }
    }
    best
}

/// A ray from a random point 4 units away towards a random point near the patch.
fn random_ray(rng: &mut Pcg32, p: &[Vec3; 4]) -> Ray {
    let (u, v) = (rng.uniform() * 1.2 - 0.1, rng.uniform() * 1.2 - 0.1);
    let target = bilinear_point(p, u, v) + uniform3(rng, -0.05, 0.05);
    let o = target + uniform3(rng, -1.0, 1.0).normalize_or_zero() * 4.0;
    Ray::new(o, normalize(target - o))
}

/// Every hit is on the patch: the (u, v) recovered by Newton from the hit point gives back
/// that point and lies in [0, 1]²; the point is on the ray at t; the geometric normal is
/// normalize(∂p/∂u × ∂p/∂v) there (no normals, no reverse orientation: that very sign).
#[test]
fn hits_satisfy_the_patch_equation_and_normals_are_the_cross_product() {
    for (name, p) in patches() {
        let scene = scene_of(mesh(p, vec![]), Transform::IDENTITY, false);
        let mut rng = Pcg32::new(1, 17);
        let mut hits = 0;
        for i in 0..3000 {
            let ray = random_ray(&mut rng, &p);
            let Some(h) = scene.intersect(&ray) else {
                continue;
            };
            hits += 1;
            let si = h.si;
            assert!(
                (ray.at(si.t) - si.p).length() < 1e-4,
                "{name} {i}: off the ray"
            );
            let (u, v, res) = invert(&p, si.p);
            assert!(res < 1e-4, "{name} {i}: {} is {res} off the patch", si.p);
            let e = 1e-4;
            assert!(
                (-e..=1.0 + e).contains(&u) && (-e..=1.0 + e).contains(&v),
                "{name} {i}: (u, v) = ({u}, {v})"
            );
            assert!((si.uv - Vec2::new(u as f32, v as f32)).length() < 1e-3);
            let (_, du, dv) = eval(&p, u, v);
            let n = du.cross(dv);
            if n.length() > 1e-3 {
                let n = n.normalize().as_vec3a();
                assert!((si.n - n).length() < 1e-3, "{name} {i}: n {} vs {n}", si.n);
            }
        }
        assert!(hits > 800, "{name}: {hits} hits");
    }
}

/// Hits agree with those of a 64 × 64 tessellation into triangles (an independent
/// intersection routine): same hit or miss, t within the facets' distance to the patch, except for rays crossing within
/// 1e-3 of the patch's border or grazing it (|cos| < 0.02).
#[test]
fn hits_agree_with_a_fine_tessellation() {
    const N: usize = 64;
    for (name, p) in patches() {
        let scene = scene_of(mesh(p, vec![]), Transform::IDENTITY, false);
        let grid =
            |i: usize, j: usize| bilinear_point(&p, i as f32 / N as f32, j as f32 / N as f32);
        let mut tris = Vec::new();
        for i in 0..N {
            for j in 0..N {
                let (a, b, c, d) = (
                    grid(i, j),
                    grid(i + 1, j),
                    grid(i, j + 1),
                    grid(i + 1, j + 1),
                );
                tris.push([a, b, d]);
                tris.push([a, d, c]);
            }
        }
        let mut rng = Pcg32::new(2, 29);
        let (mut agree, mut excused) = (0, 0);
        for i in 0..1500 {
            let ray = random_ray(&mut rng, &p);
            let tess = tris
                .iter()
                .filter_map(|t| intersect_triangle(&ray, t[0], t[1], t[2]).map(|h| (h.t, t)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let exact = scene.intersect(&ray);
            let near_border = |x: Vec3| {
                let (u, v, _) = invert(&p, x);
                u.min(v) < 1e-3 || u.max(v) > 1.0 - 1e-3
            };
            let grazing = |n: Vec3| n.normalize_or_zero().dot(ray.d).abs() < 0.02;
            match (&exact, tess) {
                (None, None) => agree += 1,
                (Some(h), Some((t, _))) => {
                    // The facets stand off the patch by at most |p₁₁ − p₁₀ − p₀₁ + p₀₀|/(4N²)
                    // (2 here), which moves t by that over |cos θ|.
                    let cos = h.si.n.dot(ray.d).abs().max(1e-3);
                    if (h.si.t - t).abs() < 1e-5 + 2.0 / (4.0 * (N * N) as f32) / cos {
                        agree += 1;
                    } else {
                        assert!(grazing(h.si.n), "{name} {i}: t {} vs {t}", h.si.t);
                        excused += 1;
                    }
                }
                (Some(h), None) => {
                    assert!(
                        near_border(h.si.p) || grazing(h.si.n),
                        "{name} {i}: hit at uv {} missed by the tessellation",
                        h.si.uv
                    );
                    excused += 1;
                }
                (None, Some((t, tri))) => {
                    let n = cross(tri[1] - tri[0], tri[2] - tri[0]);
                    assert!(
                        near_border(ray.at(t)) || grazing(n),
                        "{name} {i}: missed the tessellation's hit at {}",
                        ray.at(t)
                    );
                    excused += 1;
                }
            }
        }
        assert!(
            excused < 30 && agree > 1400,
            "{name}: {agree} agree, {excused} excused"
        );
    }
}

/// pbrt's orientation rules: ReverseOrientation and mirror transforms flip the normal;
/// vertex normals decide the side (and give the shading normal) when present.
#[test]
fn normals_follow_pbrts_orientation_rules() {
    let p = patches()[1].1;
    let ray = Ray::new(Vec3::new(0.1, 0.2, 5.0), Vec3::new(0.0, 0.0, -1.0));
    let n_of = |m: BilinearMesh, xf: Transform, rev: bool| {
        let ray = xf.ray(&ray);
        scene_of(m, xf, rev).intersect(&ray).expect("hit").si
    };
    let plain = n_of(mesh(p, vec![]), Transform::IDENTITY, false);
    let (u, v, _) = invert(&p, plain.p);
    let (_, du, dv) = eval(&p, u, v);
    let want = du.cross(dv).normalize().as_vec3a();
    assert!((plain.n - want).length() < 1e-4);
    let rev = n_of(mesh(p, vec![]), Transform::IDENTITY, true);
    assert!((rev.n + want).length() < 1e-4, "reverse orientation flips");
    let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
    let m = n_of(mesh(p, vec![]), mirror, false);
    let want_m = normalize(mirror.normal(want));
    // Mirrored, ∂p/∂u × ∂p/∂v turns over, and pbrt flips it back for a handedness-swapping
    // transform: the normal is the object-space one, transformed.
    assert!(
        (m.n - want_m).length() < 1e-4,
        "a mirror: {} {}",
        m.n,
        want_m
    );
    // Vertex normals opposite to ∂p/∂u × ∂p/∂v: the geometric normal follows them.
    let down = vec![-Vec3::Z, -Vec3::Z, -Vec3::Z, -Vec3::Z];
    let with_n = n_of(mesh(p, down.clone()), Transform::IDENTITY, false);
    assert!(with_n.n.dot(Vec3::Z) < 0.0 && (with_n.shading.n + Vec3::Z).length() < 1e-5);
    // ReverseOrientation flips the vertex normals too.
    let with_n_rev = n_of(mesh(p, down), Transform::IDENTITY, true);
    assert!(with_n_rev.n.dot(Vec3::Z) > 0.0 && (with_n_rev.shading.n - Vec3::Z).length() < 1e-5);
}

/// ∫∫ J(u, v) over [u0, u1] × [v0, v1] by the midpoint rule on a k × k grid,
/// J = |∂p/∂u × ∂p/∂v|.
fn integrate_j(p: &[Vec3; 4], (u0, u1): (f64, f64), (v0, v1): (f64, f64), k: usize) -> f64 {
    let (hu, hv) = ((u1 - u0) / k as f64, (v1 - v0) / k as f64);
    let mut s = 0.0;
    for i in 0..k {
        for j in 0..k {
            let (_, du, dv) = eval(p, u0 + (i as f64 + 0.5) * hu, v0 + (j as f64 + 0.5) * hv);
            s += du.cross(dv).length();
        }
    }
    s * hu * hv
}

/// Areas equal ∫∫ |∂p/∂u × ∂p/∂v|; sampled points lie on the patch, carry the normal a ray
/// hitting them gets, and are uniform by area: their (u, v), binned 12 × 12, fit the density
/// J(u, v)/A (chi-square). Uniform (u, v) would not fit on the twisted patches.
#[test]
fn area_sampling_is_uniform_by_area() {
    const B: usize = 12;
    const SAMPLES: usize = 60_000;
    let list = patches();
    let tests = list.len();
    for (name, p) in list {
        let scene = scene_of(mesh(p, vec![]), Transform::IDENTITY, false);
        let shape = &scene.shapes()[0];
        let area = shape.area() as f64;
        let exact = integrate_j(&p, (0.0, 1.0), (0.0, 1.0), 400);
        assert!(
            (area - exact).abs() < 1e-4 * exact,
            "{name}: area {area} vs {exact}"
        );
        let mut exp = vec![0.0; B * B];
        for i in 0..B {
            for j in 0..B {
                let range = |k: usize| (k as f64 / B as f64, (k + 1) as f64 / B as f64);
                exp[i * B + j] = integrate_j(&p, range(i), range(j), 16) / exact * SAMPLES as f64;
            }
        }
        let mut rng = Pcg32::new(9, 3);
        let mut obs = vec![0.0; B * B];
        let mut obs_uniform = vec![0.0; B * B];
        let bin = |u: f64, v: f64| {
            let (i, j) = ((u * B as f64) as usize, (v * B as f64) as usize);
            i.min(B - 1) * B + j.min(B - 1)
        };
        for k in 0..SAMPLES {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            obs_uniform[bin(u.x as f64, u.y as f64)] += 1.0;
            let s = shape.sample_area(u, scene.meshes()).expect("a sample");
            let (su, sv, res) = invert(&p, s.p);
            assert!(res < 1e-5, "{name}: sample {} is {res} off the patch", s.p);
            obs[bin(su.clamp(0.0, 1.0), sv.clamp(0.0, 1.0))] += 1.0;
            if k % 2000 == 0 {
                // A ray towards the sampled point finds it, with the same normal.
                let o = s.p + 2.0 * s.n + 0.3 * uniform3(&mut rng, -1.0, 1.0);
                if let Some(h) = scene.intersect(&Ray::new(o, s.p - o))
                    && (h.si.p - s.p).length() < 1e-4
                {
                    assert!((h.si.n - s.n).length() < 1e-4, "{name}: sample normal");
                }
            }
        }
        let (stat, dof) = pooled_chi2(&obs, &exp).unwrap();
        let pval = chi2_survival(stat, dof);
        assert!(
            pval > sidak(tests),
            "{name}: chi² {stat} ({dof} dof), p = {pval}"
        );
        if name.contains("twist") || name.contains("saddle") {
            let (stat, dof) = pooled_chi2(&obs_uniform, &exp).unwrap();
            assert!(
                chi2_survival(stat, dof) < 1e-6,
                "{name}: uniform (u, v) should not pass"
            );
        }
    }
}

/// Rays spawned from a hit (as the integrators spawn them, on either side) never find the
/// patch again at the point they leave.
#[test]
fn spawned_rays_leave_the_patch() {
    for (name, p) in patches() {
        let scene = scene_of(mesh(p, vec![]), Transform::IDENTITY, false);
        let mut rng = Pcg32::new(4, 8);
        let mut tested = 0;
        for _ in 0..2000 {
            let ray = random_ray(&mut rng, &p);
            let Some(h) = scene.intersect(&ray) else {
                continue;
            };
            let d = uniform3(&mut rng, -1.0, 1.0);
            if let Some(again) = scene.intersect(&h.si.spawn_ray(d)) {
                assert!(
                    (again.si.p - h.si.p).length() > 1e-3,
                    "{name}: re-hit at {} leaving {}",
                    again.si.p,
                    h.si.p
                );
            }
            tested += 1;
        }
        assert!(tested > 500, "{name}: {tested}");
    }
}
