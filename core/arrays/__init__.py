"""Helpers over index and geometry arrays that every stage uses.

See the map of every module in :mod:`core`.
"""
