"""The scene's meshes as the room the fire lights (``lgh explosion --scene``, the paper's
explosions in a box): every mesh object visible to the render, evaluated (modifiers applied),
triangulated and moved into the volume's own space, written as an OBJ with its MTL — each
material's diffuse colour as ``Kd`` — for the render, and deleted after it.

lgh's room is diffuse and shadowed by itself, lit by the fire through the smoke: what a
material has beyond a diffuse colour is named once — the Principled BSDF's specular and
metallic parts, its emission, any node driving the colour (its own value is used), a
material other than a Principled or Diffuse BSDF (grey 0.8, Blender's default) — and a mesh
without a material is Blender's default grey, 0.8.
"""
import os
import tempfile

from .nodes import linked_to_output

#: Blender's colour of a surface without a material, or with a shader LGH does not read.
DEFAULT_GREY = 0.8


def surface_colour(material, notes):
    """The diffuse colour of ``material`` (``None``: none), naming what is not rendered."""
    tree = material.node_tree if material is not None else None
    node = linked_to_output(tree, "OUTPUT_MATERIAL", "Surface")
    if node is None:
        return (DEFAULT_GREY,) * 3
    if node.type not in ("BSDF_PRINCIPLED", "BSDF_DIFFUSE"):
        notes.append(f"the {node.bl_label} of material '{material.name}' (LGH's room is "
                     f"diffuse: grey {DEFAULT_GREY} is used)")
        return (DEFAULT_GREY,) * 3
    colour_input = node.inputs["Base Color" if node.type == "BSDF_PRINCIPLED" else "Color"]
    if colour_input.is_linked:
        notes.append(f"the {colour_input.links[0].from_node.bl_label} node driving the colour "
                     f"of material '{material.name}' (its own value is used)")
    if node.type == "BSDF_PRINCIPLED":
        extra = []
        if node.inputs["Metallic"].default_value > 0.0 or node.inputs["Metallic"].is_linked:
            extra.append("metallic")
        if "Specular IOR Level" in node.inputs and node.inputs["Specular IOR Level"].default_value > 0:
            extra.append("specular")
        if "Emission Strength" in node.inputs and node.inputs["Emission Strength"].default_value > 0:
            colour = tuple(node.inputs["Emission Color"].default_value)[:3]
            if max(colour) > 0.0:
                extra.append("emission")
        if extra:
            notes.append(f"the {' and '.join(extra)} part of material '{material.name}' "
                         "(LGH's room is diffuse)")
    return tuple(colour_input.default_value)[:3]


def write(depsgraph, meshes, local, folder, notes):
    """Writes ``meshes`` (evaluated mesh objects) as ``room.obj`` and ``room.mtl`` in
    ``folder``, the vertices mapped by ``local`` (``(rotation_3x3, translation)`` into the
    volume's space, ``None``: the identity): the OBJ's path, or ``None`` if they have no
    triangle."""
    obj_path = os.path.join(folder, "room.obj")
    materials = {}
    lines, base = ["mtllib room.mtl"], 1
    for obj in meshes:
        mesh = obj.to_mesh(preserve_all_data_layers=False, depsgraph=depsgraph)
        try:
            mesh.calc_loop_triangles()
            if not mesh.loop_triangles:
                continue
            m = obj.matrix_world
            lines.append(f"o {obj.name.replace(' ', '_')}")
            for v in mesh.vertices:
                p = m @ v.co
                if local is not None:
                    p = local[0] @ p + local[1]
                lines.append(f"v {p.x:.9g} {p.y:.9g} {p.z:.9g}")
            current = None
            for t in mesh.loop_triangles:
                # An index past the last slot takes the last, as Cycles clamps it.
                slots = obj.material_slots
                slot = slots[min(t.material_index, len(slots) - 1)] if slots else None
                material = slot.material if slot is not None else None
                key = material.name if material is not None else "__default"
                if key not in materials:
                    materials[key] = surface_colour(material, notes)
                if key != current:
                    lines.append(f"usemtl m{list(materials).index(key)}")
                    current = key
                a, b, c = (base + i for i in t.vertices)
                lines.append(f"f {a} {b} {c}")
            base += len(mesh.vertices)
        finally:
            obj.to_mesh_clear()
    if base == 1:
        return None
    mtl = []
    for i, (name, kd) in enumerate(materials.items()):
        mtl += [f"# {name}", f"newmtl m{i}", f"Kd {kd[0]:.9g} {kd[1]:.9g} {kd[2]:.9g}", ""]
    with open(os.path.join(folder, "room.mtl"), "w") as f:
        f.write("\n".join(mtl))
    with open(obj_path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return obj_path


def digest(obj_path):
    """The SHA-256 of a room's OBJ and MTL (what the render reads of it)."""
    import hashlib

    h = hashlib.sha256()
    for path in (obj_path, os.path.join(os.path.dirname(obj_path), "room.mtl")):
        with open(path, "rb") as f:
            h.update(f.read())
    return h.hexdigest()


class Room:
    """A temporary folder holding the room's files for one render (``with Room(...) as path``;
    ``path`` is ``None`` without meshes); removed afterwards."""

    def __init__(self, depsgraph, meshes, local, notes):
        self.depsgraph, self.meshes, self.local, self.notes = depsgraph, meshes, local, notes
        self.folder = None

    def __enter__(self):
        if not self.meshes:
            return None
        self.folder = tempfile.TemporaryDirectory(prefix="lgh-room-")
        return write(self.depsgraph, self.meshes, self.local, self.folder.name, self.notes)

    def __exit__(self, *exc):
        if self.folder is not None:
            self.folder.cleanup()
        return False
