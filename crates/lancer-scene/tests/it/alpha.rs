//! Alpha cut-outs, from a pbrt scene to the rays: alpha 0 is a hole for camera and shadow rays
//! alike, a texture cuts where it is 0, and a fractional alpha lets through that fraction of
//! the rays.

use lancer::Scene;
use lancer::math::Vec3;
use lancer::ray::Ray;
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
