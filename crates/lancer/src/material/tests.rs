//! Unit tests of the material set-up: BSDFs built from materials at a hit.

use super::at_hit::slot_colour;
use super::*;
use crate::math::{Rgb, SampledSpectrum, Vec3, rgb_lanes};
use crate::spectrum::Ior;
use crate::spectrum::dense::PreparedSpectrum;
use crate::spectrum::sampled::{ColourKind, RgbSpectrum, SampledWavelengths};
use crate::texture::{FloatTex, FloatTexture, SpectrumTex, SpectrumTexture, TexCoord, TextureEval};

fn eval(m: &Material) -> BxDF {
    let tex = TextureEval {
        floats: &[],
        spectra: &[],
    };
    m.bxdf(&tex, &TexCoord::default(), None)
        .expect("a surface material")
}

fn c(v: f32) -> FloatTex {
    FloatTex::Const(v)
}

/// A flint-glass dielectric disperses: in spectral mode its index is the glass's at the
/// hero wavelength, so a ray refracts more for a blue hero than for a red one (the prism's
/// fringes); RGB mode keeps the 550 nm index; a constant index does not disperse.
#[test]
fn named_glass_refracts_blue_more_than_red() {
    let glass = Material::Dielectric(DielectricMaterial {
        eta: Ior::named_glass("glass-F11").unwrap(),
        uroughness: c(0.0),
        vroughness: c(0.0),
        remap_roughness: false,
    });
    assert!(glass.disperses());
    assert!(
        !Material::ThinDielectric(ThinDielectricMaterial {
            eta: Ior::Constant(1.5)
        })
        .disperses()
    );
    let tex = TextureEval {
        floats: &[],
        spectra: &[],
    };
    let consts = [PreparedSpectrum::BLACK; COLOUR_SLOTS];
    let eta_at = |hero: f32| {
        let mut lambda = SampledWavelengths::sample_visible(0.5);
        lambda.lambda[0] = hero;
        let spectral = Some(SpectralColours {
            lambda: &lambda,
            consts: &consts,
        });
        match glass.bxdf(&tex, &TexCoord::default(), spectral) {
            Some(BxDF::Dielectric(d)) => d.eta,
            other => panic!("{other:?}"),
        }
    };
    let (blue, red) = (eta_at(450.0), eta_at(650.0));
    assert_eq!(blue, Ior::named_glass("glass-F11").unwrap().at(450.0));
    assert!(
        matches!(eval(&glass), BxDF::Dielectric(d) if d.eta == crate::spectrum::named_ior("glass-F11").unwrap())
    );
    // Snell at 45°: sin θt = sin 45° / n; blue bends further towards the normal.
    let wi = crate::math::normalize(crate::math::Vec3::new(1.0, 0.0, 1.0));
    let n = crate::math::Vec3::Z;
    let (tb, _) = refract(wi, n, blue).unwrap();
    let (tr, _) = refract(wi, n, red).unwrap();
    let sin45 = std::f32::consts::FRAC_1_SQRT_2;
    assert!((tb.x.abs() - sin45 / blue).abs() < 1e-5);
    assert!((tr.x.abs() - sin45 / red).abs() < 1e-5);
    // ≈ 0.58° apart: sin⁻¹(0.7071/1.7766) − sin⁻¹(0.7071/1.8192).
    let spread = (tr.x.abs().asin() - tb.x.abs().asin()).to_degrees();
    assert!((spread - 0.58).abs() < 0.15, "{spread}°");
}

/// A coating whose index is a named glass disperses as a dielectric does (pbrt-v4's coated
/// materials take `eta(λ₀)` and terminate the secondary wavelengths unless it is constant):
/// its interface has the glass's index at the hero wavelength, RGB mode the 550 nm index.
#[test]
fn a_coating_of_named_glass_takes_its_index_at_the_hero_wavelength() {
    let f11 = Ior::named_glass("glass-F11").unwrap();
    let coated = Material::CoatedDiffuse(CoatedDiffuseMaterial {
        reflectance: rgb(0.5),
        uroughness: c(0.0),
        vroughness: c(0.0),
        thickness: c(0.01),
        eta: f11,
        albedo: rgb(0.0),
        g: c(0.0),
        max_depth: 10,
        n_samples: 1,
        remap_roughness: false,
    });
    let metal = Material::CoatedConductor(CoatedConductorMaterial {
        interface_uroughness: c(0.0),
        interface_vroughness: c(0.0),
        interface_eta: f11,
        conductor_eta: rgb(0.2),
        k: rgb(3.0),
        reflectance: None,
        conductor_uroughness: c(0.0),
        conductor_vroughness: c(0.0),
        thickness: c(0.01),
        albedo: rgb(0.0),
        g: c(0.0),
        max_depth: 10,
        n_samples: 1,
        remap_roughness: false,
    });
    assert!(coated.disperses() && metal.disperses());
    let mut plain = coated.clone();
    if let Material::CoatedDiffuse(CoatedDiffuseMaterial { eta, .. }) = &mut plain {
        *eta = Ior::Constant(1.5);
    }
    assert!(!plain.disperses());
    let tex = TextureEval {
        floats: &[],
        spectra: &[],
    };
    let consts = [PreparedSpectrum::BLACK; COLOUR_SLOTS];
    let mut lambda = SampledWavelengths::sample_visible(0.5);
    lambda.lambda[0] = 450.0;
    let spectral = Some(SpectralColours {
        lambda: &lambda,
        consts: &consts,
    });
    let blue = f11.at(450.0);
    match coated.bxdf(&tex, &TexCoord::default(), spectral) {
        Some(BxDF::CoatedDiffuse(b)) => assert_eq!(b.top.eta, blue),
        other => panic!("{other:?}"),
    }
    match metal.bxdf(&tex, &TexCoord::default(), spectral) {
        Some(BxDF::CoatedConductor(b)) => assert_eq!(b.top.eta, blue),
        other => panic!("{other:?}"),
    }
    match eval(&coated) {
        BxDF::CoatedDiffuse(b) => assert_eq!(b.top.eta, f11.constant_value()),
        other => panic!("{other:?}"),
    }
    assert!((blue - f11.constant_value()).abs() > 0.01);
}

fn rgb(v: f32) -> SpectrumTex {
    SpectrumTex::Const(Rgb::splat(v))
}

#[test]
fn conductors_remap_roughness_and_honour_an_artists_reflectance() {
    let m = Material::Conductor(ConductorMaterial {
        eta: rgb(0.2),
        k: rgb(3.0),
        reflectance: Some(SpectrumTex::Const(Rgb::new(0.9, 0.5, 0.1))),
        uroughness: c(0.25),
        vroughness: c(0.04),
        remap_roughness: true,
    });
    let BxDF::Conductor(b) = eval(&m) else {
        panic!("not a conductor")
    };
    // α = √roughness.
    assert_eq!((b.distrib.alpha_x(), b.distrib.alpha_y()), (0.5, 0.2));
    // η = 1, k = 2√r/√(1 − r): the normal-incidence reflectance is r.
    let f0 = fresnel_complex(1.0, b.eta, b.k);
    assert!(
        (f0 - rgb_lanes(Rgb::new(0.9, 0.5, 0.1)))
            .abs()
            .max_element()
            < 1e-4,
        "{f0}"
    );
    // Without remapping the roughness is α itself; zero makes a mirror.
    let m = Material::Conductor(ConductorMaterial {
        eta: rgb(0.2),
        k: rgb(3.0),
        reflectance: None,
        uroughness: c(0.0),
        vroughness: c(0.0),
        remap_roughness: false,
    });
    let BxDF::Conductor(b) = eval(&m) else {
        panic!("not a conductor")
    };
    assert!(b.distrib.effectively_smooth());
    assert_eq!(
        (b.eta, b.k),
        (SampledSpectrum::splat(0.2), SampledSpectrum::splat(3.0))
    );
}

#[test]
fn every_material_becomes_its_own_bxdf() {
    let d = eval(&Material::Dielectric(DielectricMaterial {
        eta: Ior::Constant(0.0),
        uroughness: c(0.09),
        vroughness: c(0.09),
        remap_roughness: true,
    }));
    // An index of 0 means 1, as in pbrt.
    assert!(
        matches!(d, BxDF::Dielectric(b) if b.eta == 1.0 && (b.distrib.alpha_x() - 0.3).abs() < 1e-6)
    );
    let t = eval(&Material::ThinDielectric(ThinDielectricMaterial {
        eta: Ior::Constant(1.33),
    }));
    assert!(matches!(t, BxDF::ThinDielectric(b) if b.eta == 1.33));
    // Diffuse transmission: both albedos scaled, then clamped to one.
    let dt = eval(&Material::DiffuseTransmission(
        DiffuseTransmissionMaterial {
            reflectance: rgb(0.3),
            transmittance: rgb(0.6),
            scale: 2.0,
        },
    ));
    assert!(
        matches!(dt, BxDF::DiffuseTransmission(b) if b.r == SampledSpectrum::splat(0.6) && b.t == SampledSpectrum::ONE)
    );
    let cd = eval(&Material::CoatedDiffuse(CoatedDiffuseMaterial {
        reflectance: rgb(1.5),
        uroughness: c(0.0),
        vroughness: c(0.0),
        thickness: c(0.01),
        eta: Ior::Constant(1.5),
        albedo: rgb(0.2),
        g: c(3.0),
        max_depth: 10,
        n_samples: 2,
        remap_roughness: true,
    }));
    let BxDF::CoatedDiffuse(l) = cd else {
        panic!("not a coated diffuse")
    };
    assert_eq!(l.bottom.r, SampledSpectrum::ONE);
    assert_eq!((l.top.eta, l.thickness, l.g), (1.5, 0.01, 1.0));
    assert_eq!(
        (l.albedo, l.max_depth, l.n_samples),
        (SampledSpectrum::splat(0.2), 10, 2)
    );
    // Under its coating the conductor's index is relative to the coating's.
    let cc = eval(&Material::CoatedConductor(CoatedConductorMaterial {
        interface_uroughness: c(0.0),
        interface_vroughness: c(0.0),
        interface_eta: Ior::Constant(1.5),
        conductor_eta: rgb(0.3),
        k: rgb(3.0),
        reflectance: None,
        conductor_uroughness: c(0.16),
        conductor_vroughness: c(0.16),
        thickness: c(0.01),
        albedo: rgb(0.0),
        g: c(0.0),
        max_depth: 10,
        n_samples: 1,
        remap_roughness: true,
    }));
    let BxDF::CoatedConductor(l) = cc else {
        panic!("not a coated conductor")
    };
    assert!(
        (l.bottom.eta - SampledSpectrum::splat(0.2))
            .abs()
            .max_element()
            < 1e-6
    );
    assert!(
        (l.bottom.k - SampledSpectrum::splat(2.0))
            .abs()
            .max_element()
            < 1e-6
    );
    assert!((l.bottom.distrib.alpha_x() - 0.4).abs() < 1e-6);
    let none = TextureEval {
        floats: &[],
        spectra: &[],
    };
    assert!(
        Material::Interface(InterfaceMaterial)
            .bxdf(&none, &TexCoord::default(), None)
            .is_none()
    );
}

/// Spectral mode's prepared colours of `m` by position, as a scene prepares them
/// ([`crate::scene::SceneSpectra`]): each constant RGB colour of its colour list uplifted
/// as the kind says.
fn prepared(m: &Material) -> [PreparedSpectrum; COLOUR_SLOTS] {
    m.colour_slots().map(|slot| match slot {
        Some((SpectrumTex::Const(c), kind)) => PreparedSpectrum::Rgb(RgbSpectrum::new(c, kind)),
        Some(_) => panic!("these materials' colours are RGB constants"),
        None => PreparedSpectrum::BLACK,
    })
}

/// Every kind with colours reads each one back from the position its colour list gave it:
/// each colour once as a constant (prepared by position, as a scene does) and once as a
/// constant texture (uplifted at the hit) must give identical BxDFs (and, for `subsurface`,
/// BSSRDFs) in spectral mode. The colours all differ, so a kind that read a colour from
/// another's position, or listed it as the wrong kind (albedo or unbounded), would fail.
#[test]
fn prepared_constant_colours_give_what_an_uplift_per_hit_gives() {
    let colours = [
        Rgb::new(0.8, 0.3, 0.1),
        Rgb::new(0.2, 0.9, 1.4),
        Rgb::new(3.9, 2.4, 1.6),
        Rgb::new(0.1, 0.6, 0.3),
    ];
    let textures: Vec<SpectrumTexture> = colours
        .iter()
        .map(|&c| SpectrumTexture::Constant(c))
        .collect();
    let floats = [FloatTexture::Constant(1.3), FloatTexture::Constant(0.4)];
    let tex = TextureEval {
        floats: &floats,
        spectra: &textures,
    };
    let (k, t) = (SpectrumTex::Const, SpectrumTex::Tex);
    let conductor = |eta, kk, r| {
        Material::Conductor(ConductorMaterial {
            eta,
            k: kk,
            reflectance: r,
            uroughness: c(0.2),
            vroughness: c(0.2),
            remap_roughness: false,
        })
    };
    let coated_diffuse = |r, a| {
        Material::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: r,
            uroughness: c(0.1),
            vroughness: c(0.1),
            thickness: c(0.01),
            eta: Ior::Constant(1.5),
            albedo: a,
            g: c(0.0),
            max_depth: 10,
            n_samples: 1,
            remap_roughness: false,
        })
    };
    let coated_conductor = |eta, kk, r, a| {
        Material::CoatedConductor(CoatedConductorMaterial {
            interface_uroughness: c(0.1),
            interface_vroughness: c(0.1),
            interface_eta: Ior::Constant(1.5),
            conductor_eta: eta,
            k: kk,
            reflectance: r,
            conductor_uroughness: c(0.2),
            conductor_vroughness: c(0.2),
            thickness: c(0.01),
            albedo: a,
            g: c(0.0),
            max_depth: 10,
            n_samples: 1,
            remap_roughness: false,
        })
    };
    let hair = |absorption| {
        Material::Hair(HairMaterial {
            absorption,
            eta: c(1.55),
            beta_m: c(0.3),
            beta_n: c(0.3),
            alpha: c(2.0),
        })
    };
    let pairs = [
        (
            Material::Diffuse(DiffuseMaterial {
                reflectance: k(colours[0]),
            }),
            Material::Diffuse(DiffuseMaterial { reflectance: t(0) }),
        ),
        (
            Material::DiffuseTransmission(DiffuseTransmissionMaterial {
                reflectance: k(colours[0]),
                transmittance: k(colours[3]),
                scale: 0.7,
            }),
            Material::DiffuseTransmission(DiffuseTransmissionMaterial {
                reflectance: t(0),
                transmittance: t(3),
                scale: 0.7,
            }),
        ),
        (
            conductor(k(colours[1]), k(colours[2]), None),
            conductor(t(1), t(2), None),
        ),
        (
            conductor(k(colours[1]), k(colours[2]), Some(k(colours[0]))),
            conductor(t(1), t(2), Some(t(0))),
        ),
        (
            coated_diffuse(k(colours[0]), k(colours[3])),
            coated_diffuse(t(0), t(3)),
        ),
        (
            coated_conductor(k(colours[1]), k(colours[2]), None, k(colours[3])),
            coated_conductor(t(1), t(2), None, t(3)),
        ),
        (
            coated_conductor(
                k(colours[1]),
                k(colours[2]),
                Some(k(colours[0])),
                k(colours[3]),
            ),
            coated_conductor(t(1), t(2), Some(t(0)), t(3)),
        ),
        (
            hair(HairAbsorption::SigmaA(k(colours[2]))),
            hair(HairAbsorption::SigmaA(t(2))),
        ),
        (
            hair(HairAbsorption::Reflectance(k(colours[0]))),
            hair(HairAbsorption::Reflectance(t(0))),
        ),
        (
            hair(HairAbsorption::Melanin {
                eumelanin: c(1.3),
                pheomelanin: c(0.4),
            }),
            hair(HairAbsorption::Melanin {
                eumelanin: FloatTex::Tex(0),
                pheomelanin: FloatTex::Tex(1),
            }),
        ),
    ];
    let lambda = SampledWavelengths::sample_visible(0.37);
    let tc = TexCoord::default();
    for (constant, textured) in pairs {
        let consts = prepared(&constant);
        let spectral = Some(SpectralColours {
            lambda: &lambda,
            consts: &consts,
        });
        let a = constant.bxdf(&tex, &tc, spectral);
        let b = textured.bxdf(&tex, &tc, spectral);
        assert_eq!(a, b, "{constant:?}");
        // And they are spectra, not the colours' RGB lanes.
        assert_ne!(a, constant.bxdf(&tex, &tc, None));
    }

    // A subsurface material's colours are read by its BSSRDF.
    let subsurface = |coefficients| {
        MaterialDesc::Subsurface(SubsurfaceMaterial {
            coefficients,
            scale: 2.0,
            eta: 1.33,
            uroughness: c(0.0),
            vroughness: c(0.0),
            remap_roughness: true,
            g: 0.0,
        })
        .build()
    };
    let media = [
        (
            SubsurfaceCoefficients::Coefficients {
                sigma_a: k(colours[1]),
                sigma_s: k(colours[2]),
            },
            SubsurfaceCoefficients::Coefficients {
                sigma_a: t(1),
                sigma_s: t(2),
            },
        ),
        (
            SubsurfaceCoefficients::Reflectance {
                reflectance: k(colours[0]),
                mfp: k(colours[2]),
            },
            SubsurfaceCoefficients::Reflectance {
                reflectance: t(0),
                mfp: t(2),
            },
        ),
    ];
    for (constant, textured) in media {
        let (constant, textured) = (subsurface(constant), subsurface(textured));
        let consts = prepared(&constant);
        let spectral = Some(SpectralColours {
            lambda: &lambda,
            consts: &consts,
        });
        let medium = |m: &Material| {
            let b = m
                .bssrdf(&tex, &tc, spectral, Vec3::ZERO, Vec3::Z)
                .expect("a subsurface material");
            (b.sigma_t, b.rho)
        };
        assert_eq!(medium(&constant), medium(&textured), "{constant:?}");
    }
}

/// Every material reads a colour slot the same way ([`slot_colour`]): in RGB mode the texture's
/// value as lanes (r, g, b, b), an albedo clamped to [0, 1] and an unbounded colour as it is;
/// in spectral mode a constant's prepared spectrum of its own slot, not the RGB value.
#[test]
fn slot_colour_clamps_albedos_in_rgb_and_reads_its_slot_in_spectral_mode() {
    let tex = TextureEval {
        floats: &[],
        spectra: &[],
    };
    let tc = TexCoord::default();
    let t = SpectrumTex::Const(Rgb::new(1.5, 0.5, -0.25));
    let albedo = slot_colour(&tex, &tc, None, 1, t, ColourKind::Albedo);
    assert_eq!(albedo, SampledSpectrum::new(1.0, 0.5, 0.0, 0.0));
    let unbounded = slot_colour(&tex, &tc, None, 1, t, ColourKind::Unbounded);
    assert_eq!(unbounded, SampledSpectrum::new(1.5, 0.5, -0.25, -0.25));
    assert_eq!(
        rgb_colour(Rgb::new(1.5, 0.5, -0.25), ColourKind::Albedo),
        albedo
    );

    // Slot 1 holds a flat spectrum of 1 (the uplift of white as an unbounded colour); the
    // others are black, so reading the wrong slot gives 0.
    let mut consts = [PreparedSpectrum::BLACK; COLOUR_SLOTS];
    consts[1] = PreparedSpectrum::Rgb(RgbSpectrum::new(Rgb::ONE, ColourKind::Unbounded));
    let lambda = SampledWavelengths::sample_visible(0.3);
    let sc = SpectralColours {
        lambda: &lambda,
        consts: &consts,
    };
    for kind in [ColourKind::Albedo, ColourKind::Unbounded] {
        let v = slot_colour(&tex, &tc, Some(sc), 1, t, kind);
        assert_eq!(v, sc.constant(1));
        for k in 0..4 {
            assert!((v[k] - 1.0).abs() < 1e-4, "lane {k}: {}", v[k]);
        }
    }
    assert_eq!(sc.constant(0), SampledSpectrum::ZERO);
}
