"""The atlas stage: charts projected, packed into one image, and the texels that sample them.

See the map of every module in :mod:`core`.
"""
