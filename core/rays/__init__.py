"""The rays stage: the rays each texel casts, the casters that cast them, and the occlusion they find.

See the map of every module in :mod:`core`.
"""
