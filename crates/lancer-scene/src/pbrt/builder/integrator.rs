//! What the integrator asks of the rest of the scene, checked once the whole file is read:
//! the films `sppm` cannot write (the media `vcm` cannot sample: `volpath.rs`).

use super::Builder;
use crate::error::Location;

impl Builder {
    /// pbrt-v4's `sppm` writes its image itself, as RGB only, whatever the film: a `gbuffer`
    /// or `spectral` film with it is written as an `rgb` film, with a warning (its other
    /// channels would hold nothing).
    pub(super) fn sppm_writes_rgb(&mut self, end: &Location) {
        use lancer::integrator::Integrator;
        if !matches!(self.desc.integrator, Integrator::Sppm(_)) {
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
