//! Alpha cut-outs, from a pbrt scene to the rays: alpha 0 is a hole for camera and shadow rays
//! alike, a texture cuts where it is 0, and a fractional alpha lets through that fraction of
//! the rays.

use lancer::Scene;
use lancer::math::{Vec2, Vec3, normalize};
use lancer::ray::Ray;
use lancer::texture::kinds::dots::inside_polka_dot;
use lancer_scene::load_pbrt_str;
use std::path::Path;

fn scene(alpha: &str) -> Scene {
    let text = format!(
        r#"WorldBegin
        Texture "checks" "float" "checkerboard" "float uscale" [2] "float vscale" [2]
            "float tex1" [1] "float tex2" [0]
        Shape "trianglemesh" "point3 P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]
            "integer indices" [0 1 2  0 2 3] "point2 uv" [0 0  1 0  1 1  0 1] {alpha}"#
    );
    let desc = load_pbrt_str(&text, "alpha.pbrt", Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc;
    Scene::build(&desc).unwrap()
}

/// Fraction of `n` rays, spread over the quad, that hit it (camera rays) and that it blocks
/// (shadow rays).
fn coverage(s: &Scene, n: u32) -> (f64, f64) {
    let (mut hits, mut blocked) = (0, 0);
    for i in 0..n {
        for j in 0..n {
            let x = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
            let y = -1.0 + 2.0 * (j as f32 + 0.5) / n as f32;
            let ray = Ray::new(Vec3::new(x, y, 2.0), Vec3::new(0.01, -0.02, -1.0));
            hits += s.intersect(&ray).is_some() as u32;
            blocked += s.intersect_p(&ray) as u32;
        }
    }
    let total = (n * n) as f64;
    (hits as f64 / total, blocked as f64 / total)
}

#[test]
fn alpha_zero_is_a_hole_and_one_is_solid() {
    let (hit, blocked) = coverage(&scene(r#""float alpha" [0]"#), 32);
    assert_eq!((hit, blocked), (0.0, 0.0));
    let (hit, blocked) = coverage(&scene(r#""float alpha" [1]"#), 32);
    assert!(hit > 0.95 && blocked > 0.95, "{hit} {blocked}");
}

#[test]
fn an_alpha_texture_cuts_where_it_is_zero() {
    // A 2×2 checkerboard over the quad: half of it remains.
    let (hit, blocked) = coverage(&scene(r#""texture alpha" "checks""#), 64);
    assert!((hit - 0.5).abs() < 0.03, "{hit}");
    assert!((blocked - 0.5).abs() < 0.03, "{blocked}");
}

#[test]
fn fractional_alpha_lets_that_fraction_through() {
    let (hit, blocked) = coverage(&scene(r#""float alpha" [0.25]"#), 100);
    assert!((hit - 0.25).abs() < 0.02, "{hit}");
    assert!((blocked - 0.25).abs() < 0.02, "{blocked}");
}

/// pbrt-v4's hit on the unit sphere of `sphere_scene` (object space mirrored by `Scale 1 1 -1`)
/// along a ray from `o` in direction `d`: for the near and the far root, t and the texture
/// coordinates (s, t) = 10·(u, v) of the `dots` texture, with u = φ/2π and
/// v = (θ − θ(zmin))/(θ(zmax) − θ(zmin)) = 1 − θ/π of the object-space point (x, y, −z)
/// (pbrt-v4's `Sphere::InteractionFromIntersection`; the mirror is undone before φ and θ).
fn mirrored_sphere_roots(o: Vec3, d: Vec3) -> Option<[(f32, Vec2); 2]> {
    // In double precision, so that the expectation is not the less accurate side.
    let (o, d) = (o.as_dvec3(), d.as_dvec3());
    let (b, c) = (o.dot(d), o.dot(o) - 1.0);
    let disc = b * b - c;
    if disc <= 0.0 {
        return None;
    }
    let st = |t: f64| {
        let p = o + t * d;
        let q = glam::DVec3::new(p.x, p.y, -p.z);
        let phi = q.y.atan2(q.x).rem_euclid(2.0 * std::f64::consts::PI);
        let theta = q.z.clamp(-1.0, 1.0).acos();
        let uv = (
            phi / (2.0 * std::f64::consts::PI),
            1.0 - theta / std::f64::consts::PI,
        );
        Vec2::new(uv.0 as f32, uv.1 as f32) * 10.0
    };
    let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
    Some([(t0 as f32, st(t0)), (t1 as f32, st(t1))])
}

/// Whether (s, t) is inside a dot, and by a margin: the points around it agree.
fn in_dot(st: Vec2) -> Option<bool> {
    let inside = inside_polka_dot(st);
    let around = [(0.02, 0.0), (-0.02, 0.0), (0.0, 0.02), (0.0, -0.02)];
    around
        .iter()
        .all(|&(a, b)| inside_polka_dot(st + Vec2::new(a, b)) == inside)
        .then_some(inside)
}

/// A whole unit sphere cut by polka dots (alpha 0 in the dots), mirrored by `Scale 1 1 -1`
/// with `ReverseOrientation`, as an exporter for a left-handed application writes it.
fn sphere_scene() -> Scene {
    let text = r#"WorldBegin
        Texture "dots" "float" "dots" "float uscale" [10] "float vscale" [10]
        AttributeBegin
            ReverseOrientation
            Scale 1 1 -1
            Shape "sphere" "texture alpha" "dots"
        AttributeEnd"#;
    let desc = load_pbrt_str(text, "dots.pbrt", Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc;
    Scene::build(&desc).unwrap()
}

#[test]
fn a_ray_through_a_hole_in_a_mirrored_sphere_meets_its_far_side_as_pbrt_v4() {
    // pbrt-v4's GeometricPrimitive::Intersect: a hit whose alpha is 0 is skipped and the same
    // primitive intersected again from there, so a ray through a dot of the near side meets
    // the far side unless a dot is there too.
    let s = sphere_scene();
    let o = Vec3::new(0.1, 0.2, -5.0);
    let (mut far_kept, mut both_cut, mut near_kept) = (0, 0, 0);
    for i in 0..40 {
        for j in 0..40 {
            let target = Vec3::new(-0.8 + 0.04 * i as f32, -0.8 + 0.04 * j as f32, 0.0);
            let d = normalize(target - o);
            let Some([(t0, st0), (t1, st1)]) = mirrored_sphere_roots(o, d) else {
                continue;
            };
            let (Some(hole0), Some(hole1)) = (in_dot(st0), in_dot(st1)) else {
                continue;
            };
            let ray = Ray::new(o, d);
            let hit = s.intersect(&ray);
            assert_eq!(s.intersect_p(&ray), hit.is_some());
            let expected = match (hole0, hole1) {
                (false, _) => Some((t0, st0)),
                (true, false) => Some((t1, st1)),
                (true, true) => None,
            };
            match (hit, expected) {
                (Some(h), Some((t, st))) => {
                    assert!((h.si.t - t).abs() < 1e-4, "t {} vs {t}", h.si.t);
                    let uv = h.si.uv * 10.0;
                    assert!((uv - st).length() < 1e-3, "st {uv} vs {st}");
                }
                (None, None) => {}
                (h, e) => panic!(
                    "ray to {target}: hit {:?}, pbrt-v4 {e:?}",
                    h.map(|h| h.si.t)
                ),
            }
            far_kept += (hole0 && !hole1) as u32;
            both_cut += (hole0 && hole1) as u32;
            near_kept += !hole0 as u32;
        }
    }
    // The grid meets all three cases.
    assert!(
        far_kept > 20 && both_cut > 5 && near_kept > 200,
        "{far_kept} {both_cut} {near_kept}"
    );
}
