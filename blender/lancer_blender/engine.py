"""The render engine "lancer": exports the scene (export.py), renders it with the lancer Python
module in bands of rows, each shown in Blender's render window as it finishes, with progress,
and stops between bands when the user cancels.

A band is the crop window of rows r0..r1 of the whole render: lancer's pixels do not depend on
the crop (the film sums are exact), so the bands make up the very image of one render."""

import shutil
import tempfile
import warnings

import numpy as np

import bpy

from . import export

#: Rows of one band: one row of lancer's 16-pixel tiles.
BAND_ROWS = 16


class LancerSettings(bpy.types.PropertyGroup):
    """lancer's settings of a scene (Render properties > lancer)."""

    samples: bpy.props.IntProperty(
        name="Samples", description="Samples per pixel", default=64, min=1, max=1 << 20
    )
    max_depth: bpy.props.IntProperty(
        name="Max Bounces",
        description="Longest path, in bounces (Cycles' total of 12 by default)",
        default=12,
        min=1,
        max=1024,
    )
    spectral: bpy.props.BoolProperty(
        name="Spectral",
        description="Render with sampled wavelengths, as pbrt-v4 does; off: in RGB, as Cycles",
        default=False,
    )


def band_crop(r0, r1, height):
    """The crop window (x0, x1, y0, y1) selecting rows r0..r1 of `height`: lancer takes rows
    ⌈h·y0⌉..⌈h·y1⌉, so y = (r − ½)/h lands half a row away from any rounding."""
    y0 = 0.0 if r0 == 0 else (r0 - 0.5) / height
    y1 = 1.0 if r1 >= height else (r1 - 0.5) / height
    return (0.0, 1.0, y0, y1)


class LancerRenderEngine(bpy.types.RenderEngine):
    """Renders the scene with lancer."""

    bl_idname = "LANCER"
    bl_label = "lancer"
    bl_use_preview = False
    bl_use_eevee_viewport = True

    def fail(self, message):
        """Refuses the render: the message goes to Blender's report and render window."""
        self.report({"ERROR"}, f"lancer: {message}")
        if hasattr(self, "error_set"):
            self.error_set(f"lancer: {message}")

    def render(self, depsgraph):
        """Blender's final render (F12, or bpy.ops.render.render)."""
        scene = depsgraph.scene
        settings = scene.lancer
        try:
            import lancer
        except ImportError as e:
            self.fail(f"the lancer Python module cannot be imported ({e}); install the "
                      "lancer-render wheel into Blender's Python")
            return
        if scene.render.use_border:
            self.report({"WARNING"}, "lancer: the render region is ignored: the whole image is rendered")
        width, height = export.render_size(scene)
        tmp = tempfile.mkdtemp(prefix="lancer-blender-")
        try:
            self.update_stats("", "lancer: exporting the scene")
            try:
                path, notes = export.export(depsgraph, tmp, settings.samples, settings.max_depth)
            except export.ExportError as e:
                self.fail(str(e))
                return
            for note in notes:
                self.report({"WARNING"}, f"lancer: {note}")
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    loaded = lancer.load_file(path)
                except lancer.SceneError as e:
                    self.fail(f"the exported scene was refused: {e}")
                    return
            for w in caught:
                self.report({"WARNING"}, f"lancer: {w.message}")
            threads = scene.render.threads if scene.render.threads_mode == "FIXED" else None
            self.render_bands(lancer, loaded, width, height, settings, threads)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)

    def render_bands(self, lancer, loaded, width, height, settings, threads):
        """Renders the bands top to bottom, each into Blender's result as it finishes."""
        bands = [(r, min(r + BAND_ROWS, height)) for r in range(0, height, BAND_ROWS)]
        for k, (r0, r1) in enumerate(bands):
            if self.test_break():
                return
            self.update_stats("", f"lancer: rows {r0}–{r1} of {height}, {settings.samples} spp")
            try:
                img = lancer.render(loaded, spp=settings.samples, resolution=(width, height),
                                    crop=band_crop(r0, r1, height), threads=threads,
                                    spectral=settings.spectral)
            except KeyboardInterrupt:
                return
            except (ValueError, RuntimeError) as e:
                self.fail(str(e))
                return
            if img.shape[:2] != (r1 - r0, width):
                self.fail(f"band of rows {r0}–{r1} came back {img.shape[1]}x{img.shape[0]}")
                return
            # Blender's rows go bottom to top; lancer's top to bottom.
            rgba = np.ones((r1 - r0, width, 4), dtype=np.float32)
            rgba[..., :3] = img[::-1]
            result = self.begin_result(0, height - r1, width, r1 - r0)
            result.layers[0].passes["Combined"].rect = rgba.reshape(-1, 4)
            self.end_result(result)
            self.update_progress((k + 1) / len(bands))


class LANCER_PT_sampling(bpy.types.Panel):
    """Render properties > lancer: samples, bounces, spectral."""

    bl_label = "lancer"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"LANCER"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        settings = context.scene.lancer
        layout = self.layout
        layout.use_property_split = True
        layout.prop(settings, "samples")
        layout.prop(settings, "max_depth")
        layout.prop(settings, "spectral")


#: Blender's own panels that show for EEVEE and make sense for lancer (format, camera, lights,
#: materials, world), found by their COMPAT_ENGINES.
_EEVEE = {"BLENDER_EEVEE", "BLENDER_EEVEE_NEXT"}


def _shared_panels():
    """Blender's panels that EEVEE uses (lancer shares them)."""
    for name in dir(bpy.types):
        panel = getattr(bpy.types, name, None)
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if isinstance(engines, set) and engines & _EEVEE:
            yield panel


def register():
    """Registers the settings, the engine and its panel; joins Blender's shared panels."""
    bpy.utils.register_class(LancerSettings)
    bpy.types.Scene.lancer = bpy.props.PointerProperty(type=LancerSettings)
    bpy.utils.register_class(LancerRenderEngine)
    bpy.utils.register_class(LANCER_PT_sampling)
    for panel in _shared_panels():
        panel.COMPAT_ENGINES.add("LANCER")


def unregister():
    """Undoes register()."""
    for panel in _shared_panels():
        panel.COMPAT_ENGINES.discard("LANCER")
    bpy.utils.unregister_class(LANCER_PT_sampling)
    bpy.utils.unregister_class(LancerRenderEngine)
    del bpy.types.Scene.lancer
    bpy.utils.unregister_class(LancerSettings)

