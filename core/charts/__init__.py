"""The charts stage: overlapping signed-axis charts, made free of folds.  See the map in :mod:`core`."""
