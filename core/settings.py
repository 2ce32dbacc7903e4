"""Every bake and export setting, defined once.

:class:`BakeSettings` (and :class:`ExportSettings`) is the single source of truth: the scene's
``PropertyGroup``, the operator's properties, the command line options and the
Python API's keyword arguments are all generated from its fields, so names,
defaults, limits and descriptions cannot drift apart.

Each field's ``metadata`` holds what a UI needs:

``label``        short name shown in the panel
``description``  one sentence, used as tooltip and ``--help`` text
``min``/``max``  hard limits (validated here, enforced by Blender's UI)
``items``        for enums: ``(identifier, label, description)`` triples
``unit``         human unit for docs ("°", "texels", "scene units", ...)
"""

import dataclasses
from dataclasses import dataclass, field

from .errors import SeamlessAOError
from .export.packings import BY_ID as PACKINGS_BY_ID, PACKINGS
from .rays.cycles_rules import BULK_PILOT_RAYS, CLASSIC_AO, first_unfollowed


def _setting(default, label, description, **extra):
    return field(default=default, metadata=dict(label=label, description=description, **extra))


FALLOFF_ITEMS = (
    ("NONE", "None (binary)", "Classic AO: a hit within the max distance occludes fully (what Cycles computes)"),
    ("LINEAR", "Linear", "A hit occludes less the farther away it is: 1 - distance / max distance (the thesis' falloff)"),
    ("OBSCURANCE", "Obscurance", "Zhukov-style obscurance: a hit at distance d leaves sqrt(d / max distance) open"),
)

DISTRIBUTION_ITEMS = (
    ("COSINE", "Cosine", "Rays cosine-distributed around the normal (Lambertian AO, as Cycles)"),
    ("UNIFORM", "Uniform", "Rays spread evenly over the cone's solid angle (unweighted visibility)"),
)

SIZE_MODE_ITEMS = (
    ("IMAGE_SIZE", "Image Size", "Choose the image size; the texel density is derived so that all charts fit"),
    ("DENSITY", "Texel Density", "Choose texels per scene unit; the image is made as large as needed"),
)

#: A .blend stores an enum setting as its item's position: new items go at the end, never in between.
CASTER_ITEMS = (
    ("GEOMETRY_NODES", "Geometry Nodes", "Blender's Raycast node on all cores (every setting)"),
    ("PYTHON_BVH", "Python BVH", "A Python loop over mathutils' BVHTree.ray_cast on one core (reference)"),
    ("CYCLES", "Cycles", "Geometry Nodes for each texel's first {} rays and to find the creases, then Cycles' AO "
     "bake on all cores for the rest, with no adaptive stop (faster in closed rooms and on large scans; classic AO "
     "only: {})".format(BULK_PILOT_RAYS, CLASSIC_AO)),
    ("AUTOMATIC", "Automatic", "Cycles when it is enabled, the settings are classic AO ({}) and there are more "
     "than {} rays per texel; Geometry Nodes otherwise".format(CLASSIC_AO, BULK_PILOT_RAYS)),
)

#: What each Quality preset bakes with: ``(image size, rays per texel)``.  Fixed settings for now, not yet chosen
#: from the mesh: on tests/bench/report.py's four meshes (Suzanne, a 250k-triangle Suzanne, a 70k scan, a
#: 1,300-piece interior) each is the cheapest tried that reaches the error its promise names (issue 52: Draft
#: Cycles' 256², 16 samples; Good the best of Cycles' 512²; Final Cycles' 1024², 256 samples) on all four
#: (docs/bench/report.md has the table).
PRESETS = {"DRAFT": (256, 4), "GOOD": (320, 24), "FINAL": (384, 48)}
QUALITY_ITEMS = (
    ("DRAFT", "Draft", "A quick look: {}² image, {} rays per texel".format(*PRESETS["DRAFT"])),
    ("GOOD", "Good", "For most uses: {}² image, {} rays per texel".format(*PRESETS["GOOD"])),
    ("FINAL", "Final", "For the final render: {}² image, {} rays per texel".format(*PRESETS["FINAL"])),
    ("CUSTOM", "Custom", "Choose the rays and the image yourself (Advanced)"),
)
#: The settings a Quality preset chooses: giving one of them (a keyword, an operator property, a command-line
#: option) without a Quality means Custom.
PRESET_CHOOSES = ("rays", "size_mode", "image_size", "texel_density")


def implied_quality(given):
    """``given`` (setting name -> value) with ``quality`` Custom added when it sets one of
    :data:`PRESET_CHOOSES` and no quality: whoever asks for 32 rays means 32 rays."""
    if "quality" in given or not any(name in given for name in PRESET_CHOOSES):
        return dict(given)
    return dict(given, quality="CUSTOM")


def item_label(items, identifier):
    """The label of enum item ``identifier`` among ``items`` (``(identifier, label, description)`` triples);
    the identifier itself if none has it."""
    return next((label for name, label, _ in items if name == identifier), identifier)


def caster_words(name):
    """What the bake report calls the caster ``name`` (a :data:`CASTER_ITEMS` identifier) that cast a bake's
    rays: its label, and for Cycles the node's part too."""
    if name == "CYCLES":
        return "{} (first rays) and {}".format(item_label(CASTER_ITEMS, "GEOMETRY_NODES"),
                                               item_label(CASTER_ITEMS, "CYCLES"))
    return item_label(CASTER_ITEMS, name)


SAVE_ITEMS = (
    ("NONE", "Packed Only", "Keep the image packed in the .blend only"),
    ("PNG", "16-bit PNG", "Also save the image as a 16-bit PNG next to the .blend"),
    ("EXR", "OpenEXR", "Also save the image as a 32-bit float OpenEXR next to the .blend"),
)


class _Settings:
    """Construction with validation, shared by :class:`BakeSettings` and :class:`ExportSettings`."""

    @classmethod
    def from_kwargs(cls, **kwargs):
        """Build validated settings from keyword arguments; unknown names are an error."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(kwargs) - names)
        if unknown:
            raise SeamlessAOError(
                "Unknown setting{} {}; valid settings are: {}".format(
                    "s" if len(unknown) > 1 else "", ", ".join(unknown), ", ".join(sorted(names))))
        settings = cls(**kwargs)
        settings.validate()
        return settings

    def replace(self, **kwargs):
        """A validated copy with some settings changed."""
        merged = dataclasses.asdict(self)
        merged.update(kwargs)
        return type(self).from_kwargs(**merged)

    def validate(self):
        """Raise :class:`SeamlessAOError` naming the first invalid setting; coerce numbers."""
        for f in dataclasses.fields(self):
            value = _coerce(f.name, type(f.default), getattr(self, f.name))
            setattr(self, f.name, value)
            meta = f.metadata
            if "items" in meta:
                valid = [item[0] for item in meta["items"]]
                if value not in valid:
                    raise SeamlessAOError("{} must be one of {} (got {!r})".format(f.name, ", ".join(valid), value))
            if "min" in meta and value < meta["min"]:
                raise SeamlessAOError("{} must be at least {} (got {})".format(f.name, meta["min"], value))
            if "max" in meta and value > meta["max"]:
                raise SeamlessAOError("{} must be at most {} (got {})".format(f.name, meta["max"], value))
        return self


@dataclass
class BakeSettings(_Settings):
    """All settings of one bake.  Angles are in degrees, distances in scene units."""

    quality: str = _setting(
        "GOOD", "Quality", "How accurate the bake is: each preset chooses the image size and the rays; Custom "
        "leaves them to you", items=QUALITY_ITEMS)

    # -- rays ------------------------------------------------------------------
    rays: int = _setting(64, "Rays", "Rays cast per texel, with Quality Custom (the thesis' default is 64)",
                         min=1, max=4096)
    auto_distance: bool = _setting(
        True, "Automatic Distance",
        "Use half the bounding-box diagonal of the object's faces as the maximum ray distance (debris far "
        "out, such as a spike to a stray vertex, left out)")
    max_distance: float = _setting(
        1.0, "Max Distance",
        "Hits farther than this do not occlude (scene units, used when Automatic Distance is off)",
        min=0.0, max=1.0e12, unit="scene units")
    cone_angle: float = _setting(
        90.0, "Cone Angle", "Half-angle of the cone around the normal that rays are cast in (90° = hemisphere)",
        min=1.0, max=90.0, unit="°")
    falloff: str = _setting("NONE", "Falloff", "How a hit's distance changes how much it occludes", items=FALLOFF_ITEMS)
    distribution: str = _setting("COSINE", "Distribution", "How rays are spread inside the cone", items=DISTRIBUTION_ITEMS)
    ignore_backfaces: bool = _setting(
        False, "Ignore Back Faces",
        "Rays pass through faces seen from behind (open scans and single-sided meshes)")
    horizon_bias: float = _setting(
        0.0, "Horizon Bias", "Hits of rays this close to the tangent plane fade out, hiding faceting on coarse smooth meshes",
        min=0.0, max=45.0, unit="°")
    adaptive: bool = _setting(
        True, "Adaptive Sampling",
        "Stop a texel after the first quarter of its rays when they and its neighbours' all agree "
        "(all open or all blocked); the rays Cycles casts get no such stop")
    weighted_rays: bool = _setting(
        False, "Weighted Rays",
        "Give a texel rays in proportion to the weight the blend shows it with (half as many at weight 1/2 "
        "or less, down to an eighth): the same shown noise for fewer rays")
    denoise: bool = _setting(
        True, "Denoise",
        "Edge-aware filter over each texel's surface neighbours (little weight across creases and contact shadows)")
    seed: int = _setting(0, "Seed", "Random seed; the same seed casts the same rays (Cycles' bulk aside: it follows "
                         "its batches)", min=0, max=2**31 - 1)
    use_scene_occluders: bool = _setting(
        False, "Scene Occluders",
        "Other visible mesh objects of the scene within the maximum ray distance also occlude (contact shadows)")
    use_ground_plane: bool = _setting(
        False, "Ground Plane", "An infinite horizontal plane at the object's lowest point occludes")
    ray_caster: str = _setting("AUTOMATIC", "Ray Caster",
                               "How rays are cast (Geometry Nodes and Python BVH give the same result)",
                               items=CASTER_ITEMS)

    # -- charts and image --------------------------------------------------------
    compare_angle: float = _setting(
        60.0, "Compare Angle",
        "A face joins an axis chart when its normal is within this angle of the axis (more = more overlap)",
        min=30.0, max=85.0, unit="°")
    size_mode: str = _setting("IMAGE_SIZE", "Resolution By", "How the image resolution is chosen, with Quality Custom",
                              items=SIZE_MODE_ITEMS)
    image_size: int = _setting(1024, "Image Size", "Width and height of the AO image, with Quality Custom",
                               min=256, max=8192, unit="texels")
    texel_density: float = _setting(
        256.0, "Texel Density", "Texels per scene unit (used when Resolution By is Texel Density)",
        min=1.0e-6, max=1.0e9, unit="texels per scene unit")
    padding: int = _setting(
        4, "Padding", "Texels kept free between large charts and filled with AO, at most: with thousands of "
        "pieces it shrinks to 2, and charts a few texels across share boxes with only the ring filtering reads",
        min=2, max=32, unit="texels")
    memory_budget_mb: int = _setting(
        4096, "Memory Budget", "Refuse to start a bake estimated to need more memory than this",
        min=64, max=1 << 20, unit="MB")

    # -- output ------------------------------------------------------------------
    hook_materials: bool = _setting(
        True, "Multiply Base Color",
        "Multiply the AO into the Base Color of every Principled BSDF (off: only add the nodes)")
    save_image: str = _setting("NONE", "Save Image", "Also write the image to a file next to the .blend", items=SAVE_ITEMS)

    # ---------------------------------------------------------------------------

    def validate(self):
        super().validate()
        if not self.auto_distance and self.max_distance <= 0.0:
            raise SeamlessAOError(
                "max_distance must be greater than 0 (got {}); turn on auto_distance to derive it "
                "from the object's size".format(self.max_distance))
        unfollowed = self.cycles_cannot_follow()
        if self.ray_caster == "CYCLES" and unfollowed:
            name, needed, reason, _ = unfollowed
            raise SeamlessAOError(
                "The Cycles ray caster cannot bake with {} = {!r}: {}. Set it to {!r}, or choose the "
                "Geometry Nodes caster.".format(name, getattr(self, name), reason, needed))
        return self

    @classmethod
    def from_kwargs(cls, **kwargs):
        """Validated settings from keyword arguments; rays or a size without a Quality mean Custom
        (:func:`implied_quality`)."""
        return super().from_kwargs(**implied_quality(kwargs))

    def replace(self, **kwargs):
        """A validated copy with some settings changed; new rays or a size without a Quality mean Custom."""
        return super().replace(**implied_quality(kwargs))

    def resolved(self):
        """These settings with the Quality preset's image size and rays filled in (``self`` when Custom): what
        a bake reads."""
        if self.quality not in PRESETS:
            return self
        image_size, rays = PRESETS[self.quality]
        if (self.size_mode, self.image_size, self.rays) == ("IMAGE_SIZE", image_size, rays):
            return self
        return dataclasses.replace(self, size_mode="IMAGE_SIZE", image_size=image_size, rays=rays)

    def chosen(self, width, height):
        """The Quality and what the bake took, in a few words for the report: "Good, 256², 32 rays" (``width``
        and ``height``: the image's texels, which the layout chooses with Texel Density)."""
        label = item_label(QUALITY_ITEMS, self.quality)
        size = "{}²".format(width) if width == height else "{}×{}".format(width, height)
        return "{}, {}, {} rays".format(label, size, self.resolved().rays)

    def cycles_cannot_follow(self):
        """The first ``(setting, value it needs, reason, in short)`` of :data:`.rays.cycles_rules.CYCLES_NEEDS`
        these settings break, or None."""
        return first_unfollowed(self)

    def caster_name(self, cycles_enabled=True):
        """The name of the ray caster a bake uses: ``ray_caster``, Automatic resolved (:meth:`caster_choice`)."""
        return self.caster_choice(cycles_enabled)[0]

    def caster_choice(self, cycles_enabled=True):
        """``(caster, why)``: ``ray_caster``, with ``AUTOMATIC`` resolved to ``CYCLES`` when Cycles is enabled in
        this Blender (``cycles_enabled``), can follow every setting (:data:`.rays.cycles_rules.CYCLES_NEEDS`)
        and has rays to cast (more than ``BULK_PILOT_RAYS`` per texel), else to ``GEOMETRY_NODES``; ``why`` says
        so in a few words for the panel (empty for a chosen caster)."""
        if self.ray_caster != "AUTOMATIC":
            return self.ray_caster, ""
        if not cycles_enabled:
            return "GEOMETRY_NODES", "Cycles is not enabled in this Blender"
        unfollowed = self.cycles_cannot_follow()
        if unfollowed:
            return "GEOMETRY_NODES", unfollowed[2]
        if self.resolved().rays <= BULK_PILOT_RAYS:
            return "GEOMETRY_NODES", "the node casts each texel's first {} rays itself".format(BULK_PILOT_RAYS)
        return "CYCLES", "all but each texel's first {} rays".format(BULK_PILOT_RAYS)

PACKING_ITEMS = tuple((packing.id, packing.label, packing.description) for packing in PACKINGS)

BIT_DEPTH_ITEMS = (
    ("16", "16-bit", "16 bits per channel (no visible banding in soft AO gradients)"),
    ("8", "8-bit", "8 bits per channel (half the size; what most engines store AO in)"),
)

DOMAIN_ITEMS = (
    ("CORNER", "Face Corner", "One value per face corner (sharp where the AO is)"),
    ("POINT", "Vertex", "One value per vertex (the corners averaged)"),
)


@dataclass
class ExportSettings(_Settings):
    """How the AO leaves Blender: resampled onto the object's own UV map, or as a colour attribute."""

    uv_map: str = _setting("", "UV Map", "UV map to resample the AO onto (empty: the render-active one)")
    size: int = _setting(1024, "Size", "Width and height of the resampled image", min=8, max=16384, unit="texels")
    padding: int = _setting(8, "Padding", "Texels of dilation around every UV island", min=0, max=64,
                            unit="texels")
    gltf_occlusion: bool = _setting(
        True, "glTF Occlusion", "Wire the resampled image into the materials as the glTF occlusion texture")
    domain: str = _setting("CORNER", "Domain", "Where the colour attribute stores the AO", items=DOMAIN_ITEMS)
    material_strength: bool = _setting(
        True, "Material Strength",
        "Apply the Strength and Interreflection set on each material's Seamless AO node, as the material shows "
        "it (off: the AO as baked)")
    packing: str = _setting("GLTF", "Packing", "Which channels of the resampled image carry the AO",
                            items=PACKING_ITEMS)
    bit_depth: str = _setting("16", "Bit Depth", "Bits per channel of the resampled image, a PNG packed into the "
                              ".blend and embedded as is by the glTF exporter", items=BIT_DEPTH_ITEMS)
    unfit_uv_map: bool = _setting(
        False, "Even If Unfit",
        "Resample even onto a UV map that cannot hold the AO (UV space shared by several faces, tiling, or "
        "faces with no UV area): the AO of one place then shows in another")


def _again(name, **change):
    """Field ``name`` of :class:`ExportSettings` for another settings class: its default, limits and unit kept,
    ``change`` (a description, items) applied: one declaration of each export setting."""
    found = next(f for f in dataclasses.fields(ExportSettings) if f.name == name)
    return field(default=found.default, metadata=dict(found.metadata, **change))


UV_POLICY_ITEMS = (
    ("auto", "Auto", "The asset's own (render-active) UV map where it can hold the AO, else a new one, AO_UV "
     "(glTF TEXCOORD_1)"),
    ("own", "Own", "Always the asset's own UV map, with a warning where it cannot hold the AO"),
    ("new", "New", "Always a new UV map, AO_UV"),
)
COLOR_ATTRIBUTE_ITEMS = (("NONE", "None", "No vertex colour"),) + DOMAIN_ITEMS
#: glTF reads occlusion from R: the packings with the AO there.
GLTF_PACKING_ITEMS = tuple(item for item in PACKING_ITEMS if PACKINGS_BY_ID[item[0]].gltf_readable)


@dataclass
class GltfSettings(_Settings):
    """How a batch writes an asset's AO into its .glb: the UV map it rides on, the occlusion texture, colours."""

    uv_policy: str = _setting("auto", "UV Policy", "glTF out: the UV map the AO rides on", items=UV_POLICY_ITEMS)
    color_attribute: str = _setting("NONE", "Color Attribute", "Also write the AO as colour attribute 'AO' on this "
                                    "domain (glTF out: COLOR_0)", items=COLOR_ATTRIBUTE_ITEMS)
    texture_size: int = _again("size", description="glTF out: width and height of the occlusion texture")
    texture_padding: int = _again("padding", description="glTF out: texels of dilation around UV islands")
    texture_packing: str = _again("packing", description="glTF out: the occlusion texture's channels",
                                  items=GLTF_PACKING_ITEMS)
    texture_bit_depth: str = _again("bit_depth", description="glTF out: bits per channel of the occlusion texture")

    def validate(self):
        packing = PACKINGS_BY_ID.get(self.texture_packing)
        if packing is not None and not packing.gltf_readable:
            readable = [item[0] for item in GLTF_PACKING_ITEMS]
            raise SeamlessAOError("{}, and a batch writes glTF: pick {} or {} packing".format(
                packing.not_gltf(), ", ".join(readable[:-1]), readable[-1]))
        return super().validate()

    def resample_settings(self):
        """The :class:`ExportSettings` of the occlusion texture's resample."""
        return ExportSettings.from_kwargs(size=self.texture_size, padding=self.texture_padding,
                                          packing=self.texture_packing, bit_depth=self.texture_bit_depth)


#: What each export writes, and which of :class:`ExportSettings` it reads.
RESAMPLE_FIELDS = ("uv_map", "size", "padding", "gltf_occlusion", "material_strength", "packing", "bit_depth",
                   "unfit_uv_map")
COLOR_FIELDS = ("domain", "material_strength")


def _coerce(name, kind, value):
    """``value`` converted to ``kind`` (bool, int, float or str), or a clear error."""
    if kind is bool:
        if isinstance(value, bool):
            return value
        raise SeamlessAOError("{} must be True or False (got {!r})".format(name, value))
    if kind is str:
        if isinstance(value, str):
            return value
        raise SeamlessAOError("{} must be text (got {!r})".format(name, value))
    if isinstance(value, bool):
        raise SeamlessAOError("{} must be a number (got {!r})".format(name, value))
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise SeamlessAOError("{} must be a number (got {!r})".format(name, value)) from None
    if number != number or number in (float("inf"), float("-inf")):
        raise SeamlessAOError("{} must be a finite number (got {!r})".format(name, value))
    if kind is int:
        if number != int(number):
            raise SeamlessAOError("{} must be a whole number (got {!r})".format(name, value))
        return int(number)
    return number


def setting_fields():
    """The dataclass fields of :class:`BakeSettings`, in declaration order."""
    return dataclasses.fields(BakeSettings)


def export_fields(names=None):
    """The dataclass fields of :class:`ExportSettings` (those named in ``names``, if given)."""
    return tuple(f for f in dataclasses.fields(ExportSettings) if names is None or f.name in names)


def gltf_fields():
    """The dataclass fields of :class:`GltfSettings`, in declaration order."""
    return dataclasses.fields(GltfSettings)
