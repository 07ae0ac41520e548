//! Spectra used as spectra: named metals, blackbody lights and `rgb eta` read from pbrt text
//! and rendered in spectral mode (issue 16).

use lancer::film::Film;
use lancer::material::MaterialDesc;
use lancer::material::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use lancer::math::Rgb;
use lancer::render::{RenderSettings, render};
use lancer::scene::Scene;
use lancer::scene::desc::SceneDesc;
use lancer::spectrum::Ior;
use lancer::texture::{CheckerboardTexture, ScaleTexture, SpectrumTex};
use lancer_scene::load_pbrt_str;
use std::path::Path;

fn scene(text: &str) -> SceneDesc {
    load_pbrt_str(text, "t.pbrt", Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc
}

/// The mean colour of a render of `desc` at 16 spp.
fn mean(desc: &SceneDesc, spectral: bool) -> Rgb {
    let s = Scene::build(desc).unwrap();
    let settings = RenderSettings {
        spectral,
        ..RenderSettings::from_desc(desc)
    };
    let (w, h) = (desc.film.xresolution, desc.film.yresolution);
    let mut film = Film::new(w, h, settings.bounds);
    render(&s, &settings, &mut film, &|_| {}, &Default::default());
    let img = film.image(1.0);
    img.iter().copied().sum::<Rgb>() / img.len() as f32
}

const GOLD: &str = r#"
LookAt 0 0 -3  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "rgb" "integer xresolution" 16 "integer yresolution" 16
Sampler "independent" "integer pixelsamples" 16
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
Material "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k"
Shape "sphere" "float radius" 1
"#;

/// Gold seen spectrally (its measured eta and k at each wavelength) is less blue than gold
/// seen through the uplift of its RGB reductions: the reductions average gold's steep fall in
/// reflectance below 500 nm into the blue channel, and the smooth uplift spreads it back.
/// pbrt-v4's render of such a scene sides with the spectral one (see the commit).
#[test]
fn spectral_gold_is_less_blue_than_its_uplifted_rgb() {
    let desc = scene(GOLD);
    let i = desc.shapes[0].material as usize;
    let MaterialDesc::Conductor(ConductorMaterial { eta, k, .. }) = desc.materials[i] else {
        panic!("{:?}", desc.materials[i])
    };
    let (SpectrumTex::Measured(me), SpectrumTex::Measured(mk)) = (eta, k) else {
        panic!("named spectra stay spectra: {eta:?} {k:?}");
    };
    let mut uplifted = desc.clone();
    if let MaterialDesc::Conductor(ConductorMaterial { eta, k, .. }) = &mut uplifted.materials[i] {
        *eta = SpectrumTex::Const(me.rgb);
        *k = SpectrumTex::Const(mk.rgb);
    }
    let spectral = mean(&desc, true);
    let via_rgb = mean(&uplifted, true);
    // RGB mode renders the reductions, whichever way they are held.
    assert_eq!(mean(&desc, false), mean(&uplifted, false));
    let (bs, bu) = (spectral.z / spectral.x, via_rgb.z / via_rgb.x);
    assert!(bs < 0.97 * bu, "blue/red: spectral {bs}, uplift {bu}");
    assert!(
        (spectral.x / via_rgb.x - 1.0).abs() < 0.03,
        "{spectral} {via_rgb}"
    );
}

/// `"rgb eta"` on a dielectric is accepted, as in pbrt-v4: a grey triple is that index, any
/// other an uplifted spectrum (larger in blue for [1.4 1.5 1.6]) that disperses.
#[test]
fn rgb_eta_on_a_dielectric() {
    let eta = |rgb: &str| {
        let d = scene(&format!(
            "WorldBegin\nMaterial \"dielectric\" \"rgb eta\" [{rgb}]\nShape \"sphere\""
        ));
        match d.materials[d.shapes[0].material as usize] {
            MaterialDesc::Dielectric(DielectricMaterial { eta, .. }) => eta,
            ref m => panic!("{m:?}"),
        }
    };
    let grey = eta("1.5 1.5 1.5");
    assert_eq!(grey, Ior::Constant(1.5));
    assert!(!grey.is_dispersive());
    let f = eta("1.4 1.5 1.6");
    assert!(f.is_dispersive(), "{f:?}");
    assert!(
        f.at(450.0) > f.at(550.0) && f.at(550.0) > f.at(650.0),
        "{f:?}"
    );
    assert!(f.at(450.0) < 1.7 && f.at(650.0) > 1.3, "{f:?}");
    assert!((f.constant_value() - f.at(550.0)).abs() < 1e-6);
}

/// Pairs and files as a dielectric's index are spectra: constant pairs give one index, varying
/// ones disperse, with RGB mode's index the value at 550 nm as before.
#[test]
fn spectrum_eta_pairs_disperse_when_they_vary() {
    let eta = |pairs: &str| {
        let d = scene(&format!(
            "WorldBegin\nMaterial \"dielectric\" \"spectrum eta\" [{pairs}]\nShape \"sphere\""
        ));
        match d.materials[d.shapes[0].material as usize] {
            MaterialDesc::Dielectric(DielectricMaterial { eta, .. }) => eta,
            ref m => panic!("{m:?}"),
        }
    };
    match eta("300 1.33 900 1.33") {
        Ior::Constant(n) => assert!((n - 1.33).abs() < 1e-6, "{n}"),
        other => panic!("{other:?}"),
    }
    let v = eta("300 1.6 900 1.4");
    assert!(v.is_dispersive());
    // Linear from 1.6 at 300 nm to 1.4 at 900 nm: 1.5 at 600 nm, 1.4833… at 550 nm.
    assert!((v.at(600.0) - 1.5).abs() < 1e-5, "{v:?}");
    assert!((v.constant_value() - (1.6 - 0.2 * 250.0 / 600.0)).abs() < 1e-5);
}

/// A blackbody area light keeps its spectrum: Planck's shape, scaled to the luminance of its
/// RGB colour (pbrt-v4 normalises an illuminant spectrum to luminance 1 before `scale`).
#[test]
fn blackbody_area_light_keeps_plancks_shape() {
    let d = scene(
        r#"WorldBegin
AttributeBegin
AreaLightSource "diffuse" "blackbody L" [3000] "float scale" 4
Shape "sphere"
AttributeEnd"#,
    );
    let a = d.shapes[0].area_light.expect("an emitter");
    let m = a.spectrum.expect("a blackbody stays a spectrum");
    assert_eq!(m.rgb, a.l / 4.0);
    let planck = |l: f32| lancer::spectrum::blackbody(l, 3000.0);
    for (l0, l1) in [(450.0, 650.0), (500.0, 700.0), (400.0, 800.0)] {
        let got = m.spectrum.at(l0) / m.spectrum.at(l1);
        let want = planck(l0) / planck(l1);
        assert!(
            (got / want - 1.0).abs() < 1e-4,
            "{l0}/{l1}: {got} vs {want}"
        );
    }
    let y = m.spectrum.luminance();
    assert!(
        (y - lancer::math::luminance(m.rgb) as f64).abs() < 1e-4,
        "{y}"
    );
    // Point lights and named illuminants too.
    let d = scene(
        r#"WorldBegin
LightSource "point" "spectrum I" "stdillum-F2"
LightSource "point" "rgb I" [1 1 1]"#,
    );
    assert!(d.light_spectra[0].is_some());
    assert!(d.light_spectra.get(1).copied().flatten().is_none());
}

/// A spectrum given inside a texture (the `constant` texture's `value`, a `checkerboard`'s
/// `tex1`/`tex2`) is sampled at the path's wavelengths as the same spectrum given to the
/// material directly: the renders agree, in both modes (issue 17).
#[test]
fn spectra_inside_textures_render_as_the_same_spectrum_given_directly() {
    const GREEN: &str = "[400 0 500 0.9 540 0.9 600 0 700 0]";
    let with = |defs: &str, material: &str| {
        scene(&format!(
            r#"LookAt 0 0 -3  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "rgb" "integer xresolution" 16 "integer yresolution" 16
Sampler "independent" "integer pixelsamples" 16
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
{defs}
Material "diffuse" {material}
Shape "sphere" "float radius" 1
"#
        ))
    };
    let direct = with("", &format!(r#""spectrum reflectance" {GREEN}"#));
    let constant = with(
        &format!(r#"Texture "g" "spectrum" "constant" "spectrum value" {GREEN}"#),
        r#""texture reflectance" "g""#,
    );
    let checker = with(
        &format!(
            r#"Texture "g" "spectrum" "checkerboard" "float uscale" 8
    "spectrum tex1" {GREEN} "spectrum tex2" {GREEN}"#
        ),
        r#""texture reflectance" "g""#,
    );
    for spectral in [true, false] {
        let want = mean(&direct, spectral);
        for desc in [&constant, &checker] {
            let got = mean(desc, spectral);
            assert!(
                (got - want).abs().max_element() <= 1e-5 * want.max_element(),
                "spectral {spectral}: {got} against {want}"
            );
        }
    }
}

/// A spectrum texture feeding a conductor's `eta` is read as an unbounded spectrum (pbrt-v4's
/// `SpectrumType::Unbounded` variant), while the same texture as a reflectance is clamped to
/// [0, 1]; a texture built on it follows.
#[test]
fn spectrum_textures_for_conductor_indices_are_unbounded() {
    let d = scene(
        r#"WorldBegin
Texture "etas" "spectrum" "checkerboard" "spectrum tex1" "metal-Au-eta" "spectrum tex2" "metal-Cu-eta"
Texture "scaled" "spectrum" "scale" "texture tex" "etas" "float scale" 1
Material "conductor" "texture eta" "scaled" "spectrum k" "metal-Au-k"
Shape "sphere"
Material "diffuse" "texture reflectance" "scaled"
Shape "sphere"
"#,
    );
    let leaf = |t: SpectrumTex| -> (Rgb, f32) {
        // scale → checkerboard → its tex1, a measured leaf.
        let SpectrumTex::Tex(i) = t else {
            panic!("{t:?}")
        };
        let lancer::texture::SpectrumTextureDesc::Scale(ScaleTexture {
            tex: SpectrumTex::Tex(j),
            ..
        }) = &d.spectrum_textures[i as usize]
        else {
            panic!()
        };
        let lancer::texture::SpectrumTextureDesc::Checkerboard(CheckerboardTexture {
            tex1: SpectrumTex::Measured(m),
            ..
        }) = &d.spectrum_textures[*j as usize]
        else {
            panic!()
        };
        (m.rgb, m.spectrum.at(400.0))
    };
    let material = |k: usize| &d.materials[d.shapes[k].material as usize];
    let &MaterialDesc::Conductor(ConductorMaterial { eta, .. }) = material(0) else {
        panic!("{:?}", material(0))
    };
    let &MaterialDesc::Diffuse(DiffuseMaterial { reflectance }) = material(1) else {
        panic!("{:?}", material(1))
    };
    // Gold's η is about 1.66 at 400 nm (pbrt-v4's metal-Au-eta): kept as is for the index,
    // clamped to 1 for a reflectance.
    let (rgb_eta, at400_eta) = leaf(eta);
    let (rgb_refl, at400_refl) = leaf(reflectance);
    assert!(at400_eta > 1.5, "{at400_eta}");
    assert_eq!(at400_refl, 1.0);
    assert!(rgb_eta.max_element() > 1.0, "{rgb_eta:?}");
    assert!(rgb_refl.max_element() <= 1.0, "{rgb_refl:?}");
}
