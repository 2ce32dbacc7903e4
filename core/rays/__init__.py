"""The rays stage: the rays each texel casts, the casters that cast them, and the occlusion they find.  See the map in :mod:`core`."""
