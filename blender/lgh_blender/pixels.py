"""lgh's image as Blender holds pixels: RGBA, rows from the bottom."""
import numpy as np


def rgba_rows_up(image):
    """``lgh``'s ``(h, w, 3)`` image, rows from the top, as Blender's RGBA rows from the
    bottom, alpha 1 (the world is opaque black), flattened (a render pass, a texture)."""
    h, w, _ = image.shape
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[:, :, :3] = image[::-1]
    return rgba.reshape(-1)
