//! Acceptance properties of every analytic shape (sphere, disk, cylinder, cone, paraboloid,
//! hyperboloid, box), with partial sweeps and cuts, under random transforms with non-uniform
//! scale and mirrors, checked against the shapes' definitions written here independently:
//!
//! - hits equal the first root of the implicit function F along the object-space ray (marched
//!   and bisected) inside the cuts: no miss, no false hit (except grazing rays and roots on a
//!   cut's edge, where both answers are right), t within 10⁻⁵ relative;
//! - normals are the normalised gradient ∇F moved to the world (by the inverse transpose);
//! - sampled points lie on the surface, inside the cuts, with the intersection's orientation;
//! - sampling is uniform by world area with the pdf 1/A integrating to 1: A equals the area
//!   integrated numerically from a parameterisation, and a chi-square test over patches of
//!   that parameterisation accepts the samples' histogram (similarity transforms: for
//!   quadrics, like pbrt, the area sampling assumes the transform scales uniformly).

use crate::common::chi2::{chi2_survival, pooled_chi2, sidak};
use crate::common::shapes::{azimuth, placement, random_unit, scene_of};
use glam::DVec3;
use lancer::math::{Transform, Vec2, Vec3};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::Geometry;
use lancer::shape::{
    BoxDesc, ConeDesc, CylinderDesc, DiskDesc, HyperboloidDesc, ParaboloidDesc, SphereDesc,
};
use std::f64::consts::PI;

fn geometries() -> Vec<Geometry> {
    vec![
        Geometry::Sphere(SphereDesc {
            radius: 1.1,
            z_min: -1.1,
            z_max: 1.1,
            phi_max: 360.0,
        }),
        Geometry::Sphere(SphereDesc {
            radius: 0.9,
            z_min: -0.5,
            z_max: 0.7,
            phi_max: 270.0,
        }),
        Geometry::Disk(DiskDesc {
            height: 0.2,
            radius: 1.0,
            inner_radius: 0.3,
            phi_max: 200.0,
        }),
        Geometry::Cylinder(CylinderDesc {
            radius: 0.8,
            z_min: -0.4,
            z_max: 0.9,
            phi_max: 300.0,
        }),
        Geometry::Cone(ConeDesc {
            radius: 0.9,
            height: 1.3,
            phi_max: 250.0,
        }),
        Geometry::Paraboloid(ParaboloidDesc {
            radius: 0.7,
            z_min: 0.3,
            z_max: 1.4,
            phi_max: 290.0,
        }),
        Geometry::Hyperboloid(HyperboloidDesc {
            p1: Vec3::new(1.0, 0.0, -0.5),
            p2: Vec3::new(0.3, 0.8, 0.7),
            phi_max: 320.0,
        }),
        Geometry::Box(BoxDesc {
            min: Vec3::new(-0.5, -1.0, -0.2),
            max: Vec3::new(0.7, 0.4, 1.3),
        }),
    ]
}

fn name(g: &Geometry) -> &'static str {
    match g {
        Geometry::Sphere(_) => "sphere",
        Geometry::Disk(_) => "disk",
        Geometry::Cylinder(_) => "cylinder",
        Geometry::Cone(_) => "cone",
        Geometry::Paraboloid(_) => "paraboloid",
        Geometry::Hyperboloid(_) => "hyperboloid",
        Geometry::Box(_) => "box",
        _ => unreachable!(),
    }
}

/// A random placement: rotation about a random axis, translation, scale (uniform when
/// `similarity`, else independent per axis), sometimes a mirror; and a random
/// `ReverseOrientation`.
fn random_placement(rng: &mut Pcg32, similarity: bool) -> (Transform, bool) {
    let axis = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5;
    let s = 0.4 + 1.2 * rng.uniform();
    let mut scale = if similarity {
        Vec3::splat(s)
    } else {
        Vec3::new(
            0.4 + 1.2 * rng.uniform(),
            0.4 + 1.2 * rng.uniform(),
            0.4 + 1.2 * rng.uniform(),
        )
    };
    if rng.uniform() < 0.3 {
        scale.x = -scale.x;
    }
    let t =
        Transform::translate((Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5) * 6.0)
            * Transform::rotate(360.0 * rng.uniform(), axis).unwrap()
            * Transform::scale(scale).unwrap();
    (t, rng.uniform() < 0.3)
}

/// The surface by its definition: F(p) (zero on the surface), ∇F, whether p is inside the
/// cuts widened by `slack` (narrowed when negative), and the sign s such that the shape's
/// natural normal (∂p/∂u × ∂p/∂v) is along s·∇F.
fn implicit(g: &Geometry, p: DVec3, slack: f64) -> (f64, DVec3, bool, f64) {
    let in_sweep = |phi_max: f32, a: f64| {
        let m = (phi_max as f64).to_radians();
        a <= m + slack || (slack > 0.0 && a >= 2.0 * PI - slack)
    };
    let within = |v: f64, lo: f64, hi: f64| v >= lo - slack && v <= hi + slack;
    match *g {
        Geometry::Sphere(SphereDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            let r = radius as f64;
            let (lo, hi) = ((z_min as f64).max(-r), (z_max as f64).min(r));
            let ok = within(p.z, lo, hi) && in_sweep(phi_max, azimuth(p.x, p.y));
            (p.length_squared() - r * r, 2.0 * p, ok, 1.0)
        }
        Geometry::Disk(DiskDesc {
            height,
            radius,
            inner_radius,
            phi_max,
        }) => {
            let rho = p.truncate().length();
            let ok = within(rho, inner_radius as f64, radius as f64)
                && in_sweep(phi_max, azimuth(p.x, p.y));
            (p.z - height as f64, DVec3::Z, ok, 1.0)
        }
        Geometry::Cylinder(CylinderDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            let r = radius as f64;
            let ok =
                within(p.z, z_min as f64, z_max as f64) && in_sweep(phi_max, azimuth(p.x, p.y));
            (
                p.x * p.x + p.y * p.y - r * r,
                DVec3::new(2.0 * p.x, 2.0 * p.y, 0.0),
                ok,
                1.0,
            )
        }
        Geometry::Cone(ConeDesc {
            radius,
            height,
            phi_max,
        }) => {
            // x² + y² = (r/h)²·(h − z)².
            let (r, h) = (radius as f64, height as f64);
            let k = (r / h) * (r / h);
            let ok = within(p.z, 0.0, h) && in_sweep(phi_max, azimuth(p.x, p.y));
            (
                p.x * p.x + p.y * p.y - k * (h - p.z) * (h - p.z),
                DVec3::new(2.0 * p.x, 2.0 * p.y, 2.0 * k * (h - p.z)),
                ok,
                1.0,
            )
        }
        Geometry::Paraboloid(ParaboloidDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            // z = zmax·(x² + y²)/r².
            let k = z_max as f64 / (radius as f64 * radius as f64);
            let ok =
                within(p.z, z_min as f64, z_max as f64) && in_sweep(phi_max, azimuth(p.x, p.y));
            (
                k * (p.x * p.x + p.y * p.y) - p.z,
                DVec3::new(2.0 * k * p.x, 2.0 * k * p.y, -1.0),
                ok,
                1.0,
            )
        }
        Geometry::Hyperboloid(HyperboloidDesc { p1, p2, phi_max }) => {
            // The segment's point q(s) at p's height; p is on the surface when its distance to
            // the axis equals q's, and inside the sweep when turning q by at most φmax about z
            // brings it onto p.
            let (a, b) = (p1.as_dvec3(), p2.as_dvec3());
            let s = (p.z - a.z) / (b.z - a.z);
            let q = a + s * (b - a);
            let dq = (b - a) / (b.z - a.z);
            let f = p.x * p.x + p.y * p.y - q.x * q.x - q.y * q.y;
            let grad = DVec3::new(2.0 * p.x, 2.0 * p.y, -2.0 * (q.x * dq.x + q.y * dq.y));
            let turn = azimuth(q.x * p.x + q.y * p.y, q.x * p.y - q.y * p.x);
            let ok = within(p.z, a.z.min(b.z), a.z.max(b.z)) && in_sweep(phi_max, turn);
            (f, grad, ok, (b.z - a.z).signum())
        }
        Geometry::Box(BoxDesc { min, max }) => {
            // F = max over axes of |p − c| − h: zero on the faces, gradient the face's normal.
            let (c, h) = ((min + max).as_dvec3() * 0.5, (max - min).as_dvec3() * 0.5);
            let q = (p - c).abs() - h;
            let k = (0..3).max_by(|&i, &j| q[i].total_cmp(&q[j])).unwrap();
            let mut grad = DVec3::ZERO;
            grad[k] = (p[k] - c[k]).signum();
            (q[k], grad, true, 1.0)
        }
        _ => unreachable!(),
    }
}

/// The first root of F along o + t·d in (t_start, t_end) inside the cuts: F sampled at
/// `steps` steps, each sign change bisected to the last bit.
fn first_root(
    g: &Geometry,
    o: DVec3,
    d: DVec3,
    (t_start, t_end): (f64, f64),
    steps: usize,
) -> Option<f64> {
    let f = |t: f64| implicit(g, o + t * d, 0.0).0;
    let (mut t0, mut f0) = (t_start, f(t_start));
    for i in 1..=steps {
        let t1 = t_start + (t_end - t_start) * i as f64 / steps as f64;
        let f1 = f(t1);
        if (f0 < 0.0) != (f1 < 0.0) {
            let (mut lo, mut hi) = (t0, t1);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if (f(mid) < 0.0) == (f0 < 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let root = 0.5 * (lo + hi);
            if root > 0.0 && implicit(g, o + root * d, 0.0).2 {
                return Some(root);
            }
        }
        (t0, f0) = (t1, f1);
    }
    None
}

/// Cosine between the ray and the surface's gradient at parameter t (small for grazing
/// rays).
fn incidence(g: &Geometry, o: DVec3, d: DVec3, t: f64) -> f64 {
    let grad = implicit(g, o + t * d, 0.0).1;
    (grad.normalize().dot(d.normalize())).abs()
}

#[test]
fn hits_and_normals_match_the_implicit_surface() {
    let mut rng = Pcg32::new(2024, 7);
    for g in geometries() {
        let (mut hits, mut exempt, mut refined) = (0, 0, 0);
        for trial in 0..6 {
            let (xf, rev) = random_placement(&mut rng, false);
            let scene = scene_of(g.clone(), xf, rev);
            let shape = &scene.shapes()[0];
            let pl = placement(shape);
            let b = shape.bounds();
            let (centre, size) = (0.5 * (b.min + b.max), (b.max - b.min).length());
            for ri in 0..500 {
                let o = centre + random_unit(&mut rng) * size * (0.1 + 1.4 * rng.uniform());
                let target = b.min
                    + (b.max - b.min) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
                let ray = Ray::new(o, target - o);
                let what = format!("{} trial {trial} ray {ri}", name(&g));
                let (oo, dd) = pl.object_ray(&ray);
                // Beyond the far side of the bounds nothing can be hit.
                let t_end = ((o - centre).length() + size) as f64 / ray.d.length() as f64;
                const STEPS: usize = 40_000;
                let mut want = first_root(&g, oo, dd, (0.0, t_end), STEPS);
                if let (Some(h), None) = (shape.intersect(&ray), want) {
                    // A chord shorter than a step (a box's edge, a grazing ray): march again,
                    // finely, around the shape's answer.
                    let step = t_end / STEPS as f64;
                    let t = h.t as f64;
                    want = first_root(
                        &g,
                        oo,
                        dd,
                        ((t - 2.0 * step).max(0.0), t + 2.0 * step),
                        20_000,
                    );
                    if want.is_some() {
                        refined += 1;
                    }
                }
                let got = shape.intersect(&ray);
                match (got, want) {
                    (None, None) => {}
                    (Some(h), Some(t)) => {
                        let ht = h.t as f64;
                        if (ht - t).abs() > 1e-5 * t.max(1.0) {
                            // Two roots: the earlier one on a cut's edge may be taken or not.
                            let p = oo + t * dd;
                            assert!(
                                !implicit(&g, p, -1e-5).2 || incidence(&g, oo, dd, t) < 1e-3,
                                "{what}: t {ht}, implicit root {t}"
                            );
                            exempt += 1;
                            continue;
                        }
                        hits += 1;
                        let si = shape.interaction(&ray, &h, scene.meshes());
                        let p = pl.to_object.transform_point3(si.p.as_dvec3());
                        let (f, grad, ok, sign) = implicit(&g, p, 1e-5);
                        assert!(ok, "{what}: hit point {p} outside the cuts");
                        assert!(f.abs() / grad.length() < 1e-5, "{what}: F = {f} at {p}");
                        // ∇F is a normal: to the world by the inverse transpose of
                        // object-to-world, which is the transpose of world-to-object.
                        let n_world = pl.to_object.transpose().transform_vector3(grad).normalize();
                        let flip = if pl.flip_normal { -1.0 } else { 1.0 };
                        let cos = si.n.as_dvec3().dot(n_world) * sign * flip;
                        assert!(
                            cos > 0.9999,
                            "{what}: normal {} vs gradient {n_world}",
                            si.n
                        );
                        assert!(
                            si.uv.cmpge(Vec2::splat(-1e-4)).all()
                                && si.uv.cmple(Vec2::splat(1.0 + 1e-4)).all(),
                            "{what}: uv {}",
                            si.uv
                        );
                    }
                    (Some(h), None) => {
                        // Only a grazing ray (two roots within one marching step) or a point on
                        // a cut's edge may escape the marcher.
                        let t = h.t as f64;
                        let p = oo + t * dd;
                        let (f, grad, ok, _) = implicit(&g, p, 1e-4);
                        assert!(
                            ok && f.abs() / grad.length() < 1e-4,
                            "{what}: false hit at t {t}, p {p}"
                        );
                        assert!(
                            incidence(&g, oo, dd, t) < 0.05 || !implicit(&g, p, -1e-4).2,
                            "{what}: the shape hits at t {t} where the marcher finds no root"
                        );
                        exempt += 1;
                    }
                    (None, Some(t)) => {
                        let p = oo + t * dd;
                        assert!(
                            incidence(&g, oo, dd, t) < 1e-3 || !implicit(&g, p, -1e-5).2,
                            "{what}: missed the root at t {t}, p {p}"
                        );
                        exempt += 1;
                    }
                }
            }
        }
        println!(
            "{}: {hits} hits ({refined} after a finer march), {exempt} grazing or on a cut's edge",
            name(&g)
        );
        assert!(hits > 600, "{}: only {hits} hits", name(&g));
        assert!(exempt * 200 < hits, "{}: {exempt} exemptions", name(&g));
    }
}

/// The shape's parametric patches (object space, (a, b) ∈ [0, 1]²), written from the shapes'
/// definitions: one for a quadric (a along the profile, b the azimuth), six for a box.
fn patch_point(g: &Geometry, patch: usize, a: f64, b: f64) -> DVec3 {
    let turn = |phi_max: f32, x: f64, y: f64, z: f64| {
        let phi = b * (phi_max as f64).to_radians();
        DVec3::new(
            x * phi.cos() - y * phi.sin(),
            x * phi.sin() + y * phi.cos(),
            z,
        )
    };
    match *g {
        Geometry::Sphere(SphereDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            let r = radius as f64;
            let (lo, hi) = ((z_min as f64).max(-r), (z_max as f64).min(r));
            let z = lo + a * (hi - lo);
            turn(phi_max, (r * r - z * z).max(0.0).sqrt(), 0.0, z)
        }
        Geometry::Disk(DiskDesc {
            height,
            radius,
            inner_radius,
            phi_max,
        }) => turn(
            phi_max,
            inner_radius as f64 + a * (radius - inner_radius) as f64,
            0.0,
            height as f64,
        ),
        Geometry::Cylinder(CylinderDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => turn(
            phi_max,
            radius as f64,
            0.0,
            z_min as f64 + a * (z_max - z_min) as f64,
        ),
        Geometry::Cone(ConeDesc {
            radius,
            height,
            phi_max,
        }) => turn(phi_max, (1.0 - a) * radius as f64, 0.0, a * height as f64),
        Geometry::Paraboloid(ParaboloidDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            let z = z_min as f64 + a * (z_max - z_min) as f64;
            turn(phi_max, radius as f64 * (z / z_max as f64).sqrt(), 0.0, z)
        }
        Geometry::Hyperboloid(HyperboloidDesc { p1, p2, phi_max }) => {
            let q = p1.as_dvec3() + a * (p2 - p1).as_dvec3();
            turn(phi_max, q.x, q.y, q.z)
        }
        Geometry::Box(BoxDesc { min, max }) => {
            let (lo, hi) = (min.as_dvec3(), max.as_dvec3());
            let k = patch % 3;
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let mut p = DVec3::ZERO;
            p[k] = if patch >= 3 { hi[k] } else { lo[k] };
            p[i] = lo[i] + a * (hi[i] - lo[i]);
            p[j] = lo[j] + b * (hi[j] - lo[j]);
            p
        }
        _ => unreachable!(),
    }
}

fn patches(g: &Geometry) -> usize {
    if matches!(g, Geometry::Box(_)) { 6 } else { 1 }
}

/// The patch and (a, b) of an object-space point of the surface (the inverse of
/// [`patch_point`]).
fn locate(g: &Geometry, p: DVec3) -> (usize, f64, f64) {
    let sweep = |phi_max: f32, x: f64, y: f64| azimuth(x, y) / (phi_max as f64).to_radians();
    match *g {
        Geometry::Sphere(SphereDesc {
            radius,
            z_min,
            z_max,
            phi_max,
        }) => {
            let r = radius as f64;
            let (lo, hi) = ((z_min as f64).max(-r), (z_max as f64).min(r));
            (0, (p.z - lo) / (hi - lo), sweep(phi_max, p.x, p.y))
        }
        Geometry::Disk(DiskDesc {
            radius,
            inner_radius,
            phi_max,
            ..
        }) => (
            0,
            (p.truncate().length() - inner_radius as f64) / (radius - inner_radius) as f64,
            sweep(phi_max, p.x, p.y),
        ),
        Geometry::Cylinder(CylinderDesc {
            z_min,
            z_max,
            phi_max,
            ..
        })
        | Geometry::Paraboloid(ParaboloidDesc {
            z_min,
            z_max,
            phi_max,
            ..
        }) => (
            0,
            (p.z - z_min as f64) / (z_max - z_min) as f64,
            sweep(phi_max, p.x, p.y),
        ),
        Geometry::Cone(ConeDesc {
            height, phi_max, ..
        }) => (0, p.z / height as f64, sweep(phi_max, p.x, p.y)),
        Geometry::Hyperboloid(HyperboloidDesc { p1, p2, phi_max }) => {
            let a = (p.z - p1.z as f64) / (p2.z - p1.z) as f64;
            let q = p1.as_dvec3() + a * (p2 - p1).as_dvec3();
            let turn = azimuth(q.x * p.x + q.y * p.y, q.x * p.y - q.y * p.x);
            (0, a, turn / (phi_max as f64).to_radians())
        }
        Geometry::Box(BoxDesc { min, max }) => {
            let (lo, hi) = (min.as_dvec3(), max.as_dvec3());
            let d_lo = (p - lo).abs();
            let d_hi = (p - hi).abs();
            let mut best = (f64::INFINITY, 0);
            for k in 0..3 {
                if d_lo[k] < best.0 {
                    best = (d_lo[k], k);
                }
                if d_hi[k] < best.0 {
                    best = (d_hi[k], k + 3);
                }
            }
            let patch = best.1;
            let k = patch % 3;
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            (
                patch,
                (p[i] - lo[i]) / (hi[i] - lo[i]),
                (p[j] - lo[j]) / (hi[j] - lo[j]),
            )
        }
        _ => unreachable!(),
    }
}

/// World area of each of `bins`×`bins` cells of each patch: ∫∫ |∂W/∂a × ∂W/∂b| da db for the
/// world map W = to_world ∘ patch, by the midpoint rule on 12×12 points per cell with central
/// differences.
fn bin_areas(g: &Geometry, to_world: &Transform, bins: usize) -> Vec<f64> {
    let m = to_world.m.as_dmat4();
    let w = |patch, a: f64, b: f64| m.transform_point3(patch_point(g, patch, a, b));
    let sub = 12;
    let n = bins * sub;
    let h = 1e-6;
    let mut out = vec![0.0; patches(g) * bins * bins];
    for patch in 0..patches(g) {
        for ia in 0..n {
            for ib in 0..n {
                let (a, b) = ((ia as f64 + 0.5) / n as f64, (ib as f64 + 0.5) / n as f64);
                let da = (w(patch, a + h, b) - w(patch, a - h, b)) / (2.0 * h);
                let db = (w(patch, a, b + h) - w(patch, a, b - h)) / (2.0 * h);
                let area = da.cross(db).length() / (n * n) as f64;
                out[patch * bins * bins + (ia / sub) * bins + ib / sub] += area;
            }
        }
    }
    out
}

#[test]
fn samples_lie_on_the_surface_and_are_uniform_by_area() {
    let mut rng = Pcg32::new(99, 1);
    let shapes = geometries();
    let per_test = sidak(shapes.len());
    for g in shapes {
        let (xf, rev) = random_placement(&mut rng, true);
        let scene = scene_of(g.clone(), xf, rev);
        let shape = &scene.shapes()[0];
        let pl = placement(shape);
        let bins = 6;
        let areas = bin_areas(&g, &xf, bins);
        let total: f64 = areas.iter().sum();
        // The pdf 1/A integrates to A_true/A: it must be 1.
        let a = shape.area() as f64;
        assert!(
            (a / total - 1.0).abs() < 2e-3,
            "{}: area {a}, integrated {total}",
            name(&g)
        );
        let n = 40_000;
        let mut obs = vec![0.0; areas.len()];
        for _ in 0..n {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let s = shape.sample_area(u, scene.meshes()).unwrap();
            let p = pl.to_object.transform_point3(s.p.as_dvec3());
            let (f, grad, ok, sign) = implicit(&g, p, 1e-4);
            let what = format!("{}: sample {p}", name(&g));
            assert!(ok, "{what} outside the cuts");
            assert!(f.abs() / grad.length() < 1e-5, "{what}: F = {f}");
            let n_world = pl.to_object.transpose().transform_vector3(grad).normalize();
            let flip = if pl.flip_normal { -1.0 } else { 1.0 };
            assert!(
                s.n.as_dvec3().dot(n_world) * sign * flip > 0.9999,
                "{what}: normal {} vs gradient {n_world}",
                s.n
            );
            let (patch, a, b) = locate(&g, p);
            let cell = |x: f64| ((x * bins as f64) as usize).min(bins - 1);
            obs[patch * bins * bins + cell(a) * bins + cell(b)] += 1.0;
        }
        let exp: Vec<f64> = areas.iter().map(|x| x / total * n as f64).collect();
        let (chi2, dof) = pooled_chi2(&obs, &exp).unwrap();
        let p_value = chi2_survival(chi2, dof);
        println!("{}: χ² = {chi2:.1} ({dof} dof), p = {p_value:.3}", name(&g));
        assert!(
            p_value > per_test,
            "{}: samples not uniform by area, χ² = {chi2} ({dof} dof), p = {p_value}",
            name(&g)
        );
    }
}
