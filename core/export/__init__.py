"""The export stage: the AO resampled onto other UV maps, packed into channels and written as PNG.

See the map of every module in :mod:`core`.
"""
