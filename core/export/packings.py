"""Every way a resampled image carries the AO: one :class:`Packing` record each, in :data:`PACKINGS`.

The settings' Packing choices (``core/settings.py``), the channels a resample
writes (:func:`pack_channels`), how many the PNG holds and whether glTF can
read the AO (its occlusion is R) are all read off these records: adding a
packing is one record here, and its test.
"""

from dataclasses import dataclass

import numpy as np

#: Channel letters, for sentences.
CHANNELS = "RGBA"


@dataclass(frozen=True)
class Packing:
    """One packing of the AO (and the material's values) into an image's channels (0 R, 1 G, 2 B, 3 A).

    ``roughness``, ``metallic`` and ``smoothness`` (1 - roughness) are -1 when not carried; the channels in
    ``zero`` are 0; every other channel holds the AO where ``grey`` (a grey image), else 1.  The PNG keeps
    the first ``png_channels`` channels.
    """

    id: str
    label: str
    description: str
    occlusion: int
    roughness: int = -1
    metallic: int = -1
    smoothness: int = -1
    zero: tuple = ()
    grey: bool = False
    png_channels: int = 3

    @property
    def carries_material(self):
        """Whether the image also carries the material's roughness, metallic or smoothness."""
        return max(self.roughness, self.metallic, self.smoothness) >= 0

    @property
    def gltf_readable(self):
        """Whether glTF, which reads occlusion from R, finds the AO in it."""
        return self.occlusion == 0

    def not_gltf(self):
        """The sentence for using it as glTF's occlusion."""
        return "{} packing carries the AO in {}, and glTF reads occlusion from R".format(
            self.label, CHANNELS[self.occlusion])


PACKINGS = (
    Packing("GLTF", "glTF Occlusion", "Grey: the AO in R, G and B (glTF reads occlusion from R)", occlusion=0,
            grey=True),
    Packing("GREY", "Greyscale", "One channel: the AO alone, in a greyscale PNG (glTF reads its grey as R)",
            occlusion=0, grey=True, png_channels=1),
    Packing("ORM", "ORM", "R occlusion, G roughness, B metallic (glTF's, Unreal's and Godot's packed texture): the "
            "materials' metallic-roughness texture where one feeds Roughness and Metallic on the same UV map, else "
            "their Roughness and Metallic values", occlusion=0, roughness=1, metallic=2),
    Packing("UNITY_MASK", "Unity Mask Map", "R metallic, G occlusion, B detail mask (0), A smoothness (Unity URP and "
            "HDRP); not for glTF occlusion, which reads R", occlusion=1, metallic=0, smoothness=3, zero=(2,),
            png_channels=4),
)
BY_ID = {packing.id: packing for packing in PACKINGS}


def pack_channels(ao, packing, roughness=None, metallic=None):
    """(h, w, 4) float32 RGBA of the AO ``ao`` (h, w) packed as ``packing`` (an id of :data:`PACKINGS`), with
    the material's ``roughness`` and ``metallic`` (h, w) where the packing carries them (0.5 and 0 when not
    given)."""
    packing = BY_ID[packing]
    ao = np.asarray(ao, dtype=np.float32)
    roughness = np.full_like(ao, 0.5) if roughness is None else np.asarray(roughness, dtype=np.float32)
    metallic = np.zeros_like(ao) if metallic is None else np.asarray(metallic, dtype=np.float32)
    rgba = np.ones(ao.shape + (4,), dtype=np.float32)
    if packing.grey:
        rgba[:, :, :3] = ao[:, :, None]
    for channel in packing.zero:
        rgba[:, :, channel] = 0.0
    rgba[:, :, packing.occlusion] = ao
    for channel, values in ((packing.roughness, roughness), (packing.metallic, metallic),
                            (packing.smoothness, 1.0 - roughness)):
        if channel >= 0:
            rgba[:, :, channel] = values
    return rgba
