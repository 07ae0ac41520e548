"""lancer for Blender: a render engine "lancer" that renders Blender's scene with lancer.

Install: Edit > Preferences > Add-ons > Install from Disk, pick lancer_blender.zip (made by
tools/blender_addon_zip.sh), and install the `lancer-render` wheel into Blender's Python
(`<blender's python> -m pip install lancer_render-*.whl`). Then choose "lancer" as the render
engine in the Render properties.

The scene is written as a pbrt-v4 scene (export.py) that lancer reads, then rendered in bands
of rows whose pixels appear in the render window as they finish (engine.py).
"""

bl_info = {
    "name": "lancer",
    "author": "the lancer authors",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Render Properties > Render Engine > lancer",
    "description": "Render with lancer, a physically based ray tracer (pbrt-v4 compatible)",
    "category": "Render",
}

from . import engine  # noqa: E402


def register():
    """Registers the render engine, its settings and its panels."""
    engine.register()


def unregister():
    """Removes what register() added."""
    engine.unregister()
