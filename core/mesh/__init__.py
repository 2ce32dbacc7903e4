"""The mesh stage: the triangle mesh the core bakes, its edges, its size and its closed pieces.

See the map of every module in :mod:`core`.
"""
