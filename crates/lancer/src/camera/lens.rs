//! What a scene says about its camera beyond a projective one, as plain data (a leaf module, so
//! that the scene description can hold it without depending on the cameras themselves): the
//! spherical camera's mapping and the realistic camera's lens prescription and aperture.

use crate::image::Image;
use std::sync::Arc;

/// How pbrt-v4's `spherical` camera lays the sphere of directions on the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SphericalMapping {
    /// pbrt-v4's default: the equal-area octahedral square (every pixel of a square image
    /// covers the same solid angle).
    #[default]
    EqualArea,
    /// Latitude–longitude: u = φ/2π, v = θ/π.
    Equirectangular,
}

/// The shape of a realistic camera's aperture stop (pbrt-v4's `aperture` parameter).
#[derive(Clone, Debug, PartialEq)]
pub enum Aperture {
    /// A disk of the stop's diameter (no `aperture` given).
    Circular,
    /// A radial Gaussian falloff, exp(−r²) − exp(−1), over the stop's disk.
    Gaussian,
    /// A square of half the stop's width.
    Square,
    /// A regular pentagon.
    Pentagon,
    /// A five-pointed star.
    Star,
    /// An image: its channel average is the transmission (row 0 at the top, as read).
    Image(Arc<Image>),
}

/// One interface of a lens system, as a row of a pbrt lens file: all lengths in millimetres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensInterface {
    /// Radius of curvature (positive: centre towards the film); 0 for the aperture stop.
    pub curvature_radius: f32,
    /// Distance along the axis to the next interface (towards the film).
    pub thickness: f32,
    /// Index of refraction of the medium behind the interface (0 or 1: air).
    pub eta: f32,
    /// Diameter of the interface's clear aperture.
    pub aperture_diameter: f32,
}

/// pbrt-v4's `realistic` camera: a lens system traced ray by ray.
#[derive(Clone, Debug, PartialEq)]
pub struct LensDesc {
    /// The interfaces from the scene side to the film side (the lens file's rows).
    pub interfaces: Vec<LensInterface>,
    /// Diameter of the aperture stop in millimetres (`aperturediameter`; clamped to the
    /// stop's own diameter in the file).
    pub aperture_diameter: f32,
    /// Distance from the film to the plane in focus, in scene units (metres).
    pub focus_distance: f32,
    /// The aperture stop's shape.
    pub aperture: Aperture,
}
