"""Helpers over index and geometry arrays that every stage uses.  See the map in :mod:`core`."""
