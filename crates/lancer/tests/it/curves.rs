//! pbrt's curves, through the whole scene (segments split into pieces, BVH): straight curves
//! against the analytic closest approach of the ray and the axis, ribbons against the
//! rectangle they sweep, and a bent curve against a dense brute-force sampling of its spine.

use crate::common;

use crate::common::shapes::uniform3;

use lancer::Scene;
use lancer::math::{PackedVec3, Transform, Vec3, cross, normalize};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::{AreaLightDesc, Geometry, SceneDesc, ShapeDesc};
use lancer::shape::{CurveBasis, CurveDesc, CurveType, bezier_eval};
use std::sync::Arc;

fn scene_of(curve: CurveDesc, to_world: Transform) -> Scene {
    common::shapes::scene_of(Geometry::Curve(Arc::new(curve)), to_world, false)
}

/// A straight cubic from a to b with evenly spaced control points (so that u is linear
/// along the axis).
fn straight(a: Vec3, b: Vec3, kind: CurveType, w0: f32, w1: f32) -> CurveDesc {
    CurveDesc {
        points: [a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]
            .map(PackedVec3::from)
            .to_vec(),
        basis: CurveBasis::Bezier,
        degree: 3,
        kind,
        width0: w0,
        width1: w1,
        normals: if kind == CurveType::Ribbon {
            vec![PackedVec3::Z, PackedVec3::Z]
        } else {
            vec![]
        },
        split_depth: 3,
    }
}

/// Closest approach of the lines o + t·d and a + s·c: (t, s, distance, side), side the sign
/// of (ray point − axis point)·(d × c).
fn closest(o: Vec3, d: Vec3, a: Vec3, c: Vec3) -> Option<(f64, f64, f64, f64)> {
    let (o, d, a, c) = (o.as_dvec3(), d.as_dvec3(), a.as_dvec3(), c.as_dvec3());
    let w = o - a;
    let (aa, bb, cc, dd, ee) = (d.dot(d), d.dot(c), c.dot(c), d.dot(w), c.dot(w));
    let den = aa * cc - bb * bb;
    if den < 1e-9 * aa * cc {
        return None;
    }
    let t = (bb * ee - cc * dd) / den;
    let s = (aa * ee - bb * dd) / den;
    let r = (o + t * d) - (a + s * c);
    Some((t, s, r.length(), r.dot(d.cross(c)).signum()))
}

/// Flat and cylinder curves that are straight line segments: the ray hits exactly when it
/// passes within w(s)/2 of the axis at an axis parameter s ∈ [0, 1], at t of closest
/// approach, with u = s and v = ½ ± distance/w. Under a rotation, uniform scale and
/// translation (the width scales too). Cylinder normals: perpendicular to the axis, turned
/// from the ray by θ = π(v − ½).
#[test]
fn straight_curves_match_the_closest_approach_of_ray_and_axis() {
    let scale = 1.5f32;
    let xf = Transform::translate(Vec3::new(0.3, -0.2, 1.0))
        * Transform::rotate(35.0, Vec3::new(1.0, 2.0, 0.5)).unwrap()
        * Transform::scale(Vec3::splat(scale)).unwrap();
    for kind in [CurveType::Flat, CurveType::Cylinder] {
        let (a0, b0) = (Vec3::new(-1.0, 0.2, 0.0), Vec3::new(1.2, -0.3, 0.4));
        let (w0, w1) = (0.3, 0.1);
        let scene = scene_of(straight(a0, b0, kind, w0, w1), xf);
        let (a, b) = (xf.point(a0), xf.point(b0));
        let mut rng = Pcg32::new(7, 1);
        let (mut hits, mut checked) = (0, 0);
        for i in 0..5000 {
            let target = a.lerp(b, -0.1 + 1.2 * rng.uniform()) + uniform3(&mut rng, -0.3, 0.3);
            let o = target + uniform3(&mut rng, -1.0, 1.0).normalize_or_zero() * 5.0;
            let ray = Ray::new(o, target - o);
            let Some((t, s, dist, side)) = closest(o, ray.d, a, b - a) else {
                continue;
            };
            let w = (w0 + (w1 - w0) * s as f32) as f64 * scale as f64;
            // Leave out rays on the edge of the decision, where rounding may go either way.
            if (dist - w / 2.0).abs() < 1e-4 || s.abs() < 1e-4 || (s - 1.0).abs() < 1e-4 {
                continue;
            }
            checked += 1;
            let expect = dist < w / 2.0 && (0.0..=1.0).contains(&s) && t > 0.0;
            let got = scene.intersect(&ray);
            assert_eq!(
                got.is_some(),
                expect,
                "{kind:?} ray {i}: dist {dist} w {w} s {s}"
            );
            let Some(h) = got else { continue };
            hits += 1;
            let si = h.si;
            assert!(
                (si.t as f64 - t).abs() < 1e-4 * t,
                "{kind:?} ray {i}: t {} vs {t}",
                si.t
            );
            assert!((si.uv.x as f64 - s).abs() < 1e-4, "u {} vs {s}", si.uv.x);
            let v = 0.5 + side * dist / w;
            assert!((si.uv.y as f64 - v).abs() < 1e-3, "v {} vs {v}", si.uv.y);
            let axis = normalize(b - a);
            assert!(si.n.dot(axis).abs() < 1e-3, "normal along the axis");
            let dperp = normalize(ray.d - axis * ray.d.dot(axis));
            let cos = si.n.dot(dperp).abs() as f64;
            let want = match kind {
                CurveType::Cylinder => (std::f64::consts::PI * (v - 0.5)).cos().abs(),
                _ => 1.0,
            };
            assert!((cos - want).abs() < 2e-3, "{kind:?}: |n·d| {cos} vs {want}");
        }
        assert!(checked > 4500 && hits > 1000, "{checked} rays, {hits} hits");
    }
}

/// A straight ribbon with a constant normal is a rectangle: rays perpendicular to its axis
/// hit it exactly where they cross the rectangle, with u the position along the axis and
/// v = ½ ± y/w across; t is pbrt's (closest approach to the axis).
#[test]
fn straight_ribbons_are_rectangles() {
    let (len, w) = (2.0f32, 0.4f32);
    let scene = scene_of(
        straight(
            Vec3::ZERO,
            Vec3::new(len, 0.0, 0.0),
            CurveType::Ribbon,
            w,
            w,
        ),
        Transform::IDENTITY,
    );
    let mut rng = Pcg32::new(3, 9);
    let (mut hits, mut checked) = (0, 0);
    for i in 0..5000 {
        let target = Vec3::new(-0.2 + 2.4 * rng.uniform(), (rng.uniform() - 0.5) * 0.8, 0.0);
        // Perpendicular to the axis (x), at least 10° away from grazing.
        let ang = (10.0f32 + 160.0 * rng.uniform()).to_radians();
        let d = Vec3::new(0.0, ang.cos(), -ang.sin());
        let o = target - 3.0 * d;
        let ray = Ray::new(o, d);
        let (x, y) = (target.x, target.y);
        if (x.abs() < 1e-4) || ((x - len).abs() < 1e-4) || ((y.abs() - w / 2.0).abs() < 1e-4) {
            continue;
        }
        checked += 1;
        let expect = (0.0..=len).contains(&x) && y.abs() <= w / 2.0;
        let got = scene.intersect(&ray);
        assert_eq!(got.is_some(), expect, "ray {i}: x {x} y {y}");
        let Some(h) = got else { continue };
        hits += 1;
        let si = h.si;
        assert!(
            (si.uv.x - x / len).abs() < 1e-4,
            "u {} vs {}",
            si.uv.x,
            x / len
        );
        assert!(
            ((si.uv.y - 0.5).abs() - y.abs() / w).abs() < 1e-3,
            "v {} vs y {y}",
            si.uv.y
        );
        // Closest approach of the ray to the x axis: t = −(o_yz·d_yz)/|d_yz|².
        let t = -(o.y * d.y + o.z * d.z) / (d.y * d.y + d.z * d.z);
        assert!((si.t - t).abs() < 1e-4 * t, "t {} vs {t}", si.t);
        assert!(
            (si.n.abs() - Vec3::Z).length() < 1e-4,
            "ribbon normal {}",
            si.n
        );
    }
    assert!(checked > 4900 && hits > 1500, "{checked} rays, {hits} hits");
}

/// A bent cylinder curve against its spine sampled at 20 000 points: rays passing a local
/// minimum of their distance to the spine closer than w(u)/2 − tol must hit, rays staying
/// farther than w(u)/2 + tol everywhere must miss (tol = w/20, pbrt's flatness bound), and
/// the nearest hit lies at the depth of the nearest such minimum.
#[test]
fn a_bent_curve_agrees_with_its_sampled_spine() {
    let cp = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.8, 1.0, 0.5),
        Vec3::new(-0.6, 2.0, -0.3),
        Vec3::new(0.3, 3.0, 0.0),
    ];
    let (w0, w1) = (0.3f32, 0.05f32);
    for kind in [CurveType::Cylinder, CurveType::Flat] {
        let desc = CurveDesc {
            points: cp.map(PackedVec3::from).to_vec(),
            basis: CurveBasis::Bezier,
            degree: 3,
            kind,
            width0: w0,
            width1: w1,
            normals: vec![],
            split_depth: 3,
        };
        let scene = scene_of(desc, Transform::IDENTITY);
        const N: usize = 20_000;
        let spine: Vec<(Vec3, f32)> = (0..=N)
            .map(|k| {
                let u = k as f32 / N as f32;
                (bezier_eval(&cp, u).0, w0 + (w1 - w0) * u)
            })
            .collect();
        let mut rng = Pcg32::new(11, 2);
        let (mut hits, mut misses, mut skipped) = (0, 0, 0);
        for i in 0..3000 {
            let k = (rng.uniform() * N as f32) as usize;
            let target = spine[k].0 + uniform3(&mut rng, -0.2, 0.2);
            let o = target + uniform3(&mut rng, -1.0, 1.0).normalize_or_zero() * 6.0;
            let d = normalize(target - o);
            let dist = |p: Vec3| cross(p - o, d).length();
            let ds: Vec<f32> = spine.iter().map(|&(p, _)| dist(p)).collect();
            let tol = 0.05 * w0;
            let mut must_hit_depth = f32::INFINITY;
            let mut must_hit_tangent = Vec3::X;
            let mut unsure_depth = f32::INFINITY;
            let mut all_far = true;
            for j in 0..=N {
                let (p, w) = spine[j];
                if ds[j] < w / 2.0 + tol {
                    all_far = false;
                }
                let local_min = j > 0 && j < N && ds[j] <= ds[j - 1] && ds[j] <= ds[j + 1];
                if !local_min {
                    continue;
                }
                let depth = (p - o).dot(d);
                // Rays running nearly along the spine see pbrt's camera-facing ribbon edge-on
                // (its projection is shorter than wide): no decision there.
                let tangent = normalize(spine[j + 1].0 - spine[j - 1].0);
                let grazing = tangent.dot(d).abs() > 0.9;
                if ds[j] < w / 2.0 - tol && !grazing {
                    if depth < must_hit_depth {
                        must_hit_depth = depth;
                        must_hit_tangent = spine[j + 1].0 - spine[j - 1].0;
                    }
                } else if ds[j] < w / 2.0 + tol || grazing {
                    unsure_depth = unsure_depth.min(depth);
                }
            }
            let got = scene.intersect(&Ray::new(o, d));
            if all_far {
                assert!(got.is_none(), "{kind:?} ray {i} should miss");
                misses += 1;
            } else if must_hit_depth.is_finite() {
                let h = got.unwrap_or_else(|| panic!("{kind:?} ray {i} should hit"));
                hits += 1;
                // The hit lies on the curve: some spine point within w/2 + tol of the ray
                // at the hit's depth.
                let on_curve = (0..=N).any(|j| {
                    ds[j] < spine[j].1 / 2.0 + tol
                        && ((spine[j].0 - o).dot(d) - h.si.t).abs() < 0.01
                });
                assert!(
                    on_curve,
                    "{kind:?} ray {i}: hit at t {} is off the curve",
                    h.si.t
                );
                // And it is the nearest part, unless the ray runs nearly along the spine there
                // (then the point of closest approach is ill-defined, in pbrt too). pbrt treats
                // each leaf of its subdivision as straight, the hit being the curve point at
                // the chord's closest approach: its depth may differ from the true closest
                // approach by a fraction of the width.
                let crossing = cross(normalize(must_hit_tangent), d).length() > 0.5;
                if unsure_depth > must_hit_depth && crossing {
                    assert!(
                        (h.si.t - must_hit_depth).abs() < 0.1,
                        "{kind:?} ray {i}: t {} vs depth {must_hit_depth}",
                        h.si.t
                    );
                }
            } else {
                skipped += 1;
            }
        }
        assert!(
            hits > 800 && misses > 500,
            "{hits} hits, {misses} misses, {skipped} unsure"
        );
        assert!(skipped < 600, "{skipped} unsure rays");
    }
}

/// A ray leaving a curve (spawned from the hit as the integrators do) does not find the
/// same spot again.
#[test]
fn spawned_rays_leave_the_curve() {
    let scene = scene_of(
        straight(
            Vec3::ZERO,
            Vec3::new(0.0, 2.0, 0.0),
            CurveType::Cylinder,
            0.2,
            0.2,
        ),
        Transform::IDENTITY,
    );
    let mut rng = Pcg32::new(5, 5);
    let mut tested = 0;
    for _ in 0..2000 {
        let target = Vec3::new((rng.uniform() - 0.5) * 0.15, 0.2 + 1.6 * rng.uniform(), 0.0);
        let o = target + Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, 3.0);
        let Some(h) = scene.intersect(&Ray::new(o, target - o)) else {
            continue;
        };
        // Back towards the side the ray came from.
        let back = h.si.wo + 0.3 * uniform3(&mut rng, -1.0, 1.0);
        let r = h.si.spawn_ray(back);
        if let Some(again) = scene.intersect(&r) {
            assert!(
                (again.si.p - h.si.p).length() > 0.05,
                "re-hit at {} from {}",
                again.si.p,
                h.si.p
            );
        }
        tested += 1;
    }
    assert!(tested > 1000);
}

/// Curves cannot be area lights (pbrt-v4 cannot sample them): building says so.
#[test]
fn an_emitting_curve_is_an_error() {
    let e = Scene::build(&SceneDesc {
        shapes: vec![ShapeDesc {
            medium_interface: None,
            geometry: Geometry::Curve(Arc::new(straight(
                Vec3::ZERO,
                Vec3::X,
                CurveType::Flat,
                0.1,
                0.1,
            ))),
            object_to_world: Transform::IDENTITY,
            reverse_orientation: false,
            material: 0,
            area_light: Some(AreaLightDesc {
                l: Vec3::ONE,
                two_sided: false,
                spectrum: None,
                power: None,
                image: None,
            }),
            alpha: None,
        }],
        ..SceneDesc::default()
    })
    .expect_err("emitting curve");
    assert!(e.to_string().contains("area light"), "{e}");
}
