use super::*;

fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Arc<Image> {
    let texels = (0..w * h)
        .map(|i| PackedRgb::splat(f(i % w, i / w)))
        .collect();
    Arc::new(Image::new(w, h, texels).unwrap())
}

fn value(img: &Image, x: u32, y: u32) -> f32 {
    img.texels[(y * img.width + x) as usize].x
}

/// A lookup at (s, t) whose footprint is `width`/2 along s per pixel in x, and `dt` along t
/// per pixel in y.
fn fp(st: Vec2, dsdx: f32, dtdy: f32) -> StFootprint {
    StFootprint {
        st,
        dsdx,
        dsdy: 0.0,
        dtdx: 0.0,
        dtdy,
    }
}

#[test]
fn the_pyramid_averages_two_by_two_boxes() {
    // 4×2 texels 0..7 in reading order.
    let m = MipMap::new(image(4, 2, |x, y| (y * 4 + x) as f32), WrapMode::Repeat);
    assert_eq!(m.levels(), 3);
    let l1 = m.level(1);
    assert_eq!((l1.width, l1.height), (2, 1));
    // (0 + 1 + 4 + 5)/4 = 2.5, (2 + 3 + 6 + 7)/4 = 4.5.
    assert_eq!((value(l1, 0, 0), value(l1, 1, 0)), (2.5, 4.5));
    // 2×1 → 1×1: the mean of the two.
    let l2 = m.level(2);
    assert_eq!((l2.width, l2.height, value(l2, 0, 0)), (1, 1, 3.5));
    // Level 0 of a power-of-two image is the image itself, not a copy.
    let img = image(2, 2, |x, _| x as f32);
    let m = MipMap::new(img.clone(), WrapMode::Clamp);
    assert!(Arc::ptr_eq(&img, &m.levels[0]));
}

#[test]
fn non_power_of_two_images_are_resampled_up() {
    // A constant stays constant under normalised weights (repeat and clamp alike).
    for wrap in [WrapMode::Repeat, WrapMode::Clamp] {
        let m = MipMap::new(image(3, 5, |_, _| 0.25), wrap);
        let l0 = m.level(0);
        assert_eq!((l0.width, l0.height), (4, 8));
        assert!(l0.texels.iter().all(|t| (t.x - 0.25).abs() < 1e-6));
        assert_eq!(m.levels(), 4);
    }
    // Equal sizes give the identity weights [0, 1, 0, 0] from the texel before.
    for (first, w) in resample_weights(4, 4) {
        assert!(
            first >= -1 && (w[1] - 1.0).abs() < 1e-6 && w[0].abs() < 1e-6,
            "{w:?}"
        );
    }
    // 2 → 4: the new texel 0 is centred at 0.25 source texels; its four taps at −1.5 … 1.5
    // from ⌊0.25 − 1.5⌋ = −2, i.e. x − c = −1.75, −0.75, 0.25, 1.25.
    let (first, w) = resample_weights(2, 4)[0];
    assert_eq!(first, -2);
    let lanczos = |x: f32| {
        let s = |x: f32| (std::f32::consts::PI * x).sin() / (std::f32::consts::PI * x);
        s(x) * s(x / 2.0)
    };
    let raw = [-1.75f32, -0.75, 0.25, 1.25].map(lanczos);
    let sum: f32 = raw.iter().sum();
    for j in 0..4 {
        assert!((w[j] - raw[j] / sum).abs() < 1e-6);
    }
}

/// Levels holding their own index: 8×8 of 0, 4×4 of 1, 2×2 of 2, 1×1 of 3.
fn numbered_levels() -> MipMap {
    MipMap::from_levels(
        (0..4)
            .map(|l| image(8 >> l, 8 >> l, move |_, _| l as f32))
            .collect(),
    )
}

#[test]
fn trilinear_picks_the_level_of_the_footprints_width() {
    let m = numbered_levels();
    let st = Vec2::new(0.3, 0.6);
    let look = |f, width: f32| m.filter(f, WrapMode::Repeat, &fp(st, width / 2.0, 0.0)).x;
    // ℓ = (4 − 1) + log₂ width: width ¼ → level 1; 2^−1.75 → 1.25 (a quarter of the way to
    // level 2); width ≥ 1 → the top texel; a zero footprint → level 0.
    assert!((look(ImageFilter::Trilinear, 0.25) - 1.0).abs() < 1e-5);
    assert!((look(ImageFilter::Trilinear, 2f32.powf(-1.75)) - 1.25).abs() < 1e-5);
    assert_eq!(look(ImageFilter::Trilinear, 1.0), 3.0);
    assert_eq!(look(ImageFilter::Trilinear, 0.0), 0.0);
    // Bilinear and point take the finer of the two levels.
    assert_eq!(look(ImageFilter::Bilinear, 2f32.powf(-1.75)), 1.0);
    assert_eq!(look(ImageFilter::Point, 2f32.powf(-0.5)), 2.0);
}

#[test]
fn ewa_of_a_constant_image_is_the_constant() {
    let m = MipMap::new(image(16, 8, |_, _| 0.7), WrapMode::Repeat);
    let ewa = ImageFilter::default();
    for (dsdx, dsdy, dtdx, dtdy) in [
        (0.01, 0.0, 0.0, 0.01),
        (0.2, 0.01, -0.003, 0.004),
        (0.0, 0.5, 0.3, 0.0),
        (1e-4, 0.0, 0.0, 3.0),
    ] {
        let c = StFootprint {
            st: Vec2::new(0.37, 0.81),
            dsdx,
            dsdy,
            dtdx,
            dtdy,
        };
        let v = m.filter(ewa, WrapMode::Repeat, &c);
        assert!((v - Rgb::splat(0.7)).abs().max_element() < 1e-5, "{v}");
    }
}

#[test]
fn a_far_checkerboard_filters_to_its_mean() {
    // 64×64 texels, cells of 4×4 texels of 0 and 1.
    let m = MipMap::new(
        image(64, 64, |x, y| ((x / 4 + y / 4) % 2) as f32),
        WrapMode::Repeat,
    );
    let st = Vec2::new(0.4, 0.55);
    // Seen at a grazing angle: 0.3 along s, 0.05 along t per pixel.
    let far = fp(st, 0.3, 0.05);
    for f in [ImageFilter::default(), ImageFilter::Trilinear] {
        let v = m.filter(f, WrapMode::Repeat, &far).x;
        assert!((v - 0.5).abs() < 0.05, "{f:?}: {v}");
    }
    // Up close (a zero footprint) the texels themselves: 0 or 1.
    let v = m.filter(ImageFilter::default(), WrapMode::Repeat, &fp(st, 0.0, 0.0));
    assert!(v.x < 0.01 || v.x > 0.99, "{v}");
}

#[test]
fn the_ewa_weights_are_pbrts_table() {
    // pbrt-v4's MIPFilterLUT starts 0.864664733, 0.849040031 and ends at 0.
    assert!((EWA_WEIGHTS[0] - 0.864_664_7).abs() < 1e-6);
    assert!((EWA_WEIGHTS[1] - 0.849_040_03).abs() < 1e-6);
    assert!(EWA_WEIGHTS[127].abs() < 1e-6);
}

#[test]
fn a_single_level_map_ignores_the_footprint() {
    let img = image(4, 4, |x, _| x as f32);
    let m = MipMap::single(img.clone());
    let c = fp(Vec2::new(0.3, 0.4), 0.5, 0.5);
    let want = img.lookup(c.st, WrapMode::Clamp, false);
    assert_eq!(m.filter(ImageFilter::default(), WrapMode::Clamp, &c), want);
}
