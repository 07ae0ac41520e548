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
    /// What the reader made that is worth printing (each displaced mesh's triangle count and
    /// memory), in file order.
    pub notes: Vec<Warning>,
}

/// The most triangles a scene's displaced meshes may have in all, unless
/// [`LoadOptions::max_displaced_triangles`] says otherwise (about 3 GiB of meshes).
pub const DEFAULT_MAX_DISPLACED_TRIANGLES: u64 = 100_000_000;

/// The command line's say in what the reader makes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Multiplies every displaced `plymesh`'s `edgelength` (pbrt-v4's
    /// `--displacementedgescale`; 1 by default).
    pub displacement_edge_scale: f32,
    /// The most triangles the scene's displaced meshes may have in all (an error names the
    /// mesh that would pass it); at most [`lancer::shape::MAX_DISPLACED_TRIANGLES`].
    pub max_displaced_triangles: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            displacement_edge_scale: 1.0,
            max_displaced_triangles: DEFAULT_MAX_DISPLACED_TRIANGLES,
        }
    }
}

/// Reads a scene file, its format chosen by the extension: `.pbrt`, `.pbrt.gz` (or none) a
/// pbrt-v4 scene; `.gltf` or `.glb` a glTF 2.0 model ([`gltf`]); `.obj`, `.ply` or `.ply.gz` a bare mesh, with the camera, lights and film of
/// [`mesh_scene::defaults`] around it.
pub fn load(path: &Path) -> Result<LoadedScene, SceneError> {
    load_with(path, &LoadOptions::default())
}

/// [`load`] with `options`.
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    let (result, files) = files_read::recording(|| load_unrecorded(path, options));
    result.map(|loaded| LoadedScene { files, ..loaded })
}

fn load_unrecorded(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
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
            finish(pbrt::builder::entry::build(&mut parser, options), &parser)
        }
        Some("pbrt") | None => {
            let mut parser = Parser::from_file(path)?;
            finish(pbrt::builder::entry::build(&mut parser, options), &parser)
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
    load_pbrt_str_with(text, name, dir, &LoadOptions::default())
}

/// [`load_pbrt_str`] with `options`.
pub fn load_pbrt_str_with(
    text: &str,
    name: &str,
    dir: &Path,
    options: &LoadOptions,
) -> Result<LoadedScene, SceneError> {
    let (result, files) = files_read::recording(|| {
        let mut parser = Parser::from_str(text, name, dir);
        finish(pbrt::builder::entry::build(&mut parser, options), &parser)
    });
    result.map(|loaded| LoadedScene { files, ..loaded })
}

fn finish(
    result: Result<pbrt::builder::Built, SceneError>,
    parser: &Parser,
) -> Result<LoadedScene, SceneError> {
    match result {
        Ok(built) => Ok(LoadedScene {
            desc: built.desc,
            warnings: fold_repeats(built.warnings),
            files: Vec::new(),
            notes: built.notes,
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
