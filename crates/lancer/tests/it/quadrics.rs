//! Cones, paraboloids, hyperboloids and boxes: hits agree with a brute-force root finder on
//! the implicit surface, hit points and normals are right, spawned rays never find their own
//! surface again, areas agree with Crofton's formula, and sampled points carry the
//! intersection's normal.
//!
//! These are the statistical checks over all of them; each shape's hand-computed hits,
//! normals, cuts and closed-form areas are unit tests beside it, in `src/shape/`.

use crate::common::shapes::{azimuth, placement, scene_of};
use glam::DVec3;
use lancer::math::{Transform, Vec2, Vec3, cross, normalize};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::Geometry;
use lancer::shape::{BoxDesc, ConeDesc, HyperboloidDesc, ParaboloidDesc, Shape};
use std::f64::consts::PI;

fn geometries() -> Vec<Geometry> {
    vec![
        Geometry::Cone(ConeDesc {
            radius: 1.2,
            height: 1.5,
            phi_max: 360.0,
        }),
        Geometry::Cone(ConeDesc {
            radius: 0.8,
            height: 2.0,
            phi_max: 250.0,
        }),
        Geometry::Paraboloid(ParaboloidDesc {
            radius: 1.0,
            z_min: 0.0,
            z_max: 1.0,
            phi_max: 360.0,
        }),
        Geometry::Paraboloid(ParaboloidDesc {
            radius: 0.7,
            z_min: 0.3,
            z_max: 1.4,
            phi_max: 290.0,
        }),
        // Skew segment: a one-sheet hyperboloid whose waist is not at z = 0.
        Geometry::Hyperboloid(HyperboloidDesc {
            p1: Vec3::new(1.0, 0.0, -0.5),
            p2: Vec3::new(0.3, 0.8, 0.7),
            phi_max: 360.0,
        }),
        // pbrt's defaults: the segment's line meets the axis, a cone.
        Geometry::Hyperboloid(HyperboloidDesc {
            p1: Vec3::ZERO,
            p2: Vec3::ONE,
            phi_max: 300.0,
        }),
        // Parallel to the axis: a cylinder.
        Geometry::Hyperboloid(HyperboloidDesc {
            p1: Vec3::new(0.5, 0.0, -1.0),
            p2: Vec3::new(0.5, 0.0, 1.0),
            phi_max: 200.0,
        }),
        // The classic hyperboloid, its segment going down.
        Geometry::Hyperboloid(HyperboloidDesc {
            p1: Vec3::new(1.0, -1.0, 1.0),
            p2: Vec3::new(1.0, 1.0, -1.0),
            phi_max: 360.0,
        }),
        Geometry::Box(BoxDesc {
            min: Vec3::new(-0.5, -1.0, -0.2),
            max: Vec3::new(0.7, 0.4, 1.3),
        }),
    ]
}

/// (transform, reverse orientation): identity; translate + rotate + non-uniform scale; a
/// mirror with reverse orientation.
fn placements() -> Vec<(Transform, bool)> {
    vec![
        (Transform::IDENTITY, false),
        (
            Transform::translate(Vec3::new(0.3, -0.7, 1.1))
                * Transform::rotate(35.0, Vec3::new(1.0, 2.0, 0.5)).unwrap()
                * Transform::scale(Vec3::new(1.3, 0.6, 0.9)).unwrap(),
            false,
        ),
        (Transform::scale(Vec3::new(-1.0, 1.2, 0.8)).unwrap(), true),
    ]
}

/// The implicit function F (zero on the surface), its gradient, whether the point lies inside
/// the shape's cuts, and the sign s with ∂p/∂u × ∂p/∂v ∝ s·∇F. Written from the shapes'
/// definitions, independently of the shape code.
fn implicit(g: &Geometry, p: DVec3) -> (f64, DVec3, bool, f64) {
    match *g {
        Geometry::Cone(ConeDesc {
            radius,
            height,
            phi_max,
        }) => {
            let (r, h) = (radius as f64, height as f64);
            let k = (r / h).powi(2);
            let f = p.x * p.x + p.y * p.y - k * (p.z - h).powi(2);
            let grad = DVec3::new(2.0 * p.x, 2.0 * p.y, -2.0 * k * (p.z - h));
            let ok = (0.0..=h).contains(&p.z) && azimuth(p.x, p.y) <= (phi_max as f64).to_radians();
            (f, grad, ok, 1.0)
        }
        Geometry::Paraboloid(ParaboloidDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            let k = z_max as f64 / (radius as f64).powi(2);
            let f = k * (p.x * p.x + p.y * p.y) - p.z;
            let grad = DVec3::new(2.0 * k * p.x, 2.0 * k * p.y, -1.0);
            let ok = (z_min as f64..=z_max as f64).contains(&p.z)
                && azimuth(p.x, p.y) <= (phi_max as f64).to_radians();
            (f, grad, ok, 1.0)
        }
        Geometry::Hyperboloid(HyperboloidDesc { p1, p2, phi_max }) => {
            let (p1, p2) = (p1.as_dvec3(), p2.as_dvec3());
            let dz = p2.z - p1.z;
            let s = (p.z - p1.z) / dz;
            // The segment's point at p's height, and its radius² there.
            let pr = p1 + s * (p2 - p1);
            let f = p.x * p.x + p.y * p.y - (pr.x * pr.x + pr.y * pr.y);
            let e = (p2 - p1).truncate();
            let dr2 = 2.0 * pr.truncate().dot(e) / dz;
            let grad = DVec3::new(2.0 * p.x, 2.0 * p.y, -dr2);
            // The angle turning the segment's point onto p.
            let turn = azimuth(pr.x * p.x + pr.y * p.y, pr.x * p.y - pr.y * p.x);
            let ok = (0.0..=1.0).contains(&s) && turn <= (phi_max as f64).to_radians();
            (f, grad, ok, dz.signum())
        }
        Geometry::Box(BoxDesc { min, max }) => {
            let (c, h) = ((min + max).as_dvec3() * 0.5, (max - min).as_dvec3() * 0.5);
            let q = (p - c).abs() - h;
            let k = if q.x >= q.y && q.x >= q.z {
                0
            } else if q.y >= q.z {
                1
            } else {
                2
            };
            let mut grad = DVec3::ZERO;
            grad[k] = (p[k] - c[k]).signum();
            (q[k], grad, true, 1.0)
        }
        _ => unreachable!(),
    }
}

/// The nearest valid root along the object-space ray by marching F in small steps up to
/// `t_end`, then bisecting each sign change.
fn brute_force(g: &Geometry, o: DVec3, d: DVec3, t_end: f64) -> Option<f64> {
    let steps = 20_000;
    let dt = t_end / steps as f64;
    let f = |t: f64| implicit(g, o + t * d).0;
    let mut t_prev = 0.0;
    let mut f_prev = f(0.0);
    for i in 1..=steps {
        let t = i as f64 * dt;
        let ft = f(t);
        if (f_prev < 0.0) != (ft < 0.0) {
            let (mut lo, mut hi) = (t_prev, t);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if (f(mid) < 0.0) == (f_prev < 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let root = 0.5 * (lo + hi);
            if root > 0.0 && implicit(g, o + root * d).2 {
                return Some(root);
            }
        }
        (t_prev, f_prev) = (t, ft);
    }
    None
}

fn random_in_ball(rng: &mut Pcg32, radius: f32) -> Vec3 {
    loop {
        let v = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - Vec3::ONE;
        if v.length_squared() <= 1.0 {
            return v * radius;
        }
    }
}

fn random_unit(rng: &mut Pcg32) -> Vec3 {
    random_in_ball(rng, 1.0).normalize_or(Vec3::Z)
}

/// Random rays from around the shape towards points of its bounds.
fn random_rays(shape: &Shape, rng: &mut Pcg32, n: usize) -> Vec<Ray> {
    let b = shape.bounds();
    let centre = 0.5 * (b.min + b.max);
    let size = (b.max - b.min).length();
    (0..n)
        .map(|_| {
            let o = centre + random_in_ball(rng, 1.5 * size);
            let target =
                b.min + (b.max - b.min) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            Ray::new(o, target - o)
        })
        .collect()
}

#[test]
fn hits_match_a_brute_force_root_finder() {
    let mut rng = Pcg32::new(7, 0);
    for (gi, g) in geometries().into_iter().enumerate() {
        for (pi, (xf, rev)) in placements().into_iter().enumerate() {
            let scene = scene_of(g.clone(), xf, rev);
            let shape = &scene.shapes()[0];
            let pl = placement(shape);
            let (mut hits, mut disagree) = (0, 0);
            let n = 1500;
            for ray in random_rays(shape, &mut rng, n) {
                let o = pl.to_object.transform_point3(ray.o.as_dvec3());
                let d = pl.to_object.transform_vector3(ray.d.as_dvec3());
                let want = brute_force(&g, o, d, 3.0);
                let got = shape.intersect(&ray).map(|h| h.t as f64);
                match (got, want) {
                    (Some(a), Some(b)) => {
                        hits += 1;
                        assert!(
                            (a - b).abs() <= 2e-6 * b.max(1.0),
                            "shape {gi} placement {pi}: t {a} but brute force {b}"
                        );
                    }
                    (None, None) => {}
                    // Grazing rays whose two roots fall within one marching step.
                    _ => disagree += 1,
                }
            }
            assert!(hits > n / 4, "shape {gi} placement {pi}: only {hits} hits");
            assert!(
                disagree * 500 <= n,
                "shape {gi} placement {pi}: {disagree} of {n} rays disagree"
            );
        }
    }
}

#[test]
fn hit_points_and_normals_follow_the_implicit_surface() {
    let mut rng = Pcg32::new(11, 0);
    for (gi, g) in geometries().into_iter().enumerate() {
        for (pi, (xf, rev)) in placements().into_iter().enumerate() {
            let scene = scene_of(g.clone(), xf, rev);
            let shape = &scene.shapes()[0];
            let pl = placement(shape);
            let mut checked = 0;
            for ray in random_rays(shape, &mut rng, 1000) {
                let Some(hit) = scene.intersect(&ray) else {
                    continue;
                };
                let si = hit.si;
                let p = pl.to_object.transform_point3(si.p.as_dvec3());
                let (f, grad, ok, sign) = implicit(&g, p);
                let what = format!("shape {gi} placement {pi} at {p}");
                assert!(ok, "{what}: hit outside the cuts");
                // Distance to the surface, to first order.
                assert!(f.abs() / grad.length() < 2e-6, "{what}: F = {f}");
                assert!((si.n.length() - 1.0).abs() < 1e-5, "{what}");
                for dp in [si.dpdu, si.dpdv] {
                    assert!(si.n.dot(dp).abs() <= 2e-5 * dp.length(), "{what}: n·dp");
                }
                let n_uv = normalize(cross(si.dpdu, si.dpdv));
                // M·a × M·b = det M · M⁻ᵀ(a × b), and n is M⁻ᵀ(a × b), flipped as placed.
                let det_sign = if xf.swaps_handedness() { -1.0 } else { 1.0 };
                let want = if pl.flip_normal { -det_sign } else { det_sign };
                assert!(
                    si.n.dot(n_uv) * want > 0.9999,
                    "{what}: n {} but ∂p/∂u × ∂p/∂v {n_uv}",
                    si.n
                );
                // ∇F moves to the world as a normal: by the inverse transpose.
                let grad_world = pl.to_object.transpose().transform_vector3(grad).normalize();
                let flip = if pl.flip_normal { -1.0 } else { 1.0 };
                let cos = si.n.as_dvec3().dot(grad_world) * sign * flip;
                assert!(cos > 0.9999, "{what}: normal {} vs gradient", si.n);
                // (u, v) within the unit square.
                assert!(
                    si.uv.cmpge(Vec2::splat(-1e-5)).all()
                        && si.uv.cmple(Vec2::splat(1.0 + 1e-5)).all(),
                    "{what}: uv {}",
                    si.uv
                );
                checked += 1;
            }
            assert!(checked > 150, "shape {gi} placement {pi}: {checked} hits");
        }
    }
}

#[test]
fn spawned_rays_never_find_their_own_surface_again() {
    let mut rng = Pcg32::new(13, 0);
    for (gi, g) in geometries().into_iter().enumerate() {
        for (pi, (xf, rev)) in placements().into_iter().enumerate() {
            let scene = scene_of(g.clone(), xf, rev);
            let shape = &scene.shapes()[0];
            let mut spawned = 0;
            // Rays from nearby, and from 10³ away, where o + t·d cancels most of its digits.
            let mut rays = random_rays(shape, &mut rng, 800);
            for r in random_rays(shape, &mut rng, 400) {
                let d = normalize(r.d);
                rays.push(Ray::new(r.o + 1000.0 * normalize(r.o - r.at(1.0)), d));
            }
            for ray in rays {
                let Some(hit) = scene.intersect(&ray) else {
                    continue;
                };
                let si = hit.si;
                for _ in 0..8 {
                    let mut d = random_unit(&mut rng);
                    for side in [1.0f32, -1.0] {
                        if d.dot(si.n) * side < 0.0 {
                            d = -d;
                        }
                        let r = si.spawn_ray(d);
                        spawned += 1;
                        if let Some(h) = shape.intersect(&r) {
                            let dist = h.t * r.d.length();
                            assert!(
                                dist > 1e-4,
                                "shape {gi} placement {pi}: ray from {} re-hit at distance {dist}",
                                si.p
                            );
                        }
                    }
                }
            }
            assert!(spawned > 3000, "shape {gi} placement {pi}: {spawned}");
        }
    }
}

/// Cauchy–Crofton: for isotropic uniform lines meeting a ball of radius R, the mean number of
/// crossings of a surface inside it is 2A/(4πR²), so A = 2πR²·E[crossings].
/// The crossing points (world space) are spread uniformly by area over the surface.
fn crofton(shape: &Shape, rng: &mut Pcg32, lines: usize) -> (f64, Vec<Vec3>) {
    let mut points = Vec::new();
    let b = shape.bounds();
    let centre = 0.5 * (b.min + b.max);
    let radius = 0.5 * (b.max - b.min).length() * 1.01;
    let mut crossings = 0usize;
    for _ in 0..lines {
        let w = random_unit(rng);
        let (t1, t2) = w.any_orthonormal_pair();
        let (a, r) = (
            2.0 * std::f32::consts::PI * rng.uniform(),
            radius * rng.uniform().sqrt(),
        );
        let foot = centre + r * (a.cos() * t1 + a.sin() * t2);
        let mut ray = Ray::new(foot - 2.0 * radius * w, w);
        ray.t_max = 4.0 * radius;
        for _ in 0..8 {
            let Some(h) = shape.intersect(&ray) else {
                break;
            };
            crossings += 1;
            let si = shape.interaction(&ray, &h, &[]);
            points.push(si.p);
            let end = ray.at(ray.t_max);
            let next = si.spawn_ray(w);
            ray = Ray {
                t_max: (end - next.o).dot(w),
                ..next
            };
        }
    }
    let area = 2.0 * PI * (radius as f64).powi(2) * crossings as f64 / lines as f64;
    (area, points)
}

/// A placement under which the shape's area and area sampling are exact: quadrics (like
/// pbrt's) assume a similarity transform; the box handles any affine map.
fn area_exact_placement(g: &Geometry) -> Transform {
    if matches!(g, Geometry::Box(_)) {
        placements()[1].0
    } else {
        Transform::translate(Vec3::new(0.2, 0.1, -0.3))
            * Transform::rotate(50.0, Vec3::new(0.3, 1.0, 0.2)).unwrap()
            * Transform::scale(Vec3::splat(1.4)).unwrap()
    }
}

#[test]
fn areas_agree_with_crofton() {
    let mut rng = Pcg32::new(17, 0);
    for (gi, g) in geometries().into_iter().enumerate() {
        let xf = area_exact_placement(&g);
        let scene = scene_of(g, xf, false);
        let shape = &scene.shapes()[0];
        let (want, _) = crofton(shape, &mut rng, 200_000);
        let got = shape.area() as f64;
        // 200 000 lines: a relative standard error well under 1%.
        assert!(
            (got - want).abs() < 0.02 * want,
            "shape {gi}: area {got} but Crofton gives {want}"
        );
    }
}

#[test]
fn sampled_points_lie_on_the_surface_with_the_intersection_normal() {
    for (gi, g) in geometries().into_iter().enumerate() {
        for (pi, (xf, rev)) in placements().into_iter().enumerate() {
            let scene = scene_of(g.clone(), xf, rev);
            let shape = &scene.shapes()[0];
            let pl = placement(shape);
            let mut rng = Pcg32::new(19, 0);
            let mut compared = 0;
            for _ in 0..400 {
                let u = Vec2::new(rng.uniform(), rng.uniform());
                let s = shape.sample_area(u, scene.meshes()).expect("samples");
                let what = format!("shape {gi} placement {pi} sample {}", s.p);
                let p = pl.to_object.transform_point3(s.p.as_dvec3());
                let (f, grad, ok, _) = implicit(&g, p);
                assert!(f.abs() / grad.length() < 2e-6, "{what}: F = {f}");
                assert!(ok, "{what}: outside the cuts");
                for side in [1.0f32, -1.0] {
                    let o = s.p + s.n * (0.05 * side);
                    let ray = Ray::new(o, s.p - o);
                    let Some(hit) = scene.intersect(&ray) else {
                        panic!("{what}: the ray at it missed");
                    };
                    if (hit.si.p - s.p).length() > 1e-3 {
                        continue; // another part of the shape is in the way
                    }
                    assert!(
                        hit.si.n.dot(s.n) > 0.999,
                        "{what}: sampled normal {} but intersection normal {}",
                        s.n,
                        hit.si.n
                    );
                    compared += 1;
                }
            }
            assert!(compared > 400, "shape {gi} placement {pi}: {compared}");
        }
    }
}

#[test]
fn samples_are_uniform_by_area() {
    // Crofton's crossing points are uniform by area, independently of the shapes' samplers:
    // both sets must put the same share of points in each octant around the surface's
    // centroid (object space, so that the partial sweeps and cuts split unevenly).
    let mut rng = Pcg32::new(23, 0);
    for (gi, g) in geometries().into_iter().enumerate() {
        let scene = scene_of(g.clone(), area_exact_placement(&g), false);
        let shape = &scene.shapes()[0];
        let pl = placement(shape);
        let (_, crossings) = crofton(shape, &mut rng, 100_000);
        let samples: Vec<Vec3> = (0..crossings.len())
            .map(|_| {
                let u = Vec2::new(rng.uniform(), rng.uniform());
                shape.sample_area(u, &[]).unwrap().p
            })
            .collect();
        let object = |ps: &[Vec3]| -> Vec<DVec3> {
            ps.iter()
                .map(|p| pl.to_object.transform_point3(p.as_dvec3()))
                .collect()
        };
        let (crossings, samples) = (object(&crossings), object(&samples));
        let centre = crossings.iter().sum::<DVec3>() / crossings.len() as f64;
        let shares = |ps: &[DVec3]| {
            let mut count = [0usize; 8];
            for p in ps {
                let q = p.cmpgt(centre);
                count[q.x as usize + 2 * q.y as usize + 4 * q.z as usize] += 1;
            }
            count.map(|c| c as f64 / ps.len() as f64)
        };
        let (a, b) = (shares(&crossings), shares(&samples));
        for o in 0..8 {
            // Two shares of ≥ 100 000 points: standard error ≤ 0.0023.
            assert!(
                (a[o] - b[o]).abs() < 0.01,
                "shape {gi} octant {o}: Crofton {} but samples {}",
                a[o],
                b[o]
            );
        }
    }
}
