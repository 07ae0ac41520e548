//! The sums of a `gbuffer` film's auxiliary channels (see [`crate::gbuffer`], which fills
//! them and writes them): one [`GPixel`] per pixel, beside the colour sums of
//! [`super::PixelSum`].

use crate::math::{Rgb, Transform, Vec2, Vec3};

/// The channel names pbrt-v4's g-buffer film writes, in its order.
pub const CHANNELS: [&str; 25] = [
    "R",
    "G",
    "B",
    "Albedo.R",
    "Albedo.G",
    "Albedo.B",
    "P.X",
    "P.Y",
    "P.Z",
    "dzdx",
    "dzdy",
    "N.X",
    "N.Y",
    "N.Z",
    "Ns.X",
    "Ns.Y",
    "Ns.Z",
    "u",
    "v",
    "Variance.R",
    "Variance.G",
    "Variance.B",
    "RelativeVariance.R",
    "RelativeVariance.G",
    "RelativeVariance.B",
];

/// What a `gbuffer` film asks for beyond colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GbufferDesc {
    /// Positions and normals in world space (`"world"`) rather than camera space (`"camera"`,
    /// pbrt-v4's default).
    pub world_space: bool,
}

/// The first surface seen by a camera ray, as pbrt-v4's `VisibleSurface`: world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibleSurface {
    /// The point.
    pub p: Vec3,
    /// Geometric normal, turned towards the camera.
    pub n: Vec3,
    /// Shading normal, turned towards the camera.
    pub ns: Vec3,
    /// Surface parameterisation.
    pub uv: Vec2,
    /// Change of `p` for one pixel step in x (the camera ray's differentials, scaled as
    /// pbrt-v4 scales them: by max(1/8, 1/√spp)).
    pub dpdx: Vec3,
    /// Change of `p` for one pixel step in y.
    pub dpdy: Vec3,
    /// The BSDF's directional albedo towards the camera (linear RGB).
    pub albedo: Rgb,
}

/// A running mean and sum of squared deviations (Welford's update, as pbrt-v4's
/// `VarianceEstimator`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Variance {
    /// Values added.
    pub n: u64,
    /// Their mean.
    pub mean: f64,
    /// Σ (x − mean)².
    pub s: f64,
}

impl Variance {
    /// Adds x: δ = x − mean, mean += δ/n, S += δ·(x − mean').
    pub fn add(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.s += d * (x - self.mean);
    }

    /// Adds another estimator's values (Chan et al.'s pairwise update, as pbrt-v4's `Merge`).
    pub fn merge(&mut self, o: &Variance) {
        if o.n == 0 {
            return;
        }
        let (n, m) = (self.n as f64, o.n as f64);
        self.s += o.s + (o.mean - self.mean).powi(2) * n * m / (n + m);
        self.mean = (n * self.mean + m * o.mean) / (n + m);
        self.n += o.n;
    }

    /// The sample variance S / (n − 1) (0 for fewer than two values).
    pub fn variance(&self) -> f64 {
        if self.n > 1 {
            self.s / (self.n - 1) as f64
        } else {
            0.0
        }
    }

    /// Variance / mean (0 with no value or a zero mean).
    pub fn relative(&self) -> f64 {
        if self.n < 1 || self.mean == 0.0 {
            0.0
        } else {
            self.variance() / self.mean
        }
    }
}

/// One pixel's g-buffer sums (the colour itself stays in [`crate::film::PixelSum`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GPixel {
    /// Σ w over every sample (the albedo's divisor, as in pbrt-v4).
    pub weight: f64,
    /// Σ w over the samples that saw a surface.
    pub g_weight: f64,
    /// Σ w·P.
    pub p: [f64; 3],
    /// Σ w·N.
    pub n: [f64; 3],
    /// Σ w·Ns.
    pub ns: [f64; 3],
    /// Σ w·(u, v).
    pub uv: [f64; 2],
    /// Σ w·∂z/∂x, Σ w·∂z/∂y.
    pub dz: [f64; 2],
    /// Σ w·albedo.
    pub albedo: [f64; 3],
    /// Running variance of each colour channel over the samples that saw a surface.
    pub variance: [Variance; 3],
}

impl GPixel {
    /// Adds a sample of colour `rgb` (the sensor's, whose variance pbrt-v4 keeps, after the NaN
    /// and `maxcomponentvalue` rules: [`crate::gbuffer::variance_rgb`]), filter weight `w`,
    /// and its visible surface, already in output space.
    pub fn add(&mut self, rgb: Rgb, w: f32, vs: Option<&VisibleSurface>) {
        let w = w as f64;
        self.weight += w;
        let Some(v) = vs else { return };
        self.g_weight += w;
        for c in 0..3 {
            self.variance[c].add(rgb[c] as f64);
            self.p[c] += w * v.p[c] as f64;
            self.n[c] += w * v.n[c] as f64;
            self.ns[c] += w * v.ns[c] as f64;
            self.albedo[c] += w * v.albedo[c] as f64;
        }
        self.uv[0] += w * v.uv.x as f64;
        self.uv[1] += w * v.uv.y as f64;
        self.dz[0] += w * v.dpdx.z as f64;
        self.dz[1] += w * v.dpdy.z as f64;
    }

    /// Adds another pixel's sums.
    pub fn merge(&mut self, o: &GPixel) {
        self.weight += o.weight;
        self.g_weight += o.g_weight;
        for c in 0..3 {
            self.p[c] += o.p[c];
            self.n[c] += o.n[c];
            self.ns[c] += o.ns[c];
            self.albedo[c] += o.albedo[c];
            self.variance[c].merge(&o.variance[c]);
        }
        for i in 0..2 {
            self.uv[i] += o.uv[i];
            self.dz[i] += o.dz[i];
        }
    }

    /// The auxiliary channels of [`CHANNELS`] after R, G, B (22 values, in order).
    pub fn channels(&self) -> [f32; 22] {
        let div = |s: f64, w: f64| if w != 0.0 { (s / w) as f32 } else { 0.0 };
        let unit = |v: [f64; 3]| {
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.0 {
                v.map(|x| (x / l) as f32)
            } else {
                [0.0; 3]
            }
        };
        let (n, ns) = (unit(self.n), unit(self.ns));
        let g = self.g_weight;
        let var = self.variance.map(|v| v.variance() as f32);
        let rel = self.variance.map(|v| v.relative() as f32);
        [
            div(self.albedo[0], self.weight),
            div(self.albedo[1], self.weight),
            div(self.albedo[2], self.weight),
            div(self.p[0], g),
            div(self.p[1], g),
            div(self.p[2], g),
            div(self.dz[0], g).abs(),
            div(self.dz[1], g).abs(),
            n[0],
            n[1],
            n[2],
            ns[0],
            ns[1],
            ns[2],
            div(self.uv[0], g),
            div(self.uv[1], g),
            var[0],
            var[1],
            var[2],
            rel[0],
            rel[1],
            rel[2],
        ]
    }
}

/// How a render fills a g-buffer: the space its positions and normals are written in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GbufferConfig {
    /// World space → output space (camera space by default, else the identity).
    pub output_from_world: Transform,
    /// Samples per pixel of the whole render (the ray differentials' scale depends on it).
    pub spp: u32,
    /// Filled for the denoiser rather than for a `gbuffer` film: the visible surface is the
    /// first one that is not perfectly specular (mirrors and glass are followed, as Open Image
    /// Denoise asks), and no ray differentials are traced.
    pub for_denoiser: bool,
}

impl GbufferConfig {
    /// The configuration `desc` asks for, with `camera_from_world` the camera's transform.
    pub fn new(desc: GbufferDesc, camera_from_world: Transform, spp: u32) -> GbufferConfig {
        GbufferConfig {
            output_from_world: if desc.world_space {
                Transform::IDENTITY
            } else {
                camera_from_world
            },
            spp,
            for_denoiser: false,
        }
    }

    /// The configuration of the denoiser's auxiliary images: albedo, and shading normals in
    /// camera space, of the first surface that is not perfectly specular.
    pub fn denoiser(camera_from_world: Transform, spp: u32) -> GbufferConfig {
        GbufferConfig {
            output_from_world: camera_from_world,
            spp,
            for_denoiser: true,
        }
    }

    /// `v` moved to output space.
    pub fn to_output(&self, v: &VisibleSurface) -> VisibleSurface {
        let t = &self.output_from_world;
        VisibleSurface {
            p: t.point(v.p),
            n: t.normal(v.n),
            ns: t.normal(v.ns),
            dpdx: t.vector(v.dpdx),
            dpdy: t.vector(v.dpdy),
            ..*v
        }
    }
}

/// A film's g-buffer: the configuration and one [`GPixel`] per pixel of the film's bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct GbufferFilm {
    /// How it is filled.
    pub config: GbufferConfig,
    /// Sums, row-major over the film's bounds.
    pub pixels: Vec<GPixel>,
}

impl GbufferFilm {
    /// An empty g-buffer of `pixels` pixels.
    pub fn new(config: GbufferConfig, pixels: usize) -> GbufferFilm {
        GbufferFilm {
            config,
            pixels: vec![GPixel::default(); pixels],
        }
    }

    /// The denoiser's auxiliary images, row-major over the film's bounds: the albedo
    /// Σw·a / Σw (over every sample, with the film's filter weights w) and the shading normal
    /// Σw·n normalised (0 where no sample saw a surface).
    pub fn denoiser_images(&self) -> (Vec<Rgb>, Vec<Rgb>) {
        self.pixels
            .iter()
            .map(|p| {
                let c = p.channels();
                (Rgb::new(c[0], c[1], c[2]), Rgb::new(c[11], c[12], c[13]))
            })
            .unzip()
    }
}
