"""Seamless AO core: numpy (+ mathutils for ray casting) only.

No ``bpy``, no operators, no UI.  Every step of the bake is a function over
arrays that can be called and tested on its own, and :mod:`.pipeline` chains
them: meshes and a ray caster in, the AO image, the layout and the report's
numbers out, step by step.

Every module, by stage: one subpackage per stage, in the order a bake runs
them, and the modules that chain or serve them all at the top.

==================================  ===========================================
module                              what it holds
==================================  ===========================================
**the bake** (``core/``)
:mod:`.pipeline`                    the whole bake on arrays, step by step
:mod:`.layout`                      mesh -> charts -> atlas -> texels, chained and timed
:mod:`.settings`                    every bake and export setting, defined once
:mod:`.keys`                        every name the add-on stores Blender data under
:mod:`.errors`                      the two exceptions
:mod:`.budget`                      the memory a bake will need, before it starts
:mod:`.freed_memory`                memory a big bake freed: held for its next stage, handed back before Cycles
**mesh** (``core/mesh/``)
:mod:`.mesh.triangle_mesh`          triangle meshes, normals, the mesh report
:mod:`.mesh.corner_values`          values at triangle corners, held at the mesh's own corners
:mod:`.mesh.weld`                   vertices at one position, or within a tolerance, made one
:mod:`.mesh.adjacency`              faces that share an edge (sorted edge keys)
:mod:`.mesh.extent`                 a mesh's size, a stray spike left out
:mod:`.mesh.sealed`                 triangles of closed pieces (what "inside" means)
:mod:`.mesh.proxy`                  vertices clustered in texel-wide cubes, and their triangles
**charts** (``core/charts/``)
:mod:`.charts.clustering`           overlapping signed-axis charts, made injective
:mod:`.charts.coarse`               the charts of a mesh far finer than its image, made on a texel-scale proxy
:mod:`.charts.overlap`              fold conflicts of a chart, found from its boundary
:mod:`.charts.candidates`           which shapes of a chart to compare (a uniform grid)
:mod:`.charts.sides`                a chart's sides grouped by edge (one sort per mesh)
:mod:`.charts.steep`                which boundary sides to compare where a boundary runs steep (cells with bounds)
:mod:`.charts.splitting`            how a folding chart is cut
**atlas** (``core/atlas/``)
:mod:`.atlas.chart_atlas`           chart projection, density, the packed atlas and its UVs
:mod:`.atlas.long_charts`           charts too long for the image, packed at a density of their own
:mod:`.atlas.packing`               where each chart goes at one density (xatlas)
:mod:`.atlas.cover`                 coarse covers of charts, for the packer
:mod:`.atlas.settled_atlas`         an xatlas atlas let go of once its threads sleep (its destructor can hang)
:mod:`.atlas.shelf`                 shelf packing of the small charts
:mod:`.atlas.raster`                texels and the surface point each samples
:mod:`.atlas.rim`                   which triangles have a side on their chart's border
:mod:`.atlas.viewport_uv`           AO UVs for a surface other than the one baked
**rays** (``core/rays/``)
:mod:`.rays.ray_setup`              a mesh's rays: parameters, ray space, the casters
:mod:`.rays.sampling`               ray directions in a cone
:mod:`.rays.ao`                     the occlusion of rays, buried points, the adaptive stop
:mod:`.rays.targets`                what rays are cast for: texels or points
:mod:`.rays.job`                    the rays of every target, in batches
:mod:`.rays.cycles_rules`           what the Cycles caster can follow: every Cycles fact
**image** (``core/image/``)
:mod:`.image.denoise`               the edge-aware texel filter
:mod:`.image.fill`                  the finished image (pull-push)
:mod:`.image.shown`                 what a material shows: the node group's blend in numpy
**export** (``core/export/``)
:mod:`.export.export_pipeline`      the whole export on arrays: a bake as it renders in, PNG or colours out
:mod:`.export.transfer`             the AO onto another UV map and into PNG bytes; corners
:mod:`.export.packings`             every packing of a resampled image, one record each
:mod:`.export.png`                  PNG bytes of float images
:mod:`.export.uv_fitness`           whether a UV map can hold the AO
**other processes** (``core/other_processes/``)
:mod:`.other_processes.batch_plan`  a batch without Blender data: assets, outputs, stamps
:mod:`.other_processes.handoff`     a bake handed to another process, as files
**shared helpers** (``core/arrays/``)
:mod:`.arrays.graph`                components, runs, pairs, sorts and scatters over index arrays
:mod:`.arrays.geometry2d`           2D geometry on arrays of triangles and segments
:mod:`.arrays.grid`                 passes over a texel's 8 neighbours
:mod:`.arrays.reduce`               least, greatest and row lengths of narrow arrays, a column at a time
:mod:`.arrays.blocks`               long arrays a block of rows at a time (small temporaries)
==================================  ===========================================
"""
