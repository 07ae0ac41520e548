//! `lancer.Scene`: a scene description read by lancer-scene, and the scene built from it for
//! rendering (kept while the film size stays the same).

use crate::{SceneError, SceneWarning};
use lancer::scene::desc::Projection;
use lancer::{Scene, SceneDesc};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Name under which the scene text given to `load_string` appears in messages.
const STRING_NAME: &str = "<string>";

/// A scene built for rendering, with the film size (width, height) it was built for.
type Built = ((u32, u32), Arc<Scene>);

/// A loaded scene: `lancer.load_file(path)` or `lancer.load_string(text)`; render it with
/// `lancer.render(scene)`, describe it with `scene.info()`.
#[pyclass(frozen, name = "Scene", module = "lancer")]
pub struct PyScene {
    /// The description as read (the render's overrides are applied to a copy).
    pub desc: SceneDesc,
    /// Where it came from: the path, or `<string>`.
    name: String,
    /// The reader's warnings, `file:line:column: message`.
    warnings: Vec<String>,
    /// Every file read, absolute.
    files: Vec<String>,
    /// The last scene built, with the film size it was built for (the camera is the only part
    /// of a built scene that depends on the film).
    built: Mutex<Option<Built>>,
}

impl PyScene {
    /// The scene built from `desc` (this scene's description with a render's overrides), from
    /// the cache when the film size is the one of the last build. Runs without the GIL.
    pub fn built(&self, desc: &SceneDesc) -> Result<Arc<Scene>, String> {
        let key = (desc.film.xresolution, desc.film.yresolution);
        let mut built = self.built.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((k, scene)) = built.as_ref()
            && *k == key
        {
            return Ok(scene.clone());
        }
        let scene = Arc::new(Scene::build(desc).map_err(|e| format!("scene: {e}"))?);
        *built = Some((key, scene.clone()));
        Ok(scene)
    }

    /// A `Scene` from what a reader returned; its warnings are issued as `lancer.SceneWarning`.
    fn from_loaded(
        py: Python<'_>,
        name: String,
        result: Result<lancer_scene::LoadedScene, lancer_scene::SceneError>,
    ) -> PyResult<PyScene> {
        let loaded = result.map_err(|e| scene_error(py, &e))?;
        let warnings: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
        let category = py.get_type::<SceneWarning>();
        for w in &warnings {
            let message = CString::new(w.replace('\0', " ")).unwrap_or_default();
            PyErr::warn(py, category.as_any(), &message, 2)?;
        }
        Ok(PyScene {
            desc: loaded.desc,
            name,
            warnings,
            files: loaded
                .files
                .iter()
                .map(|f| f.display().to_string())
                .collect(),
            built: Mutex::new(None),
        })
    }
}

/// A `lancer.SceneError` from a reader's error: the message as `lancer render` prints it
/// (`file:line:column: message`, then the line and a caret), and the place as attributes.
pub fn scene_error(py: Python<'_>, e: &lancer_scene::SceneError) -> PyErr {
    let mut message = e.to_string();
    for line in e.excerpt_lines() {
        message.push('\n');
        message.push_str(&line);
    }
    let err = SceneError::new_err(message);
    let value = err.value(py);
    let loc = e.location.as_ref();
    // Setting attributes on a fresh exception instance cannot fail.
    let _ = value.setattr("file", loc.map(|l| l.file.to_string()));
    let _ = value.setattr("line", loc.map(|l| l.line));
    let _ = value.setattr("column", loc.map(|l| l.col));
    err
}

/// Reads a scene file: pbrt-v4 (`.pbrt`), glTF (`.gltf`, `.glb`) or a bare mesh (`.obj`,
/// `.ply`, framed and lit as `lancer render` does). Raises `lancer.SceneError` on a malformed
/// scene (the message locates it) or an unreadable file; issues `lancer.SceneWarning`s for
/// what lancer does differently.
#[pyfunction]
pub fn load_file(py: Python<'_>, path: PathBuf) -> PyResult<PyScene> {
    let result = py.detach(|| lancer_scene::load(&path));
    PyScene::from_loaded(py, path.display().to_string(), result)
}

/// Reads pbrt-v4 scene text. Messages name it `<string>`; relative file names in it (meshes,
/// textures, includes) are found in `base_dir`, the current folder by default.
#[pyfunction]
#[pyo3(signature = (text, base_dir = None))]
pub fn load_string(py: Python<'_>, text: &str, base_dir: Option<PathBuf>) -> PyResult<PyScene> {
    let dir = base_dir.unwrap_or_else(|| PathBuf::from("."));
    let text = text.to_owned();
    let result = py.detach(|| lancer_scene::load_pbrt_str(&text, STRING_NAME, Path::new(&dir)));
    PyScene::from_loaded(py, STRING_NAME.to_string(), result)
}

#[pymethods]
impl PyScene {
    /// What the scene holds, as a dict: `camera` (projection, fov in degrees for a perspective
    /// camera, eye position and viewing direction in world space), `resolution` (width,
    /// height), `spp`, `seed`, `shapes` (world shapes by kind), `shape_count`, `lights` (by
    /// kind, area lights as `area`), `light_count`, `material_count`, `triangles` (of world
    /// shapes and of every object instance), `instances`, `warnings` (`file:line:column:
    /// message`) and `files` (every file read).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = &self.desc;
        let camera = PyDict::new(py);
        match &d.camera.projection {
            Projection::Perspective { fov } => {
                camera.set_item("projection", "perspective")?;
                camera.set_item("fov", fov)?;
            }
            Projection::Orthographic => camera.set_item("projection", "orthographic")?,
            Projection::Spherical { .. } => camera.set_item("projection", "spherical")?,
            Projection::Realistic(_) => camera.set_item("projection", "realistic")?,
        }
        let world_from_camera = d.camera.camera_from_world.inverse();
        let eye = world_from_camera.point(lancer::math::Vec3::ZERO);
        let forward = world_from_camera.vector(lancer::math::Vec3::new(0.0, 0.0, 1.0));
        camera.set_item("eye", (eye.x, eye.y, eye.z))?;
        camera.set_item("forward", (forward.x, forward.y, forward.z))?;
        camera.set_item("lens_radius", d.camera.lens_radius)?;

        let c = d.counts();
        let shapes = &c.shapes;
        let shape_count = d.shapes.len();
        let triangles = c.triangles + c.instanced_triangles;
        // As pbrt names them, an infinite light with an image counted as `infinite`.
        let mut lights: BTreeMap<&str, u64> = BTreeMap::new();
        for l in &d.lights {
            *lights.entry(l.pbrt_name()).or_default() += 1;
        }
        if c.area_lights > 0 {
            lights.insert("area", c.area_lights);
        }
        let light_count: u64 = lights.values().sum();

        let info = PyDict::new(py);
        info.set_item("name", &self.name)?;
        info.set_item("camera", camera)?;
        info.set_item("resolution", (d.film.xresolution, d.film.yresolution))?;
        info.set_item("spp", d.sampler.spp)?;
        info.set_item("seed", d.sampler.seed)?;
        info.set_item("shapes", shapes)?;
        info.set_item("shape_count", shape_count)?;
        info.set_item("lights", lights)?;
        info.set_item("light_count", light_count)?;
        info.set_item("material_count", d.materials.len())?;
        info.set_item("triangles", triangles)?;
        info.set_item("instances", d.instances.len())?;
        info.set_item("warnings", self.warnings.clone())?;
        info.set_item("files", self.files.clone())?;
        Ok(info)
    }

    fn __repr__(&self) -> String {
        let d = &self.desc;
        format!(
            "<lancer.Scene {:?}: {}x{}, {} spp, {} shapes, {} lights>",
            self.name,
            d.film.xresolution,
            d.film.yresolution,
            d.sampler.spp,
            d.shapes.len(),
            d.lights.len()
        )
    }
}
