//! `LightSource` and `AreaLightSource`: pbrt-v4's `point`, `spot`, `distant` and `infinite`
//! lights, placed by the current transformation, and the `diffuse` area light, with pbrt-v4's
//! normalisation by `power` and `illuminance`.

use super::convert::{Fallback, Reader, locate};
use super::params::ParamList;
use super::search_path::SearchPath;
use crate::error::{Location, SceneError};
use crate::image_read::Encoding;
use lancer::light::environment_mapping;
use lancer::light::{
    DistantDesc, GoniometricDesc, ImageInfiniteDesc, PointDesc, PortalInfiniteDesc, ProjectionDesc,
    SpotDesc, SunskyDesc, SunskyParams, UniformInfiniteDesc,
};
use lancer::math::{Rgb, Transform, Vec3};
use lancer::scene::desc::{AreaLightDesc, LightDesc};
use lancer::spectrum::SpectrumKind;
use std::f32::consts::PI;

/// A light's emission: its colour (RGB passes through; spectra are normalised to luminance 1,
/// as pbrt-v4 divides `scale` by the spectrum's photometric value) times `scale`.
fn emission(params: &ParamList, name: &str, dir: &SearchPath) -> Result<Rgb, SceneError> {
    let c = params
        .color(name, SpectrumKind::Illuminant, dir)?
        .unwrap_or(Rgb::ONE);
    Ok(c * params.float("scale", 1.0)?)
}

/// The light `ty` at `loc`, placed by `ctm`; `None` for the kinds lancer skips (with their
/// warning).
pub fn light(
    r: &Reader,
    ty: &str,
    ctm: Transform,
    loc: &Location,
) -> Result<Fallback<Option<LightDesc>>, SceneError> {
    let params = r.params;
    let power = params.float("power", -1.0)?;
    let light = match ty {
        "point" => {
            let mut i = emission(params, "I", r.dir)?;
            if power > 0.0 {
                // Φ = 4π·I for an isotropic point light.
                i *= power / (4.0 * PI);
            }
            LightDesc::Point(PointDesc {
                from: ctm.point(params.point3("from", Vec3::ZERO)?),
                intensity: i,
            })
        }
        "spot" => {
            let mut i = emission(params, "I", r.dir)?;
            let cone_angle = params
                .float_checked("coneangle", 30.0, "in (0, 180]", |v| v > 0.0 && v <= 180.0)?;
            let cone_delta_angle = params.float_checked(
                "conedeltaangle",
                5.0,
                "between 0 and the cone angle",
                |v| (0.0..=cone_angle).contains(&v),
            )?;
            if power > 0.0 {
                // Φ = 2π·I·((1 − cos θ_start) + (cos θ_start − cos θ_end)/2): the smoothstep
                // falloff integrates to half its width.
                let c_end = cone_angle.to_radians().cos();
                let c_start = (cone_angle - cone_delta_angle).to_radians().cos();
                let k = 2.0 * PI * ((1.0 - c_start) + (c_start - c_end) / 2.0);
                i *= power / k;
            }
            LightDesc::Spot(SpotDesc {
                from: ctm.point(params.point3("from", Vec3::ZERO)?),
                to: ctm.point(params.point3("to", Vec3::Z)?),
                intensity: i,
                cone_angle,
                cone_delta_angle,
            })
        }
        "distant" => {
            let mut l = emission(params, "L", r.dir)?;
            let w = params.point3("from", Vec3::ZERO)? - params.point3("to", Vec3::Z)?;
            let illuminance = params.float("illuminance", -1.0)?;
            if illuminance > 0.0 {
                // pbrt-v4 multiplies the scale by E: the illuminance on a patch facing the
                // light (its comment speaks of an upward patch, its code does not divide by
                // that patch's cos θ), E = L for a unit-luminance colour.
                l *= illuminance;
            }
            LightDesc::Distant(DistantDesc {
                direction: ctm.vector(w),
                l,
            })
        }
        "infinite" => return Ok(infinite(r, ctm, loc)?.map(Some)),
        "sunsky" => return Ok(sunsky(r, ctm, loc)?.map(Some)),
        "goniometric" | "projection" => return Ok(image_light(r, ty, ctm, power, loc)?.map(Some)),
        _ => {
            return Err(SceneError::at(
                loc.clone(),
                format!(
                    "unknown light \"{ty}\" (expected point, spot, distant, infinite, goniometric, projection or sunsky)"
                ),
            ));
        }
    };
    // lancer's rules on lights (a spot's ends apart, a distant light's direction not zero),
    // about two parameters at once: at the directive.
    light
        .validate()
        .map_err(|m| SceneError::at(loc.clone(), m))?;
    Ok(Fallback::done(Some(light)))
}

/// lancer's `sunsky` light (an extension): the Hosek–Wilkie sky and sun of Mitsuba 3's
/// `sunsky` emitter, in the light's space whose zenith is +z (as the environment maps of
/// pbrt-v4's `imgtool makesky`). `vector3 sundirection` points towards the sun (default
/// makesky's, 10° above the horizon: (0, cos 10°, sin 10°)); `float turbidity` in [1, 10]
/// (3), `float albedo` of the ground in [0, 1] (0.3), `float sunscale`, `skyscale` and
/// `scale` (1) multiply the sun, the sky and both. A sun below the horizon leaves the light
/// black, as Mitsuba's, with a warning.
fn sunsky(r: &Reader, ctm: Transform, loc: &Location) -> Result<Fallback<LightDesc>, SceneError> {
    let params = r.params;
    let e = 10f32.to_radians();
    let mut p =
        SunskyParams::new(params.vector3("sundirection", Vec3::new(0.0, e.cos(), e.sin()))?);
    p.turbidity = params.float("turbidity", p.turbidity)?;
    p.albedo = params.float("albedo", p.albedo)?;
    p.sun_scale = params.float("sunscale", 1.0)?;
    p.sky_scale = params.float("skyscale", 1.0)?;
    p.scale = params.float("scale", 1.0)?;
    let light = LightDesc::Sunsky(SunskyDesc {
        light_to_world: ctm,
        params: p,
    });
    light
        .validate()
        .map_err(|m| SceneError::at(loc.clone(), format!("sunsky light: {m}")))?;
    Ok(if p.sun_direction.z < 0.0 {
        Fallback::noted(
            light,
            vec!["the sunsky light's sun is below the horizon: it gives no light".to_string()],
        )
    } else {
        Fallback::done(light)
    })
}

/// pbrt-v4's `goniometric` light (intensity `I` times `scale` times the channel average of the
/// square equal-area image `filename`; `power` Φ makes I·4π·mean(image) = Φ) and `projection`
/// light (the image `filename` times `scale`, projected over `fov` degrees, 90 by default;
/// `power` Φ makes the luminance it emits Φ).
fn image_light(
    r: &Reader,
    ty: &str,
    ctm: Transform,
    power: f32,
    loc: &Location,
) -> Result<Fallback<LightDesc>, SceneError> {
    let params = r.params;
    let at = |message: String| SceneError::at(loc.clone(), message);
    let (path, encoding) = r
        .image_file(&format!("a \"{ty}\" light"))
        .map_err(|e| locate(e, loc))?;
    let image = r
        .images
        .rgb(&path, encoding)
        .map_err(|e| at(e.to_string()))?;
    if image.texels.iter().any(|t| !t.is_finite()) {
        return Err(at(format!(
            "{}: the image holds infinite or NaN values and cannot be a light",
            path.display()
        )));
    }
    let light = if ty == "goniometric" {
        if image.width != image.height {
            return Err(at(format!(
                "{}: a goniometric light's image must be square (equal-area), not {}×{}",
                path.display(),
                image.width,
                image.height
            )));
        }
        let mut intensity = emission(params, "I", r.dir)?;
        if power > 0.0 {
            // Φ = I · 4π · mean(Y), Y the channel average.
            let mean_y = image
                .texels
                .iter()
                .map(|&t| {
                    let c = Rgb::from(t);
                    ((c.x + c.y + c.z) / 3.0) as f64
                })
                .sum::<f64>()
                / image.texels.len() as f64;
            let k = 4.0 * PI * mean_y as f32;
            if k > 0.0 {
                intensity *= power / k;
            }
        }
        LightDesc::Goniometric(GoniometricDesc {
            light_to_world: ctm,
            intensity,
            image,
        })
    } else {
        let fov = params.float_checked("fov", 90.0, "in (0, 180)", |v| v > 0.0 && v < 180.0)?;
        let mut scale = params.float("scale", 1.0)?;
        if power > 0.0 {
            // Φ = scale · ∫ Y(image(ω)) dω over the projector's field.
            let tan_half = (fov.to_radians() / 2.0).tan();
            let k = lancer::light::projected_sum(&image, tan_half, lancer::math::luminance);
            if k > 0.0 {
                scale *= power / k;
            }
        }
        LightDesc::Projection(ProjectionDesc {
            light_to_world: ctm,
            scale,
            fov,
            image,
        })
    };
    Ok(Fallback::done(light))
}

/// pbrt-v4's `infinite` light: a uniform sky of radiance `L`, or the image `filename`
/// (equal-area octahedral, or, as a lancer extension, 2:1 latitude-longitude) times `scale`.
/// With `illuminance` E, a sky is scaled so that an upward patch receives E (L·π = E); an
/// image is scaled by E over the illuminance pbrt-v4 computes for it, which is half the
/// physical one (see `EnvMapping::pbrt_illuminance`), so that lancer matches pbrt-v4's images.
/// A `portal` with `L` and no image is, as in pbrt-v4, a 1×1 image of L's colour.
fn infinite(r: &Reader, ctm: Transform, loc: &Location) -> Result<Fallback<LightDesc>, SceneError> {
    let params = r.params;
    let illuminance = params.float("illuminance", -1.0)?;
    let portal_sky = !params.has("filename") && params.has("portal");
    if !params.has("filename") && !portal_sky {
        let mut l = emission(params, "L", r.dir)?;
        if illuminance > 0.0 {
            // A uniform sky of radiance L gives an illuminance of π·L.
            l *= illuminance / PI;
        }
        return Ok(Fallback::done(LightDesc::UniformInfinite(
            UniformInfiniteDesc { l },
        )));
    }
    let at = |message: String| SceneError::at(loc.clone(), message);
    if params.has("L") && !portal_sky {
        return Err(at(
            "an \"infinite\" light takes either \"L\" or \"filename\", not both".into(),
        ));
    }
    let mut scale = params.float("scale", 1.0)?;
    let (image, name) = if portal_sky {
        // pbrt-v4 makes a uniform `L` behind a portal a 1×1 image of L's RGB colour (so the
        // sky is lit only in front of the portal's plane, and sampled through the portal).
        let c = params
            .color("L", SpectrumKind::Illuminant, r.dir)?
            .unwrap_or(Rgb::ONE);
        let texels = vec![c.into()];
        let image = lancer::image::Image::new(1, 1, texels).expect("1×1 with one texel");
        (
            std::sync::Arc::new(image),
            "the \"L\" of an infinite light".to_string(),
        )
    } else {
        // pbrt-v4 reads environment images with their default encoding (sRGB for PNG).
        let (path, _) = r
            .image_file("an \"infinite\" light with an image")
            .map_err(|e| locate(e, loc))?;
        let image = r
            .images
            .rgb(&path, Encoding::Srgb)
            .map_err(|e| at(e.to_string()))?;
        (image, path.display().to_string())
    };
    // lancer's rules on environment images (the ones `LightDesc::validate` checks), after the
    // file's name.
    let mapping = environment_mapping(&image).map_err(|m| at(format!("{name}: {m}")))?;
    let mut warnings = Vec::new();
    if illuminance > 0.0 {
        let e = mapping.pbrt_illuminance(&image);
        if e > 0.0 {
            scale *= illuminance / e;
        } else {
            warnings.push(format!(
                "{name} is black above the horizon, so \"illuminance\" cannot scale it; ignored"
            ));
        }
    }
    // pbrt-v4's portal: four world-space corners (not moved by the CTM).
    let value = match params.point3s("portal")? {
        Some(p) => {
            let portal: [Vec3; 4] = match p.as_slice() {
                [a, b, c, d] => [(*a).into(), (*b).into(), (*c).into(), (*d).into()],
                _ => {
                    return Err(at(format!(
                        "an infinite light's \"portal\" takes 4 points, not {}",
                        p.len()
                    )));
                }
            };
            lancer::light::portal_frame(&portal).map_err(at)?;
            LightDesc::PortalInfinite(PortalInfiniteDesc {
                light_to_world: ctm,
                l: Rgb::splat(scale),
                image,
                portal,
            })
        }
        None => LightDesc::ImageInfinite(ImageInfiniteDesc {
            light_to_world: ctm,
            l: Rgb::splat(scale),
            image,
        }),
    };
    Ok(Fallback { value, warnings })
}

/// `AreaLightSource "diffuse"`: radiance `L` times `scale`, from one side or both
/// (`twosided`).
pub fn area_light(
    params: &ParamList,
    ty: &str,
    dir: &SearchPath,
    loc: &Location,
) -> Result<AreaLightDesc, SceneError> {
    if ty != "diffuse" {
        return Err(SceneError::at(
            loc.clone(),
            format!("unknown area light \"{ty}\" (expected \"diffuse\")"),
        ));
    }
    // pbrt-v4's `power` Φ: the radiance is scaled by Φ / (π · sides · area) per primitive,
    // which only the scene build knows (the area of each triangle in world space, of each
    // quadric in object space).
    let power = params.float("power", -1.0)?;
    Ok(AreaLightDesc {
        l: emission(params, "L", dir)?,
        two_sided: params.bool("twosided", false)?,
        spectrum: None,
        power: (power > 0.0).then_some(power),
        image: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::convert::TextureNames;
    use crate::pbrt::convert::testing::{err, typed_in, unused, with_textures};
    use std::path::{Path, PathBuf};

    type Converted = (Result<Fallback<Option<LightDesc>>, SceneError>, Vec<String>);

    /// The one `LightSource` of `text` under `ctm`, and its unread parameters.
    fn convert_in(text: &str, dir: &Path, ctm: Transform) -> Converted {
        let (ty, params, loc) = typed_in(text, dir);
        let names = TextureNames::default();
        let out = with_textures(&params, dir, &names, |r| light(r, &ty, ctm, &loc));
        (out, unused(&params))
    }

    /// A light that converts without warnings and reads every parameter.
    #[track_caller]
    fn converted(text: &str, ctm: Transform) -> LightDesc {
        let (out, unused) = convert_in(text, Path::new("."), ctm);
        let f = out.unwrap_or_else(|e| panic!("{e}"));
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
        assert!(unused.is_empty(), "{unused:?}");
        f.value.expect("a light")
    }

    #[track_caller]
    fn error(text: &str) -> String {
        err(convert_in(text, Path::new("."), Transform::IDENTITY).0)
    }

    #[track_caller]
    fn assert_close(a: Rgb, b: Rgb) {
        assert!(
            (a - b).abs().max_element() <= 1e-5 * b.abs().max_element().max(1.0),
            "{a} != {b}"
        );
    }

    const ID: Transform = Transform::IDENTITY;

    #[test]
    fn point_lights() {
        assert_eq!(
            converted(r#"LightSource "point""#, ID),
            LightDesc::Point(PointDesc {
                from: Vec3::ZERO,
                intensity: Rgb::ONE
            })
        );
        // Placed by the CTM; I times scale.
        let ctm = Transform::translate(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(
            converted(
                r#"LightSource "point" "point3 from" [0 1 0] "rgb I" [1 2 3] "float scale" 2"#,
                ctm
            ),
            LightDesc::Point(PointDesc {
                from: Vec3::new(1.0, 3.0, 3.0),
                intensity: Rgb::new(2.0, 4.0, 6.0)
            })
        );
        // `power` Φ gives I = Φ / 4π: Φ = 8π gives 2.
        let power = 8.0 * PI;
        let LightDesc::Point(PointDesc { intensity, .. }) = converted(
            &format!("LightSource \"point\" \"float power\" {power}"),
            ID,
        ) else {
            panic!("a point light")
        };
        assert_close(intensity, Rgb::splat(2.0));
    }

    #[test]
    fn spot_lights() {
        assert_eq!(
            converted(r#"LightSource "spot""#, ID),
            LightDesc::Spot(SpotDesc {
                from: Vec3::ZERO,
                to: Vec3::Z,
                intensity: Rgb::ONE,
                cone_angle: 30.0,
                cone_delta_angle: 5.0,
            })
        );
        let LightDesc::Spot(SpotDesc {
            from,
            to,
            intensity,
            cone_angle,
            cone_delta_angle,
        }) = converted(
            r#"LightSource "spot" "point3 from" [1 0 0] "point3 to" [1 0 5] "rgb I" [2 2 2]
               "float coneangle" 60 "float conedeltaangle" 60 "float power" 1"#,
            ID,
        )
        else {
            panic!("a spot light")
        };
        assert_eq!((from, to), (Vec3::X, Vec3::new(1.0, 0.0, 5.0)));
        assert_eq!((cone_angle, cone_delta_angle), (60.0, 60.0));
        // Φ = 2π·I·((1 − cos 0°) + (cos 0° − cos 60°)/2) = π/2·I: pbrt-v4 multiplies the colour
        // by Φ / (π/2), so "I" 2 with "power" 1 gives 2·2/π.
        assert_close(intensity, Rgb::splat(4.0 / PI));
        assert_eq!(
            error("LightSource \"spot\"\n  \"float coneangle\" 200"),
            "t.pbrt:2:3: \"float coneangle\" must be in (0, 180], not 200"
        );
        assert_eq!(
            error("LightSource \"spot\"\n  \"float conedeltaangle\" 40"),
            "t.pbrt:2:3: \"float conedeltaangle\" must be between 0 and the cone angle, not 40"
        );
        assert_eq!(
            error(r#"LightSource "spot" "point3 to" [0 0 0]"#),
            "t.pbrt:1:1: spot light with \"from\" equal to \"to\""
        );
    }

    #[test]
    fn sunsky_lights() {
        let ctm = Transform::rotate(-90.0, Vec3::X).expect("a rotation");
        let LightDesc::Sunsky(SunskyDesc {
            light_to_world,
            params,
        }) = converted(
            r#"LightSource "sunsky" "vector3 sundirection" [-0.45 0.6 0.65] "float turbidity" 4
               "float albedo" 0.5 "float sunscale" 2 "float skyscale" 0.5 "float scale" 3"#,
            ctm,
        )
        else {
            panic!("a sunsky light")
        };
        assert_eq!(light_to_world, ctm);
        assert_eq!(params.sun_direction, Vec3::new(-0.45, 0.6, 0.65));
        assert_eq!(
            (
                params.turbidity,
                params.albedo,
                params.sun_scale,
                params.sky_scale,
                params.scale
            ),
            (4.0, 0.5, 2.0, 0.5, 3.0)
        );
        // Defaults: Mitsuba's turbidity and albedo, makesky's sun 10° above the horizon.
        let LightDesc::Sunsky(SunskyDesc { params, .. }) = converted(r#"LightSource "sunsky""#, ID)
        else {
            panic!("a sunsky light")
        };
        assert_eq!((params.turbidity, params.albedo), (3.0, 0.3));
        assert!((params.sun_direction.z - 10f32.to_radians().sin()).abs() < 1e-6);
        assert_eq!(
            error(r#"LightSource "sunsky" "float turbidity" 11"#),
            "t.pbrt:1:1: sunsky light: turbidity 11 is outside [1, 10]"
        );
        assert_eq!(
            error(r#"LightSource "sunsky" "vector3 sundirection" [0 0 0]"#),
            "t.pbrt:1:1: sunsky light: the sun's direction must be a non-zero vector, not [0, 0, 0]"
        );
        let (out, _) = convert_in(
            r#"LightSource "sunsky" "vector3 sundirection" [0 1 -0.1]"#,
            Path::new("."),
            ID,
        );
        let warnings = out.expect("a light").warnings;
        assert_eq!(
            warnings,
            ["the sunsky light's sun is below the horizon: it gives no light"]
        );
    }

    #[test]
    fn distant_lights() {
        assert_eq!(
            converted(r#"LightSource "distant""#, ID),
            LightDesc::Distant(DistantDesc {
                direction: -Vec3::Z,
                l: Rgb::ONE
            })
        );
        // Light travels from "from" to "to"; the colour times scale (5·2) is multiplied by
        // E = 3, as pbrt-v4 does.
        let LightDesc::Distant(DistantDesc { direction, l }) = converted(
            r#"LightSource "distant" "point3 from" [0 1 0] "point3 to" [0 0 0] "rgb L" [5 5 5]
               "float scale" 2 "float illuminance" 3"#,
            Transform::scale(Vec3::splat(2.0)).unwrap(),
        ) else {
            panic!("a distant light")
        };
        assert_eq!(direction, Vec3::new(0.0, 2.0, 0.0));
        assert_close(l, Rgb::splat(30.0));
        // Slanted light gets the same factor: pbrt-v4 does not divide by the upward patch's
        // cos θ.
        let LightDesc::Distant(DistantDesc { l, .. }) = converted(
            r#"LightSource "distant" "point3 from" [1 1 0] "point3 to" [0 0 0] "float illuminance" 3"#,
            ID,
        ) else {
            panic!("a distant light")
        };
        assert_close(l, Rgb::splat(3.0));
        assert_eq!(
            error(r#"LightSource "distant" "point3 from" [0 0 1]"#),
            "t.pbrt:1:1: distant light with \"from\" equal to \"to\""
        );
    }

    #[test]
    fn uniform_skies() {
        let ctm = Transform::translate(Vec3::X);
        assert_eq!(
            converted(r#"LightSource "infinite""#, ctm),
            LightDesc::UniformInfinite(UniformInfiniteDesc { l: Rgb::ONE })
        );
        // A unit sky gives E = π: illuminance 2π multiplies the colour 4 by 2.
        let e = 2.0 * PI;
        let LightDesc::UniformInfinite(UniformInfiniteDesc { l }) = converted(
            &format!("LightSource \"infinite\" \"rgb L\" [4 4 4] \"float illuminance\" {e}"),
            ID,
        ) else {
            panic!("a sky")
        };
        assert_close(l, Rgb::splat(8.0));
    }

    /// A fresh folder holding 8-bit RGB PNGs of one grey `value`: (name, width, height, value).
    fn folder_with_pngs(test: &str, images: &[(&str, u32, u32, u8)]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("lancer-lights-{test}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for &(name, w, h, v) in images {
            let file = std::fs::File::create(dir.join(name)).unwrap();
            let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            let data = vec![v; (3 * w * h) as usize];
            enc.write_header().unwrap().write_image_data(&data).unwrap();
        }
        dir
    }

    #[test]
    fn image_skies() {
        let dir = folder_with_pngs(
            "sky",
            &[
                ("sky.png", 2, 2, 255),
                ("black.png", 1, 1, 0),
                ("wide.png", 3, 1, 255),
            ],
        );
        let convert = |text: &str| {
            let (out, unused) = convert_in(text, &dir, ID);
            (out.unwrap_or_else(|e| panic!("{e}")), unused)
        };
        let (f, unused) =
            convert(r#"LightSource "infinite" "string filename" "sky.png" "float scale" 3"#);
        assert!(f.warnings.is_empty() && unused.is_empty());
        let Some(LightDesc::ImageInfinite(ImageInfiniteDesc { l, image, .. })) = f.value else {
            panic!("a sky")
        };
        assert_eq!(l, Rgb::splat(3.0));
        assert_eq!((image.width, image.height, image.texels[0].x), (2, 2, 1.0));
        let (f, _) = convert(
            r#"LightSource "infinite" "string filename" "black.png" "float illuminance" 1
               "point3 portal" [0 0 0 1 0 0 1 1 0 0 1 0]"#,
        );
        let black = dir.join("black.png");
        assert_eq!(
            f.warnings,
            [format!(
                "{} is black above the horizon, so \"illuminance\" cannot scale it; ignored",
                black.display()
            )]
        );
        // The portal's corners are world space, whatever the CTM.
        let Some(LightDesc::PortalInfinite(PortalInfiniteDesc { portal, .. })) = f.value else {
            panic!("a portal light")
        };
        assert_eq!(portal[2], Vec3::new(1.0, 1.0, 0.0));
        // A uniform `L` behind a portal: pbrt-v4's 1×1 image of L's colour, `scale` apart;
        // its `illuminance` divides by pbrt-v4's 2π·Y of that texel (2π·0.5 = π here).
        let (f, unused) = convert(
            r#"LightSource "infinite" "rgb L" [0.5 0.5 0.5] "float scale" 2
               "float illuminance" 6.2831853 "point3 portal" [0 0 0 1 0 0 1 1 0 0 1 0]"#,
        );
        assert!(f.warnings.is_empty() && unused.is_empty());
        let Some(LightDesc::PortalInfinite(PortalInfiniteDesc { l, image, .. })) = f.value else {
            panic!("a portal light")
        };
        assert_eq!((image.width, image.height, image.texels[0].x), (1, 1, 0.5));
        // scale 2 · E / (2π·0.5) = 2 · 2π / π = 4.
        assert!((l.x - 4.0).abs() < 1e-4, "{l:?}");
        let error = |text: &str| err(convert_in(text, &dir, ID).0);
        assert_eq!(
            error(
                r#"LightSource "infinite" "string filename" "sky.png" "point3 portal" [0 0 0 1 0 0 1 1 0]"#
            ),
            "t.pbrt:1:1: an infinite light's \"portal\" takes 4 points, not 3"
        );
        assert_eq!(
            error(
                r#"LightSource "infinite" "string filename" "sky.png" "point3 portal" [0 0 0 1 0 0 2 1 0 0 1 0]"#
            ),
            "t.pbrt:1:1: an infinite light's portal must be a rectangle, its corners in order"
        );
        assert_eq!(
            error(r#"LightSource "infinite" "string filename" "sky.png" "rgb L" [1 1 1]"#),
            "t.pbrt:1:1: an \"infinite\" light takes either \"L\" or \"filename\", not both"
        );
        assert_eq!(
            error(r#"LightSource "infinite" "string filename" "wide.png""#),
            format!(
                "t.pbrt:1:1: {}: an environment image must be square (equal-area octahedral) or twice as wide as high (latitude-longitude), not 3×1",
                dir.join("wide.png").display()
            )
        );
        let missing = error(r#"LightSource "infinite" "string filename" "nope.exr""#);
        assert!(
            missing.starts_with("t.pbrt:1:1: ") && missing.contains("nope.exr"),
            "{missing}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The rules the reader and lancer both know are checked once, by lancer: the reader's
    /// error is lancer's message for the same description, after the directive's location (and
    /// for an image, its file name).
    #[test]
    fn the_readers_errors_are_lancers_rules() {
        let spot = LightDesc::Spot(SpotDesc {
            from: Vec3::Z,
            to: Vec3::Z,
            intensity: Rgb::ONE,
            cone_angle: 30.0,
            cone_delta_angle: 5.0,
        });
        let rule = spot.validate().unwrap_err();
        assert_eq!(
            error(r#"LightSource "spot" "point3 from" [0 0 1]"#),
            format!("t.pbrt:1:1: {rule}")
        );
        let sun = LightDesc::Distant(DistantDesc {
            direction: Vec3::ZERO,
            l: Rgb::ONE,
        });
        let rule = sun.validate().unwrap_err();
        assert_eq!(
            error(r#"LightSource "distant" "point3 to" [0 0 0]"#),
            format!("t.pbrt:1:1: {rule}")
        );
        let dir = folder_with_pngs("rules", &[("wide.png", 3, 1, 255)]);
        let wide = LightDesc::ImageInfinite(ImageInfiniteDesc {
            light_to_world: ID,
            l: Rgb::ONE,
            image: std::sync::Arc::new(lancer::image::Image {
                width: 3,
                height: 1,
                texels: vec![lancer::math::PackedRgb::ONE; 3],
            }),
        });
        let rule = wide.validate().unwrap_err();
        assert_eq!(
            err(convert_in(
                r#"LightSource "infinite" "string filename" "wide.png""#,
                &dir,
                ID
            )
            .0),
            format!("t.pbrt:1:1: {}: {rule}", dir.join("wide.png").display())
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn goniometric_and_projection_lights() {
        // The images of shared/scenes/lights (skipped when the shared folder is absent).
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes/lights");
        if !dir.join("gonio.exr").exists() {
            eprintln!("skipped: no {}", dir.display());
            return;
        }
        let ctm = Transform::translate(Vec3::new(0.0, 1.0, 0.0));
        let (out, unused) = convert_in(
            r#"LightSource "goniometric" "string filename" "gonio.exr" "rgb I" [2 2 2] "float scale" 1.5"#,
            &dir,
            ctm,
        );
        let f = out.unwrap();
        assert!(f.warnings.is_empty() && unused.is_empty());
        let Some(LightDesc::Goniometric(GoniometricDesc {
            light_to_world,
            intensity,
            image,
        })) = f.value
        else {
            panic!("a goniometric light")
        };
        assert_eq!((light_to_world, intensity), (ctm, Rgb::splat(3.0)));
        assert_eq!(image.width, image.height);
        // `power` Φ: I · 4π · mean(Y) = Φ.
        let (out, _) = convert_in(
            r#"LightSource "goniometric" "string filename" "gonio.exr" "float power" 10"#,
            &dir,
            ID,
        );
        let Some(LightDesc::Goniometric(GoniometricDesc {
            intensity, image, ..
        })) = out.unwrap().value
        else {
            panic!("a goniometric light")
        };
        let light = lancer::light::GoniometricLight::new(ID, intensity, &image).unwrap();
        assert!((light.power() - 10.0).abs() < 1e-3, "{}", light.power());
        let (out, unused) = convert_in(
            r#"LightSource "projection" "string filename" "slide.png" "float fov" 35 "float scale" 6"#,
            &dir,
            ctm,
        );
        assert!(unused.is_empty());
        let Some(LightDesc::Projection(ProjectionDesc { scale, fov, .. })) = out.unwrap().value
        else {
            panic!("a projection light")
        };
        assert_eq!((scale, fov), (6.0, 35.0));
        assert_eq!(
            err(convert_in(
                "LightSource \"projection\" \"string filename\" \"slide.png\"\n  \"float fov\" 180",
                &dir,
                ID
            )
            .0),
            "t.pbrt:2:3: \"float fov\" must be in (0, 180), not 180"
        );
        assert_eq!(
            error(r#"LightSource "laser""#),
            "t.pbrt:1:1: unknown light \"laser\" (expected point, spot, distant, infinite, goniometric, projection or sunsky)"
        );
    }

    #[test]
    fn area_lights() {
        let area = |text: &str| {
            let (ty, params, loc) = typed_in(text, Path::new("."));
            let out = area_light(&params, &ty, &SearchPath::new(Path::new(".")), &loc);
            (out, unused(&params))
        };
        let (out, unused) = area(r#"AreaLightSource "diffuse""#);
        assert_eq!(
            out,
            Ok(AreaLightDesc {
                l: Rgb::ONE,
                two_sided: false,
                spectrum: None,
                power: None,
                image: None,
            })
        );
        assert!(unused.is_empty());
        let (out, unused) = area(
            r#"AreaLightSource "diffuse" "rgb L" [1 2 3] "float scale" 2 "bool twosided" true"#,
        );
        assert_eq!(
            out,
            Ok(AreaLightDesc {
                l: Rgb::new(2.0, 4.0, 6.0),
                two_sided: true,
                spectrum: None,
                power: None,
                image: None,
            })
        );
        assert!(unused.is_empty());
        // `power` is kept for the build (which knows each primitive's area); 0 or less is
        // pbrt-v4's "not given".
        let (out, unused) = area(r#"AreaLightSource "diffuse" "float power" 20"#);
        assert_eq!(out.unwrap().power, Some(20.0));
        assert!(unused.is_empty());
        let (out, _) = area(r#"AreaLightSource "diffuse" "float power" 0"#);
        assert_eq!(out.unwrap().power, None);
        // A spectrum is normalised to luminance 1 (before `scale`).
        let (out, _) = area(r#"AreaLightSource "diffuse" "blackbody L" 3000"#);
        let l = out.unwrap().l;
        let luminance = 0.2126 * l.x + 0.7152 * l.y + 0.0722 * l.z;
        assert!((luminance - 1.0).abs() < 1e-3, "{luminance}");
        assert_eq!(
            err(area(r#"AreaLightSource "spot""#).0),
            "t.pbrt:1:1: unknown area light \"spot\" (expected \"diffuse\")"
        );
        assert_eq!(
            err(area("AreaLightSource \"diffuse\"\n  \"rgb L\" [-1 1 1]").0),
            "t.pbrt:2:3: \"rgb L\" has a negative component: -1 1 1"
        );
    }
}
