"""Seamless AO core: numpy (+ mathutils for ray casting) only.

No ``bpy``, no operators, no UI.  Every step of the bake is a function over
arrays that can be called and tested on its own, and :mod:`.pipeline` chains
them: meshes and a ray caster in, the AO image, the layout and the report's
numbers out, step by step.

Every module, by stage:

=======================  ======================================================
module                   what it holds
=======================  ======================================================
**the bake**
:mod:`.pipeline`         the whole bake on arrays, step by step
:mod:`.settings`         every bake and export setting, defined once
:mod:`.keys`             every name the add-on stores Blender data under
:mod:`.errors`           the two exceptions
:mod:`.budget`           the memory a bake will need, before it starts
**mesh**
:mod:`.mesh`             triangle meshes, welding, normals, the mesh report
:mod:`.adjacency`        faces that share an edge (sorted edge keys)
:mod:`.extent`           a mesh's size, a stray spike left out
:mod:`.sealed`           triangles of closed pieces (what "inside" means)
**charts**
:mod:`.clustering`       overlapping signed-axis charts, made injective
:mod:`.overlap`          fold conflicts of a chart, found from its boundary
:mod:`.candidates`       which shapes of a chart to compare (a uniform grid)
:mod:`.splitting`        how a folding chart is cut
**atlas**
:mod:`.atlas`            chart projection, density, the packed atlas and its UVs
:mod:`.packing`          where each chart goes at one density (xatlas)
:mod:`.cover`            coarse covers of charts, for the packer
:mod:`.shelf`            shelf packing of the small charts
:mod:`.raster`           texels and the surface point each samples
:mod:`.layout`           mesh -> charts -> atlas -> texels, chained and timed
:mod:`.viewport_uv`      AO UVs for a surface other than the one baked
**rays**
:mod:`.rays`             a mesh's rays: parameters, ray space, the casters
:mod:`.sampling`         ray directions in a cone
:mod:`.ao`               the occlusion of rays, buried points, the adaptive stop
:mod:`.targets`          what rays are cast for: texels or points
:mod:`.job`              the rays of every target, in batches
**image**
:mod:`.denoise`          the edge-aware texel filter
:mod:`.fill`             the finished image (pull-push)
:mod:`.shown`            what a material shows: the node group's blend in numpy
**export**
:mod:`.transfer`         the AO onto another UV map and into PNG bytes; corners
:mod:`.packings`         every packing of a resampled image, one record each
:mod:`.png`              PNG bytes of float images
:mod:`.uv_fitness`       whether a UV map can hold the AO
**other processes**
:mod:`.batch_plan`       a batch without Blender data: assets, outputs, stamps
:mod:`.handoff`          a bake handed to another process, as files
**shared helpers**
:mod:`.graph`            components, runs, pairs and sorts over index arrays
:mod:`.geometry2d`       2D geometry on arrays of triangles and segments
:mod:`.grid`             passes over a texel's 8 neighbours
=======================  ======================================================
"""
