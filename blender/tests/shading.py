"""The Principled Volume of the add-on's test scenes, in a module of its own that imports nothing
but ``bpy``: ``blender/domain_check.py`` builds the same material inside Blender 3.4.1, whose
Python has neither numpy nor pytest.
"""
import bpy


def principled(data, inputs=None, flame=None):
    """A material of a Principled Volume given to ``data`` (a volume or a mesh): ``inputs`` set
    on it, the attribute ``flame`` linked to its Blackbody Intensity if given. The node."""
    mat = bpy.data.materials.new("fire")
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    out = nodes.new("ShaderNodeOutputMaterial")
    pv = nodes.new("ShaderNodeVolumePrincipled")
    settings = {"Density": 4.0, "Color": (0.7, 0.7, 0.7, 1.0),
                "Absorption Color": (0.0, 0.0, 0.0, 1.0), "Blackbody Intensity": 1.0,
                "Temperature": 1.0}
    settings.update(inputs or {})
    for k, v in settings.items():
        pv.inputs[k].default_value = v
    mat.node_tree.links.new(pv.outputs["Volume"], out.inputs["Volume"])
    if flame is not None:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_name = flame
        mat.node_tree.links.new(attr.outputs["Fac"], pv.inputs["Blackbody Intensity"])
    data.materials.append(mat)
    return pv
