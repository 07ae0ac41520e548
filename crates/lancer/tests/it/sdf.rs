//! Signed-distance objects: the expression language's errors, every primitive's distance
//! against an independent closed form or brute force, the operators' laws, and sphere-traced
//! hits and normals against analytic sphere, box and torus intersections on thousands of rays.

use glam::{DMat3, DVec3};
use lancer::math::{Transform, Vec3, normalize};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::shape::sdf::{Aabb, SdfFunction};
use lancer::shape::{Cuboid, Placement, Sdf, Shape, Sphere};
use std::sync::Arc;

fn f(src: &str) -> SdfFunction {
    SdfFunction::parse(src).unwrap_or_else(|e| panic!("{src}: {e}"))
}

fn rnd(rng: &mut Pcg32, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.uniform() as f64
}

fn rnd_point(rng: &mut Pcg32, r: f64) -> DVec3 {
    DVec3::new(rnd(rng, -r, r), rnd(rng, -r, r), rnd(rng, -r, r))
}

fn rnd_dir(rng: &mut Pcg32) -> DVec3 {
    loop {
        let v = rnd_point(rng, 1.0);
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Checks `sdf` against `reference` at 2 000 random points of [−r, r]³.
#[track_caller]
fn agrees(src: &str, r: f64, tol: f64, reference: impl Fn(DVec3) -> f64) {
    let func = f(src);
    let mut rng = Pcg32::new(7, 0);
    for _ in 0..2000 {
        let p = rnd_point(&mut rng, r);
        let (got, want) = (func.eval(p), reference(p));
        assert!((got - want).abs() <= tol, "{src} at {p}: {got} vs {want}");
    }
}

/// Distance from p to the box [−h, h] (0 inside).
fn outside_box(p: DVec3, h: DVec3) -> f64 {
    (p - p.clamp(-h, h)).length()
}

/// Exact signed distance to the box [−h, h], written the textbook way.
fn box_sd(p: DVec3, h: DVec3) -> f64 {
    if p.abs().cmple(h).all() {
        -(h - p.abs()).min_element()
    } else {
        outside_box(p, h)
    }
}

/// Distance from 2D point q to the segment a–b, by dense sampling (error ≤ |b − a|/2N).
fn seg_brute(q: [f64; 2], a: [f64; 2], b: [f64; 2], n: usize) -> f64 {
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
            (q[0] - x).hypot(q[1] - y)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn primitives_match_closed_forms() {
    agrees("sphere(1.3)", 3.0, 1e-12, |p| p.length() - 1.3);
    let h = DVec3::new(0.5, 1.0, 1.5);
    agrees("box([0.5, 1, 1.5])", 3.0, 1e-12, |p| box_sd(p, h));
    // A rounded box is the inner box h − r grown by r: its distance is the inner one minus r.
    let hi = h - DVec3::splat(0.25);
    agrees("round_box([0.5, 1, 1.5], 0.25)", 3.0, 1e-12, |p| {
        box_sd(p, hi) - 0.25
    });
    // Torus around y: distance to the core circle of radius R in the xz plane, minus r.
    agrees("torus(1.2, 0.3)", 2.5, 1e-12, |p| {
        let c = DVec3::new(p.x, 0.0, p.z).normalize() * 1.2;
        (p - c).length() - 0.3
    });
    // Capsule: dense sampling of the segment.
    let (a, b) = (DVec3::new(-0.5, 0.2, 0.1), DVec3::new(0.7, -0.4, 0.9));
    agrees(
        "capsule([-0.5, 0.2, 0.1], [0.7, -0.4, 0.9], 0.35)",
        2.0,
        1e-3,
        |p| {
            (0..=2000)
                .map(|i| (p - a.lerp(b, i as f64 / 2000.0)).length())
                .fold(f64::INFINITY, f64::min)
                - 0.35
        },
    );
    // Capped cylinder, y ∈ [−0.8, 0.8], radius 0.6: nearest point of the (ρ, y) rectangle.
    agrees("cylinder(0.8, 0.6)", 2.0, 1e-12, |p| {
        let (rho, y) = (p.x.hypot(p.z), p.y);
        if rho <= 0.6 && y.abs() <= 0.8 {
            -(0.6 - rho).min(0.8 - y.abs())
        } else {
            (rho - rho.min(0.6)).hypot(y - y.clamp(-0.8, 0.8))
        }
    });
    // Cone, base radius 0.7 at y = 0, apex at y = 1.5: the (ρ, y) triangle by dense sampling
    // of its two sides, inside by the half-plane tests.
    agrees("cone(0.7, 1.5)", 2.0, 1e-3, |p| {
        let q = [p.x.hypot(p.z), p.y];
        let d = seg_brute(q, [0.0, 0.0], [0.7, 0.0], 2000).min(seg_brute(
            q,
            [0.7, 0.0],
            [0.0, 1.5],
            2000,
        ));
        let inside = q[1] >= 0.0 && q[0] / 0.7 + q[1] / 1.5 <= 1.0;
        if inside { -d } else { d }
    });
    // Plane with an unnormalised normal: n̂·p − d.
    agrees("plane([0, 2, 0], 0.5)", 3.0, 1e-12, |p| p.y - 0.5);
    agrees("plane([1, 1, 0], 0)", 3.0, 1e-12, |p| {
        (p.x + p.y) / 2f64.sqrt()
    });
}

#[test]
fn ellipsoid_is_a_conservative_distance() {
    let r = DVec3::new(1.0, 0.5, 0.8);
    let func = f("ellipsoid([1, 0.5, 0.8])");
    // The surface sampled densely (spacing below 3·10⁻³).
    let mut surf = Vec::new();
    for i in 0..=400 {
        let theta = std::f64::consts::PI * i as f64 / 400.0;
        for j in 0..800 {
            let phi = std::f64::consts::TAU * j as f64 / 800.0;
            surf.push(
                DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ) * r,
            );
        }
    }
    let mut rng = Pcg32::new(3, 0);
    for _ in 0..200 {
        let p = rnd_point(&mut rng, 1.5);
        let v = func.eval(p);
        let inside = (p / r).length() < 1.0;
        assert_eq!(v < 0.0, inside, "{p}: {v}");
        let d = surf
            .iter()
            .map(|s| (p - *s).length())
            .fold(f64::INFINITY, f64::min);
        // Never more than the true distance (up to the sampling), never less than its share
        // min r / max r.
        assert!(v.abs() <= d + 3e-3, "{p}: {v} vs {d}");
        assert!(v.abs() >= d * 0.5 - 3e-3, "{p}: {v} vs {d}");
    }
    // Exact along the shortest semi-axis.
    assert!((func.eval(DVec3::new(0.0, 2.0, 0.0)) - 1.5).abs() < 1e-12);
}

#[test]
fn operators_obey_their_laws() {
    let mut rng = Pcg32::new(11, 0);
    let a = f("sphere(1)");
    let b = f("translate([0.8, 0, 0], box([0.5, 0.5, 0.5]))");
    let cases = [
        (
            "union(sphere(1), translate([0.8, 0, 0], box([0.5, 0.5, 0.5])))",
            0,
        ),
        (
            "intersection(sphere(1), translate([0.8, 0, 0], box([0.5, 0.5, 0.5])))",
            1,
        ),
        (
            "difference(sphere(1), translate([0.8, 0, 0], box([0.5, 0.5, 0.5])))",
            2,
        ),
    ];
    let k = 0.3;
    let su = f("smooth_union(sphere(1), translate([0.8, 0, 0], box([0.5, 0.5, 0.5])), 0.3)");
    let si = f("smooth_intersection(sphere(1), translate([0.8, 0, 0], box([0.5, 0.5, 0.5])), 0.3)");
    let sd = f("smooth_difference(sphere(1), translate([0.8, 0, 0], box([0.5, 0.5, 0.5])), 0.3)");
    let rot = f("rotate(90, [0, 0, 1], box([2, 1, 0.5]))");
    let scaled = f("scale(2.5, sphere(1))");
    let twist0 = f("twist(0, box([0.3, 1, 0.6]))");
    let twisted_cyl = f("twist(2, cylinder(1, 0.5))");
    for _ in 0..2000 {
        let p = rnd_point(&mut rng, 2.5);
        let (x, y) = (a.eval(p), b.eval(p));
        for (src, which) in cases {
            let want = [x.min(y), x.max(y), x.max(-y)][which];
            assert!((f(src).eval(p) - want).abs() < 1e-12, "{src}");
        }
        // The blends stay within k/4 of the sharp version, on the right side, and equal it
        // where the operands differ by more than k.
        let (u, i, d) = (su.eval(p), si.eval(p), sd.eval(p));
        assert!(u <= x.min(y) + 1e-12 && u >= x.min(y) - k / 4.0 - 1e-12);
        assert!(i >= x.max(y) - 1e-12 && i <= x.max(y) + k / 4.0 + 1e-12);
        assert!(d >= x.max(-y) - 1e-12 && d <= x.max(-y) + k / 4.0 + 1e-12);
        if (x - y).abs() > k {
            assert!((u - x.min(y)).abs() < 1e-12);
        }
        // A box turned a quarter about z swaps its x and y extents.
        assert!((rot.eval(p) - box_sd(p, DVec3::new(1.0, 2.0, 0.5))).abs() < 1e-9);
        assert!((scaled.eval(p) - (p.length() - 2.5)).abs() < 1e-12);
        assert!((twist0.eval(p) - box_sd(p, DVec3::new(0.3, 1.0, 0.6))).abs() < 1e-12);
        // A twist leaves a body of revolution about y unchanged.
        let cyl = f("cylinder(1, 0.5)").eval(p);
        assert!((twisted_cyl.eval(p) - cyl).abs() < 1e-12);
    }
    // Endless repetition along x: the nearest of the spheres at x = 2k.
    let rep = f("repeat([2, 0, 0], sphere(0.5))");
    assert!(!rep.bounds().is_finite());
    let limited = f("repeat([2, 0, 0], [1, 0, 0], sphere(0.5))");
    let lb = limited.bounds();
    assert!((lb.lo.x + 2.5).abs() < 1e-12 && (lb.hi.x - 2.5).abs() < 1e-12);
    for _ in 0..500 {
        let p = rnd_point(&mut rng, 10.0);
        let near = |n: i32| {
            (-n..=n)
                .map(|k| (p - DVec3::new(2.0 * k as f64, 0.0, 0.0)).length() - 0.5)
                .fold(f64::INFINITY, f64::min)
        };
        assert!((rep.eval(p) - near(10)).abs() < 1e-12, "{p}");
        assert!((limited.eval(p) - near(1)).abs() < 1e-12, "{p}");
    }
}

#[test]
fn bounds_contain_the_solid_and_lipschitz_bounds_hold() {
    let mut rng = Pcg32::new(5, 0);
    for src in [
        "smooth_union(sphere(0.6), translate([0, 0.5, 0], torus(0.7, 0.18)), 0.25)",
        "twist(1.5, box([0.6, 1, 0.2]))",
        "rotate(30, [1, 1, 0], difference(round_box([1, 0.5, 0.7], 0.1), cylinder(1, 0.3)))",
        "scale(0.5, translate([1, 0, 0], cone(0.5, 1)))",
        "intersection(plane([0, 1, 0], 0.2), sphere(1))",
        "repeat([1, 0, 1], [2, 0, 2], ellipsoid([0.3, 0.5, 0.2]))",
    ] {
        let func = f(src);
        let b = func.bounds();
        assert!(b.is_finite(), "{src}");
        let pad = 0.5 * (b.hi - b.lo);
        let region = Aabb {
            lo: b.lo - pad,
            hi: b.hi + pad,
        };
        let l = func.lipschitz(&region);
        let mut worst: f64 = 0.0;
        for _ in 0..20000 {
            let p = region.lo
                + (region.hi - region.lo)
                    * DVec3::new(
                        rnd(&mut rng, 0.0, 1.0),
                        rnd(&mut rng, 0.0, 1.0),
                        rnd(&mut rng, 0.0, 1.0),
                    );
            // Every point of the solid lies in the box.
            if func.eval(p) < 0.0 {
                assert!(p.cmpge(b.lo).all() && p.cmple(b.hi).all(), "{src}: {p}");
            }
            let q = p + rnd_dir(&mut rng) * rnd(&mut rng, 1e-4, 0.1);
            if q.cmpge(region.lo).all() && q.cmple(region.hi).all() {
                worst = worst.max((func.eval(p) - func.eval(q)).abs() / (p - q).length());
            }
        }
        assert!(worst <= l * (1.0 + 1e-9), "{src}: slope {worst} > L = {l}");
        if src.starts_with("twist") {
            // The twist really stretches: its bound is above 1, and so is the slope found.
            assert!(l > 1.2 && worst > 1.05, "{src}: {worst} vs {l}");
        }
    }
}

#[test]
fn meaning_errors_name_the_problem_and_its_column() {
    let cases: [(&str, usize, &str); 10] = [
        (
            "spher(1)",
            0,
            "unknown function 'spher'; the functions are sphere, box, round_box",
        ),
        (
            "sphere(-1)",
            7,
            "sphere: the radius must be positive, found -1",
        ),
        ("sphere(1, 2)", 10, "sphere: expected 1 argument(s)"),
        ("box(1)", 4, "box: expected a vector [x, y, z]"),
        ("union(sphere(1), 2)", 17, "expected a distance expression"),
        (
            "union(sphere(1))",
            15,
            "expected at least 2 distance expressions",
        ),
        ("translate(sphere(1), [1, 0, 0])", 10, "expected a vector"),
        ("round_box([1, 1, 1], 2)", 21, "in [0, min half-extent]"),
        (
            "repeat([1, 0, 0], [1.5, 0, 0], sphere(0.2))",
            18,
            "whole numbers",
        ),
        ("rotate(10, [0, 0, 0], sphere(1))", 11, "the axis is zero"),
    ];
    for (src, col, msg) in cases {
        let e = SdfFunction::parse(src).unwrap_err();
        assert_eq!(e.offset, col, "{src}: {e}");
        assert!(e.message.contains(msg), "{src}: {e}");
    }
}

/// A placement turning and stretching the object (non-uniform scale), off the origin.
fn placement() -> Placement {
    let t = Transform::translate(Vec3::new(0.3, -0.2, 0.5)).m
        * Transform::rotate(35.0, Vec3::new(1.0, 2.0, 0.5)).unwrap().m
        * Transform::scale(Vec3::new(1.3, 0.8, 1.1)).unwrap().m;
    Placement::new(Transform::from_matrix(t).unwrap(), false)
}

fn sdf_shape(src: &str, placement: Placement) -> Shape {
    Shape::Sdf(Box::new(
        Sdf::new(placement, Arc::new(f(src)), None).unwrap(),
    ))
}

/// Random rays aimed near a shape of world bounding radius ~`r` around `c`: from outside
/// (at 3–6 r) and, one in five, from inside.
fn rays(n: usize, seed: u64, c: Vec3, r: f32) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    (0..n)
        .map(|i| {
            let target = c + rnd_point(&mut rng, r as f64).as_vec3a();
            let o = if i % 5 == 0 {
                c + rnd_point(&mut rng, 0.2 * r as f64).as_vec3a()
            } else {
                c + rnd_dir(&mut rng).as_vec3a() * rnd(&mut rng, 3.0, 6.0) as f32 * r
            };
            let mut ray = Ray::new(o, (target - o) * rnd(&mut rng, 0.3, 2.0) as f32);
            if i % 7 == 0 {
                // Some rays stop short.
                ray.t_max = rnd(&mut rng, 0.2, 1.2) as f32;
            }
            ray
        })
        .collect()
}

/// Compares the sphere-traced object with an analytic `reference` on thousands of rays: the
/// same hit or miss, t within 10⁻⁴ relative plus the hit tolerance over the cosine, normals
/// within 10⁻³ of the implicit function's normalised gradient at the hit point; rays grazing the surface (the reference changes its answer when the surface
/// moves by 10⁻³, `grazing`) are left out, and must be few.
fn compare_with(
    name: &str,
    sdf: &Shape,
    reference: impl Fn(&Ray) -> Option<f64>,
    gradient: impl Fn(DVec3) -> DVec3,
    grazing: impl Fn(&Ray) -> bool,
    rays: &[Ray],
) {
    let Shape::Sdf(shape) = sdf else {
        panic!("not an sdf")
    };
    let pl = shape.placement;
    let normal_to_world = DMat3::from_mat4(pl.to_world.m.as_dmat4())
        .inverse()
        .transpose();
    let (mut hits, mut skipped) = (0, 0);
    for ray in rays {
        if grazing(ray) {
            skipped += 1;
            continue;
        }
        let got = sdf.intersect(ray);
        match (got, reference(ray)) {
            (None, None) => {}
            (Some(h), Some(t)) => {
                hits += 1;
                let si = sdf.interaction(ray, &h, &[]);
                // The implicit function's gradient at the shape's own hit point.
                let p_obj = pl.to_object.transform_point3(si.p.as_dvec3());
                let n = (normal_to_world * gradient(p_obj)).normalize().as_vec3a();
                let d = normalize(ray.d);
                let cos = n.dot(d).abs().max(1e-3) as f64;
                let dist = t * ray.d.length() as f64;
                let tol = 1e-4 * t + 2.0 * (1e-5 * dist + 1e-5) / cos / ray.d.length() as f64;
                assert!(
                    (h.t as f64 - t).abs() <= tol,
                    "{name}: t {} vs {t} (tol {tol}) on {ray:?}",
                    h.t
                );
                assert!(
                    (si.n - n).length() < 1e-3,
                    "{name}: normal {} vs {n} on {ray:?}",
                    si.n
                );
            }
            (g, r) => panic!("{name}: sdf {g:?} vs reference {r:?} on {ray:?}"),
        }
    }
    assert!(hits > rays.len() / 4, "{name}: only {hits} hits");
    assert!(
        skipped < rays.len() / 50,
        "{name}: {skipped} grazing rays skipped"
    );
}

#[test]
fn sphere_traced_sphere_matches_the_quadric() {
    let pl = placement();
    let sdf = sdf_shape("sphere(0.9)", pl);
    let sphere = |r: f32| Shape::Sphere(Box::new(Sphere::new(pl, r, -r, r, 360.0)));
    let (exact, small, big) = (sphere(0.9), sphere(0.899), sphere(0.901));
    let rays = rays(6000, 1, Vec3::new(0.3, -0.2, 0.5), 1.2);
    // ∇(x² + y² + z² − r²) ∝ p.
    const GRADIENT: fn(DVec3) -> DVec3 = |p| p;
    compare_with(
        "sphere",
        &sdf,
        |ray| exact.intersect(ray).map(|h| h.t as f64),
        GRADIENT,
        |ray| {
            let (a, b) = (small.intersect(ray), big.intersect(ray));
            a.is_some() != b.is_some()
                || a.zip(b)
                    .is_some_and(|(a, b)| (a.t - b.t).abs() > 0.05 * a.t)
        },
        &rays,
    );
}

#[test]
fn sphere_traced_box_matches_the_slab_test() {
    let pl = placement();
    let sdf = sdf_shape("translate([0.1, 0.2, 0], box([0.7, 0.4, 0.9]))", pl);
    let cuboid = |e: f32| {
        let c = Vec3::new(0.1, 0.2, 0.0);
        let h = Vec3::new(0.7, 0.4, 0.9) + Vec3::splat(e);
        Shape::Box(Box::new(Cuboid::new(pl, c - h, c + h)))
    };
    let (exact, small, big) = (cuboid(0.0), cuboid(-1e-3), cuboid(1e-3));
    let rays = rays(6000, 2, Vec3::new(0.3, -0.2, 0.5), 1.2);
    // Off the edges, the normal of the face whose slab the point is most outside of.
    const GRADIENT: fn(DVec3) -> DVec3 = |p| {
        let q = (p - DVec3::new(0.1, 0.2, 0.0)) / DVec3::new(0.7, 0.4, 0.9);
        let k = q.abs().max_position();
        DVec3::AXES[k] * q[k].signum()
    };
    compare_with(
        "box",
        &sdf,
        |ray| exact.intersect(ray).map(|h| h.t as f64),
        GRADIENT,
        |ray| {
            let (a, b) = (small.intersect(ray), big.intersect(ray));
            a.is_some() != b.is_some()
                || a.zip(b)
                    .is_some_and(|(a, b)| (a.t - b.t).abs() > 0.05 * a.t)
        },
        &rays,
    );
}

/// The first root of the torus's implicit quartic along the ray, in object space:
/// F(p) = (|p|² + R² − r²)² − 4R²(x² + z²), by a fine scan for a sign change and bisection.
fn torus_reference(o: DVec3, d: DVec3, big: f64, r: f64, t_max: f64) -> Option<f64> {
    let imp = |t: f64| {
        let p = o + d * t;
        let s = p.length_squared() + big * big - r * r;
        s * s - 4.0 * big * big * (p.x * p.x + p.z * p.z)
    };
    // Only inside the bounding sphere |p| ≤ R + r + 0.01: |o + t·d|² = ρ² at t = (−b ± √Δ)/a.
    let rho = big + r + 0.01;
    let (a, b, c) = (d.length_squared(), o.dot(d), o.length_squared() - rho * rho);
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let (enter, exit) = ((-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a);
    // Step a fiftieth of the tube radius (along |d|), far shorter than any chord.
    let dt = 0.02 * r / d.length();
    let end = t_max.min(exit);
    let start = enter.max(0.0);
    let (mut t0, mut f0) = (start, imp(start));
    while t0 < end {
        let t1 = (t0 + dt).min(end);
        let f1 = imp(t1);
        if (f0 < 0.0) != (f1 < 0.0) {
            let (mut a, mut b) = (t0, t1);
            for _ in 0..100 {
                let m = 0.5 * (a + b);
                if (imp(m) < 0.0) == (f0 < 0.0) {
                    a = m
                } else {
                    b = m
                }
            }
            return Some(0.5 * (a + b));
        }
        (t0, f0) = (t1, f1);
    }
    None
}

#[test]
fn sphere_traced_torus_matches_its_quartic() {
    let pl = placement();
    let (big, r) = (0.8, 0.25);
    let sdf = sdf_shape("torus(0.8, 0.25)", pl);
    let to_obj = pl.to_object;
    let rays = rays(6000, 3, Vec3::new(0.3, -0.2, 0.5), 1.4);
    let obj = |ray: &Ray| {
        (
            to_obj.transform_point3(ray.o.as_dvec3()),
            to_obj.transform_vector3(ray.d.as_dvec3()),
        )
    };
    compare_with(
        "torus",
        &sdf,
        |ray| {
            let (o, d) = obj(ray);
            torus_reference(o, d, big, r, ray.t_max as f64)
        },
        // ∇F = 4(|p|² + R² − r²)p − 8R²(x, 0, z).
        |p| {
            let k = p.length_squared() + big * big - r * r;
            4.0 * k * p - 8.0 * big * big * DVec3::new(p.x, 0.0, p.z)
        },
        |ray| {
            let (o, d) = obj(ray);
            let tm = ray.t_max as f64;
            let (a, b) = (
                torus_reference(o, d, big, r - 1e-3, tm),
                torus_reference(o, d, big, r + 1e-3, tm),
            );
            a.is_some() != b.is_some() || a.zip(b).is_some_and(|(a, b)| (a - b).abs() > 0.05 * a)
        },
        &rays,
    );
}

#[test]
fn rays_leaving_the_surface_do_not_find_it_again() {
    let pl = placement();
    let mut rng = Pcg32::new(9, 0);
    for src in [
        "sphere(0.9)",
        "box([0.7, 0.4, 0.9])",
        "smooth_union(sphere(0.6), translate([0, 0.5, 0], torus(0.7, 0.18)), 0.25)",
    ] {
        let shape = sdf_shape(src, pl);
        let convex = !src.starts_with("smooth");
        let mut found = 0;
        for ray in rays(3000, 4, Vec3::new(0.3, -0.2, 0.5), 1.2) {
            let Some(h) = shape.intersect(&ray) else {
                continue;
            };
            let si = shape.interaction(&ray, &h, &[]);
            // At a box's edge the normal blends two faces and "inward" is ambiguous: skip the
            // points within 10⁻³ of two faces.
            let q = pl.to_object.transform_point3(si.p.as_dvec3()).abs();
            let h = DVec3::new(0.7, 0.4, 0.9);
            if src.starts_with("box")
                && ((q - h).abs().cmplt(DVec3::splat(1e-3)).bitmask()).count_ones() >= 2
            {
                continue;
            }
            // Outward: a convex solid is never met again; any solid is not met at t ≈ 0.
            // Directions at least 11° off the tangent plane, so that inward chords are long.
            let mut w = rnd_dir(&mut rng).as_vec3a();
            while w.dot(si.n).abs() < 0.2 {
                w = rnd_dir(&mut rng).as_vec3a();
            }
            if w.dot(si.n) < 0.0 {
                w = -w;
            }
            let out = si.spawn_ray(w);
            if let Some(again) = shape.intersect(&out) {
                assert!(
                    !convex,
                    "{src}: left at {} and met again at {}",
                    si.p, again.t
                );
                assert!(
                    again.t * w.length() > 1e-3,
                    "{src}: self-hit at t = {}",
                    again.t
                );
            }
            // Inward: the far side, never the point itself.
            let inward = si.spawn_ray(-w);
            let back = shape.intersect(&inward).unwrap_or_else(|| {
                panic!("{src}: a ray into the solid never leaves: {inward:?} from {si:?}")
            });
            assert!(back.t > 1e-3, "{src}: inward ray stopped at {}", back.t);
            // A shadow ray to a point outside.
            let target = si.p + si.n * 0.5;
            assert!(shape.intersect(&si.spawn_ray_to(target)).is_none() || !convex);
            found += 1;
        }
        assert!(found > 500, "{src}: {found}");
    }
}

#[test]
fn scenes_build_sdf_objects_and_refuse_them_as_emitters() {
    use lancer::Scene;
    use lancer::math::Rgb;
    use lancer::scene::desc::{AreaLightDesc, Geometry, SceneDesc, ShapeDesc};
    use lancer::shape::SdfDesc;
    let shape = |src: &str, bounds, area_light| SceneDesc {
        shapes: vec![ShapeDesc {
            medium_interface: None,
            geometry: Geometry::Sdf(SdfDesc {
                function: Arc::new(f(src)),
                bounds,
            }),
            object_to_world: Transform::translate(Vec3::new(0.0, 0.0, -3.0)),
            reverse_orientation: false,
            material: 0,
            area_light,
            alpha: None,
        }],
        ..SceneDesc::default()
    };
    assert!(Scene::build(&shape("sphere(1)", None, None)).is_ok());
    let light = AreaLightDesc {
        l: Rgb::ONE,
        two_sided: false,
        spectrum: None,
        power: None,
        image: None,
    };
    let e = Scene::build(&shape("sphere(1)", None, Some(light)))
        .err()
        .unwrap();
    assert!(e.to_string().contains("area light"), "{e}");
    let e = Scene::build(&shape("plane([0, 1, 0], 0)", None, None))
        .err()
        .unwrap();
    assert!(e.to_string().contains("point3 min"), "{e}");
    let clipped = Some((Vec3::splat(-1.0), Vec3::splat(1.0)));
    assert!(Scene::build(&shape("plane([0, 1, 0], 0)", clipped, None)).is_ok());
}
