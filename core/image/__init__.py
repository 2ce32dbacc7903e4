"""The image stage: the baked texels denoised and filled into the finished image.

See the map of every module in :mod:`core`.
"""
