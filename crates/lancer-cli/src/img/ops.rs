//! What `lancer img convert` does to the pixels: crop, resize by a box filter, exposure and
//! tone mapping. Images are linear RGB, row-major, row 0 at the top.

use lancer::math::Rgb;

/// A linear RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, `y·width + x`.
    pub pixels: Vec<Rgb>,
}

/// A pixel rectangle `[x0, x1) × [y0, y1)` (pbrt's `--crop x0,x1,y0,y1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

/// How `convert` maps linear values before writing them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Tonemap {
    /// Values unchanged (a PNG clamps them to [0, 1]).
    None,
    /// Narkowicz's 2015 fit of the ACES filmic curve.
    Aces,
    /// Reinhard's x / (1 + x).
    Reinhard,
}

impl Tonemap {
    /// The curve applied to one channel value `x`; negative values are taken as 0 by the two
    /// curves (both are meant for radiance, which is not negative), NaN stays NaN.
    pub fn apply(self, x: f32) -> f32 {
        match self {
            Tonemap::None => x,
            // Reinhard et al. 2002, the simple global operator: x / (1 + x), in [0, 1).
            Tonemap::Reinhard => {
                let x = x.max(0.0);
                if x.is_infinite() { 1.0 } else { x / (1.0 + x) }
            }
            // Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve" (2015): the fit
            // x(a x + b) / (x(c x + d) + e), a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14,
            // clamped to [0, 1]; applied to x as given (his post's 0.6 pre-scale is left to
            // --exposure: −0.737 stops is ×0.6).
            Tonemap::Aces => {
                let x = x.max(0.0);
                if x.is_infinite() {
                    return 1.0;
                }
                let (a, b, c, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
                ((x * (a * x + b)) / (x * (c * x + d) + e)).clamp(0.0, 1.0)
            }
        }
    }
}

impl Picture {
    /// The pixels of `crop`; an error says why the rectangle does not fit.
    pub fn crop(&self, crop: Crop) -> Result<Picture, String> {
        let Crop { x0, x1, y0, y1 } = crop;
        if x0 >= x1 || y0 >= y1 {
            return Err(format!(
                "the crop {x0},{x1},{y0},{y1} is empty (it needs x0 < x1 and y0 < y1)"
            ));
        }
        if x1 > self.width || y1 > self.height {
            return Err(format!(
                "the crop {x0},{x1},{y0},{y1} goes past the image's {}x{} pixels",
                self.width, self.height
            ));
        }
        let w = self.width as usize;
        let pixels = (y0..y1)
            .flat_map(|y| {
                let row = y as usize * w;
                self.pixels[row + x0 as usize..row + x1 as usize]
                    .iter()
                    .copied()
            })
            .collect();
        Ok(Picture {
            width: x1 - x0,
            height: y1 - y0,
            pixels,
        })
    }

    /// Resamples to `width × height` with a box filter: each new pixel is the area-weighted
    /// average of the old pixels its footprint covers. New pixel `i` of a row covers old columns
    /// `[i·W/w, (i+1)·W/w)` (W the old width, w the new); an old pixel counts with the length of
    /// its overlap, and the weights of a new pixel add up to 1. Rows likewise; the 2-D weight is
    /// the product (the box is separable). Enlarging repeats pixels (nearest neighbour, with
    /// blends where a new pixel straddles two old ones).
    pub fn resize(&self, width: u32, height: u32) -> Picture {
        let wx = box_weights(self.width, width);
        let wy = box_weights(self.height, height);
        let w = self.width as usize;
        // Rows first: each old row resampled to `width` pixels, in f64.
        let rows: Vec<[f64; 3]> = (0..self.height as usize)
            .flat_map(|y| {
                let row = &self.pixels[y * w..(y + 1) * w];
                wx.iter().map(move |taps| {
                    let mut s = [0.0f64; 3];
                    for &(x, k) in taps {
                        for (c, sc) in s.iter_mut().enumerate() {
                            *sc += k * row[x][c] as f64;
                        }
                    }
                    s
                })
            })
            .collect();
        let nw = width as usize;
        let pixels = wy
            .iter()
            .flat_map(|taps| {
                let rows = &rows;
                (0..nw).map(move |x| {
                    let mut s = [0.0f64; 3];
                    for &(y, k) in taps {
                        for (c, sc) in s.iter_mut().enumerate() {
                            *sc += k * rows[y * nw + x][c];
                        }
                    }
                    Rgb::new(s[0] as f32, s[1] as f32, s[2] as f32)
                })
            })
            .collect();
        Picture {
            width,
            height,
            pixels,
        }
    }

    /// Multiplies every value by 2^stops.
    pub fn expose(&mut self, stops: f32) {
        let k = stops.exp2();
        for p in &mut self.pixels {
            *p *= k;
        }
    }

    /// Applies `tonemap` to every channel of every pixel.
    pub fn tonemap(&mut self, tonemap: Tonemap) {
        for p in &mut self.pixels {
            for c in 0..3 {
                p[c] = tonemap.apply(p[c]);
            }
        }
    }
}

/// For each of `to` new pixels along an axis of `from` old ones: the old pixels it overlaps and
/// their weights, `overlap length / footprint length` with footprint `[i·from/to, (i+1)·from/to)`.
/// Computed in units of 1/to of an old pixel so the ends are exact integers: new pixel `i` is
/// `[i·from, (i+1)·from)` and old pixel `j` is `[j·to, (j+1)·to)`.
fn box_weights(from: u32, to: u32) -> Vec<Vec<(usize, f64)>> {
    let (from, to) = (from as u64, to as u64);
    (0..to)
        .map(|i| {
            let (a, b) = (i * from, (i + 1) * from);
            (a / to..b.div_ceil(to))
                .filter_map(|j| {
                    let overlap = b.min((j + 1) * to).saturating_sub(a.max(j * to));
                    (overlap > 0).then(|| (j as usize, overlap as f64 / from as f64))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_weights_by_hand() {
        // 3 → 2: new pixel 0 is [0, 1.5): old 0 whole and half of old 1.
        let w = box_weights(3, 2);
        assert_eq!(w[0], vec![(0, 2.0 / 3.0), (1, 1.0 / 3.0)]);
        assert_eq!(w[1], vec![(1, 1.0 / 3.0), (2, 2.0 / 3.0)]);
        // 2 → 4: each old pixel repeated twice.
        let w = box_weights(2, 4);
        assert_eq!(
            w,
            vec![
                vec![(0, 1.0)],
                vec![(0, 1.0)],
                vec![(1, 1.0)],
                vec![(1, 1.0)]
            ]
        );
    }

    #[test]
    fn tonemaps_on_known_values() {
        assert_eq!(Tonemap::Reinhard.apply(1.0), 0.5);
        assert_eq!(Tonemap::Reinhard.apply(3.0), 0.75);
        assert_eq!(Tonemap::Reinhard.apply(-1.0), 0.0);
        // ACES at 1: (2.51 + 0.03) / (2.43 + 0.59 + 0.14) = 2.54 / 3.16.
        assert!((Tonemap::Aces.apply(1.0) - 2.54 / 3.16).abs() < 1e-6);
        assert_eq!(Tonemap::Aces.apply(0.0), 0.0);
        assert_eq!(Tonemap::Aces.apply(100.0), 1.0);
        assert_eq!(Tonemap::None.apply(7.5), 7.5);
    }
}
