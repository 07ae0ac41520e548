//! Scene formats read into lancer's plain-data [`SceneDesc`]: pbrt-v4 files, with the PLY and
//! OBJ meshes their `plymesh` and `objmesh` shapes name, and bare `.obj`/`.ply` meshes made
//! into a scene around them ([`mesh_scene`]); glTF models ([`gltf`]).
//!
//! Every error names its place (`file:line:column`) and comes with the offending line; what
//! lancer reads but does not do yet is a [`Warning`] saying what it does instead.

pub mod error;
pub mod files_read;
pub mod gltf;
pub mod image_read;
pub mod mesh_scene;
pub mod nanovdb;
pub mod obj;
pub mod pbrt;
pub mod ply;
pub mod vox;

pub use error::{Location, SceneError, Warning};

use lancer::SceneDesc;
use pbrt::parser::Parser;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A scene read from a file, and what the reader had to warn about.
#[derive(Debug)]
pub struct LoadedScene {
    /// The scene.
    pub desc: SceneDesc,
    /// Warnings, in file order; repeats of the same message are folded into the first.
    pub warnings: Vec<Warning>,
    /// Every file read (scene, includes, meshes, textures, spectra), absolute, in first-read
    /// order; filled by [`load`] and [`load_pbrt_str`] (see [`files_read`]).
    pub files: Vec<PathBuf>,
}

/// Reads a scene file, its format chosen by the extension: `.pbrt`, `.pbrt.gz` (or none) a
/// pbrt-v4 scene; `.gltf` or `.glb` a glTF 2.0 model ([`gltf`]); `.obj`, `.ply` or `.ply.gz` a bare mesh, with the camera, lights and film of
/// [`mesh_scene::defaults`] around it.
pub fn load(path: &Path) -> Result<LoadedScene, SceneError> {
    let (result, files) = files_read::recording(|| load_unrecorded(path));
    result.map(|loaded| LoadedScene { files, ..loaded })
}

fn load_unrecorded(path: &Path) -> Result<LoadedScene, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    // The format of a `.gz` file: the extension before it.
    let gzipped = |format: &str| {
        path.file_stem()
            .and_then(|s| Path::new(s).extension())
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case(format))
    };
    match ext.as_deref() {
        Some("gz") if gzipped("pbrt") => {
            let mut parser = Parser::from_file(path)?;
            finish(pbrt::builder::build(&mut parser), &parser)
        }
        Some("pbrt") | None => {
            let mut parser = Parser::from_file(path)?;
            finish(pbrt::builder::build(&mut parser), &parser)
        }
        Some("obj") => mesh_scene::load_obj_scene(path).map(fold),
        Some("ply") => mesh_scene::load_ply_scene(path).map(fold),
        Some("gz") if gzipped("ply") => mesh_scene::load_ply_scene(path).map(fold),
        Some("gltf") | Some("glb") => gltf::load_gltf_scene(path).map(fold),
        Some(other) => Err(SceneError::general(format!(
            "{}: unknown scene format '.{other}' (lancer reads .pbrt scenes, .gltf/.glb models and .obj/.ply meshes)",
            path.display()
        ))),
    }
}

fn fold(loaded: LoadedScene) -> LoadedScene {
    LoadedScene {
        warnings: fold_repeats(loaded.warnings),
        ..loaded
    }
}

/// Reads pbrt-v4 scene text held in memory; `name` names it in messages and `dir` is where its
/// relative file names point.
pub fn load_pbrt_str(text: &str, name: &str, dir: &Path) -> Result<LoadedScene, SceneError> {
    let (result, files) = files_read::recording(|| {
        let mut parser = Parser::from_str(text, name, dir);
        finish(pbrt::builder::build(&mut parser), &parser)
    });
    result.map(|loaded| LoadedScene { files, ..loaded })
}

fn finish(
    result: Result<(SceneDesc, Vec<Warning>), SceneError>,
    parser: &Parser,
) -> Result<LoadedScene, SceneError> {
    match result {
        Ok((desc, warnings)) => Ok(LoadedScene {
            desc,
            warnings: fold_repeats(warnings),
            files: Vec::new(),
        }),
        Err(mut e) => {
            if e.source_line.is_none()
                && let Some(loc) = &e.location
                && let Some(src) = parser.source(&loc.file)
            {
                e.source_line = pbrt::lexer::source_line(src, loc.line);
            }
            Err(e)
        }
    }
}

/// Keeps the first of warnings that say the same thing, noting how many more there were (a
/// mesh-heavy scene would otherwise repeat one line thousands of times).
fn fold_repeats(warnings: Vec<Warning>) -> Vec<Warning> {
    let mut first: HashMap<String, usize> = HashMap::new();
    let mut out: Vec<(Warning, usize)> = Vec::new();
    for w in warnings {
        match first.get(&w.message) {
            Some(&i) => out[i].1 += 1,
            None => {
                first.insert(w.message.clone(), out.len());
                out.push((w, 0));
            }
        }
    }
    out.into_iter()
        .map(|(mut w, more)| {
            if more > 0 {
                w.message.push_str(&format!(" ({more} more like it)"));
            }
            w
        })
        .collect()
}
