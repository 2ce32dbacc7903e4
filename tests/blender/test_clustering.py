"""Charts of a mesh read from Blender (Suzanne subdivided)."""

from blender_scenes import suzanne
from layout_checks import check_charts


def test_subdivided_suzanne(fresh_scene):
    from seamless_ao.operators.adapters.mesh_data import read_triangles
    mesh, _ = read_triangles(suzanne(2).data)
    topology, charts = check_charts(mesh)
    assert topology.report.non_manifold_edges == 0
    assert charts.count > 6
