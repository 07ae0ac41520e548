//! pbrt-v4's `gbuffer` film: besides colour, per-pixel auxiliary channels of the surface first
//! seen through each pixel (a denoiser's inputs).
//!
//! The channels, as pbrt-v4 names them: `R G B`, `Albedo.{R,G,B}`, `P.{X,Y,Z}`, `dzdx`,
//! `dzdy`, `N.{X,Y,Z}`, `Ns.{X,Y,Z}`, `u`, `v`, `Variance.{R,G,B}`,
//! `RelativeVariance.{R,G,B}`; positions and normals in camera space unless the film's
//! `"string coordinatesystem"` is `"world"`.

/// What a `gbuffer` film asks for beyond colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GbufferDesc {
    /// Positions and normals in world space (`"world"`) rather than camera space (`"camera"`,
    /// pbrt-v4's default).
    pub world_space: bool,
}
