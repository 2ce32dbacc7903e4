"""Seamless AO core: numpy (+ mathutils for ray casting) only.

No ``bpy``, no operators, no UI.  Every step of the bake is a function over
arrays that can be called and tested on its own, and :mod:`.pipeline` chains
them: meshes and a ray caster in, the AO image, the layout and the report's
numbers out, step by step.

========================  ==============================================
module                    step
========================  ==============================================
:mod:`.mesh`              triangle meshes, welding, normals, the mesh report
:mod:`.adjacency`         face adjacency by shared edges (sorted keys)
:mod:`.clustering`        overlapping signed-axis clusters, injective charts
:mod:`.overlap`           2D overlap candidates and fold conflicts
:mod:`.atlas`             chart projection, density, xatlas packing, UVs
:mod:`.raster`            texel points and normals (covered + padding)
:mod:`.layout`            the steps above chained: where the AO is stored
:mod:`.rays`              a mesh's rays: parameters, ray space, casters
:mod:`.sampling`          low-discrepancy ray directions
:mod:`.ao`                the occlusion of rays, buried points, the adaptive stop
:mod:`.targets`           what rays are cast for: texels or points
:mod:`.job`               the rays of every target, in batches
:mod:`.denoise`           the edge-aware texel filter
:mod:`.fill`              the finished image
:mod:`.pipeline`          the whole bake, step by step
:mod:`.shown`             the node group's normal-squared blend in numpy
:mod:`.transfer`          the AO onto another UV map, corners, vertices
========================  ==============================================
"""
