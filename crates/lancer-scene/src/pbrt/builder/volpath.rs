//! The integrator that cannot go through participating media yet (lancer's `vcm`), replaced
//! by `volpath`.

use super::Builder;
use crate::error::Location;

impl Builder {
    /// lancer's `vcm` does not sample participating media yet: a scene with media that asks
    /// for it is rendered with `volpath` (same depth), with a warning, rather than as if its
    /// media were not there.
    pub(super) fn volumes_need_volpath(&mut self, end: &Location) {
        use lancer::integrator::Integrator;
        if self.desc.media.is_empty() {
            return;
        }
        let Integrator::Vcm(o) = self.desc.integrator else {
            return;
        };
        self.warn(
            end,
            format!(
                "integrator \"vcm\" through participating media is not supported yet; lancer \
                 uses \"volpath\" with maxdepth {}",
                o.max_depth
            ),
        );
        self.desc.integrator = Integrator::VolPath {
            max_depth: o.max_depth,
            regularize: false,
        };
    }
}
