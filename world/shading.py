"""TinyRenderer's lighting of a flat face, reproduced bit for bit.

pybullet's TinyRenderer colours a fragment, per channel and in float32, as
``min(int(ambient * c + (diffuse * max(0, n . l)) * c), 255)`` where ``c = int(texel * rgba)``
is the material colour (texel 255 without a texture), ``n`` the face normal and ``l`` the
normalized light direction (specular is zero and shadows are off here). On a flat face
``n`` is constant, so each texel of the face has one colour, computed here once.
"""

from __future__ import annotations

import numpy as np

from world.config import RenderConfig

F32 = np.float32


def material_rgb(rgba: tuple[float, float, float, float], texels: np.ndarray | None = None) -> np.ndarray:
    """TinyRenderer's ``int(texel * rgba)`` per channel: uint8 (..., 3); untextured faces have texel 255."""
    base = np.full(3, 255, np.uint8) if texels is None else texels
    return (base.astype(F32) * np.asarray(rgba[:3], F32)).astype(np.uint8)


def flat_shade(rgb: np.ndarray, normal: tuple[float, float, float], render: RenderConfig) -> np.ndarray:
    """Colours (uint8 (..., 3)) of material colours ``rgb`` on a face whose unit normal is ``normal`` (world)."""
    light = np.asarray(render.light_direction, F32).astype(float)
    light = (light / np.linalg.norm(light)).astype(F32)
    n = np.asarray(normal, F32)
    diffuse = max(F32(0.0), n[0] * light[0] + n[1] * light[1] + n[2] * light[2])
    colour = rgb.astype(F32)
    value = F32(render.ambient) * colour + (F32(render.diffuse) * diffuse) * colour
    return np.minimum(value.astype(np.int32), 255).astype(np.uint8)
