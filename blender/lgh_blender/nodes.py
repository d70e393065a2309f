"""Shader node trees as Blender evaluates them: the node linked to a socket of the active output
node (a material's for Cycles, a world's)."""


def linked_to_output(tree, output_type, socket):
    """The node linked to input ``socket`` of ``tree``'s active ``output_type`` node
    (``OUTPUT_MATERIAL`` for Cycles or all renderers, ``OUTPUT_WORLD``; the first such node if
    none is marked active): ``None`` without a tree, an output or a link."""
    if tree is None:
        return None
    outputs = [n for n in tree.nodes
               if n.type == output_type and getattr(n, "target", "ALL") in ("ALL", "CYCLES")]
    active = [n for n in outputs if n.is_active_output] or outputs
    if not active or not active[0].inputs[socket].is_linked:
        return None
    return active[0].inputs[socket].links[0].from_node
