"""Values at triangle corners held as a mesh's values at its own corners: what a reader has without gathering
every triangle's rows (:class:`CornerValues`, the corner normals a bake reads for its texels only)."""

from dataclasses import dataclass

import numpy as np


@dataclass
class CornerValues:
    """(t, 3, k) values at triangle corners, held as a mesh's values at its own corners and each triangle
    corner's index into them: what a reader has without gathering every triangle's rows (a million triangles'
    corner normals, 36 MB in float32, of which a bake reads its texels' few).  Indexed like the (t, 3, k) array
    (``values[corner[triangle]]``); numpy makes the whole array of it where one is asked for.

    Parameters
    ----------
    values : (l, k), at the mesh's corners
    corner : (t, 3) int, the corner of each triangle corner, ``0 .. l - 1``
    """

    values: np.ndarray
    corner: np.ndarray

    def __post_init__(self):
        self.values = np.asarray(self.values)
        self.corner = np.asarray(self.corner).reshape(-1, 3)
        if len(self.corner) and (int(self.corner.min()) < 0 or int(self.corner.max()) >= len(self.values)):
            raise ValueError("corner index out of range")

    shape = property(lambda self: (len(self.corner), 3) + self.values.shape[1:])
    dtype = property(lambda self: self.values.dtype)

    def __len__(self):
        return len(self.corner)

    def __getitem__(self, triangle):
        return self.values[self.corner[triangle]]

    def __array__(self, dtype=None, copy=None):
        gathered = self.values[self.corner]
        return gathered if dtype is None else gathered.astype(dtype, copy=False)
