"""Blender's camera as ``lgh explosion``'s: the eye, a target along the view, the vertical field
of view, the up direction (the camera's roll) and the lens shift, from the object's matrix, the
lens, the sensor and its fit, and the render's resolution.

Blender's perspective projection (Cycles' ``blender_camera_viewplane``): the sensor's size
``sensor`` spans the *fitted* side of the image — with fit ``AUTO`` the sensor width spans the
larger side (the width when the image is strictly wider than tall), ``HORIZONTAL`` the sensor
width spans the width, ``VERTICAL`` the sensor height spans the height — so that side's half
extent on the image plane at distance 1 is ``t = sensor / (2 lens)``. The shift moves the image
plane by ``shift`` times that side's whole extent ``2 t``. lgh's camera takes the vertical field
of view and a shift in units of the image's larger side (``--camera-shift``), so both are
converted here. The camera looks down its local -Z with +Y up; the object's scale is ignored,
as Blender ignores it.
"""
import math

from .errors import Refused


def resolution(render):
    """The image size Blender renders: the resolution times its percentage (integer division,
    as ``BKE_render_resolution``)."""
    pct = render.resolution_percentage
    return render.resolution_x * pct // 100, render.resolution_y * pct // 100


def projection(sensor_fit, sensor_width, sensor_height, lens, shift, width, height):
    """``(fov_y_degrees, (shift_x, shift_y))`` of lgh's camera for Blender's lens ``lens`` (mm),
    sensor ``sensor_width × sensor_height`` (mm) fitted by ``sensor_fit`` (``AUTO``,
    ``HORIZONTAL``, ``VERTICAL``) and lens shift ``shift`` on a ``width × height`` image.

    >>> fov, s = projection("AUTO", 36.0, 24.0, 50.0, (0.0, 0.0), 1920, 1080)
    >>> round(fov, 4)  # the 50 mm lens on a 36 mm sensor, 16:9: 2 atan(18/50 · 9/16)
    22.8952
    >>> projection("VERTICAL", 36.0, 24.0, 50.0, (0.1, 0.0), 1000, 500)[1]  # height fitted
    (0.05, 0.0)
    """
    if sensor_fit == "AUTO":
        size, horizontal = sensor_width, width > height
    elif sensor_fit == "HORIZONTAL":
        size, horizontal = sensor_width, True
    else:
        size, horizontal = sensor_height, False
    t_fit = size / (2.0 * lens)
    t_vertical = t_fit * height / width if horizontal else t_fit
    fov_y = math.degrees(2.0 * math.atan(t_vertical))
    larger = 2.0 * t_vertical * max(width / height, 1.0)
    scale = 2.0 * t_fit / larger
    return fov_y, (shift[0] * scale, shift[1] * scale)


def view(matrix):
    """``(eye, forward, up)`` of a camera object's world matrix (a ``mathutils.Matrix``): its
    translation, its -Z and +Y axes normalised (scale ignored)."""
    rot = matrix.to_3x3()
    forward = -rot.col[2].normalized()
    up = rot.col[1].normalized()
    return matrix.translation.copy(), forward, up


def settings(scene, camera_object, local=None):
    """``lgh explosion``'s camera settings (``camera``, ``camera_up``, ``camera_shift``, ``width``,
    ``height``) for ``camera_object`` rendering ``scene``; ``local`` maps the world into the
    volume's own space (the inverse of its rigid placement: ``(matrix_3x3, translation)``).
    Anything but a perspective camera with square pixels is refused."""
    cam = camera_object.data
    if cam.type != "PERSP":
        kind = {"ORTHO": "orthographic", "PANO": "panoramic"}.get(cam.type, cam.type.lower())
        raise Refused(f"camera '{camera_object.name}' is {kind}: LGH renders perspective "
                      "cameras only (Camera > Lens > Type: Perspective)")
    r = scene.render
    if r.pixel_aspect_x != r.pixel_aspect_y:
        raise Refused(f"pixel aspect {r.pixel_aspect_x:g}:{r.pixel_aspect_y:g}: LGH renders "
                      "square pixels (Output > Format > Aspect 1:1)")
    width, height = resolution(r)
    fov, shift = projection(cam.sensor_fit, cam.sensor_width, cam.sensor_height, cam.lens,
                            (cam.shift_x, cam.shift_y), width, height)
    return flags(view(camera_object.matrix_world), fov, shift, (width, height), local)


def flags(eye_forward_up, fov, shift, size, local=None):
    """The camera settings of a view ``(eye, forward, up)`` in the world, its vertical field of
    view (degrees), lens shift (fractions of the larger side) and image ``size``, moved by
    ``local`` (``(rotation_3x3, translation)``: the world into the volume's own space)."""
    eye, forward, up = eye_forward_up
    if local is not None:
        rot, move = local
        eye, forward, up = rot @ eye + move, (rot @ forward).normalized(), (rot @ up).normalized()
    out = {"width": size[0], "height": size[1], "camera": (*eye, *(eye + forward), fov),
           "camera_up": tuple(up)}
    if shift != (0.0, 0.0):
        out["camera_shift"] = shift
    return out
