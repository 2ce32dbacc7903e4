"""Seamless AO core: numpy (+ mathutils for ray casting) only.

No ``bpy.context``, no operators, no UI.  Every step of the pipeline is a
function over arrays that can be called and tested on its own:

========================  ==============================================
module                    pipeline step
========================  ==============================================
:mod:`.mesh`              welding, triangle normals/areas, mesh report
:mod:`.adjacency`         face adjacency by shared edges (sorted keys)
:mod:`.clustering`        overlapping signed-axis clusters, injective charts
:mod:`.overlap`           2D triangle overlap candidates and tests
:mod:`.atlas`             chart projection, density, xatlas packing, UVs
:mod:`.raster`            texel points and normals (covered + padding)
:mod:`.sampling`          low-discrepancy ray directions
:mod:`.ao`                ambient occlusion per texel with a ray caster
:mod:`.blend`             the node group's normal-squared blend in numpy
:mod:`.pipeline`          the steps chained, with progress and cancel
========================  ==============================================
"""
