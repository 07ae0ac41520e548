//! What the integrator asks of the rest of the scene, checked once the whole file is read:
//! media that `bdpt` and `lightpath` cannot sample yet, and the films `sppm` cannot write.

use super::Builder;
use crate::error::Location;

impl Builder {
    /// lancer's `bdpt` and `lightpath` do not sample participating media yet: a scene with
    /// media that asks for them is rendered with `volpath` (same depth), with a warning, as
    /// before they existed, rather than as if its media were not there.
    pub(super) fn volumes_need_volpath(&mut self, end: &Location) {
        use lancer::integrator::Integrator;
        if self.desc.media.is_empty() {
            return;
        }
        let (name, max_depth, regularize) = match self.desc.integrator {
            Integrator::Bdpt {
                max_depth,
                regularize,
                ..
            } => ("bdpt", max_depth, regularize),
            Integrator::LightPath { max_depth } => ("lightpath", max_depth, false),
            _ => return,
        };
        self.warn(
            end,
            format!(
                "integrator \"{name}\" through participating media is not supported yet; lancer \
                 uses \"volpath\" with maxdepth {max_depth}"
            ),
        );
        self.desc.integrator = Integrator::VolPath {
            max_depth,
            regularize,
        };
    }

    /// pbrt-v4's `sppm` writes its image itself, as RGB only, whatever the film: a `gbuffer`
    /// or `spectral` film with it is written as an `rgb` film, with a warning (its other
    /// channels would hold nothing).
    pub(super) fn sppm_writes_rgb(&mut self, end: &Location) {
        use lancer::integrator::Integrator;
        if !matches!(self.desc.integrator, Integrator::Sppm { .. }) {
            return;
        }
        let film = &mut self.desc.film;
        let kind = if film.gbuffer.take().is_some() {
            "gbuffer"
        } else if film.spectral.take().is_some() {
            "spectral"
        } else {
            return;
        };
        self.warn(
            end,
            format!(
                "integrator \"sppm\" writes an RGB image, as pbrt-v4's does: the \"{kind}\" \
                 film's other channels are not written (Film \"rgb\")"
            ),
        );
    }
}
