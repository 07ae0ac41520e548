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
    /// `ambientocclusion`, and lancer's debug views `normals` and `depth`.
    pub fn pbrt_name(&self) -> &'static str {
        match self {
            Integrator::Whitted { .. } => "whitted",
            Integrator::Path { .. } => "path",
            Integrator::VolPath { .. } => "volpath",
            Integrator::AmbientOcclusion { .. } => "ambientocclusion",
            Integrator::Normals => "normals",
            Integrator::Depth => "depth",
        }
    }

    /// True for the integrators that compute radiance (path tracing, Whitted), which spectral
    /// mode applies to; the debug views output other quantities and always work in RGB.
    pub fn computes_radiance(&self) -> bool {
        matches!(
            self,
            Integrator::Whitted { .. } | Integrator::Path { .. } | Integrator::VolPath { .. }
        )
    }
}
