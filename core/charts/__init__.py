"""The charts stage: overlapping signed-axis charts, made free of folds.

See the map of every module in :mod:`core`.
"""
