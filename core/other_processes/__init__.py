"""A bake or a batch handed to other processes, as files: nothing here touches Blender data.

See the map of every module in :mod:`core`.
"""
