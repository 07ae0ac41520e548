//! [`Integrator`]: the light transport algorithm as the scene describes it (plain data, filled
//! in by the readers); [`super`] runs it.

/// The light transport algorithm: what the scene asks for and what the renderer runs (its
/// methods are in [`crate::integrator`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// The course: direct light from every light with shadows, plus perfect specular
    /// reflection and refraction up to `max_depth` levels.
    Whitted {
        /// Specular recursion depth.
        max_depth: u32,
    },
    /// Unidirectional path tracing with next-event estimation and MIS.
    Path {
        /// Maximum number of bounces.
        max_depth: u32,
        /// Roughen near-specular lobes after the first non-specular bounce (pbrt's
        /// `regularize`).
        regularize: bool,
    },
    /// Path tracing with the caustics the camera sees directly rendered by light tracing
    /// (lancer's `Integrator "path" "bool caustics" [true]`; [`crate::integrator::caustics`]):
    /// one light path per camera sample, through specular bounces only, joined to the lens.
    PathCaustics {
        /// Maximum number of bounces.
        max_depth: u32,
        /// Light paths per camera sample (`causticpaths`, in (0, 1], default
        /// [`crate::integrator::caustics::DEFAULT_PATHS`]): each camera sample traces one with
        /// this probability, its splats weighted by its inverse.
        paths: f32,
    },
    /// Ambient occlusion.
    AmbientOcclusion {
        /// Cosine-weighted sampling.
        cos_sample: bool,
        /// Occluders farther than this are ignored.
        max_distance: f32,
    },
    /// Volumetric path tracing (pbrt-v4's `volpath`): path tracing through participating
    /// media by delta tracking, with spectral MIS.
    VolPath {
        /// Maximum number of scattering events (surfaces and media).
        max_depth: u32,
        /// As for [`Integrator::Path`].
        regularize: bool,
    },
    /// Light tracing (pbrt-v4's `lightpath`): paths from the lights, each vertex connected
    /// to the camera and splatted onto the film.
    LightPath {
        /// Maximum number of bounces.
        max_depth: u32,
    },
    /// Bidirectional path tracing (pbrt-v4's `bdpt`): every way of joining a light subpath
    /// to a camera subpath, weighted by multiple importance sampling.
    Bdpt {
        /// Maximum number of bounces.
        max_depth: u32,
        /// As for [`Integrator::Path`].
        regularize: bool,
        /// pbrt-v4's `visualizestrategies`: one image per strategy (s, t), unweighted
        /// ([`crate::render::strategies`]).
        visualize_strategies: bool,
        /// pbrt-v4's `visualizeweights`: one image per strategy, weighted (these add up to
        /// the image).
        visualize_weights: bool,
    },
    /// Metropolis light transport over bdpt's strategies in primary sample space (pbrt-v4's
    /// `mlt`): Markov chains instead of pixel samples ([`crate::integrator::mlt`]).
    Mlt(MltOptions),
    /// Stochastic progressive photon mapping (pbrt-v4's `sppm`): per iteration (one per
    /// sample per pixel), a visible point per pixel and photons from the lights gathered at
    /// them within a radius that shrinks from iteration to iteration.
    Sppm(SppmOptions),
    /// Vertex connection and merging (lancer's extension; Georgiev et al. 2012): per
    /// iteration (one per sample per pixel), one light subpath per pixel, and per pixel a
    /// camera subpath joined to them by every bidirectional connection and by merging with
    /// the light vertices within a radius that shrinks from iteration to iteration, all
    /// weighted by multiple importance sampling ([`crate::integrator::vcm`]).
    Vcm(VcmOptions),
    /// pbrt-v4's `simplepath`: path tracing without MIS, light sampling and BSDF sampling
    /// each optional.
    SimplePath {
        /// Maximum number of bounces.
        max_depth: u32,
        /// Sample a light at each surface (`samplelights`).
        sample_lights: bool,
        /// Continue by BSDF sampling (`samplebsdf`), else uniformly.
        sample_bsdf: bool,
    },
    /// pbrt-v4's `randomwalk`: directions uniform over the sphere, no light sampling.
    RandomWalk {
        /// Maximum number of bounces.
        max_depth: u32,
    },
    /// pbrt-v4's `simplevolpath`: delta tracking through media at one wavelength, emission
    /// gathered where the walk meets it, no light sampling; surfaces only pass rays between
    /// media (`interface`) or end the path.
    SimpleVolPath {
        /// Maximum number of scattering events in media.
        max_depth: u32,
    },
    /// Debug view: shading normals mapped to colours, (n + 1)/2.
    Normals,
    /// Debug view: distance to the first hit.
    Depth,
}

impl Default for Integrator {
    /// pbrt's default: `volpath`, maxdepth 5.
    fn default() -> Self {
        Integrator::VolPath {
            max_depth: 5,
            regularize: false,
        }
    }
}

impl Integrator {
    /// The pbrt-v4 name of this integrator (`Integrator "…"`): `path`, `volpath`, `whitted`,
    /// `ambientocclusion`, `lightpath`, `bdpt`, `mlt`, `sppm`, `simplepath`, `randomwalk`,
    /// `simplevolpath`, lancer's `vcm`, and lancer's debug
    /// views `normals` and `depth`.
    pub fn pbrt_name(&self) -> &'static str {
        match self {
            Integrator::Whitted { .. } => "whitted",
            Integrator::Path { .. } | Integrator::PathCaustics { .. } => "path",
            Integrator::VolPath { .. } => "volpath",
            Integrator::AmbientOcclusion { .. } => "ambientocclusion",
            Integrator::LightPath { .. } => "lightpath",
            Integrator::Bdpt { .. } => "bdpt",
            Integrator::Mlt(_) => "mlt",
            Integrator::Sppm(_) => "sppm",
            Integrator::Vcm(_) => "vcm",
            Integrator::SimplePath { .. } => "simplepath",
            Integrator::RandomWalk { .. } => "randomwalk",
            Integrator::SimpleVolPath { .. } => "simplevolpath",
            Integrator::Normals => "normals",
            Integrator::Depth => "depth",
        }
    }

    /// True for the integrators that compute radiance (path tracing, Whitted), which spectral
    /// mode applies to; the debug views output other quantities and always work in RGB.
    pub fn computes_radiance(&self) -> bool {
        matches!(
            self,
            Integrator::Whitted { .. }
                | Integrator::Path { .. }
                | Integrator::PathCaustics { .. }
                | Integrator::VolPath { .. }
                | Integrator::LightPath { .. }
                | Integrator::Bdpt { .. }
                | Integrator::Mlt(_)
                | Integrator::Sppm(_)
                | Integrator::Vcm(_)
                | Integrator::SimplePath { .. }
                | Integrator::RandomWalk { .. }
                | Integrator::SimpleVolPath { .. }
        )
    }

    /// True for the integrators that trace light paths and splat what they carry anywhere on
    /// the film ([`Integrator::li_splatting`]): `lightpath`, `bdpt`, `mlt` (whose image
    /// is splats alone), `vcm` and `path` with `caustics`. They need a perspective camera
    /// ([`crate::camera::Camera::light_path_support`]).
    pub fn splats(&self) -> bool {
        matches!(
            self,
            Integrator::LightPath { .. }
                | Integrator::PathCaustics { .. }
                | Integrator::Bdpt { .. }
                | Integrator::Mlt(_)
                | Integrator::Vcm(_)
        )
    }

    /// The length of a render's axis of sample indices: its samples per pixel `spp`, or for
    /// `mlt`, whose units of work are Markov chains and not pixel samples, its chains (a
    /// render's sample range, `--samples a..b` or a split by samples, is then a range of
    /// chains).
    pub fn sample_indices(&self, spp: u32) -> u32 {
        match self {
            Integrator::Mlt(o) => o.chains,
            _ => spp,
        }
    }
}

/// The `mlt` settings of a render (pbrt-v4's parameters and defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MltOptions {
    /// Longest path, in bounces (`maxdepth`, 5).
    pub max_depth: u32,
    /// Bootstrap vectors per depth (`bootstrapsamples`, 100000).
    pub bootstrap_samples: u32,
    /// Markov chains (`chains`, 1000).
    pub chains: u32,
    /// Mutations per pixel of the film's sample bounds (`mutationsperpixel`, 100).
    pub mutations_per_pixel: u32,
    /// Probability of a large step (`largestepprobability`, 0.3).
    pub large_step_probability: f32,
    /// Deviation of a small step (`sigma`, 0.01).
    pub sigma: f32,
    /// As for bdpt (`regularize`, false).
    pub regularize: bool,
}

/// The `sppm` settings of a render (pbrt-v4's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SppmOptions {
    /// Longest camera path and longest photon path, in bounces (`maxdepth`, default 5).
    pub max_depth: u32,
    /// Photons traced per iteration (`photonsperiteration`); `None` (pbrt-v4's −1, or any
    /// value ≤ 0): as many as the render has pixels.
    pub photons_per_iteration: Option<u32>,
    /// Every pixel's initial search radius, in world units (`radius`, default 1).
    pub radius: f32,
    /// Seed of the photons' scrambled Halton points (`seed`); `None`: the render's seed.
    pub seed: Option<u64>,
}

/// The `vcm` settings of a render (lancer's extension).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VcmOptions {
    /// Longest path, in bounces (`maxdepth`, default 5).
    pub max_depth: u32,
    /// The merge radius of the first iteration, in world units (`radius`); `None`: 0.003 ×
    /// the radius of the scene's bounding sphere, as the paper's reference implementation
    /// (SmallVCM) chooses ([`crate::integrator::vcm::DEFAULT_RADIUS_FRACTION`]).
    pub radius: Option<f32>,
    /// How fast the radius shrinks (`alpha`, in (0, 1], default 0.75): iteration i (from 1)
    /// merges within r_i = r_1 · i^((α − 1)/2).
    pub alpha: f32,
}
