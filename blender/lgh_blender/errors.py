"""What stops a render before it starts: one clear message for Blender's report."""


class Refused(Exception):
    """The scene asks for what LGH cannot render at all (an orthographic camera, a volume
    without the grids its shader names, a missing cache): the render is not made, and this
    message is the report's error."""
