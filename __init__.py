"""Seamless AO: bake ambient occlusion for any mesh in one click.

No UV unwrap by the user and no visible seams: triangles are clustered into
overlapping charts along the six signed axes, AO is ray-cast for every texel
at its exact surface point, and a node group blends three lookups with the
squared object-space normal.  See README.md.

The package must be imported with relative imports only: Blender loads it as
``bl_ext.<repository>.seamless_ao``, the tests under another name.
"""

from . import operators, panels


def register():
    operators.register()
    panels.register()


def unregister():
    panels.unregister()
    operators.unregister()
