"""A Blender scene as one ``lgh explosion`` render: the VDB file of the frame, every setting (the
keyword arguments of ``lgh.render_explosion``), and the notes — what the scene asks for that
LGH does not render, each named once for Blender's report. Never a silently different image:
what is read here is rendered as Cycles renders it, what is not is named, and what cannot be
rendered at all is refused (:class:`~.errors.Refused`).

What is read:

- the scene camera (:mod:`.camera`) and the render's resolution;
- the first volume (by name) visible to the render — an OpenVDB Volume object, its file for
  the current frame (``grids.frame_filepath``), or a Mantaflow gas domain, its cache's file
  for the frame (:mod:`.domain`) — and its placement: translation, rotation and a uniform
  scale, undone by moving the camera into the volume's own space (a scale ``s`` multiplies the
  extinction and the emission per unit of the file's length by ``s``: the same image);
- its material's Principled Volume (Cycles' ``svm_node_principled_volume``): with density
  ``d``, scattering colour ``c`` and absorption colour ``a``, Cycles' extinction is
  ``d (c + (1 - c)(1 - sqrt(a)))`` per unit of the density attribute and its albedo
  ``c / (c + (1 - c)(1 - sqrt(a)))``: lgh's ``density_scale`` and ``albedo`` (grey colours; a
  coloured one is named and its mean used); the blackbody intensity (times a grey tint, or
  the attribute linked to it: lgh's flame grid), the temperature and its attribute; an
  attribute linked to the emission colour as an RGB emission grid times the emission strength;
- Blender 4.x/5.x's interpolation of each attribute on its own (``emission_interpolation``);
- the world's constant colour as the background (``background``; its light on the smoke is
  named);
- the visible meshes, as the room the fire lights (:mod:`.room`);
- the engine's own Sampling settings (``scene.lgh``, :mod:`.sampling`).
"""
import math
import os

import bpy

from . import camera, domain, sampling
from .errors import Refused
from .nodes import linked_to_output

#: How far apart a fluid domain's cells may be from cubes in the world: named up to it, refused
#: beyond (Blender rounds each side's count of cells).
CELL_TOLERANCE = 0.02

#: Object types that are no part of the render's image (a camera is the view, an empty nothing).
SILENT = {"CAMERA", "EMPTY", "LIGHT_PROBE", "SPEAKER", "ARMATURE", "LATTICE"}


class Job:
    """One render: ``vdb``, the file; ``settings``, ``lgh.render_explosion``'s keyword
    arguments; ``notes``, what is not rendered, one sentence each; ``local``, the map from the
    world into the volume's own space (``None``: the identity), for other cameras."""

    def __init__(self, vdb, settings, notes, local=None, meshes=()):
        self.vdb = vdb
        self.settings = settings
        self.notes = notes
        self.local = local
        #: The mesh objects of the room the fire lights (:mod:`.room` writes them).
        self.meshes = list(meshes)
        #: What must live as long as the job: the room's files of a preview.
        self.keep = None

    def with_settings(self, settings):
        """This job with other settings."""
        other = Job(self.vdb, settings, self.notes, self.local, self.meshes)
        other.keep = self.keep
        return other

    def __repr__(self):
        return f"Job({self.vdb!r}, {self.settings!r}, {self.notes!r})"


def grey(rgb):
    """Whether an RGB colour is grey (its channels equal to 1e-6)."""
    return max(rgb) - min(rgb) <= 1e-6


class Shader:
    """A Principled Volume node's inputs, each its own value unless an attribute drives it;
    anything else linked to an input is named in ``notes``."""

    def __init__(self, node, material, notes):
        self.node, self.material, self.notes = node, material, notes

    def linked(self, name):
        """The node linked to input ``name``, or ``None``."""
        socket = self.node.inputs[name]
        return socket.links[0].from_node if socket.is_linked and socket.links else None

    def attribute(self, name):
        """The attribute (by name) an Attribute node feeding input ``name`` reads, else ``None``
        (any other node is named: the input's own value is used)."""
        node = self.linked(name)
        if node is None:
            return None
        if node.type == "ATTRIBUTE" and node.attribute_type == "GEOMETRY" and node.attribute_name:
            return node.attribute_name
        self.notes.append(
            f"material '{self.material}': the {node.bl_label} node driving the Principled "
            f"Volume's {name} (its own value is used)")
        return None

    def value(self, name):
        """The input's own value: a float, or an RGB tuple."""
        v = self.node.inputs[name].default_value
        return tuple(v)[:3] if hasattr(v, "__len__") else float(v)

    def text(self, name):
        """A string input (an attribute's name)."""
        return self.node.inputs[name].default_value


def colour(shader, name):
    """A colour input as one number: the value if grey, else its mean, named."""
    rgb = shader.value(name)
    if shader.attribute(name) is not None:
        shader.notes.append(f"material '{shader.material}': an attribute driving the "
                            f"Principled Volume's {name} (its own value is used)")
    if not grey(rgb):
        shader.notes.append(
            f"material '{shader.material}': the coloured {name} "
            f"({rgb[0]:.3g}, {rgb[1]:.3g}, {rgb[2]:.3g}): lgh's medium is grey, its mean is used")
    return sum(rgb) / 3.0


def volume_shader(obj):
    """The Principled Volume of ``obj``'s first material, with the material's name and node
    tree."""
    material = obj.material_slots[0].material if obj.material_slots else None
    if material is None:
        raise Refused(f"volume '{obj.name}' has no material: give it one with a Principled "
                      "Volume shader")
    if bpy.app.version < (5, 0, 0) and not material.use_nodes:
        raise Refused(f"material '{material.name}' of '{obj.name}' uses no nodes: LGH renders "
                      "the Principled Volume shader")
    node = linked_to_output(material.node_tree, "OUTPUT_MATERIAL", "Volume")
    if node is None:
        raise Refused(f"material '{material.name}' of '{obj.name}' has no volume shader: "
                      "link a Principled Volume to the Material Output's Volume")
    if node.type != "PRINCIPLED_VOLUME":
        raise Refused(f"material '{material.name}' of '{obj.name}': its volume shader is a "
                      f"{node.bl_label}, LGH renders the Principled Volume")
    return node, material.name, material.node_tree


def medium(obj, scale, source, notes):
    """The settings of ``obj``'s Principled Volume, ``scale`` the uniform scale of its
    placement, ``source`` its file (:class:`~.domain.Source`: the grid of each attribute)."""
    node, material, tree = volume_shader(obj)
    if linked_to_output(tree, "OUTPUT_MATERIAL", "Surface") is not None:
        notes.append(f"material '{material}': the surface shader (LGH renders the volume)")
    sh = Shader(node, material, notes)
    out = {}

    # Density: Density x the density attribute.
    if sh.attribute("Density") is not None:
        notes.append(f"material '{material}': an attribute linked to the Density (the "
                     "Density Attribute is read)")
    density_attr = sh.text("Density Attribute")
    if not density_attr:
        raise Refused(f"material '{material}': the Principled Volume has no Density "
                      "Attribute: LGH renders smoke from a density grid")
    density_grid = source.grid(density_attr, material, "Density Attribute")
    d = sh.value("Density")
    c = colour(sh, "Color")
    a = colour(sh, "Absorption Color")
    if sh.text("Color Attribute"):
        notes.append(f"material '{material}': the Color Attribute "
                     f"'{sh.text('Color Attribute')}' (lgh's medium is grey)")
    absorption = max(1.0 - c, 0.0) * max(1.0 - math.sqrt(max(a, 0.0)), 0.0)
    extinction = max(c, 0.0) + absorption
    out["density_grid"] = density_grid
    out["density_scale"] = d * extinction * scale
    out["albedo"] = min(max(c, 0.0) / extinction, 1.0) if extinction > 0.0 else 0.0
    if sh.value("Anisotropy") != 0.0:
        notes.append(f"material '{material}': the anisotropy {sh.value('Anisotropy'):g} (lgh "
                     "scatters isotropically)")

    # Emission: the blackbody, or an RGB emission attribute.
    blackbody = sh.value("Blackbody Intensity")
    flame = sh.attribute("Blackbody Intensity")
    tint = sh.value("Blackbody Tint") if "Blackbody Tint" in node.inputs else (1.0, 1.0, 1.0)
    emission_rgb = sh.attribute("Emission Color")
    strength = sh.value("Emission Strength")
    if sh.attribute("Emission Strength") is not None:
        notes.append(f"material '{material}': an attribute linked to the Emission Strength")
    if emission_rgb is not None and strength != 0.0:
        out["emission_grid"] = source.grid(emission_rgb, material, "Emission Color")
        out["emission_scale"] = strength * scale
        out["flame_grid"] = "none"
        if blackbody != 0.0 or flame is not None:
            notes.append(f"material '{material}': the blackbody emission beside the Emission "
                         "Color's attribute (lgh renders one emission)")
        return out
    if strength != 0.0:
        notes.append(f"material '{material}': the Emission Strength {strength:g} with a "
                     "constant Emission Color (lgh's light is the grids' emission)")
    temperature_attr = sh.text("Temperature Attribute")
    if sh.attribute("Temperature") is not None:
        notes.append(f"material '{material}': an attribute linked to the Temperature")
    if not grey(tint):
        notes.append(f"material '{material}': the coloured Blackbody Tint (its mean is used)")
    tint = sum(tint) / 3.0
    if flame is not None:
        out["flame_grid"] = source.grid(flame, material, "Blackbody Intensity")
        intensity = 1.0
    else:
        out["flame_grid"], intensity = "none", blackbody
    if intensity * tint != 0.0:
        if not temperature_attr:
            raise Refused(f"material '{material}': a blackbody emission without a "
                          "Temperature Attribute: LGH's lights are a temperature grid's voxels")
        out["emission_grid"], extra = source.temperature(temperature_attr, material)
        out.update(extra)
    out["emission_model"] = "blender"
    out["temperature_scale"] = sh.value("Temperature")
    out["emission_scale"] = intensity * tint * scale
    return out


def placement(source, notes):
    """``(scale, local)`` of a :class:`~.domain.Source`'s matrix (its file's space to the
    world): its uniform scale and its inverse (``None`` for the identity). A volume's
    non-uniform scale, shear or mirror is refused; a domain's cells that are not cubes in the
    world to 1e-5 (Blender rounds each side's count of cells) are named up to
    ``CELL_TOLERANCE`` apart and refused beyond."""
    m = source.matrix
    rot_scale = m.to_3x3()
    scales = [rot_scale.col[i].length for i in range(3)]
    s = sum(scales) / 3.0
    spread = (max(scales) - min(scales)) / s if s > 0.0 else math.inf
    sides = ", ".join(f"{x:.6g}" for x in scales)
    if spread > 1e-5 and (source.exact or spread > CELL_TOLERANCE):
        if source.exact:
            raise Refused(f"{source.name} has a non-uniform scale ({sides}): LGH renders "
                          "volumes scaled alike on every axis (apply the scale to the file, or "
                          "make it uniform)")
        raise Refused(f"{source.name}: its cells are not cubes in the world ({sides}): LGH's "
                      "voxels are cubes (scale the domain alike on every axis)")
    if spread > 1e-5:
        notes.append(f"{source.name}: its cells are {100 * spread:.2g}% from cubes in the world "
                     f"({sides}): LGH's voxels are cubes, the smoke is stretched by as much")
    rot = rot_scale * (1.0 / s)
    if abs(rot.determinant() - 1.0) > 3 * spread + 1e-4 or any(
            abs(rot.col[i].dot(rot.col[j])) > 1e-4 for i in range(3) for j in range(i)):
        raise Refused(f"{source.name} is sheared or mirrored: LGH renders volumes "
                      "translated, rotated and uniformly scaled")
    if m == m.Identity(4):
        return 1.0, None
    inverse = m.inverted()
    return s, (inverse.to_3x3(), inverse.translation.copy())


def world(scene, notes):
    """The world as LGH renders it: its constant colour × strength seen behind the smoke
    (``background``; ``None`` when black, or with *Film > Transparent*, which Blender shows
    as alpha). Its light on the smoke, which LGH does not render, is named; so is a world that
    is not one colour (a texture, a sky), rendered black."""
    w = scene.world
    if w is None:
        return None
    colour, strength = tuple(w.color), 1.0
    if bpy.app.version >= (5, 0, 0) or w.use_nodes:
        node = linked_to_output(w.node_tree, "OUTPUT_WORLD", "Surface")
        if node is None:
            return None
        if node.type != "BACKGROUND" or node.inputs["Color"].is_linked or \
                node.inputs["Strength"].is_linked:
            notes.append(f"the world '{w.name}' ({node.bl_label}): not one colour, LGH renders "
                         "a black world")
            return None
        colour, strength = tuple(node.inputs["Color"].default_value)[:3], \
            node.inputs["Strength"].default_value
    radiance = tuple(c * strength for c in colour)
    if max(radiance) <= 0.0:
        return None
    notes.append(f"the world's light on the smoke (its colour ({colour[0]:.3g}, {colour[1]:.3g}, "
                 f"{colour[2]:.3g}) x {strength:g} is the background; LGH's only light is the "
                 "fire)")
    return None if scene.render.film_transparent else radiance


def job(depsgraph, view_only=False):
    """The render of ``depsgraph``'s scene at its current frame (see the module's text).
    ``view_only``: for the viewport, whose view replaces the scene camera (which may then be
    missing or orthographic): no camera settings."""
    scene = depsgraph.scene
    if scene.camera is None and not view_only:
        raise Refused("the scene has no camera (Scene > Camera)")
    notes = []
    final = depsgraph.mode == "RENDER"
    volumes, meshes = [], []
    instanced = sorted({i.object.name for i in depsgraph.object_instances
                        if i.is_instance and i.object.type in ("VOLUME", "MESH", "LIGHT")})
    if instanced:
        notes.append(f"the instanced objects {', '.join(repr(n) for n in instanced[:5])}"
                     f"{' and more' if len(instanced) > 5 else ''} (LGH renders objects "
                     "themselves, not their instances)")
    for obj in depsgraph.objects:
        if obj.type == "VOLUME":
            volumes.append(obj)
        elif obj.type == "LIGHT":
            notes.append(f"the lamp '{obj.name}' (the fire is LGH's only light)")
        elif obj.type == "MESH" and domain.gas_domain(obj, final) is not None:
            volumes.append(obj)
        elif obj.type == "MESH" and domain.fluid(obj) is not None:
            notes.append(f"the fluid object '{obj.name}' (LGH renders gas domains and OpenVDB "
                         "Volume objects)")
        elif obj.type == "MESH":
            meshes.append(obj)
        elif obj.type not in SILENT:
            notes.append(f"the {obj.type.lower()} '{obj.name}' (LGH renders a volume)")
    if not volumes:
        raise Refused("no volume to render: add a Volume object (Add > Volume > Import "
                      "OpenVDB) or a smoke/fire domain baked to OpenVDB")
    volumes.sort(key=lambda o: o.name)
    obj = volumes[0]
    for other in volumes[1:]:
        notes.append(f"the volume '{other.name}' (LGH renders one volume, '{obj.name}')")
    ds = domain.gas_domain(obj, final) if obj.type == "MESH" else None
    if ds is None:
        source = volume_source(obj, scene.frame_current)
    else:
        source = domain.source(obj, ds, scene.frame_current, lgh_inspect)
        # The fluid modifier makes the domain's box; others before or after it change nothing
        # that Cycles draws of the smoke but its own mesh's surface, not rendered here.
    if any(m.show_render and m.type != "FLUID" for m in obj.modifiers):
        notes.append(f"the modifiers of '{obj.name}' (LGH renders its file)")
    scale, local = placement(source, notes)
    r = scene.render
    if view_only:
        settings = {}
    else:
        view = scene.camera.evaluated_get(depsgraph)
        settings = camera.settings(scene, view, local)
        if view.data.dof.use_dof:
            notes.append(f"the depth of field of camera '{view.name}' (LGH's camera is a "
                         "pinhole)")
    if r.use_motion_blur:
        notes.append("motion blur")
    settings.update(medium(obj, scale, source, notes))
    background = world(scene, notes)
    if background is not None:
        settings["background"] = background
    settings.update(source.settings)
    settings.update(sampling.settings(scene))
    settings.update({
        "up": "z",
        "emission_interpolation": "attributes" if bpy.app.version >= (4, 0, 0) else "temperature",
        "allow_dark": True,
    })
    return Job(source.path, settings, notes, local, sorted(meshes, key=lambda o: o.name))


def lgh_inspect(path):
    """``lgh.inspect``: the grids of an OpenVDB file (imported here, as the engine imports
    lgh: the add-on registers without it)."""
    import lgh

    return lgh.inspect(path)


def volume_source(obj, frame):
    """The :class:`~.domain.Source` of Volume object ``obj`` at ``frame``: its file as Blender
    resolves it, each grid an attribute of its own name, placed by the object's matrix."""
    data = obj.data
    data.grids.load()
    path = bpy.path.abspath(data.grids.frame_filepath or data.filepath, library=data.library)
    if not path:
        raise Refused(f"volume '{obj.name}' has no file (Volume > OpenVDB File)")
    if not os.path.isfile(path):
        raise Refused(f"volume '{obj.name}': {path}: no such file (frame {frame})")
    if data.grids.error_message:
        raise Refused(f"volume '{obj.name}': {data.grids.error_message} ({path})")
    grids = {g.name: (g.name, {}) for g in data.grids}
    return domain.Source(f"volume '{obj.name}'", path, grids, obj.matrix_world, True,
                         {"no_domain_offset": True})
