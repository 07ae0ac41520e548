//! Where the relative file names of a directive point: [`SearchPath`], shared by the parser
//! (for `Include`) and the parameter readers (for meshes, images and spectra).

use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where a directive's relative file names are looked for.
///
/// pbrt-v4 resolves every relative name (in `Include` and in parameters alike) against the
/// folder of the main scene file, so an included `geometry/a.pbrt` names its meshes
/// `geometry/mesh.ply`. Scenes written by hand often expect the including file's folder
/// instead; lancer tries pbrt's folder first and the directive's own folder second.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SearchPath {
    /// The folder of the main scene file.
    pub scene: Arc<Path>,
    /// The folder of the file holding the directive.
    pub file: Arc<Path>,
}

impl SearchPath {
    /// The same folder for both rules (a scene without includes).
    pub fn new(dir: &Path) -> SearchPath {
        let dir: Arc<Path> = Arc::from(dir);
        SearchPath {
            scene: dir.clone(),
            file: dir,
        }
    }

    /// The file a relative `name` means: in the scene's folder if it exists there, else in
    /// the directive's folder if it exists there, else (for the error message) the scene's.
    pub fn resolve(&self, name: &str) -> PathBuf {
        let in_scene = self.scene.join(name);
        if in_scene.exists() || self.file == self.scene {
            return in_scene;
        }
        let in_file = self.file.join(name);
        if in_file.exists() { in_file } else { in_scene }
    }
}
