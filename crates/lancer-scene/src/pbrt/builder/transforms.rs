//! The transformation directives and pbrt's two current transformation matrices: one for the
//! shutter's start time and one for its end (`ActiveTransform` chooses which the directives
//! change, `TransformTimes` gives their times). Where the two differ, things move: a moving
//! shape becomes a [`MovingShapeDesc`](lancer::scene::desc::MovingShapeDesc).

use super::{Active, Builder};
use crate::error::{Location, SceneError};
use crate::pbrt::parser::Directive;
use crate::pbrt::singular::{is_singular, kept};
use lancer::math::{AnimatedTransform, Mat4, Transform, Vec3};

impl Builder {
    /// `ctm ← ctm · t`, as pbrt post-multiplies every transformation.
    pub(super) fn concat(
        &mut self,
        t: Option<Transform>,
        what: &str,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let t = t.ok_or_else(|| {
            SceneError::at(
                loc.clone(),
                format!(
                    "{what} gives a singular transformation (it flattens space and cannot be inverted)"
                ),
            )
        })?;
        if self.gs.active.start {
            self.gs.ctm = self.gs.ctm * t;
        }
        if self.gs.active.end {
            self.gs.ctm_end = self.gs.ctm_end * t;
        }
        Ok(())
    }

    /// Sets the active CTMs to `t` (`Identity`, `Transform`).
    pub(super) fn set_ctm(&mut self, t: Transform) {
        if self.gs.active.start {
            self.gs.ctm = t;
        }
        if self.gs.active.end {
            self.gs.ctm_end = t;
        }
    }

    /// The CTM over the shutter interval (moving when the two CTMs differ).
    pub(super) fn animated_ctm(&self) -> AnimatedTransform {
        let [t0, t1] = self.gs.times;
        AnimatedTransform::new(self.gs.ctm, t0, self.gs.ctm_end, t1)
    }

    /// The directives that change the current transformation (and the orientation).
    pub(super) fn transform(&mut self, d: Directive, loc: &Location) -> Result<(), SceneError> {
        use Directive as D;
        match d {
            D::Identity => self.set_ctm(Transform::IDENTITY),
            D::Translate([x, y, z]) => self.concat(
                Some(Transform::translate(Vec3::new(x, y, z))),
                "Translate",
                loc,
            )?,
            D::Scale([x, y, z]) => {
                // Transform::scale's exact reciprocals when it has them (as before).
                let s = Vec3::new(x, y, z);
                let t = Transform::scale(s).unwrap_or_else(|| kept(Mat4::from_scale(s.into())));
                self.concat(Some(t), "Scale", loc)?
            }
            D::Rotate([a, x, y, z]) => {
                let r = Transform::rotate(a, Vec3::new(x, y, z));
                if r.is_none() {
                    return Err(SceneError::at(loc.clone(), "Rotate about a zero axis"));
                }
                self.concat(r, "Rotate", loc)?
            }
            D::LookAt(v) => {
                let t = Transform::look_at(
                    Vec3::new(v[0], v[1], v[2]),
                    Vec3::new(v[3], v[4], v[5]),
                    Vec3::new(v[6], v[7], v[8]),
                );
                if t.is_none() {
                    return Err(SceneError::at(
                        loc.clone(),
                        "LookAt: the eye and the point looked at coincide, or 'up' is parallel \
                         to the viewing direction",
                    ));
                }
                self.concat(t, "LookAt", loc)?
            }
            D::Transform(m) => {
                // pbrt's 16 numbers are the matrix column by column.
                let t = kept(Mat4::from_cols_array(&m));
                self.set_ctm(Transform::IDENTITY);
                self.concat(Some(t), "Transform", loc)?
            }
            D::ConcatTransform(m) => {
                let t = kept(Mat4::from_cols_array(&m));
                self.concat(Some(t), "ConcatTransform", loc)?
            }
            D::CoordinateSystem(name) => {
                self.named_coords
                    .insert(name, (self.gs.ctm, self.gs.ctm_end));
            }
            D::CoordSysTransform(name) => match self.named_coords.get(&name) {
                Some(&(t0, t1)) => (self.gs.ctm, self.gs.ctm_end) = (t0, t1),
                None => self.warn(
                    loc,
                    format!("no coordinate system named \"{name}\"; CoordSysTransform ignored"),
                ),
            },
            D::ActiveTransform(which) => {
                self.gs.active = Active {
                    start: which != "EndTime",
                    end: which != "StartTime",
                }
            }
            D::TransformTimes([t0, t1]) => {
                self.require_options("TransformTimes", loc)?;
                if t0 > t1 || t0.is_nan() || t1.is_nan() {
                    return Err(SceneError::at(
                        loc.clone(),
                        format!(
                            "TransformTimes: the end time {t1} comes before the start time {t0}"
                        ),
                    ));
                }
                self.gs.times = [t0, t1];
            }
            D::ReverseOrientation => self.gs.reverse_orientation ^= true,
            other => unreachable!("not a transformation directive: {other:?}"),
        }
        Ok(())
    }

    /// The moving transformation of a shape about to be added, when the two CTMs differ
    /// (pbrt-v4's animated shapes; inside an object definition, see `object_motion`). pbrt-v4
    /// refuses moving area lights; a moving shape whose transformation is singular at either
    /// end stands at its start pose, and a moving shape's alpha is ignored (each with a
    /// warning).
    pub(super) fn moving_shape(
        &mut self,
        emits: bool,
        alpha: bool,
        loc: &Location,
    ) -> Result<Option<AnimatedTransform>, SceneError> {
        let moving = self.animated_ctm();
        if !moving.is_animated() {
            return Ok(None);
        }
        if emits {
            return Err(SceneError::at(
                loc.clone(),
                "this area light's shape moves during the shutter: pbrt-v4 refuses moving area \
                 lights (keep the AreaLightSource outside the ActiveTransform block)",
            ));
        }
        if alpha {
            self.warn_once(
                "moving-alpha",
                loc,
                "alpha cut-outs on moving shapes are not supported yet: lancer renders them \
                 opaque",
            );
        }
        if is_singular(&self.gs.ctm) || is_singular(&self.gs.ctm_end) {
            self.warn(
                loc,
                "this moving shape's transformation is singular at one end: lancer uses its \
                 start pose",
            );
            return Ok(None);
        }
        Ok(Some(moving))
    }
}
